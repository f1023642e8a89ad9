"""``skillwright check`` as a user runs it."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from skillwright.cli import main
from tests.conftest import SHIPPED_CAPABILITIES
from tests.interfaces.test_load import cut_recording

RECORDING = SHIPPED_CAPABILITIES / "recordings" / "mr1"
GOOD = SHIPPED_CAPABILITIES / "skills" / "navigate_to_point.py"


def args(skill: Path, *extra: str) -> list[str]:
    return [
        "check",
        str(skill),
        "--capability",
        str(SHIPPED_CAPABILITIES / "navigate-to-point.ttl"),
        "--spec",
        str(SHIPPED_CAPABILITIES / "navigate-to-point.spec.yaml"),
        "--interfaces",
        str(RECORDING),
        *extra,
    ]


def test_example_skill_passes_against_the_real_recording() -> None:
    result = CliRunner().invoke(main, args(GOOD), terminal_width=200)
    assert result.exit_code == 0, result.output
    assert "passed, 0 error(s), 0 warning(s)" in result.stdout


def test_a_recording_cut_short_is_warned_about(tmp_path: Path) -> None:
    cut = cut_recording(tmp_path)
    arguments = args(GOOD)
    arguments[arguments.index(str(RECORDING))] = str(cut)
    result = CliRunner().invoke(main, arguments, terminal_width=200)
    assert f"warning: {cut}: read only up to byte " in result.stderr


def test_findings_are_printed_compiler_style_and_exit_1(tmp_path: Path) -> None:
    broken = tmp_path / "skill.py"
    broken.write_text(
        GOOD.read_text()
        .replace('"/navigate_to_pose"', '"/navigate"')
        .replace("goal.pose.pose", "goal.target.pose"),
        encoding="utf-8",
    )
    result = CliRunner().invoke(
        main, [*args(broken), "--retrieved", "/navigate_to_pose"], terminal_width=200
    )
    assert result.exit_code == 1
    assert f"{broken}:" in result.stdout
    assert "action /navigate does not exist on this robot" in result.stdout
    assert "has no field 'target'" in result.stdout
    assert "/navigate_to_pose was retrieved but the code never uses it" in result.stdout


def test_json_report(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, [*args(GOOD), "--json"])
    report = json.loads(result.stdout)
    assert report["findings"] == []
    # The skill reads the robot pose through a tf2 listener: that is a use of /tf.
    assert report["used_interfaces"] == ["/cmd_vel", "/navigate_to_pose", "/tf"]


def test_missing_skill_file_is_an_input_error(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, args(tmp_path / "none.py"))
    assert result.exit_code == 2
    assert "no such file" in result.stderr
