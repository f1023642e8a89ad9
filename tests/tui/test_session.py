"""The session file: written atomically, read back, and never a reason not to start."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from skillwright.tui.session import SessionState, SpecDraft, load_session, save_session


def test_a_session_reads_back_as_it_was_written(tmp_path: Path) -> None:
    state = SessionState(
        active_tab="retrieval",
        capability="rotate.ttl",
        spec_draft=SpecDraft(name="rotate", states={"execute": "turn"}),
        interfaces="recordings/mr1",
        pinned=("/cmd_vel",),
        dropped=("/backup",),
        model="tiny",
        k=6,
        dense=False,
    )
    path = tmp_path / ".skillwright" / "session.json"
    save_session(path, state)
    assert load_session(path) == (state, None)
    assert not list(path.parent.glob("*.tmp"))


def test_no_session_file_means_a_fresh_session_without_complaint(tmp_path: Path) -> None:
    assert load_session(tmp_path / "session.json") == (SessionState(), None)


@pytest.mark.parametrize(
    ("text", "problem"),
    [
        ("{not json", "line 1"),
        ("[]", "not a JSON object"),
        ('{"version": 99}', "layout version 99"),
        ('{"version": 1, "k": "four"}', "k has the wrong type"),
        ('{"version": 1, "spec_draft": {"states": []}}', "spec_draft"),
        ('{"version": 1, "pinned": [1, 2]}', "text only"),
    ],
)
def test_an_unusable_session_is_kept_aside_and_the_tui_starts_afresh(
    tmp_path: Path, text: str, problem: str
) -> None:
    path = tmp_path / "session.json"
    path.write_text(text, encoding="utf-8")
    state, message = load_session(path)
    assert state == SessionState()
    assert message is not None
    assert problem in message
    assert str(path) in message
    assert (tmp_path / "session.json.unreadable").read_text(encoding="utf-8") == text
    assert not path.exists()


def test_unknown_keys_from_a_newer_session_are_ignored(tmp_path: Path) -> None:
    path = tmp_path / "session.json"
    path.write_text(json.dumps({"version": 1, "future": True, "k": 7}), encoding="utf-8")
    state, message = load_session(path)
    assert message is None
    assert state.k == 7


def test_an_unknown_tab_falls_back_to_the_first(tmp_path: Path) -> None:
    path = tmp_path / "session.json"
    path.write_text(json.dumps({"version": 1, "active_tab": "gone"}), encoding="utf-8")
    assert load_session(path)[0].active_tab == "capability"


def test_the_draft_becomes_a_specification_document_without_empty_states() -> None:
    draft = SpecDraft(
        name=" rotate ",
        description="Turn.",
        skill_interface="MQTT",
        states={"execute": "turn", "stopping": "  "},
    )
    assert draft.document() == {
        "name": "rotate",
        "description": "Turn.",
        "skill_interface": "MQTT",
        "states": {"execute": "turn"},
    }
    assert not draft.is_empty
    assert SpecDraft(states={"execute": " "}).is_empty
