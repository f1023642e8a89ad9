"""The workspace: what is found where, and where results go."""

from __future__ import annotations

from datetime import datetime
from pathlib import Path

import pytest

from skillwright.tui.workspace import Workspace, resolve_workspace


def test_the_shipped_capabilities_folder_is_a_workspace_as_it_is(workspace: Path) -> None:
    found = Workspace(workspace)
    assert [p.name for p in found.capabilities()][:3] == [
        "collision-avoidance.ttl",
        "get-distance-to-nearest-object.ttl",
        "get-position.ttl",
    ]
    assert len(found.capabilities()) == 9
    assert len(found.specs()) == 9
    assert found.interface_sources() == [workspace / "recordings" / "mr1"]


def test_a_capabilitys_own_specification_is_found_by_name(workspace: Path) -> None:
    found = Workspace(workspace)
    assert found.spec_for(workspace / "rotate.ttl") == workspace / "rotate.spec.yaml"
    (workspace / "lonely.ttl").write_text("", encoding="utf-8")
    assert found.spec_for(workspace / "lonely.ttl") is None


def test_inventories_and_recordings_are_listed_but_not_the_files_inside_a_bag(
    tmp_path: Path,
) -> None:
    (tmp_path / "bags" / "run1").mkdir(parents=True)
    (tmp_path / "bags" / "run1" / "metadata.yaml").write_text("", encoding="utf-8")
    (tmp_path / "bags" / "run1" / "run1_0.mcap").write_bytes(b"")
    (tmp_path / "single.mcap").write_bytes(b"")
    (tmp_path / "robot.inventory.json").write_text("{}", encoding="utf-8")
    (tmp_path / "notes.json").write_text("{}", encoding="utf-8")
    assert Workspace(tmp_path).interface_sources() == [
        tmp_path / "bags" / "run1",
        tmp_path / "robot.inventory.json",
        tmp_path / "single.mcap",
    ]


def test_results_and_our_own_state_are_not_mistaken_for_inputs(tmp_path: Path) -> None:
    for folder in ("generated/x-20250101-120000", ".skillwright", ".hidden"):
        (tmp_path / folder).mkdir(parents=True)
        (tmp_path / folder / "copy.ttl").write_text("", encoding="utf-8")
    assert Workspace(tmp_path).capabilities() == []


def test_results_are_listed_newest_first_and_need_a_record(tmp_path: Path) -> None:
    space = Workspace(tmp_path)
    names = [
        "rotate-20250101-120000",
        "move_forward-20250301-090000",
        "rotate-20250301-090000-2",
        "broken-20260101-000000",
    ]
    for name in names:
        (space.generated_dir / name).mkdir(parents=True)
        if not name.startswith("broken"):
            (space.generated_dir / name / "record.json").write_text("{}", encoding="utf-8")
    assert [p.name for p in space.results()] == [
        "rotate-20250301-090000-2",
        "move_forward-20250301-090000",
        "rotate-20250101-120000",
    ]


def test_two_results_in_the_same_second_get_their_own_folders(tmp_path: Path) -> None:
    space = Workspace(tmp_path)
    moment = datetime(2025, 6, 1, 8, 30, 5)
    first = space.new_result_dir("rotate", moment)
    assert first == tmp_path / "generated" / "rotate-20250601-083005"
    first.mkdir(parents=True)
    assert space.new_result_dir("rotate", moment).name == "rotate-20250601-083005-2"


def test_paths_inside_the_workspace_are_kept_relative(tmp_path: Path) -> None:
    space = Workspace(tmp_path / "ws")
    assert space.relative(tmp_path / "ws" / "a" / "b.ttl") == "a/b.ttl"
    assert space.absolute("a/b.ttl") == tmp_path / "ws" / "a" / "b.ttl"
    outside = tmp_path / "elsewhere.ttl"
    assert space.relative(outside) == str(outside.resolve())
    assert space.absolute(str(outside)) == outside


@pytest.mark.parametrize(
    ("explicit", "has_capabilities", "expected"),
    [
        ("given", True, "given"),
        (None, True, "capabilities"),
        (None, False, "."),
    ],
)
def test_the_workspace_defaults_to_the_capabilities_folder_then_the_current_one(
    tmp_path: Path, explicit: str | None, has_capabilities: bool, expected: str
) -> None:
    if has_capabilities:
        (tmp_path / "capabilities").mkdir()
    chosen = resolve_workspace(tmp_path / explicit if explicit else None, tmp_path)
    assert chosen == (tmp_path / expected).resolve()


def test_the_ontologies_folder_is_read_with_every_model_and_not_listed(tmp_path: Path) -> None:
    (tmp_path / "ontologies").mkdir()
    (tmp_path / "ontologies" / "robot.ttl").write_text("", encoding="utf-8")
    (tmp_path / "ontologies" / "notes.txt").write_text("", encoding="utf-8")
    (tmp_path / "weld.ttl").write_text("", encoding="utf-8")
    workspace = Workspace(tmp_path)
    assert workspace.ontologies() == (tmp_path / "ontologies" / "robot.ttl",)
    assert workspace.capabilities() == [tmp_path / "weld.ttl"]
    assert "the workspace's ontologies/ folder" in workspace.ontology_hint()
    assert Workspace(tmp_path / "empty").ontologies() == ()
