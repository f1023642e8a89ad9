"""``skillwright run`` as a user runs it."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from skillwright.cli import main
from skillwright.errors import InvalidArgumentError
from skillwright.runtime.commands import parse_inputs
from tests.runtime.conftest import MR1_RECORDING, skill_path


def test_a_clean_run_prints_the_states_and_outputs_and_exits_0() -> None:
    result = CliRunner().invoke(
        main,
        ["run", str(skill_path("get_position")), "--interfaces", str(MR1_RECORDING)],
        terminal_width=200,
    )
    assert result.exit_code == 0, result.output
    assert (
        "normal run: starting done, execute done, completing done, resetting done" in result.stdout
    )
    assert "outHeading = 0.0" in result.stdout
    assert "run passed, 0 error(s), 0 warning(s) (world: none" in result.stdout


def test_findings_are_printed_compiler_style_and_exit_1(tmp_path: Path) -> None:
    broken = tmp_path / "skill.py"
    broken.write_text(
        skill_path("get_position")
        .read_text(encoding="utf-8")
        .replace("transform.transform.translation", "transform.translation"),
        encoding="utf-8",
    )
    result = CliRunner().invoke(
        main, ["run", str(broken), "--interfaces", str(MR1_RECORDING)], terminal_width=200
    )
    assert result.exit_code == 1
    assert (
        f"{broken}:79:0: error SW604 [run.field] execute raised MessageFieldError: 'TransformStamped' object "
        "has no attribute 'translation' (geometry_msgs/msg/TransformStamped has: header, "
        "child_frame_id, transform)" in result.stdout
    )


def test_inputs_world_json_and_report_file(tmp_path: Path) -> None:
    out = tmp_path / "report.json"
    result = CliRunner().invoke(
        main,
        [
            "run",
            str(skill_path("move_forward")),
            "--interfaces",
            str(MR1_RECORDING),
            "--world",
            "kinematic",
            "-i",
            "inDistance=0.2 inLinearVelocity=0.2",
            "--json",
            "-o",
            str(out),
        ],
    )
    assert result.exit_code == 0, result.output
    report = json.loads(result.stdout)
    assert report["trace"]["inputs"] == {"inDistance": 0.2, "inLinearVelocity": 0.2}
    assert report["trace"]["world"] == "kinematic"
    assert [e["name"] for e in report["trace"]["episodes"]] == ["normal", "stop"]
    assert json.loads(out.read_text(encoding="utf-8")) == report


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["-i", "inDistance"], "write each input as NAME=VALUE"),
        (["-i", "inDistance=1.0"], "needs input(s) inLinearVelocity"),
        (["--scenario", "/nonexistent.yaml"], "scenario /nonexistent.yaml: no such file"),
    ],
)
def test_bad_input_is_one_error_line_and_exit_2(extra: list[str], message: str) -> None:
    result = CliRunner().invoke(
        main, ["run", str(skill_path("move_forward")), "--interfaces", str(MR1_RECORDING), *extra]
    )
    assert result.exit_code == 2
    assert message in result.stderr
    assert "Traceback" not in result.output


def test_a_missing_skill_file_is_named() -> None:
    result = CliRunner().invoke(main, ["run", "absent.py", "--interfaces", str(MR1_RECORDING)])
    assert result.exit_code == 2
    assert "skill file absent.py: no such file" in result.stderr


def test_inputs_parse_to_numbers_booleans_and_text() -> None:
    assert parse_inputs(("a=1 b=2.5", "c=true", "d=map")) == {
        "a": 1,
        "b": 2.5,
        "c": True,
        "d": "map",
    }
    with pytest.raises(InvalidArgumentError, match="NAME=VALUE"):
        parse_inputs(("=1",))


def test_a_wait_too_short_for_the_motion_gets_a_measured_timeout(tmp_path: Path) -> None:
    from tests.runtime.test_waits import drive

    skill = tmp_path / "skill.py"
    skill.write_text(drive(1.0), encoding="utf-8")
    result = CliRunner().invoke(
        main,
        ["run", str(skill), "--interfaces", str(MR1_RECORDING), "--world", "kinematic"],
        terminal_width=400,
    )
    assert result.exit_code == 1
    assert "[run.exception] execute raised RuntimeError: the base did not cover 1 m" in (
        result.stdout
    )
    assert "[run.short_wait] the wait that gave up allows 1 s, less than execute needs" in (
        result.stdout
    )
    assert skill.read_text(encoding="utf-8") == drive(1.0)  # advice only: the file stays


def test_a_folder_for_the_skill_says_so(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, ["run", str(tmp_path), "--interfaces", str(MR1_RECORDING)])

    assert result.exit_code == 2
    assert f"skill file {tmp_path}: is a folder; give the skill's .py file" in result.output
