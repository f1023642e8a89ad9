"""Which of a skill's parameters and outputs stands for which input and output of its capability.

pySkillUp names a skill's parameters and outputs as their ``@skill_parameter(name=...)`` and
``@skill_output(name=...)`` say; nothing in pySkillUp asks for the capability's names. A
skill written for the capability ``moveForward`` may call its inputs ``distance`` and
``duration`` where the capability model has ``inDistance`` and ``inTime``. A skill is bound to
its capability by what each annotation *means*:

1. **by name**: the annotation's name is the capability's (``inDistance``), or the same once
   case, separators and the ``in``/``out`` prefix are set aside (``in_distance``);
2. **by meaning**: the quantities the annotation's name and description speak of, the unit
   they name and the axis (``x``, ``y``, ``z``) against the capability parameter's name, its
   DIN EN 61360 unit and definition: ``traveled_distance`` ("the actual distance travelled in
   meters") is ``outDistance`` (a length in m), ``target_angular_speed`` is ``inVelocity``,
   ``goal_position_x`` is the component ``inPositionX`` of the composite ``inPosition``;
3. **explicitly**: ``--bind skill_name=capabilityName`` settles what the words cannot.

Parameters bind to inputs and outputs to outputs, each capability name to one annotation at
most. An annotation whose best meaning is shared by two capability names, or that means
nothing the capability has, is left unbound and said so (with the candidates), never guessed.
A composite input (``inPosition`` with the components ``inPositionX`` and ``inPositionY``) is
bound per component, as the run gives its values.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal

from skillwright.capability.model import Capability, Parameter

__all__ = ["Annotation", "Binding", "Bound", "Target", "bind", "targets"]

Direction = Literal["input", "output"]

_CONCEPTS: dict[str, tuple[str, ...]] = {
    "length": ("distance", "length", "far", "meter", "metre"),
    "time": ("time", "duration", "elapsed", "second", "period", "long"),
    "velocity": ("velocity", "speed", "rate"),
    "angle": ("angle", "degree", "rotation", "rotate", "orientation", "yaw", "heading", "turn"),
    "position": ("position", "coordinate", "location", "point", "goal", "pose"),
    "obstacle": ("obstacle", "nearest", "closest"),
    "map": ("map", "grid", "occupancy"),
    "area": ("area", "region", "field"),
}
"""The quantities of the capability models' DIN EN 61360 types, with the words a skill's
author names them by (a length is a distance travelled, a velocity a speed)."""

_UNITS: dict[str, str] = {
    "m": "length",
    "mm": "length",
    "cm": "length",
    "s": "time",
    "ms": "time",
    "m/s": "velocity",
    "rad/s": "velocity",
    "°/s": "velocity",
    "deg/s": "velocity",
    "°": "angle",
    "deg": "angle",
    "rad": "angle",
}
"""The quantity of each unit the capability models use."""

_WORD_OF: dict[str, str] = {word: concept for concept, words in _CONCEPTS.items() for word in words}
_AXES = frozenset({"x", "y", "z"})
_STOP = frozenset({"in", "out", "the", "of", "a", "an", "to", "is", "this", "type", "any"})


@dataclass(frozen=True)
class Annotation:
    """A ``@skill_parameter`` or ``@skill_output`` of a skill."""

    name: str
    direction: Direction
    description: str = ""
    line: int = 0


@dataclass(frozen=True)
class Target:
    """A capability name a run gives or reads a value by: a parameter with one data element,
    or a component of a composite one."""

    name: str
    direction: Direction
    parameter: str
    unit: str | None
    words: str


@dataclass(frozen=True)
class Bound:
    """One annotation bound to one capability name."""

    annotation: str
    target: str
    how: Literal["name", "meaning", "explicit"]


@dataclass
class Binding:
    """A skill's annotations against its capability's inputs and outputs."""

    bound: list[Bound] = field(default_factory=list)
    ambiguous: dict[str, list[str]] = field(default_factory=dict)
    """Annotation -> the capability names it could equally mean."""
    unknown: list[str] = field(default_factory=list)
    """Annotations that mean nothing the capability has."""
    unbound: list[str] = field(default_factory=list)
    """Capability names no annotation stands for."""

    def target_of(self, annotation: str) -> str | None:
        """The capability name ``annotation`` is bound to."""
        return next((b.target for b in self.bound if b.annotation == annotation), None)

    def annotation_of(self, target: str) -> str | None:
        """The annotation bound to the capability name ``target``."""
        return next((b.annotation for b in self.bound if b.target == target), None)


def targets(capability: Capability) -> list[Target]:
    """The names a skill of ``capability`` is given and read values by."""
    found = []
    for parameter in [*capability.inputs, *capability.outputs]:
        found += _targets_of(parameter)
    return found


def _targets_of(parameter: Parameter) -> list[Target]:
    elements = parameter.components if len(parameter.components) > 1 else [parameter.element]
    found = []
    for element in elements:
        name = element.name if len(parameter.components) > 1 else parameter.name
        words = " ".join(
            w for w in (name, parameter.name, parameter.comment, element.definition) if w
        )
        found.append(Target(name, parameter.direction, parameter.name, element.unit, words))
    return found


def _tokens(text: str) -> list[str]:
    """Lower-case words of ``text``: camelCase and snake_case split, plurals made singular."""
    spaced = re.sub(r"(?<=[a-z0-9])(?=[A-Z])", " ", text)
    words = re.findall(r"[a-z]+|[0-9]+", spaced.lower())
    return [w[:-1] if len(w) > 3 and w.endswith("s") and not w.endswith("ss") else w for w in words]


def _normal(name: str) -> str:
    """``name`` without case, separators and the ``in``/``out`` prefix."""
    words = _tokens(name)
    if words and words[0] in {"in", "out"}:
        words = words[1:]
    return "".join(words)


_RATE = re.compile(
    r"\b(?:meters?|metres?|m|degrees?|radians?|rad|°)\s*(?:per|/)\s*(?:seconds?|sec|s)\b",
    re.IGNORECASE,
)
"""A rate written out (``meters per second``, ``m/s``, ``rad/s``): a velocity, not a length
and a time."""


def _meaning(text: str, unit: str | None) -> tuple[set[str], set[str]]:
    """The quantities and the axes ``text`` (and ``unit``) speak of."""
    words = [w for w in _tokens(_RATE.sub(" velocity ", text)) if w not in _STOP]
    concepts = {_WORD_OF[w] for w in words if w in _WORD_OF}
    if unit is not None and unit in _UNITS:
        concepts.add(_UNITS[unit])
    if "angular" in words and "velocity" in concepts:
        concepts.add("angle")
    return concepts, {w for w in words if w in _AXES}


def _score(annotation: Annotation, target: Target) -> float:
    """How well ``annotation`` means ``target``: 0 for nothing in common or another axis.

    The annotation's own name counts most, its description adds; a quantity either name
    speaks of that the other side lacks counts against it. An axis named on both sides must
    be the same; an annotation that names none may mean any of them (and is then left to
    ``--bind`` when the capability has several)."""
    mine, my_axes = _meaning(f"{annotation.name} {annotation.description}", None)
    name_meaning, name_axes = _meaning(annotation.name, None)
    theirs, _ = _meaning(target.words, target.unit)
    target_meaning, target_axes = _meaning(target.name, None)
    axes = name_axes or my_axes
    if axes and target_axes and axes != target_axes:
        return 0.0
    shared = mine & theirs
    if not shared:
        return 0.0
    score = 2.0 * len(name_meaning & theirs) + len(shared)
    score -= 0.5 * (len(name_meaning - theirs) + len(target_meaning - mine))
    if target.unit is not None and target.unit in _UNITS and _UNITS[target.unit] in mine:
        score += 0.5
    if axes and axes == target_axes:
        score += 1.0
    return max(score, 0.0)


def bind(
    annotations: Sequence[Annotation],
    capability: Capability,
    explicit: Mapping[str, str] | None = None,
) -> Binding:
    """``annotations`` bound to ``capability``'s inputs and outputs (see the module's text);
    ``explicit`` maps an annotation's name to a capability name (``--bind``)."""
    binding = Binding()
    open_targets = {t.name: t for t in targets(capability)}
    left: list[Annotation] = []
    for annotation in annotations:
        chosen = _by_name(annotation, open_targets.values(), explicit or {})
        if chosen is None:
            left.append(annotation)
            continue
        target, how = chosen
        binding.bound.append(Bound(annotation.name, target.name, how))
        del open_targets[target.name]
    pairs = sorted(
        (
            (_score(a, t), a.name, t.name)
            for a in left
            for t in open_targets.values()
            if t.direction == a.direction
        ),
        key=lambda p: (-p[0], p[1], p[2]),
    )
    taken: set[str] = set()
    for score, name, target_name in pairs:
        if score <= 0 or name in taken or target_name not in open_targets:
            continue
        rivals = [
            t
            for s, n, t in pairs
            if n == name and s == score and t != target_name and t in open_targets
        ]
        taken.add(name)
        if rivals:
            binding.ambiguous[name] = sorted([target_name, *rivals])
            continue
        binding.bound.append(Bound(name, target_name, "meaning"))
        del open_targets[target_name]
    binding.unknown = [a.name for a in left if a.name not in taken]
    binding.unbound = sorted(open_targets)
    return binding


def _by_name(
    annotation: Annotation, open_targets: Iterable[Target], explicit: Mapping[str, str]
) -> tuple[Target, Literal["name", "explicit"]] | None:
    candidates = list(open_targets)
    wanted = explicit.get(annotation.name)
    if wanted is not None:
        match = next((t for t in candidates if t.name == wanted), None)
        return (match, "explicit") if match is not None else None
    same = [t for t in candidates if t.direction == annotation.direction]
    exact = next((t for t in same if t.name == annotation.name), None)
    if exact is not None:
        return exact, "name"
    normal = [t for t in same if _normal(t.name) == _normal(annotation.name)]
    return (normal[0], "name") if len(normal) == 1 else None
