"""Which of the given interfaces the skeleton wires: those the skill is asked to use.

Retrieval gives the first ``k`` interfaces by score, however few the capability needs, and
every handle a skeleton makes is one a small model will use: a reverse-by-distance skill
handed a client of Nav2's ``/backup`` action sends its goal instead of driving by velocity
command. What a skill does is said by its specification's state texts and by the
capability's inputs and outputs (VDI 3682 Information, with its name and comment) and its
own description (label and ``rdfs:comment``). An interface is **called for** when one of
them names its role (:func:`~skillwright.interfaces.roles.interface_role`: "watch the lidar"
calls for a laser scan, "publish a zero command" for the velocity command, "with Nav2" for
the navigation action) or the interface by its own words. Where several roles are means to
one end (an arm moves through MoveIt or by a joint trajectory), words that name the end
only ("move the manipulator") call for every means the texts do not choose between; once a
text names one ("planned by MoveIt"), the others need their own words. The data types'
definitions (DIN EN 61360 type descriptions such as "a length or distance, in metres") are
left out: they describe a type many capabilities share, not what this one does.

Always wired besides:

- the interfaces the user pinned (``--pin``): a decision about the robot no text overrides;
- the base's velocity command when a state stops the base
  (:func:`~skillwright.retrieval.policy.stop_request`; retrieval added it for that);
- the velocity command and odometry when the skeleton itself brings the base to rest for an
  output the capability asserts (:mod:`skillwright.generation.assured`);
- the best-ranked interface when nothing else is called for: a skeleton without a handle
  can do nothing, and the ranking is then the only evidence left.

The others get no handle; the task card lists them as available but not wired, so the
model knows they exist without being handed a client it would reach for.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass

from skillwright.capability.model import Capability
from skillwright.generation.assured import rest_outputs
from skillwright.generation.model import InterfaceRef, Unwired
from skillwright.interfaces.roles import TWIST_TYPES, Role, interface_role, normalised_words
from skillwright.retrieval.policy import stop_request
from skillwright.spec.model import SkillSpec

__all__ = ["Wiring", "called_for_texts", "wire"]


@dataclass(frozen=True)
class Wiring:
    """The given interfaces split into those the skeleton wires and the others."""

    wired: list[InterfaceRef]
    unwired: list[Unwired]
    reasons: dict[str, str]
    """Why each wired interface is wired, by name."""


def called_for_texts(capability: Capability, spec: SkillSpec) -> list[tuple[str, str]]:
    """(where, normalised words) of every text that says what the skill does: the
    capability's label and comment, each input's and output's name and comment, the
    specification's description and each state's text."""
    texts = [("the capability", f"{capability.label} {capability.comment or ''}")]
    for parameter in (*capability.inputs, *capability.outputs):
        names = " ".join(c.name for c in parameter.components)
        texts.append(
            (f"{parameter.direction} {parameter.name}", f"{names} {parameter.comment or ''}")
        )
    if spec.description:
        texts.append(("the description", spec.description))
    texts += [(f"the {state} state", text) for state, text in spec.states.items()]
    return [(where, normalised_words(text)) for where, text in texts]


def _is_twist_command(interface: InterfaceRef) -> bool:
    return interface.role == "publish" and interface.type_name in TWIST_TYPES


def _is_odometry(interface: InterfaceRef) -> bool:
    return interface.role == "subscribe" and interface.type_name.endswith("/Odometry")


def wire(
    capability: Capability,
    spec: SkillSpec,
    interfaces: Sequence[InterfaceRef],
    *,
    pinned: Collection[str] = (),
) -> Wiring:
    """Splits ``interfaces`` (in rank order) into the ones the skeleton wires and the ones
    nothing calls for (see the module docstring)."""
    texts = called_for_texts(capability, spec)
    stop = stop_request(spec)
    # The skeleton brings the base to rest itself only when it can command the base.
    commands = any(_is_twist_command(i) for i in interfaces)
    resting = [o.name for o in rest_outputs(capability)] if commands else []
    reasons: dict[str, str] = {}
    found: dict[str, Role] = {}
    families: set[str | None] = set()
    for interface in interfaces:
        role = interface_role(interface.name, interface.kind, interface.type_name, interface.role)
        found[interface.name] = role
        if interface.name in pinned:
            reasons[interface.name] = "pinned by the user"
            continue
        if stop is not None and _is_twist_command(interface):
            reasons[interface.name] = f"the {stop[0]} state stops the base ({stop[1]!r})"
            continue
        for where, words in texts:
            cue = role.called_for(words)
            if cue is not None:
                reasons[interface.name] = f"{role.name}: {where} says {cue!r}"
                families.add(role.family)
                break
        rest_reading = _is_twist_command(interface) or _is_odometry(interface)
        if interface.name not in reasons and resting and rest_reading:
            reasons[interface.name] = (
                f"the skeleton brings the base to rest for {', '.join(resting)}, which the "
                "capability asserts"
            )
    # A family's generic words ("move the arm") call for each of its means only when the
    # texts chose none of them by name ("with MoveIt").
    for interface in interfaces:
        role = found[interface.name]
        if interface.name in reasons or role.family is None or role.family in families:
            continue
        for where, words in texts:
            cue = role.called_for_generically(words)
            if cue is not None:
                reasons[interface.name] = f"{role.family}: {where} says {cue!r}"
                break
    if interfaces and not reasons:
        first = interfaces[0]
        reasons[first.name] = "nothing calls for any of them; the best-ranked keeps its handle"
    wired = [i for i in interfaces if i.name in reasons]
    unwired = [
        Unwired(
            interface=i,
            reason="nothing calls for it: no state text, input or output names its role "
            f"({found[i.name].name}) or the interface",
        )
        for i in interfaces
        if i.name not in reasons
    ]
    return Wiring(wired, unwired, reasons)
