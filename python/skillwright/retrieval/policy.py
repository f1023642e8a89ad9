"""Which of the ranked interfaces the skill is given: the user's pins, weak hits set aside,
and the base's velocity command when a state stops the base.

Ranking (:func:`~skillwright.retrieval.retrieve.rank_interfaces`) orders the robot's
interfaces by how well they match the capability and its specification; the first ``k``
are the candidates. Every interface given to generation becomes a handle in the skeleton (a
publisher, a subscription, a service or action client) and a section of the task card, and
a model writes the behaviour with the handles it has. :func:`given_interfaces` applies three
rules to the candidates, in this order:

1. **Pins** (:func:`with_pins`): the user knows the robot; an interface they pinned is given
   whatever its score.
2. **Weak hits set aside** (:func:`set_aside_weak`): a candidate far behind the best matched
   the capability only by a word or two; given, it is a handle the model would use anyway.
3. **The stop command** (:func:`with_stop_command`): a state that stops the base needs the
   base's velocity command, whatever the capability is about.

The interfaces set aside stay in the list (the record keeps them and says why) but are not
given to the skeleton.
"""

from __future__ import annotations

import re
from collections.abc import Collection, Sequence
from dataclasses import dataclass, replace

from skillwright.interfaces.inventory import Inventory
from skillwright.interfaces.roles import TWIST_TYPES, command_topic
from skillwright.retrieval.retrieve import Hit
from skillwright.spec.model import SkillSpec

__all__ = [
    "SCORE_PLACES",
    "Given",
    "given_interfaces",
    "set_aside_weak",
    "stop_request",
    "with_pins",
    "with_stop_command",
]

SCORE_PLACES = 4
"""Decimal places a score is compared and recorded at: the record shows the scores the
set-aside compared, so a reader can redo each decision from it."""


@dataclass(frozen=True)
class Given:
    """One interface of the retrieval's result: ranked, pinned or added."""

    name: str
    kind: str
    type_name: str
    hit: Hit | None
    """The ranked hit; ``None`` for a pinned interface ranking did not return and for the
    velocity command added for a stop."""
    reason: str
    """Why it is in the list: the ranking's reason, a pin, the stop it was added for."""
    pinned: bool = False
    """Pinned by the user."""
    set_aside: bool = False
    """In the list but not given to the skeleton."""

    @property
    def score(self) -> float | None:
        """The ranking's score at :data:`SCORE_PLACES`; ``None`` when it was not ranked."""
        return None if self.hit is None else round(self.hit.score, SCORE_PLACES)


def given_interfaces(
    hits: Sequence[Hit],
    inventory: Inventory,
    spec: SkillSpec,
    *,
    pinned: Sequence[str] = (),
    dropped: Collection[str] = (),
    min_share: float = 0.1,
) -> list[Given]:
    """The ranked ``hits`` with the user's ``pinned`` interfaces, those under ``min_share``
    of the best score set aside, and the base's velocity command when a state of ``spec``
    stops the base (unless the user ``dropped`` it); see the module docstring."""
    return with_stop_command(
        set_aside_weak(with_pins(hits, inventory, pinned), min_share), inventory, spec, dropped
    )


def with_pins(hits: Sequence[Hit], inventory: Inventory, pinned: Sequence[str]) -> list[Given]:
    """``hits`` in rank order (each marked pinned if it is), then each ``pinned`` interface
    ranking did not return, in the order pinned, once: the user's pin is a decision about
    the robot (which of two velocity topics its driver reads) that no score can override."""
    given = [Given(h.name, h.kind, h.type_name, h, h.reason, pinned=h.name in pinned) for h in hits]
    chosen = {h.name for h in hits}
    for name in pinned:
        if name in chosen:
            continue
        interface = inventory.interface(name)
        given.append(
            Given(
                name,
                interface.kind,
                interface.type_name,
                None,
                "pinned by the user",
                pinned=True,
            )
        )
        chosen.add(name)
    return given


def set_aside_weak(given: Sequence[Given], share: float) -> list[Given]:
    """``given`` with each ranked interface that scores under ``share`` of the best score
    marked set aside (never a pinned one; ``share`` 0 sets none aside).

    The first ``k`` always hold ``k`` interfaces, however few the capability needs. One that
    matched only a word or two of it is a handle the skeleton would create and the task card
    describe, and a small model uses the handles it has: a move by velocity command that is
    also handed a Nav2 ``NavigateToPose`` action client and a tf2 listener may drive by a
    navigation goal instead. On the labelled robots (``tests/retrieval/robots``) a share of
    0.1 keeps 357 of the 363 needed interfaces the first four hold and leaves out 111 of
    their 312 others."""
    best = max((g.score for g in given if g.score is not None), default=0.0)
    return [
        replace(g, set_aside=True)
        if not g.pinned and g.score is not None and g.score < share * best
        else g
        for g in given
    ]


_ASKS_TO_STOP = re.compile(
    r"zero velocit|velocit(y|ies)\b[^.;]*\b(to|at|of) zero\b|\bstop(s|ping)? the base\b|"
    r"\bbase stops\b",
    re.IGNORECASE,
)
"""A sentence that stops the base by its velocity command ("publish a zero velocity
command", "set the velocity of the robot to zero in all directions", "stop the base")."""


def stop_request(spec: SkillSpec) -> tuple[str, str] | None:
    """The first state of ``spec`` that asks to stop the base, with the sentence that does
    (the specification says per PackML state what the skill does, so this is where a stop
    is asked for: ``stopping``, ``aborting``, or ``execute`` at its end)."""
    for state, text in spec.states.items():
        if _ASKS_TO_STOP.search(text):
            sentence = next(s for s in re.split(r"(?<=[.;])\s+", text) if _ASKS_TO_STOP.search(s))
            return state, sentence.strip()
    return None


def with_stop_command(
    given: Sequence[Given], inventory: Inventory, spec: SkillSpec, dropped: Collection[str] = ()
) -> list[Given]:
    """``given`` with the base's velocity command added (or taken back from the set-aside)
    when a state of ``spec`` asks to stop the base (:func:`stop_request`), no interface
    given to the skeleton is a velocity command and the user did not drop it.

    A mobile base moves by the ``geometry_msgs/Twist`` (or ``TwistStamped``) its driver reads
    on its velocity command topic (``cmd_vel``: ros2_control's diff-drive controller, Nav2's
    velocity smoother's output, a robot's own driver), and keeps the last one until a new
    one comes or its command timeout runs out; it stops on a zero Twist there. A skill can
    only publish one with a publisher on that topic. Ranking weighs what the capability is
    about (a map, a navigation goal), so when the stop is a side matter of the
    specification the command may not be among the first ``k``; without it the stopping
    state has nothing to stop the base with. The command is the robot's Twist topic that
    :func:`~skillwright.interfaces.roles.command_topic` names the base's."""
    request = stop_request(spec)
    twists = [
        i.name for i in inventory.interfaces if i.kind == "topic" and i.type_name in TWIST_TYPES
    ]
    command = command_topic(twists)
    if request is None or command is None or command in dropped:
        return list(given)
    if any(g.type_name in TWIST_TYPES for g in given if not g.set_aside):
        return list(given)
    state, sentence = request
    why = f"added: {state} asks to stop the base ({sentence!r}), by its velocity command"
    if any(g.name == command for g in given):
        return [
            replace(g, set_aside=False, reason=f"{g.reason}; {why}") if g.name == command else g
            for g in given
        ]
    interface = inventory.interface(command, "topic")
    return [*given, Given(command, "topic", interface.type_name, None, why)]
