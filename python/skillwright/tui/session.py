"""The TUI session: what the user chose and typed, saved as it changes and restored on start.

The session lives in ``<workspace>/.skillwright/session.json``. It is written atomically
(:func:`skillwright.fileio.write_atomic`) a moment after each change, so killing the
process loses at most that moment. Paths inside the workspace are stored relative to it,
so a workspace can be moved or shared.

A session file that cannot be read (damaged, written by a newer version) never stops the
TUI: it is kept aside as ``session.json.unreadable`` and the TUI starts with a fresh session,
saying so. This module uses the standard library only (it is read before the first paint).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from skillwright.fileio import write_atomic

__all__ = ["SESSION_VERSION", "TABS", "SessionState", "SpecDraft", "load_session", "save_session"]

SESSION_VERSION = 1
"""Layout version of ``session.json``; a file with another version is not read."""

TABS = ("capability", "specification", "interfaces", "retrieval", "generation", "history")
"""The tabs of the main screen, in order; their ids in the session."""


@dataclass(frozen=True)
class SpecDraft:
    """The specification form as typed, valid or not."""

    name: str = ""
    description: str = ""
    skill_interface: str = "REST"
    states: dict[str, str] = field(default_factory=dict)
    """Text per PackML acting state, as typed (empty states left out)."""

    def document(self) -> dict[str, Any]:
        """The draft as a specification document in the short form (for ``parse_spec``)."""
        return {
            "name": self.name.strip(),
            "description": self.description,
            "skill_interface": self.skill_interface,
            "states": {k: v for k, v in self.states.items() if v.strip()},
        }

    @property
    def is_empty(self) -> bool:
        """True when nothing has been typed."""
        return not (self.name or self.description or any(v.strip() for v in self.states.values()))


@dataclass(frozen=True)
class SessionState:
    """Everything the TUI restores on start. Paths are workspace-relative where possible."""

    active_tab: str = "capability"
    capability: str | None = None
    """The selected capability model."""
    capability_iri: str | None = None
    """Which capability of that file, when it holds several."""
    spec_path: str | None = None
    """The file the draft was loaded from or last saved to."""
    spec_draft: SpecDraft = field(default_factory=SpecDraft)
    interfaces: str | None = None
    """The interface source: inventory, recording, rosbag2 folder or report."""
    show_infrastructure: bool = False
    enrich_engine: str = "rules"
    """Enrichment engine: ``rules`` or ``llm`` (the generation model)."""
    pinned: tuple[str, ...] = ()
    """Interfaces the user forces into generation."""
    dropped: tuple[str, ...] = ()
    """Interfaces the user removed from generation."""
    model: str | None = None
    """models.toml id; None for the configured default."""
    skeleton: bool = False
    """Write the deterministic skeleton only, without a model."""
    k: int = 4
    dense: bool = False
    """Use the embedding model in retrieval (else lexical only)."""
    attempts: int = 3
    """Answers the model may give per method: the first, then repairs."""
    candidates: int = 1
    """Candidate skills of the first round (best-of-N); 1: the greedy answer alone."""
    last_result: str | None = None
    """The result folder the Generation tab showed last, shown again on start."""
    ranked: bool = False
    """The Retrieval tab showed a ranking: it ranks again once the inputs are loaded."""

    def to_json(self) -> str:
        """The document written to ``session.json``."""
        data = asdict(self)
        data["pinned"] = list(self.pinned)
        data["dropped"] = list(self.dropped)
        return json.dumps({"version": SESSION_VERSION, **data}, indent=2, sort_keys=True) + "\n"

    @classmethod
    def from_json(cls, text: str) -> SessionState:
        """Reads a ``session.json``; ``ValueError`` says what is wrong with it."""
        try:
            data = json.loads(text)
        except json.JSONDecodeError as error:
            raise ValueError(f"line {error.lineno}: {error.msg}") from None
        if not isinstance(data, dict):
            raise ValueError("not a JSON object")
        version = data.pop("version", None)
        if version != SESSION_VERSION:
            raise ValueError(
                f"layout version {version!r}, this skillwright reads {SESSION_VERSION}"
            )
        known = {f.name for f in fields(cls)}
        values = {k: v for k, v in data.items() if k in known}
        draft = values.pop("spec_draft", {}) or {}
        if not isinstance(draft, dict) or not isinstance(draft.get("states", {}), dict):
            raise ValueError("spec_draft is not an object with a 'states' object")
        draft_fields = {f.name for f in fields(SpecDraft)}
        spec_draft = SpecDraft(
            **{k: v for k, v in draft.items() if k in draft_fields and v is not None}
        )
        state = cls(spec_draft=spec_draft, **values)
        state = replace(state, pinned=tuple(state.pinned), dropped=tuple(state.dropped))
        if state.active_tab not in TABS:
            state = replace(state, active_tab="capability")
        if state.enrich_engine not in ("rules", "llm"):
            state = replace(state, enrich_engine="rules")
        _check_types(state)
        return state


def _check_types(state: SessionState) -> None:
    expected: dict[str, type | tuple[type, ...]] = {
        "active_tab": str,
        "capability": (str, type(None)),
        "capability_iri": (str, type(None)),
        "spec_path": (str, type(None)),
        "interfaces": (str, type(None)),
        "show_infrastructure": bool,
        "enrich_engine": str,
        "model": (str, type(None)),
        "skeleton": bool,
        "k": int,
        "dense": bool,
        "attempts": int,
        "candidates": int,
        "last_result": (str, type(None)),
        "ranked": bool,
    }
    for name, kind in expected.items():
        if not isinstance(getattr(state, name), kind):
            raise ValueError(f"{name} has the wrong type ({getattr(state, name)!r})")
    draft = state.spec_draft
    texts = [draft.name, draft.description, draft.skill_interface, *draft.states.values()]
    if not all(isinstance(t, str) for t in [*texts, *draft.states, *state.pinned, *state.dropped]):
        raise ValueError("spec_draft, pinned and dropped must hold text only")


def load_session(path: Path) -> tuple[SessionState, str | None]:
    """The saved session and, when it could not be used, a message saying why.

    An unreadable file is moved aside (``session.json.unreadable``) so the next save does not
    destroy what the user might want to recover by hand.
    """
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        return SessionState(), None
    except (OSError, UnicodeDecodeError) as error:
        return SessionState(), f"session {path} cannot be read ({error}); starting afresh"
    try:
        return SessionState.from_json(text), None
    except (ValueError, TypeError) as error:
        aside = path.with_name(path.name + ".unreadable")
        try:
            path.replace(aside)
        except OSError:
            aside = path
        return SessionState(), (
            f"session {path} is not usable ({error}); kept as {aside.name}, starting afresh"
        )


def save_session(path: Path, state: SessionState) -> None:
    """Writes the session atomically; raises :class:`~skillwright.errors.InputFileError`."""
    write_atomic(path, state.to_json())
