"""The catalog the static checks use, built from an inventory."""

from __future__ import annotations

from collections.abc import Sequence

from skillwright.interfaces.inventory import Inventory, MessageField
from skillwright.validation.model import SEQUENCE_METHODS, Catalog, CatalogEntry, FieldTree

__all__ = ["catalog_from_inventory"]

# Definition role in the inventory -> suffix of the type the code constructs.
_ROLE_SUFFIX = {
    "message": "",
    "request": ".Request",
    "response": ".Response",
    "goal": ".Goal",
    "result": ".Result",
    "feedback": ".Feedback",
}


def _tree(
    fields: Sequence[MessageField],
    nested: dict[str, FieldTree],
    constants: dict[str, list[str]],
) -> FieldTree:
    tree: FieldTree = {}
    for field in fields:
        if field.builtin or not field.resolved:
            tree[field.name] = None
            continue
        subtree = _tree(field.fields, nested, constants)
        nested.setdefault(field.base_type, subtree)
        if field.array != "none":
            subtree = {**subtree, **dict.fromkeys(SEQUENCE_METHODS)}
        tree[field.name] = subtree
        constants.setdefault(field.base_type, [c.name for c in field.constants])
    return tree


def catalog_from_inventory(inventory: Inventory) -> Catalog:
    """Every interface with its type, and the field tree of every message type it uses.

    Nested message types (``geometry_msgs/msg/Vector3`` inside a Twist, ``PoseStamped``
    inside a navigation goal) get their own entries, so code that constructs them is
    checked too.
    """
    entries: dict[str, CatalogEntry] = {}
    fields: dict[str, FieldTree] = {}
    nested: dict[str, FieldTree] = {}
    constants: dict[str, list[str]] = {}
    for interface in inventory.interfaces:
        entries.setdefault(
            interface.name,
            CatalogEntry(name=interface.name, kind=interface.kind, type_name=interface.type_name),
        )
        for role, definition in interface.definitions.items():
            if definition.fields is None or role not in _ROLE_SUFFIX:
                continue
            key = interface.type_name + _ROLE_SUFFIX[role]
            fields[key] = _tree(definition.fields, nested, constants)
            constants[key] = [c.name for c in definition.constants]
    for type_name, tree in nested.items():
        fields.setdefault(type_name, tree)
    return Catalog(entries=entries, fields=fields, constants=constants)
