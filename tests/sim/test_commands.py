"""``skillwright validate`` from the command line."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from skillwright.cli import main
from tests.conftest import SHIPPED_CAPABILITIES

HERE = Path(__file__).parent
RECORDING = SHIPPED_CAPABILITIES / "recordings" / "mr1"
CAPABILITY = SHIPPED_CAPABILITIES / "move-forward.ttl"


def _text(output: str) -> str:
    """The output with line wrapping undone (the console's width depends on the terminal)."""
    return " ".join(output.split())


def _args(tmp_path: Path, *extra: str) -> list[str]:
    return [
        "validate",
        str(HERE / "skills" / "move_forward.py"),
        "--capability",
        str(CAPABILITY),
        "--interfaces",
        str(RECORDING),
        "--scenario",
        str(HERE / "move_forward.scenarios.yaml"),
        "--only",
        "fast",
        "-o",
        str(tmp_path),
        *extra,
    ]


def test_validate_prints_verdicts_and_artefacts_and_exits_zero_when_all_pass(
    tmp_path: Path,
) -> None:
    result = CliRunner().invoke(main, _args(tmp_path, "--no-plot"))
    assert result.exit_code == 0, result.output
    assert "truth:distanceCovered" in result.stdout
    assert "behaviour passed: 1 scenario(s), 0 oracle(s) failed" in _text(result.stdout)
    assert (tmp_path / "fast.trace.json").is_file()
    assert not (tmp_path / "fast.png").exists()


def test_validate_json_has_the_overall_verdict_and_every_oracle(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, _args(tmp_path, "--json"))
    assert result.exit_code == 0, result.output
    document = json.loads(result.stdout)
    assert document["passed"] is True
    verdicts = document["scenarios"][0]["episodes"][0]["verdicts"]
    assert {"outcome", "limit:linearVelocity", "contact"} <= {v["oracle"] for v in verdicts}
    assert document["scenarios"][0]["plot"] == str(tmp_path / "fast.png")


def test_validate_reports_bad_input_with_exit_status_two(tmp_path: Path) -> None:
    missing = CliRunner().invoke(
        main,
        [
            "validate",
            str(tmp_path / "none.py"),
            "--capability",
            str(CAPABILITY),
            "--interfaces",
            str(RECORDING),
        ],
    )
    assert missing.exit_code == 2
    assert "no such file" in missing.stderr
    unknown = CliRunner().invoke(main, [*_args(tmp_path)[:-4], "--only", "nope"])
    assert unknown.exit_code == 2
    assert "has no such scenario (metre, fast)" in _text(unknown.stderr)


def test_validate_with_a_spec_stops_at_failed_static_checks(tmp_path: Path) -> None:
    broken = tmp_path / "broken.py"
    broken.write_text("def (:\n")
    result = CliRunner().invoke(
        main,
        [
            "validate",
            str(broken),
            "--capability",
            str(CAPABILITY),
            "--interfaces",
            str(RECORDING),
            "--spec",
            str(SHIPPED_CAPABILITIES / "move-forward.spec.yaml"),
        ],
    )
    assert result.exit_code == 1
    assert "the static checks failed; the skill was not run" in _text(result.stdout)


def test_validate_reports_the_rules_selected(tmp_path: Path) -> None:
    """A static rule the project ignores no longer stops the run; the oracles still judge."""
    skill = tmp_path / "skill.py"
    text = (HERE / "skills" / "move_forward.py").read_text(encoding="utf-8")
    logged = '        self.node.get_logger().info(f"travelled {self.out_distance:.3f} m")\n'
    assert logged in text
    unset = logged + '        self.node.get_logger().info(f"{self.never_set}")\n'
    skill.write_text(text.replace(logged, unset), encoding="utf-8")
    arguments = [
        *_args(tmp_path / "out"),
        "--spec",
        str(SHIPPED_CAPABILITIES / "move-forward.spec.yaml"),
    ]
    arguments[1] = str(skill)
    stopped = CliRunner().invoke(main, arguments, terminal_width=200)
    assert stopped.exit_code == 1
    assert "the static checks failed; the skill was not run" in _text(stopped.stdout)
    codes = {line.split()[2] for line in stopped.stdout.splitlines() if " error SW" in line}
    assert codes == {"SW313"}  # attribute-never-set
    (tmp_path / "pyproject.toml").write_text(
        f"[tool.skillwright]\nignore = {sorted(codes)!r}\n".replace("'", '"'), encoding="utf-8"
    )
    ran = CliRunner().invoke(main, arguments, terminal_width=200)
    assert "the skill was not run" not in _text(ran.stdout)
    assert "fast" in ran.stdout
