"""``skillwright spec check`` as a user sees it."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from skillwright.cli import main


def test_check_lists_states_and_says_valid(shared_data: Path) -> None:
    spec = shared_data / "cap2skill" / "skill-specs" / "rotate.json"
    result = CliRunner().invoke(main, ["spec", "check", str(spec)], terminal_width=200)
    assert result.exit_code == 0
    assert "rotate (REST)" in result.stdout
    assert "valid, 5 states" in result.stdout


def test_check_json_prints_the_normalised_spec(shared_data: Path) -> None:
    spec = shared_data / "cap2skill" / "skill-specs" / "mapping.json"
    result = CliRunner().invoke(main, ["spec", "check", str(spec), "--json"])
    assert json.loads(result.stdout)["name"] == "mapping"


def test_invalid_spec_exits_2_with_the_reason(tmp_path: Path) -> None:
    path = tmp_path / "s.yaml"
    path.write_text("name: s\nskill_interface: REST\nstates:\n  starting: go\n", encoding="utf-8")
    result = CliRunner().invoke(main, ["spec", "check", str(path)])
    assert result.exit_code == 2
    assert "the 'execute' state is required" in result.stderr
    assert "Traceback" not in result.output
