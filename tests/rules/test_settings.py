"""Which rules apply: the project's [tool.skillwright] table and the command line's choice."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.errors import ConfigError, InvalidArgumentError
from skillwright.rules.registry import get
from skillwright.rules.settings import Selection, project_selection


def _finding(code: str):  # type: ignore[no-untyped-def]
    return get(code).finding(line=1, message="m")


def _project(tmp_path: Path, table: str) -> Path:
    (tmp_path / "pyproject.toml").write_text(f"[tool.skillwright]\n{table}\n", encoding="utf-8")
    skill = tmp_path / "skills" / "skill.py"
    skill.parent.mkdir()
    skill.write_text("", encoding="utf-8")
    return skill


def test_without_a_project_setting_every_rule_is_reported(tmp_path: Path) -> None:
    selection = project_selection(tmp_path / "skill.py")
    assert selection == Selection()
    assert selection.keeps(_finding("SW301"))


def test_the_nearest_pyproject_above_the_skill_chooses(tmp_path: Path) -> None:
    skill = _project(tmp_path, 'select = ["SW3", "waits"]\nignore = ["SW310"]')
    selection = project_selection(skill)
    assert selection.source == str(tmp_path / "pyproject.toml")
    kept = {
        c for c in ("SW301", "SW310", "SW401", "SW405", "SW101") if selection.keeps(_finding(c))
    }
    assert kept == {"SW301", "SW401", "SW405"}


def test_the_command_line_replaces_select_and_adds_to_ignore(tmp_path: Path) -> None:
    skill = _project(tmp_path, 'select = ["SW3"]\nignore = ["SW310"]')
    selection = project_selection(skill).narrowed(["SW1,SW310"], ["no-skill-class"])
    assert not selection.keeps(_finding("SW301"))  # select replaced
    assert selection.keeps(_finding("SW101"))
    assert not selection.keeps(_finding("SW102"))  # ignored by name on the command line
    assert not selection.keeps(_finding("SW310"))  # the project's ignore stays


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ('select = ["SW999"]', "names 'SW999', which no rule has"),
        ('select = "SW1"', "select must be a list of strings"),
        ('selekt = ["SW1"]', "has no setting 'selekt'"),
        ("select = [", "cannot be read as TOML"),
    ],
)
def test_a_bad_project_setting_names_the_file(tmp_path: Path, table: str, message: str) -> None:
    skill = _project(tmp_path, table)
    with pytest.raises(ConfigError, match=message) as raised:
        project_selection(skill)
    assert str(tmp_path / "pyproject.toml") in str(raised.value)


def test_an_unknown_rule_on_the_command_line_is_a_clear_error() -> None:
    with pytest.raises(InvalidArgumentError, match="--ignore SW9: no rule has that code"):
        Selection().narrowed([], ["SW9"])
