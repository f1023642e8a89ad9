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


# ------------------------------------------------------------------ rules: fixes, selection


def _with_cases(tmp_path: Path, *codes: str) -> Path:
    """move_forward_good with the INVALID edits of the rules ``codes`` (tests/rules/cases)."""
    from tests.rules.cases import GOOD as GOOD_SKILL
    from tests.rules.cases import edited, load

    text = GOOD_SKILL.read_text(encoding="utf-8")
    cases = load("static")
    for code in codes:
        case = cases[code]["invalid"][0]
        assert case["skill"] == "move_forward_good"
        text = edited(text, case["edits"])
    skill = tmp_path / "skill.py"
    skill.write_text(text, encoding="utf-8")
    return skill


def move_forward_args(skill: Path, *extra: str) -> list[str]:
    return [
        "check",
        str(skill),
        "--capability",
        str(SHIPPED_CAPABILITIES / "move-forward.ttl"),
        "--spec",
        str(SHIPPED_CAPABILITIES / "move-forward.spec.yaml"),
        "--interfaces",
        str(RECORDING),
        *extra,
    ]


def test_fix_puts_in_the_safe_fixes_only_and_says_what_is_left(tmp_path: Path) -> None:
    skill = _with_cases(tmp_path, "SW205", "SW402")  # a safe fix and an unsafe one
    result = CliRunner().invoke(main, move_forward_args(skill), terminal_width=200)
    assert result.exit_code == 1
    assert "error SW205 [grounding]" in result.stdout
    assert "1 fixable with --fix, 1 more with --fix --unsafe-fixes" in result.stdout
    result = CliRunner().invoke(main, move_forward_args(skill, "--fix"), terminal_width=200)
    assert "fixed 1 finding(s): SW205" in result.stderr
    text = skill.read_text(encoding="utf-8")
    assert "self.odom_msg.pose.pose.position\n" in text  # the safe fix is in
    assert "SW205" not in result.stdout
    assert "SW402" in result.stdout
    assert "time.sleep(0.05)\n        self.start_x" not in text  # the unsafe one is not
    result = CliRunner().invoke(
        main, move_forward_args(skill, "--fix", "--unsafe-fixes"), terminal_width=200
    )
    assert result.exit_code == 0, result.output
    assert "fixed 1 finding(s): SW402" in result.stderr
    assert "time.sleep(0.05)\n        self.start_x" in skill.read_text(encoding="utf-8")


def test_unsafe_fixes_need_fix(tmp_path: Path) -> None:
    skill = _with_cases(tmp_path, "SW402")
    result = CliRunner().invoke(main, move_forward_args(skill, "--unsafe-fixes"))
    assert result.exit_code == 2
    assert "--unsafe-fixes goes with --fix" in result.stderr


def test_select_and_ignore_choose_the_rules_reported(tmp_path: Path) -> None:
    skill = _with_cases(tmp_path, "SW205", "SW402")
    ignored = CliRunner().invoke(main, move_forward_args(skill, "--ignore", "SW2"))
    assert "SW205" not in ignored.stdout
    assert "SW402" in ignored.stdout
    selected = CliRunner().invoke(main, move_forward_args(skill, "--select", "unknown-field"))
    assert "SW205" in selected.stdout
    assert "SW402" not in selected.stdout
    (tmp_path / "pyproject.toml").write_text(
        '[tool.skillwright]\nignore = ["loop-never-sleeps"]\n', encoding="utf-8"
    )
    project = CliRunner().invoke(main, move_forward_args(skill))
    assert "SW205" in project.stdout
    assert "SW402" not in project.stdout
    unknown = CliRunner().invoke(main, move_forward_args(skill, "--select", "SW999"))
    assert unknown.exit_code == 2
    assert "--select SW999: no rule has that code" in unknown.stderr


def test_explain_prints_a_rule_s_documentation() -> None:
    result = CliRunner().invoke(main, ["check", "--explain", "SW402"], terminal_width=200)
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("SW402 loop-never-sleeps (static, error")
    assert "Why it matters" in result.stdout
    assert "Fix (unsafe)" in result.stdout
    by_name = CliRunner().invoke(main, ["check", "--explain", "loop-never-sleeps"])
    assert by_name.stdout == result.stdout
    unknown = CliRunner().invoke(main, ["check", "--explain", "SW000"])
    assert unknown.exit_code == 2
    assert "--explain SW000: no rule has that code or name" in unknown.stderr


def test_rules_lists_every_rule() -> None:
    from skillwright.rules.registry import all_rules

    listed = CliRunner().invoke(main, ["rules"], terminal_width=200)
    assert listed.exit_code == 0
    lines = listed.stdout.splitlines()
    assert [line.split()[0] for line in lines] == [r.code for r in all_rules()]
    as_json = json.loads(CliRunner().invoke(main, ["rules", "--json"]).stdout)
    assert {r["fix"] for r in as_json} == {None, "safe", "unsafe"}
    one = CliRunner().invoke(main, ["rules", "SW701"])
    assert one.stdout.startswith("SW701 sim-outcome (simulation, error")


def test_bind_names_what_a_parameter_stands_for(tmp_path: Path) -> None:
    from tests.rules.cases import GOOD as GOOD_SKILL

    skill = tmp_path / "skill.py"
    skill.write_text(
        GOOD_SKILL.read_text(encoding="utf-8").replace(
            'name="inDistance", description="Distance [m]."', 'name="knob", description="A knob."'
        ),
        encoding="utf-8",
    )
    unbound = CliRunner().invoke(main, move_forward_args(skill), terminal_width=200)
    assert "no @skill_parameter for the capability's input inDistance" in unbound.stdout
    bound = CliRunner().invoke(
        main, move_forward_args(skill, "--bind", "knob=inDistance"), terminal_width=200
    )
    assert bound.exit_code == 0, bound.output
    bad = CliRunner().invoke(main, move_forward_args(skill, "--bind", "knob"))
    assert bad.exit_code == 2
    assert "is not SKILL_NAME=CAPABILITY_NAME" in bad.output
