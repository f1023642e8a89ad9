"""The retrieval query for a capability: a text for the embedder and weighted terms.

The paper embedded only the capability's ``rdfs:comment``. A small local embedding model
cannot bridge from that prose to terse ROS names, so the query also carries what the
model states precisely: the names of inputs and outputs, their units (a unit of m/s means
a velocity is involved), the constraints, and the specification's state texts.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field

from skillwright.capability.model import Capability
from skillwright.retrieval.text import UNIT_WORDS, tokens
from skillwright.spec.model import SkillSpec

__all__ = ["Query", "build_query"]

# How much each part of the inputs counts in the lexical query.
WEIGHTS = {
    "name": 3.0,
    "parameter": 2.0,
    "unit": 1.5,
    "comment": 1.0,
    "constraint": 0.5,
    "spec_description": 1.0,
    "execute": 1.0,
    "other_state": 0.4,
}


@dataclass
class Query:
    """What retrieval searches with."""

    text: str
    terms: dict[str, float] = field(default_factory=dict)


def build_query(capability: Capability, spec: SkillSpec | None = None) -> Query:
    """Builds the query from everything the capability (and the spec, if given) says."""
    terms: defaultdict[str, float] = defaultdict(float)

    def add(text: str, part: str) -> None:
        for term in tokens(text):
            terms[term] += WEIGHTS[part]

    add(capability.label, "name")
    add(capability.comment or "", "comment")
    io_sentences = []
    for parameter in (*capability.inputs, *capability.outputs):
        for component in parameter.components:
            add(component.name, "parameter")
            unit = (component.unit or "").strip().lower()
            if unit in UNIT_WORDS:
                add(UNIT_WORDS[unit], "unit")
            quantity = (
                f" ({UNIT_WORDS[unit].split()[0]} in {component.unit})"
                if unit in UNIT_WORDS
                else ""
            )
            io_sentences.append(
                f"{parameter.direction} {' '.join(tokens(component.name))}{quantity}"
            )
    for constraint in capability.constraints:
        add(constraint.text, "constraint")

    parts = [f"{capability.label}.", capability.comment or ""]
    if io_sentences:
        parts.append("It has " + ", ".join(io_sentences) + ".")
    if spec is not None:
        add(spec.description, "spec_description")
        parts.append(spec.description)
        for state, text in spec.states.items():
            add(text, "execute" if state == "execute" else "other_state")
        parts.append(spec.states["execute"])
    text = " ".join(p.strip() for p in parts if p.strip())
    return Query(text=text, terms=dict(terms))
