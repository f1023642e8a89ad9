"""Scenario files: valid ones load, mistakes name the file, the line or the field."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.errors import FileFormatError, InputFileNotFoundError
from skillwright.runtime.scenario import load_scenario
from tests.runtime.conftest import SKILLS


@pytest.mark.parametrize("path", sorted(SKILLS.glob("*.scenario.yaml")), ids=lambda p: p.stem)
def test_shipped_scenarios_load(path: Path) -> None:
    assert load_scenario(path).description


def test_a_scenario_scripts_interfaces_and_deadlines(tmp_path: Path) -> None:
    path = tmp_path / "s.yaml"
    path.write_text(
        "world: kinematic\n"
        "inputs: {inDistance: 1.0}\n"
        "actions:\n  /navigate_to_pose: {accept: false}\n"
        "services:\n  /map_saver/save_map: {response: {result: false}, delay: 0.5}\n"
        "topics:\n  /scan: {silent: true}\n"
        "deadlines: {state: 30}\n"
        "expect: abort\n",
        encoding="utf-8",
    )

    scenario = load_scenario(path)

    assert scenario.actions["/navigate_to_pose"].accept is False
    assert scenario.services["/map_saver/save_map"].response == {"result": False}
    assert scenario.topics["/scan"].silent
    assert scenario.deadlines.state == 30
    assert scenario.deadlines.busy == 5.0


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("world: [kinematic\n", r"s\.yaml:2:1: YAML syntax error"),
        ("- a\n- b\n", "a mapping of settings, not a list"),
        ("wrld: kinematic\n", r"wrld: Extra inputs are not permitted"),
        (
            "actions:\n  /nav: {outcome: explode}\n",
            r"actions\./nav\.outcome: Input should be 'succeed', 'abort' or 'never'",
        ),
        ("deadlines: {state: -1}\n", r"deadlines\.state: Input should be greater than 0"),
    ],
)
def test_mistakes_name_the_file_and_where(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "s.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(FileFormatError, match=message):
        load_scenario(path)


def test_a_missing_scenario_file_is_named(tmp_path: Path) -> None:
    with pytest.raises(InputFileNotFoundError, match="no such file"):
        load_scenario(tmp_path / "absent.yaml")


def test_an_empty_file_is_the_default_scenario(tmp_path: Path) -> None:
    path = tmp_path / "empty.yaml"
    path.write_text("", encoding="utf-8")
    assert load_scenario(path).expect == "complete"
