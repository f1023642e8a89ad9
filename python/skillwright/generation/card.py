"""The task card: everything a model needs to write a skill's states, in few tokens.

On two CPU cores a 1.5B model reads about 16 prompt tokens a second, so the card is the
skill's context written as tightly as it can be without losing a fact the code needs: the
inputs and outputs as the attributes that hold them (with units), the constraints, the
resource's limits as the class constants the skeleton defines, and each retrieved interface
as the handle the skeleton made for it with its message fields flattened into paths
(``pose.pose.position.{x,y,z}``). The card is written once per skill and stays in the
model's context for all of its states.

A retrieved interface nothing calls for (:mod:`~skillwright.generation.wiring`) has no
handle; the card names it, with its type and no fields, as available but not wired: the
model (and whoever reads the transcript) sees what retrieval found and that it is left out
on purpose, and is not shown a goal or message it could fill in. Outputs the skeleton sets
itself (a velocity the capability asserts zero for, :mod:`~skillwright.generation.assured`)
are marked, so the model does not set them again.
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Sequence
from dataclasses import dataclass

from skillwright.capability.model import Capability
from skillwright.generation.model import InterfaceRef, Skeleton
from skillwright.generation.names import python_import, snake_case
from skillwright.generation.skeleton import (
    class_constants,
    handle_attribute,
    helper_summaries,
    is_tf,
)
from skillwright.interfaces.inventory import Interface, MessageField

__all__ = ["CardInterface", "field_paths", "latest_message_attribute", "task_card"]

_TIME_TYPES = {
    "builtin_interfaces/msg/Time",
    "builtin_interfaces/msg/Duration",
    "builtin_interfaces/Time",
    "builtin_interfaces/Duration",
}
_SHORT_TYPES = {"float64": "", "float32": "", "string": "str", "bool": "bool"}
_ROLES = {"topic": ("message",), "service": ("request", "response"), "action": ("goal", "result")}
_ROLE_WORDS = {
    "message": "",
    "request": "Request",
    "response": "Response",
    "goal": "Goal",
    "result": "Result",
    "feedback": "Feedback",
}


@dataclass(frozen=True)
class CardInterface:
    """A retrieved interface with the skeleton's handle for it."""

    interface: Interface
    ref: InterfaceRef


def latest_message_attribute(ref: InterfaceRef) -> str:
    """The attribute where the skeleton's callback keeps a subscription's latest message."""
    return f"{snake_case(ref.name)}_msg"


def _leaf_type(field: MessageField) -> str:
    base = field.base_type.rsplit("/", 1)[-1]
    if field.array == "none":
        return _SHORT_TYPES.get(base, field.base_type)
    size = f"{field.array_size}" if field.array == "fixed" and field.array_size else ""
    return f"{base}[{size}]"


def _leaves(fields: Sequence[MessageField], prefix: str, depth: int) -> list[tuple[str, str, str]]:
    """(parent path, name, type) for every leaf field; nested messages flattened."""
    out: list[tuple[str, str, str]] = []
    for field in fields:
        if field.base_type in _TIME_TYPES:
            out.append((prefix, field.name, "time"))
        elif field.fields and not field.builtin and field.array == "none" and depth > 0:
            out += _leaves(field.fields, f"{prefix}{field.name}.", depth - 1)
        elif field.fields and not field.builtin and field.array == "none":
            out.append((prefix, field.name, field.base_type.rsplit("/", 1)[-1]))
        elif field.fields and not field.builtin:
            short = field.base_type.rsplit("/", 1)[-1]
            inner = ", ".join(f.name for f in field.fields) if depth > 0 else ""
            out.append((prefix, field.name, f"{short}[] of {inner}" if inner else f"{short}[]"))
        else:
            out.append((prefix, field.name, _leaf_type(field)))
    return out


def field_paths(fields: Sequence[MessageField] | None, *, depth: int = 4) -> str:
    """Fields as flattened paths, siblings of one type grouped:
    ``linear.{x,y,z}, angular.{x,y,z}`` (numbers unmarked; other types in brackets)."""
    if not fields:
        return "(no fields)"
    parts = []
    leaves = _leaves(fields, "", depth)
    for (parent, kind), group in itertools.groupby(leaves, key=lambda leaf: (leaf[0], leaf[2])):
        names = [name for _, name, _ in group]
        joined = names[0] if len(names) == 1 else "{" + ",".join(names) + "}"
        parts.append(f"{parent}{joined}" + (f" ({kind})" if kind else ""))
    return ", ".join(parts)


_DEFINITION_CHARACTERS = 420
"""About 100 tokens: a big definition (MoveIt's goals run to thousands) is shown shallower."""


def _definition(interface: Interface, role: str) -> str:
    definition = interface.definitions.get(role)
    if definition is None:
        return "(definition unknown: use only what the type name makes certain)"
    text = ""
    for depth in (4, 2, 1, 0):
        text = field_paths(definition.fields, depth=depth)
        if len(text) <= _DEFINITION_CHARACTERS:
            return text
    cut = text[:_DEFINITION_CHARACTERS].rsplit(", ", 1)[0]
    return f"{cut}, … (more fields)"


def _interface_line(item: CardInterface) -> str:
    ref = item.ref
    cls = python_import(ref.type_name, ref.kind)[1]
    handle = f"self.{handle_attribute(ref)}"
    if ref.kind == "topic" and ref.role == "publish":
        return f"- {handle} publishes {cls} on {ref.name}. {cls}: " + _definition(
            item.interface, "message"
        )
    if is_tf(ref):
        return (
            f"- self.tf_buffer: a tf2 Buffer that {handle} (a TransformListener) fills from "
            f"{ref.name} and /tf_static; read it with self._transform"
        )
    if ref.kind == "topic":
        latest = f"self.{latest_message_attribute(ref)}"
        return (
            f"- {latest}: latest {cls} from {ref.name} (None until one arrives). {cls}: "
            + _definition(item.interface, "message")
        )
    pieces = []
    for role in (*_ROLES[ref.kind], *(("feedback",) if ref.kind == "action" else ())):
        if role in item.interface.definitions or role != "feedback":
            label = (
                f"{cls}.{_ROLE_WORDS[role]}()" if role in ("request", "goal") else _ROLE_WORDS[role]
            )
            pieces.append(f"{label}: {_definition(item.interface, role)}")
    what = "ActionClient" if ref.kind == "action" else "service client"
    return f"- {handle}: {what} for {cls} on {ref.name}. " + ". ".join(pieces)


def _first_sentence(text: str | None, limit: int = 220) -> str:
    if not text:
        return ""
    flat = " ".join(text.split())
    match = re.match(r"(.+?[.!?])(\s|$)", flat)
    sentence = match.group(1) if match else flat
    return sentence if len(sentence) <= limit else sentence[: limit - 1].rstrip() + "…"


def task_card(
    capability: Capability, skeleton: Skeleton, interfaces: Sequence[CardInterface]
) -> str:
    """The card for one skill (see the module docstring)."""
    resource = f" of {capability.resource.name}" if capability.resource else ""
    lines = [f"Skill {skeleton.class_name}: capability {capability.name}{resource}."]
    purpose = _first_sentence(capability.comment)
    if purpose:
        lines.append(purpose)
    where = "completing" if "completing" in skeleton.prologues else "execute"
    for direction, title in (("input", "Inputs (set before starting)"), ("output", "Outputs")):
        chosen = [p for p in skeleton.parameters if p.direction == direction]
        listed = ", ".join(
            f"self.{p.attribute} ({p.python_type}{_unit(p.description)}"
            + (
                f"; set by the skeleton in {where} once the base is at rest"
                if p.attribute in skeleton.assured
                else ""
            )
            + ")"
            for p in chosen
        )
        lines.append(f"{title}: {listed or 'none'}")
    if capability.constraints:
        lines.append("Constraints: " + "; ".join(c.text for c in capability.constraints))
    limits = class_constants(capability)
    if limits:
        lines.append(
            "Limits: "
            + ", ".join(f"self.{name} = {value}{_unit_of(c)}" for name, value, c in limits)
        )
    handled = {ref.name for ref in skeleton.interfaces}
    wired = [item for item in interfaces if item.ref.name in handled]
    if wired:
        lines.append("Interfaces (handles made in starting, released in resetting):")
        lines += [_interface_line(item) for item in wired]
    if skeleton.unwired:
        lines.append(
            "Not wired (nothing in the specification calls for them; no handle): "
            + ", ".join(
                f"{u.interface.name} ({u.interface.type_name.rsplit('/', 1)[-1]} "
                f"{u.interface.kind})"
                for u in skeleton.unwired
            )
        )
    summaries = helper_summaries(skeleton.interfaces)
    helpers = [summaries[name] for name in skeleton.helpers if name in summaries]
    if helpers:
        lines.append("Helpers: " + "; ".join(helpers) + ".")
    return "\n".join(lines)


def _unit(description: str) -> str:
    match = re.search(r"Unit: ([^.]+)\.", description)
    return f", {match.group(1)}" if match else ""


def _unit_of(comment: str) -> str:
    match = re.search(r"[<>=]+ \S+ (\S+)$", comment)
    return f" ({match.group(1)})" if match else ""
