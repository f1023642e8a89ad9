"""Labelled retrieval sets and recall measurement, shared by the tests and the benchmark.

A labelled set (``tests/retrieval/labels/*.yaml``) names, for each capability, the
interfaces a correct skill needs on one robot: ``required`` ones, and ``alternatives``
groups of which any one member is enough. Each required interface and each group is one
*need*. ``recall@k`` counts the needs with a member among the first ``k`` hits.

A capability can need more interfaces than ``k`` (the MR-1's mapping needs six); those
needs cannot all be found at that ``k`` by any ranking, so :class:`Recall` also reports
the *attainable* count, ``min(needs, k)`` summed over the capabilities.

The Cap2Skill report (the paper's robot) is read by a small parser here until report
import lands in ``skillwright.interfaces.sources``.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import yaml

from skillwright.capability import Capability, load_capability
from skillwright.interfaces.infrastructure import classify
from skillwright.interfaces.inventory import (
    Description,
    Interface,
    InterfaceKind,
    Inventory,
    MessageDefinition,
    MessageField,
    Relevance,
    Resource,
    Source,
)
from skillwright.interfaces.load import load_inventory
from skillwright.interfaces.ros2msg import BUILTIN_TYPES
from skillwright.spec import SkillSpec, load_spec
from tests.conftest import REPO_ROOT, SHARED

LABELS = Path(__file__).resolve().parent / "labels"

SETS = ("mr1", "cap2skill", "cap2skill-filtered")
"""The labelled settings: our MR-1 recording; the paper's robot with its full report
(infrastructure left out by our rules); the same robot with only the 33 interfaces the
paper's relevance filter kept, carrying the paper's LLM-written descriptions."""

Ranker = Callable[[Inventory, Capability, SkillSpec, int], Sequence[str]]
"""(inventory, capability, spec, k) -> interface names, best first."""


@dataclass(frozen=True)
class Case:
    """One capability with the interfaces its skill needs."""

    name: str
    capability: Capability
    spec: SkillSpec
    required: tuple[str, ...]
    alternatives: tuple[tuple[str, ...], ...]

    @property
    def needs(self) -> list[tuple[str, ...]]:
        """Each need as the names that satisfy it."""
        return [(name,) for name in self.required] + list(self.alternatives)


@dataclass(frozen=True)
class LabelledSet:
    """A robot's inventory and the labelled capabilities."""

    name: str
    inventory: Inventory
    cases: tuple[Case, ...]

    @property
    def need_count(self) -> int:
        """Needs over all cases."""
        return sum(len(c.needs) for c in self.cases)


@dataclass
class Recall:
    """How many needs a ranking found in its first ``k`` hits."""

    k: int
    found: int = 0
    total: int = 0
    attainable: int = 0
    misses: list[str] = field(default_factory=list)

    def __str__(self) -> str:
        return f"{self.found}/{self.total}"


def measure(labelled: LabelledSet, rank: Ranker, k: int) -> Recall:
    """Recall@k of ``rank`` over the set; ``misses`` names each need not found."""
    result = Recall(k)
    for case in labelled.cases:
        hits = list(rank(labelled.inventory, case.capability, case.spec, k))[:k]
        result.total += len(case.needs)
        result.attainable += min(len(case.needs), k)
        for need in case.needs:
            if any(name in hits for name in need):
                result.found += 1
            else:
                result.misses.append(f"{case.name}: {'|'.join(need)}")
    return result


@cache
def load_set(name: str) -> LabelledSet:
    """One of :data:`SETS`; the Cap2Skill ones need ``../shared/data``."""
    label_file = "mr1.yaml" if name == "mr1" else "cap2skill.yaml"
    document = yaml.safe_load((LABELS / label_file).read_text(encoding="utf-8"))
    root = REPO_ROOT if name == "mr1" else SHARED / "data"
    if name == "mr1":
        inventory = load_inventory(root / document["inventory"])
    elif name == "cap2skill":
        inventory = read_report(root / document["inventory"])
    else:
        inventory = read_report(root / document["filtered_inventory"])
    cases = []
    for stem, entry in document["capabilities"].items():
        names = {"name": stem, "snake": stem.replace("-", "_")}
        capability = load_capability(root / document["models"].format(**names)).capability
        spec = load_spec(root / document["specs"].format(**names))
        cases.append(
            Case(
                name=stem,
                capability=capability,
                spec=spec,
                required=tuple(entry["required"] or {}),
                alternatives=tuple(tuple(group) for group in entry["alternatives"] or []),
            )
        )
    return LabelledSet(name, inventory, tuple(cases))


# --- the Cap2Skill report, until skillwright.interfaces.sources.report exists ---------------

_ROLES: dict[str, tuple[str, ...]] = {
    "topic": ("message",),
    "service": ("request", "response"),
    "action": ("goal", "result", "feedback"),
}
_SECTIONS = {
    "purpose": "Purpose of the ROS2 Element:",
    "module": "Mobile Robot Module:",
    "tasks": "Relevance for Specific Tasks:",
    "used_by": "Usage in the ROS2 System:",
}


def _fields(lines: list[str]) -> list[MessageField]:
    """The report's expanded definitions: one field per line, nesting by leading tabs."""
    root: list[MessageField] = []
    stack: list[tuple[int, list[MessageField]]] = [(-1, root)]
    for raw in lines:
        text = raw.split("#", 1)[0].rstrip()
        if not text.strip():
            continue
        depth = len(text) - len(text.lstrip("\t"))
        parts = text.split()
        if len(parts) < 2 or "=" in text:  # constants are not fields
            continue
        type_name, name = parts[0], parts[1]
        base = re.sub(r"\[.*\]$", "", type_name).split("<=")[0]
        node = MessageField(
            name=name,
            type=type_name,
            base_type=base,
            builtin=base in BUILTIN_TYPES,
            array="unbounded" if type_name.endswith("[]") else "none",
        )
        while stack[-1][0] >= depth:
            stack.pop()
        stack[-1][1].append(node)
        stack.append((depth, node.fields))
    return root


def _definitions(kind: str, type_name: str, details: str) -> dict[str, MessageDefinition]:
    parts: list[list[str]] = [[]]
    for line in details.splitlines():
        if line.strip() == "---":
            parts.append([])
        else:
            parts[-1].append(line)
    return {
        role: MessageDefinition(
            type_name=type_name, encoding="ros2msg", raw="\n".join(lines), fields=_fields(lines)
        )
        for role, lines in zip(_ROLES[kind], parts, strict=False)
    }


def _description(text: str) -> Description:
    found: dict[str, str] = {}
    for key, heading in _SECTIONS.items():
        start = text.find(heading)
        if start < 0:
            continue
        rest = text[start + len(heading) :]
        ends = [rest.find(h) for h in _SECTIONS.values() if rest.find(h) >= 0]
        chunk = rest[: min(ends)] if ends else rest
        found[key] = " ".join(chunk.replace("-", " ").split())
    return Description(
        purpose=found.get("purpose", " ".join(text.split())),
        module=found.get("module", "other"),
        tasks=[found["tasks"]] if "tasks" in found else [],
        used_by=[found["used_by"]] if "used_by" in found else [],
        engine="report",
    )


_KEPT = Relevance(
    relevant=True,
    category="control",
    reason="kept by the paper's LLM relevance filter",
    engine="report",
)


def read_report(path: Path) -> Inventory:
    """A Cap2Skill ``ros2_system_report*.json`` as an inventory (names, types, fields)."""
    document = json.loads(path.read_text(encoding="utf-8"))
    entities = document["ros2_control_entities"]
    if isinstance(entities, dict):  # the full report groups by kind; the filtered one does not
        entities = [e for group in entities.values() for e in group]
    interfaces = []
    for entity in entities:
        kind: InterfaceKind = entity["type"]
        type_name = entity["interfaces"][0]["name"]
        described = "description" in entity
        interfaces.append(
            Interface(
                name=entity["name"],
                kind=kind,
                type_name=type_name,
                definitions=_definitions(kind, type_name, entity["interfaces"][0]["details"]),
                infrastructure=classify(kind, entity["name"], type_name),
                description=_description(entity["description"]) if described else None,
                # what the paper's relevance filter kept is a candidate, whatever our rules say
                relevance=_KEPT if described else None,
            )
        )
    interfaces.sort(key=lambda i: ({"topic": 0, "service": 1, "action": 2}[i.kind], i.name))
    return Inventory(
        resource=Resource(name="mmo700"),
        sources=[Source(kind="report", location=str(path))],
        interfaces=interfaces,
    )
