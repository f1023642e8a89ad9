"""``skillwright capability show`` as a user sees it."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from skillwright.cli import main


def test_show_summarises_inputs_outputs_constraints_and_limits(shared_data: Path) -> None:
    model = shared_data / "cap2skill" / "capability-models" / "move-forward.ttl"
    result = CliRunner().invoke(main, ["capability", "show", str(model)], terminal_width=200)
    assert result.exit_code == 0, result.output
    for expected in (
        "Move forward",
        "inDistance",
        "outVelocity",
        "m/s",
        "constraintDistance: inDistance = outDistance",
        "limit: velocity <= 0.8 m/s",
    ):
        assert expected in result.stdout
    assert "owl:imports" in result.stderr


def test_show_json_prints_the_capability_document(shared_data: Path) -> None:
    model = shared_data / "cap2skill" / "capability-models" / "rotate.ttl"
    result = CliRunner().invoke(main, ["capability", "show", str(model), "--json"])
    assert result.exit_code == 0
    document = json.loads(result.stdout)
    assert document["capability"]["name"] == "rotate"
    assert document["capability"]["constraints"][0]["relation"] == "="


def test_bad_file_gives_a_message_and_exit_status_2(tmp_path: Path) -> None:
    path = tmp_path / "broken.ttl"
    path.write_text("@prefix : <http://x#> .\n:a :b \n", encoding="utf-8")
    result = CliRunner().invoke(main, ["capability", "show", str(path)])
    assert result.exit_code == 2
    assert result.stderr.startswith("error: ")
    assert "broken.ttl:" in result.stderr
    assert "Traceback" not in result.output


def test_missing_file_gives_a_message_and_exit_status_2(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, ["capability", "show", str(tmp_path / "x.ttl")])
    assert result.exit_code == 2
    assert "no such file" in result.stderr
