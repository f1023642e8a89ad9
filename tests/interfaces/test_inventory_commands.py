"""``skillwright inventory show|describe`` on the shipped MR-1 recording and saved inventories."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from skillwright.cli import main
from skillwright.interfaces.inventory import Inventory
from tests.conftest import SHIPPED_CAPABILITIES
from tests.interfaces.test_load import cut_recording

RECORDING = SHIPPED_CAPABILITIES / "recordings" / "mr1"


@pytest.fixture(autouse=True)
def _cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("SKILLWRIGHT_CACHE_DIR", str(tmp_path / "cache"))


@pytest.fixture
def saved(tmp_path: Path) -> Path:
    target = tmp_path / "mr1.json"
    result = CliRunner().invoke(main, ["discover", str(RECORDING), "-o", str(target), "--json"])
    assert result.exit_code == 0, result.output
    return target


def _row(output: str, name: str) -> str:
    return next(line for line in output.splitlines() if line.startswith(name + " "))


def test_show_warns_when_the_recording_was_read_only_in_part(tmp_path: Path) -> None:
    cut = cut_recording(tmp_path)
    result = CliRunner().invoke(main, ["inventory", "show", str(cut)])
    assert result.exit_code == 0, result.output
    assert f"warning: {cut}: read only up to byte " in result.stderr
    assert "/cmd_vel" in result.stdout


def test_show_lists_control_interfaces_with_short_descriptions() -> None:
    result = CliRunner().invoke(main, ["inventory", "show", str(RECORDING)])
    assert result.exit_code == 0, result.output
    row = _row(result.output, "/scan")
    assert "sensor_msgs/msg/LaserScan" in row
    assert "control*" in row
    assert "2-D range measurements around the robot" in row
    assert "/rosout" not in result.output
    assert "infrastructure hidden (--all shows them)" in result.output
    assert "* not stored" in result.output


def test_show_all_includes_infrastructure_and_kind_filters() -> None:
    result = CliRunner().invoke(
        main, ["inventory", "show", str(RECORDING), "--all", "--kind", "service"]
    )
    assert result.exit_code == 0, result.output
    assert "infrastructure*" in _row(result.output, "/slam_toolbox/get_parameters")
    assert "/scan " not in result.output
    assert "/navigate_to_pose" not in result.output


def test_show_json_prints_the_entries() -> None:
    result = CliRunner().invoke(
        main, ["inventory", "show", str(RECORDING), "--json", "--kind", "action"]
    )
    assert result.exit_code == 0, result.output
    entries = json.loads(result.stdout)
    assert len(entries) == 10
    assert {e["kind"] for e in entries} == {"action"}
    assert "goal" in entries[0]["definitions"]


def test_describe_rewrites_a_saved_inventory_in_place(saved: Path) -> None:
    result = CliRunner().invoke(main, ["inventory", "describe", str(saved)])
    assert result.exit_code == 0, result.output
    assert "77 interfaces: 77 described by rules" in result.output
    assert "relevance: 38 control, 39 infrastructure" in result.output
    inventory = Inventory.model_validate_json(saved.read_text())
    scan = inventory.interface("/scan")
    assert scan.description is not None
    assert scan.description.engine == "rules"
    assert scan.relevance is not None
    assert scan.relevance.category == "control"
    assert [p.name for p in saved.parent.iterdir() if p.name.startswith(".")] == []

    shown = CliRunner().invoke(main, ["inventory", "show", str(saved)])
    row = _row(shown.output, "/scan")
    assert "control*" not in row
    assert row.rstrip().endswith("rules")
    assert "* not stored" not in shown.output


def test_describe_a_recording_needs_an_output_file(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, ["inventory", "describe", str(RECORDING)])
    assert result.exit_code == 2
    assert "give -o FILE" in result.output
    target = tmp_path / "out.json"
    result = CliRunner().invoke(main, ["inventory", "describe", str(RECORDING), "-o", str(target)])
    assert result.exit_code == 0, result.output
    assert f"inventory written to {target}" in result.output
    assert all(
        i.relevance is not None
        for i in Inventory.model_validate_json(target.read_text()).interfaces
    )


def test_describe_rules_engine_refuses_a_model(saved: Path) -> None:
    result = CliRunner().invoke(main, ["inventory", "describe", str(saved), "--model", "coder"])
    assert result.exit_code == 2
    assert "--engine llm" in result.output


@pytest.mark.parametrize("command", ["show", "describe"])
def test_a_missing_inventory_is_an_error_naming_it(command: str, tmp_path: Path) -> None:
    missing = tmp_path / "nope.json"
    result = CliRunner().invoke(main, ["inventory", command, str(missing)])
    assert result.exit_code == 2
    assert "nope.json: no such file or folder" in result.output
    assert "Traceback" not in result.output


def test_describe_keeps_the_descriptions_a_report_brought(
    shared_data: Path, tmp_path: Path
) -> None:
    report = (
        shared_data
        / "cap2skill"
        / "interface-reports"
        / "ros2_system_report_with_descriptions.json"
    )
    target = tmp_path / "paper.json"
    result = CliRunner().invoke(main, ["inventory", "describe", str(report), "-o", str(target)])
    assert result.exit_code == 0, result.output
    assert (
        "33 interfaces: 33 described by rules, 33 report descriptions kept (verdicts filled)"
        in result.output
    )
    cmd_vel = Inventory.model_validate_json(target.read_text()).interface("/cmd_vel")
    assert cmd_vel.description is not None
    assert cmd_vel.description.engine == "report"
    assert cmd_vel.relevance is not None
    assert cmd_vel.relevance.engine == "rules"
    replaced = CliRunner().invoke(
        main, ["inventory", "describe", str(target), "--replace-report-descriptions"]
    )
    assert replaced.exit_code == 0, replaced.output
    assert "kept" not in replaced.output
    cmd_vel = Inventory.model_validate_json(target.read_text()).interface("/cmd_vel")
    assert cmd_vel.description is not None
    assert cmd_vel.description.engine == "rules"
