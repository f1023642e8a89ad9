"""Standard ROS 2 definitions from an offline type store, for sources that name types only.

A report entry without details, a bag recorded without schemas, or a live graph whose
definition could not be fetched still says which type an interface has. For the standard
types (``std_msgs``, ``geometry_msgs``, ``sensor_msgs``, ``nav_msgs``, ``action_msgs``,
...) the definitions ship with `rosbags <https://gitlab.com/ternaris/rosbags>`_, per ROS 2
distribution; this module fills them in, marked ``origin="type_store"`` with a note naming
the store. A type no store has is marked unknown; nothing is ever guessed.

The stores hold the field lists and constants of messages, not their comments or default
values (the note says so), and no ``.srv`` / ``.action`` types: a service's or action's
parts (``pkg/srv/T_Request`` ...) come from the installed interface packages' ament index
(:mod:`skillwright.interfaces.rosidl_index`), using the store's messages.
"""

from __future__ import annotations

import threading
from collections.abc import Iterable
from dataclasses import dataclass
from functools import cache
from typing import Any, Final

from skillwright.cancel import raise_if_cancelled
from skillwright.interfaces.inventory import Interface, InterfaceKind, MessageDefinition
from skillwright.interfaces.ros2msg import definition_from_text, normalize_type_name
from skillwright.interfaces.rosidl_index import index_texts

__all__ = [
    "FALLBACK_DISTROS",
    "TypeStore",
    "fill_missing_definitions",
    "filled_note",
    "missing_roles",
    "store_texts",
    "unknown_note",
]

FALLBACK_DISTROS: Final = ("jazzy", "humble")
"""Stores tried, in order, when the source's ROS distribution is unknown (or lacks a type)."""

_ROLES: dict[InterfaceKind, tuple[tuple[str, str], ...]] = {
    "topic": (("message", ""),),
    "service": (("request", "_Request"), ("response", "_Response")),
    "action": (("goal", "_Goal"), ("result", "_Result"), ("feedback", "_Feedback")),
}
# Roles under which a source keeps a definition in another form (a non-ros2msg service
# event schema, report text that did not split): the source has one, nothing to fill.
_OTHER_FORMS = ("event", "details")


@cache
def _rosbags_store(distro: str) -> Any | None:
    """rosbags' store for a ROS 2 distribution (``jazzy``), or ``None`` if it has none."""
    from rosbags.typesys import Stores, get_typestore

    try:
        store = Stores(f"ros2_{distro}")
    except ValueError:
        return None
    return get_typestore(store)


def store_texts(distro: str) -> dict[str, str]:
    """Every type of a distribution's store as full ros2msg text (``MSG:`` blocks
    included), by type name, with the services' and actions' parts of the installed
    interface packages (:mod:`skillwright.interfaces.rosidl_index`); empty when neither
    has anything for ``distro``."""
    texts = dict(_rosbags_texts(distro.strip().lower()))
    for name, text in _indexed(distro.strip().lower()).items():
        texts.setdefault(name, text)
    return texts


@cache
def _rosbags_texts(distro: str) -> dict[str, str]:
    store = _rosbags_store(distro)
    if store is None:
        return {}
    return {
        name: str(store.generate_msgdef(name, ros_version=2)[0]) for name in sorted(store.fielddefs)
    }


@cache
def _indexed(distro: str) -> dict[str, str]:
    """The index's types of ``distro``, their messages completed from rosbags' store."""
    return index_texts(distro, _rosbags_texts(distro))


@dataclass(frozen=True)
class TypeStore:
    """Looks types up in rosbags' stores: the source's distribution first, then
    :data:`FALLBACK_DISTROS`."""

    distro: str | None = None

    @property
    def distros(self) -> tuple[str, ...]:
        """Distributions searched, in order."""
        first = (self.distro.strip().lower(),) if self.distro and self.distro.strip() else ()
        return tuple(dict.fromkeys((*first, *FALLBACK_DISTROS)))

    def text(self, type_name: str) -> tuple[str, str] | None:
        """The full ros2msg text (``MSG:`` blocks included) of a message type, and the
        distribution whose store has it; ``None`` when no store has the type."""
        wanted = normalize_type_name(type_name)
        for distro in self.distros:
            store = _rosbags_store(distro)
            if store is not None and wanted in store.fielddefs:
                text, _ = store.generate_msgdef(wanted, ros_version=2)
                return str(text), distro
            indexed = _indexed(distro).get(wanted)
            if indexed is not None:
                return indexed, distro
        return None

    def definition(self, type_name: str) -> MessageDefinition | None:
        """The store's definition of ``type_name``, marked as filled in, or ``None``."""
        found = self.text(type_name)
        if found is None:
            return None
        text, distro = found
        definition = definition_from_text(type_name, text)
        definition.origin = "type_store"
        note = (
            f"filled in from the offline ROS 2 {distro.capitalize()} type store (rosbags); "
            "it has no comments or default values"
            if normalize_type_name(type_name) in _rosbags_texts(distro)
            else f"filled in from the installed ROS 2 {distro.capitalize()} interface packages"
        )
        if self.distro and distro != self.distro.strip().lower():
            note += f" (the source's distribution {self.distro} does not define the type)"
        definition.notes.insert(0, note)
        return definition


def _is_empty(definition: MessageDefinition) -> bool:
    """A definition that holds nothing: the source recorded an empty text for the type."""
    return definition.encoding == "ros2msg" and definition.fields is None and not definition.raw


def missing_roles(interface: Interface) -> list[tuple[str, str]]:
    """``(role, part type)`` of the definitions an interface lacks."""
    if not interface.type_name or any(r in interface.definitions for r in _OTHER_FORMS):
        return []
    missing = []
    for role, suffix in _ROLES[interface.kind]:
        present = interface.definitions.get(role)
        if present is None or _is_empty(present):
            missing.append((role, interface.type_name + suffix))
    return missing


def unknown_note(type_name: str, store: TypeStore) -> str:
    """The note on an interface whose definition nobody has."""
    names = ", ".join(d.capitalize() for d in store.distros)
    return f"definition unknown: {type_name} is not in the offline type stores ({names})"


def filled_note(count: int) -> str:
    """The source note saying how many definitions were filled in."""
    return (
        f"{count} definition(s) filled in from the offline type stores (rosbags); "
        "they are marked `origin: type_store`"
    )


def fill_missing_definitions(
    interfaces: Iterable[Interface],
    distro: str | None = None,
    store: TypeStore | None = None,
    *,
    cancel: threading.Event | None = None,
) -> int:
    """Fills every missing definition the stores know; returns how many were filled.

    An interface only partly found (a service whose request is in a store but not its
    response) keeps what was found and a note for the rest. ``cancel`` is looked at before
    each interface (see :mod:`skillwright.cancel`).
    """
    lookup = store or TypeStore(distro)
    filled = 0
    for interface in interfaces:
        raise_if_cancelled(cancel, "filling in definitions")
        missing = missing_roles(interface)
        unknown: list[str] = []
        for role, part_type in missing:
            definition = lookup.definition(part_type)
            if definition is None:
                unknown.append(part_type)
                continue
            previous = interface.definitions.get(role)
            if previous is not None:
                definition.notes.extend(previous.notes)
            interface.definitions[role] = definition
            filled += 1
        if unknown:
            # Services and actions: name the interface type, their parts are not files.
            shown = interface.type_name if interface.kind != "topic" else unknown[0]
            note = unknown_note(shown, lookup)
            if note not in interface.notes:
                interface.notes.append(note)
    return filled
