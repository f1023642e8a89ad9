"""``skillwright discover``: summary, JSON, atomic output file, user-facing errors."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from skillwright.cli import main
from skillwright.interfaces.inventory import Inventory
from tests.interfaces.sources.recordings import Topic, write_recording

pytest.importorskip("mcap")


@pytest.fixture
def bag(tmp_path: Path) -> Path:
    return write_recording(
        tmp_path / "robot.mcap",
        [
            Topic("/cmd_vel", "geometry_msgs/msg/Twist", "float64 x", messages=11),
            Topic("/rosout", "rcl_interfaces/msg/Log", "string msg", messages=2),
            Topic("/arm/home/_service_event", "demo/srv/Home_Event", "---\nbool ok", messages=2),
        ],
    )


def test_summary_lists_duration_counts_and_interfaces(bag: Path) -> None:
    result = CliRunner().invoke(main, ["discover", str(bag)], terminal_width=200)
    assert result.exit_code == 0, result.output
    assert "Duration:   1.000 s" in result.output
    assert "Messages:   15" in result.output
    assert "2 topics, 1 services, 0 actions" in result.output
    row = next(line for line in result.output.splitlines() if "/cmd_vel" in line)
    assert "geometry_msgs/msg/Twist" in row
    assert "~10.00" in row  # summary path: rate over chunk bounds
    assert "~ rate over chunk time bounds" in result.output
    assert "rosout" in next(line for line in result.output.splitlines() if "/rosout" in line)


def test_json_prints_only_the_inventory(bag: Path) -> None:
    result = CliRunner().invoke(main, ["discover", str(bag), "--json"])
    assert result.exit_code == 0, result.output
    inventory = Inventory.model_validate_json(result.stdout)
    assert [i.name for i in inventory.interfaces] == ["/cmd_vel", "/rosout", "/arm/home"]


def test_output_file_is_written_whole(bag: Path, tmp_path: Path) -> None:
    target = tmp_path / "out" / "inventory.json"
    target.parent.mkdir()
    result = CliRunner().invoke(main, ["discover", str(bag), "-o", str(target), "--read", "scan"])
    assert result.exit_code == 0, result.output
    assert f"inventory written to {target}" in result.output
    document = json.loads(target.read_text())
    assert document["sources"][0]["files"][0]["read_method"] == "scan"
    assert document["interfaces"][0]["traffic"]["times_exact"] is True
    assert "~" not in result.output
    assert list(target.parent.iterdir()) == [target]  # no temporary file left behind


def test_partial_recording_warns_with_the_offset(bag: Path, tmp_path: Path) -> None:
    data = bag.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) - 200])
    result = CliRunner().invoke(main, ["discover", str(cut)])
    assert result.exit_code == 0, result.output
    assert "warning:" in result.stderr
    assert "read only up to byte" in result.stderr


def test_non_mcap_input_is_a_one_line_error(tmp_path: Path) -> None:
    path = tmp_path / "notes.txt"
    path.write_text("hello")
    result = CliRunner().invoke(main, ["discover", str(path)])
    assert result.exit_code == 2
    assert result.stderr.startswith(f"error: {path}: not an MCAP file")
    assert "(at byte 0)" in result.stderr
    assert "Traceback" not in result.output


def test_output_folder_is_created_when_missing(bag: Path, tmp_path: Path) -> None:
    target = tmp_path / "new-folder" / "inventory.json"
    result = CliRunner().invoke(main, ["discover", str(bag), "-o", str(target)])
    assert result.exit_code == 0
    assert target.is_file()


def test_unwritable_output_is_a_user_error(bag: Path, tmp_path: Path) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    target = blocker / "inventory.json"
    result = CliRunner().invoke(main, ["discover", str(bag), "-o", str(target)])
    assert result.exit_code == 2
    assert "cannot write" in result.stderr


REPORT = '{"timestamp": "2025-03-04 13:46:42", "ros2_control_entities": {"topics": [{"name": "/cmd_vel", "type": "topic", "interfaces": [{"name": "geometry_msgs/msg/Twist", "details": "Vector3 linear\\n\\tfloat64 x"}]}], "services": [], "actions": []}}'


def test_report_source_is_summarised_without_recording_lines(tmp_path: Path) -> None:
    path = tmp_path / "system.json"
    path.write_text(REPORT, encoding="utf-8")
    result = CliRunner().invoke(main, ["discover", str(path)], terminal_width=200)
    assert result.exit_code == 0, result.output
    assert f"Source:     {path} (report)" in result.output
    assert "Captured:   2025-03-04 13:46:42" in result.output
    assert "Duration" not in result.output
    assert "1 topics, 0 services, 0 actions" in result.output


def test_recording_exports_as_a_report(bag: Path, tmp_path: Path) -> None:
    target = tmp_path / "report.json"
    result = CliRunner().invoke(
        main, ["discover", str(bag), "-o", str(target), "--format", "report"]
    )
    assert result.exit_code == 0, result.output
    assert f"report written to {target}" in result.output
    document = json.loads(target.read_text())
    topics = {e["name"]: e for e in document["ros2_control_entities"]["topics"]}
    assert topics["/cmd_vel"]["interfaces"] == [
        {"name": "geometry_msgs/msg/Twist", "details": "float64 x"}
    ]
    (service,) = document["ros2_control_entities"]["services"]
    assert service["interfaces"][0]["details"] == "---\nbool ok"


def test_report_json_goes_to_stdout_and_back_in(tmp_path: Path) -> None:
    path = tmp_path / "system.txt"  # told apart by content, not by name
    path.write_text(REPORT, encoding="utf-8")
    result = CliRunner().invoke(
        main, ["discover", str(path), "--json", "--format", "report", "--resource", "mr1"]
    )
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout) == json.loads(REPORT)
    result = CliRunner().invoke(main, ["discover", str(path), "--json", "--name", "mr1"])
    assert Inventory.model_validate_json(result.stdout).resource.name == "mr1"
