"""Finding the simulation's data: worlds, scenarios, the override."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.errors import InputFileNotFoundError
from skillwright.sim.assets import WORLD_NAMES, resolve_world, scenario_files, sim_dir


def test_the_shipped_worlds_and_scenarios_are_found() -> None:
    for name in WORLD_NAMES:
        assert resolve_world(name).is_file()
    assert len(scenario_files()) == 9


def test_a_world_file_resolves_relative_to_a_folder_and_a_bad_name_says_what_exists(
    tmp_path: Path,
) -> None:
    (tmp_path / "mine.xml").write_text("<mujoco/>")
    assert resolve_world("mine.xml", tmp_path) == tmp_path / "mine.xml"
    with pytest.raises(InputFileNotFoundError, match="open_floor, corridor, walled_room"):
        resolve_world("moon")


def test_the_data_folder_can_be_moved_with_an_environment_variable(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("SKILLWRIGHT_SIM_DIR", str(tmp_path))
    with pytest.raises(InputFileNotFoundError, match="SKILLWRIGHT_SIM_DIR"):
        sim_dir()
    (tmp_path / "worlds").mkdir()
    assert sim_dir() == tmp_path
    assert scenario_files() == []
