"""Relevance verdicts: is an interface for controlling the resource, or plumbing?

``control`` interfaces command, sense or plan for the resource; ``infrastructure`` ones
serve ROS 2 and its tooling (parameters, logging, introspection, lifecycle and bring-up,
time, metadata, visualisation, the simulator's own services). Infrastructure stays in the
inventory, but retrieval leaves it out by default.

The ``rules`` engine here is the rule table of :mod:`~skillwright.interfaces.infrastructure`
(each rule carries its reason) plus the description rules' account of how a control
interface serves the resource. :func:`agreement` compares a set of verdicts with a
reference selection, e.g. the Cap2Skill paper's filtered report.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from skillwright.interfaces.description import Role, control_role
from skillwright.interfaces.infrastructure import RULES
from skillwright.interfaces.inventory import Interface, InterfaceKind, Relevance

__all__ = [
    "RULES_ENGINE",
    "Agreement",
    "agreement",
    "relevance_by_rules",
    "relevance_by_rules_for",
]

RULES_ENGINE = "rules"
"""The engine name recorded in verdicts of the rule table."""

_ROLE_REASONS: dict[Role, str] = {
    "command": "commands the resource",
    "sense": "senses the resource or its surroundings",
    "plan": "plans or carries out a task for the resource",
    "manage": "selects or checks the controllers the resource is commanded through",
}

_UNKNOWN_REASONS: dict[InterfaceKind, str] = {
    "topic": "no infrastructure rule covers it, so this topic of the robot's software is "
    "taken to command or sense the resource",
    "service": "no infrastructure rule covers it, so this service of the robot's software "
    "is taken to act for the resource",
    "action": "an action is a goal-directed behaviour of the resource, and no "
    "infrastructure rule covers it",
}


def relevance_by_rules_for(kind: InterfaceKind, name: str, type_name: str) -> Relevance:
    """The rules engine's verdict for an interface given by kind, name and type."""
    for rule in RULES:
        if rule.matches(kind, name, type_name):
            return Relevance(
                relevant=False,
                category="infrastructure",
                reason=f"{rule.reason} (rule {rule.rule})",
                engine=RULES_ENGINE,
            )
    role = control_role(kind, name, type_name)
    if role is not None:
        package = type_name.split("/", 1)[0]
        reason = f"{_ROLE_REASONS[role]} ({package}, {type_name.rsplit('/', 1)[-1]})"
    else:
        reason = _UNKNOWN_REASONS[kind]
    return Relevance(relevant=True, category="control", reason=reason, engine=RULES_ENGINE)


def relevance_by_rules(interface: Interface) -> Relevance:
    """The rules engine's verdict for ``interface``.

    The rule table is applied afresh rather than trusting a stored
    :attr:`~skillwright.interfaces.inventory.Interface.infrastructure` flag, so an inventory
    saved by an older version gets today's rules.
    """
    return relevance_by_rules_for(interface.kind, interface.name, interface.type_name)


@dataclass(frozen=True)
class Agreement:
    """How a ``control`` selection compares with a reference selection of the same interfaces."""

    total: int
    """Interfaces judged."""
    both: frozenset[str]
    """Control for both (true positives)."""
    only_ours: frozenset[str]
    """Control for us, left out by the reference (false positives)."""
    only_reference: frozenset[str]
    """Kept by the reference, infrastructure for us (false negatives)."""

    @property
    def precision(self) -> float:
        """Share of our control set the reference keeps (1.0 for an empty set)."""
        chosen = len(self.both) + len(self.only_ours)
        return len(self.both) / chosen if chosen else 1.0

    @property
    def recall(self) -> float:
        """Share of the reference's set we call control (1.0 for an empty reference)."""
        kept = len(self.both) + len(self.only_reference)
        return len(self.both) / kept if kept else 1.0

    @property
    def disagreements(self) -> frozenset[str]:
        """Interfaces judged differently."""
        return self.only_ours | self.only_reference


def agreement(verdicts: Mapping[str, Relevance], reference: Iterable[str]) -> Agreement:
    """Compares ``verdicts`` (interface name -> verdict) with the names ``reference`` keeps.

    Names in ``reference`` without a verdict are an error: the comparison would be unfair.
    """
    kept = frozenset(reference)
    missing = sorted(kept - verdicts.keys())
    if missing:
        raise ValueError(f"no verdict for reference interface(s): {', '.join(missing)}")
    ours = frozenset(name for name, verdict in verdicts.items() if verdict.relevant)
    return Agreement(
        total=len(verdicts),
        both=ours & kept,
        only_ours=ours - kept,
        only_reference=kept - ours,
    )
