"""The retrieval query for a capability: facets of evidence, each with text and terms.

The paper embedded only the capability's ``rdfs:comment``. A small local embedding model
cannot bridge from that prose to terse ROS names, and one pooled query lets the loudest
topic (a rotation capability's many heading words) drown the quieter needs (the stopping
state's zero velocity command). So the query is split into *facets*, one per piece of
evidence the inputs state precisely:

- the capability itself: its name, ``rdfs:comment`` and the spec's description;
- each input and output, with its data elements' names, definitions and units (a unit of
  m/s means a velocity is involved); parameters that share a type (``inDistance`` and
  ``outDistance``) form one facet;
- each sentence of each state of the skill specification (what ``execute`` does, what
  ``stopping`` needs).

Retrieval scores every interface against every facet and then picks interfaces that cover
the facets (see :mod:`skillwright.retrieval.retrieve`); a hit's reason names the facet.
"""

from __future__ import annotations

import math
import re
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Literal

from skillwright.capability.model import Capability, Parameter
from skillwright.retrieval.text import UNIT_WORDS, weighted_tokens
from skillwright.spec.model import SkillSpec

__all__ = ["FACET_WEIGHTS", "Facet", "Intent", "Query", "build_query", "intent_of"]

Intent = Literal["command", "measure"]

FACET_WEIGHTS = {
    "capability": 1.0,
    "parameter": 0.6,
    "execute": 0.8,
    "state": 0.5,
}
"""How much each kind of facet counts when facets are combined."""

# How much each part of a facet's text counts in its lexical terms.
_PART_WEIGHTS = {
    "name": 3.0,
    "comment": 1.0,
    "description": 1.0,
    "parameter": 2.0,
    "definition": 1.0,
    "unit": 1.5,
    "constraint": 0.5,
    "state": 1.0,
}

# Direction prefixes of parameter names: inDistance and outDistance are about distance.
_DIRECTION = re.compile(r"^(in|out)(?=[A-Z_])")


@dataclass(frozen=True)
class Facet:
    """One piece of evidence the query is built from."""

    key: str
    """Stable identifier: ``capability``, ``parameter:distance``, ``state:stopping``."""
    label: str
    """How a reason names it, e.g. ``the stopping state`` or ``inDistance/outDistance``."""
    text: str
    """What the embedding model reads."""
    terms: dict[str, float]
    """Weighted lexical terms."""
    weight: float
    """How much the facet counts among the others."""
    intent: Intent | None = None
    """For a state's sentence: whether it sends something (``command``: "Set the velocity
    to zero") or reads something (``measure``: "Print the current velocity"), by its verb."""


@dataclass
class Query:
    """What retrieval searches with: the facets, and their union."""

    text: str
    """All the evidence as one text (for a single embedding)."""
    terms: dict[str, float] = field(default_factory=dict)
    """The facets' terms summed (for a single lexical query)."""
    facets: list[Facet] = field(default_factory=list)
    """The facets, capability first."""


def _terms(parts: list[tuple[str, str]]) -> dict[str, float]:
    terms: defaultdict[str, float] = defaultdict(float)
    for text, part in parts:
        for term, weight in weighted_tokens(text, query=True):
            terms[term] += weight * _PART_WEIGHTS[part]
    return dict(terms)


def _words(name: str) -> str:
    """``inLinearVelocity`` -> ``linear velocity`` (the readable, direction-free name)."""
    bare = _DIRECTION.sub("", name)
    return re.sub(r"(?<=[a-z0-9])(?=[A-Z])", " ", bare).replace("_", " ").strip().lower()


def _parameter_facets(capability: Capability) -> list[Facet]:
    # inDistance and outDistance with the same type description are one piece of evidence
    groups: dict[tuple[str, str, str], list[Parameter]] = {}
    for parameter in (*capability.inputs, *capability.outputs):
        first = parameter.components[0]
        key = (_words(parameter.name), first.definition or "", first.unit or "")
        groups.setdefault(key, []).append(parameter)
    facets = []
    for (words, definition, unit), group in groups.items():
        components = {c.name: c for p in group for c in p.components}
        parts = [(_words(name), "parameter") for name in components]
        quantity = UNIT_WORDS.get(unit.strip().lower(), "")
        text = f"The {' and '.join(sorted({p.direction for p in group}))} {words}"
        if len(group[0].components) > 1:
            text += f" ({', '.join(_words(c.name) for c in group[0].components)})"
        if definition:
            parts.append((definition, "definition"))
            text += f": {definition}"
        if quantity:
            parts.append((quantity, "unit"))
            text += f" ({quantity.split()[0]} in {unit})"
        facets.append(
            Facet(
                key=f"parameter:{words}",
                label="/".join(p.name for p in group),
                text=text,
                terms=_terms(parts),
                weight=FACET_WEIGHTS["parameter"],
            )
        )
    return facets


# A state text is split into sentences: "Cancel the goal. Publish a zero velocity command."
# names two needs, and each sentence can then be covered by its own interface.
_SENTENCE_END = re.compile(r"(?<=[.;!?])\s+(?=[A-Z])")


# The verb a specified state's sentence starts with says which way data flows.
_COMMAND_VERBS = frozenset(
    [
        "set",
        "publish",
        "send",
        "command",
        "drive",
        "move",
        "turn",
        "rotate",
        "stop",
        "cancel",
        "reset",
        "zero",
        "trigger",
    ]
)
_MEASURE_VERBS = frozenset(
    ["print", "read", "retrieve", "get", "measure", "report", "return", "obtain"]
)


def intent_of(sentence: str) -> Intent | None:
    """``command`` or ``measure`` by the sentence's first word, else ``None``."""
    words = sentence.split(maxsplit=1)
    verb = words[0].lower().strip(",.;:") if words else ""
    if verb in _COMMAND_VERBS:
        return "command"
    if verb in _MEASURE_VERBS:
        return "measure"
    return None


def _sentences(text: str) -> list[str]:
    return [p.strip() for p in _SENTENCE_END.split(" ".join(text.split())) if p.strip()]


def build_query(capability: Capability, spec: SkillSpec | None = None) -> Query:
    """Builds the query from everything the capability (and the spec, if given) says."""
    summary = [(capability.label, "name"), (capability.comment or "", "comment")]
    summary += [(c.text, "constraint") for c in capability.constraints]
    if spec is not None:
        summary.append((spec.description, "description"))
    texts = [f"{capability.label}.", capability.comment or ""]
    if spec is not None:
        texts.append(spec.description)
    facets = [
        Facet(
            key="capability",
            label=f"capability {capability.name}",
            text=" ".join(t.strip() for t in texts if t.strip()),
            terms=_terms(summary),
            weight=FACET_WEIGHTS["capability"],
        )
    ]
    facets += _parameter_facets(capability)
    if spec is not None:
        for state, text in spec.states.items():
            weight = FACET_WEIGHTS["execute" if state == "execute" else "state"]
            pieces = _sentences(text) or [text]
            for number, piece in enumerate(pieces, 1):
                suffix = f".{number}" if len(pieces) > 1 else ""
                facets.append(
                    Facet(
                        key=f"state:{state}{suffix}",
                        label=f"the {state} state",
                        text=piece,
                        terms=_terms([(piece, "state")]),
                        # a long state counts more than a short one, but not n times more
                        weight=weight / math.sqrt(len(pieces)),
                        intent=intent_of(piece),
                    )
                )
    union: defaultdict[str, float] = defaultdict(float)
    for facet in facets:
        for term, weight in facet.terms.items():
            union[term] += weight * facet.weight
    text = " ".join(f.text for f in facets)
    return Query(text=text, terms=dict(union), facets=facets)
