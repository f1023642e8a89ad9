"""Typed messages the TUI's workers post back to the widgets that started them.

Workers run the engine in threads and never touch widgets; they post one of these
(``post_message`` is thread-safe) and the widget's handler updates the screen on the
event loop. Engine types are imported for type checking only, so importing this module
stays cheap.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from textual.message import Message

if TYPE_CHECKING:
    from rich.console import RenderableType

    from skillwright.capability.model import CapabilityChoice, CapabilityLoad
    from skillwright.interfaces.inventory import Inventory
    from skillwright.retrieval.retrieve import Hit
    from skillwright.spec.model import SkillSpec

__all__ = [
    "CapabilityChoices",
    "CapabilityLoaded",
    "EnrichProgress",
    "GenerationEvent",
    "GenerationFinished",
    "HistoryLoaded",
    "InventoryEnriched",
    "InventoryLoaded",
    "JobFailed",
    "ModelsListed",
    "ResultRestored",
    "RetrievalFinished",
    "SpecFileLoaded",
    "SpecFormReady",
]


class _ForThePoster(Message):
    """A message only the widget that posted it handles: it does not bubble up through the
    tabs and the screen, whose queues a streaming worker would otherwise keep busy."""

    bubble = False


@dataclass
class JobFailed(Message):
    """An engine call failed with a :class:`~skillwright.errors.SkillwrightError`."""

    job: str
    """Which job: capability, specification, interfaces, enrichment, retrieval, ..."""
    message: str
    """The engine's message, written for the user (file, line, IRI and what to do)."""
    cancelled: bool = False
    """True when the job stopped because the user cancelled it."""


@dataclass
class CapabilityLoaded(_ForThePoster):
    """A capability model was read."""

    path: Path
    load: CapabilityLoad
    summary: RenderableType
    """The engine's readable summary (``render_capability``)."""


@dataclass
class CapabilityChoices(_ForThePoster):
    """A capability file holds several capabilities; the user chooses one."""

    path: Path
    choices: list[CapabilityChoice]
    wanted: str | None = None
    """The IRI asked for that matched none or several of them, if one was."""


@dataclass
class SpecFormReady(_ForThePoster):
    """The specification module is imported; the form can be built."""

    states: tuple[str, ...]
    interfaces: tuple[str, ...]


@dataclass
class SpecFileLoaded(_ForThePoster):
    """A specification file was read and checked."""

    path: Path
    spec: SkillSpec
    fill: bool = False
    """True when the user asked to load it into the form (else it is only compared)."""


@dataclass
class InventoryLoaded(_ForThePoster):
    """An interface source was read into an inventory."""

    source: Path
    inventory: Inventory


@dataclass
class EnrichProgress(_ForThePoster):
    """Enrichment finished ``done`` of ``total`` interfaces."""

    done: int
    total: int
    current: str = ""


@dataclass
class InventoryEnriched(_ForThePoster):
    """Enrichment finished; the enriched inventory was saved to ``saved_to``."""

    inventory: Inventory
    saved_to: Path
    summary: str = ""
    """What the engine did, in one line (counts of described, cached, verdicts)."""


@dataclass
class RetrievalFinished(_ForThePoster):
    """Retrieval ranked the interfaces."""

    hits: list[Hit]
    dense: bool
    """True when the embedding model took part (hybrid), False for BM25 alone."""


@dataclass
class ModelsListed(_ForThePoster):
    """The generation models of models.toml, as (label, id) pairs, and the default id."""

    options: list[tuple[str, str]]
    default: str | None


@dataclass
class GenerationEvent(_ForThePoster):
    """One event of :func:`skillwright.pipeline.run_generation` (stage, tokens, stats)."""

    event: Any


@dataclass
class GenerationFinished(_ForThePoster):
    """Generation wrote its result folder; ``outcome`` is the pipeline's ``Outcome``."""

    outcome: Any


@dataclass
class ResultRestored(_ForThePoster):
    """The last session's result was read: its folder and ``GenerationRecord``."""

    folder: Path
    record: Any


@dataclass
class HistoryLoaded(_ForThePoster):
    """The workspace's earlier generations: (folder, record) pairs, newest first."""

    entries: list[tuple[Path, Any]] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
