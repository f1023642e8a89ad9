"""Message types of the simulated graph: from the inventory, then the offline type store.

The host answers the child's questions about types (``geometry_msgs/msg/Twist``, a
service ``nav2_msgs/srv/SaveMap`` and its ``_Request`` / ``_Response`` parts, an action
and its ``_Goal`` / ``_Result`` / ``_Feedback`` parts), builds default messages, and
checks every message that crosses from the child or a world plug-in against its type.

A type exists when the inventory's definitions hold it (top level or nested) or when the
standard type store of the source's ROS distribution does (what any ROS 2 installation
has). The store's texts are cached in the cache folder after their first use, because
loading rosbags' stores takes seconds.
"""

from __future__ import annotations

import contextlib
import importlib.metadata
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache, cached_property
from typing import Any, Final

from skillwright.interfaces.inventory import Constant, Inventory, MessageDefinition, MessageField
from skillwright.interfaces.ros2msg import BUILTIN_TYPES, definition_from_text

__all__ = [
    "FieldDef",
    "TypeDef",
    "TypeRegistry",
    "is_zero_motion",
    "registry_for",
    "standard_texts",
]

_FLOATS: Final = frozenset({"float32", "float64"})
_INTEGERS: Final = frozenset(
    {"int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64", "byte", "char"}
)
_STRINGS: Final = frozenset({"string", "wstring"})
_SERVICE_PARTS: Final = ("Request", "Response")
_ACTION_PARTS: Final = ("Goal", "Result", "Feedback")
_ROLE_PART: Final = {
    "request": "Request",
    "response": "Response",
    "goal": "Goal",
    "result": "Result",
    "feedback": "Feedback",
}
MAX_ELEMENTS: Final = 8_000_000
"""Elements a message may hold in all its arrays together (a big occupancy grid is ~4 M)."""


@dataclass(frozen=True)
class FieldDef:
    """One field of a message type."""

    name: str
    base: str
    """A builtin (``float64``) or a full message type name."""
    array: str
    """``none``, ``fixed``, ``bounded`` or ``unbounded``."""
    size: int | None
    string_bound: int | None
    default: Any

    @cached_property
    def builtin(self) -> bool:
        """Whether the element type is a ROS 2 builtin."""
        return self.base in BUILTIN_TYPES

    def spec(self) -> list[Any]:
        """The form the child reads."""
        return [self.name, self.base, self.array, self.size, self.string_bound, self.default]


@dataclass(frozen=True)
class TypeDef:
    """One message type: its fields and constants."""

    name: str
    fields: tuple[FieldDef, ...]
    constants: tuple[tuple[str, Any], ...] = ()


def _field(field: MessageField) -> FieldDef:
    return FieldDef(
        name=field.name,
        base=field.base_type,
        array=field.array,
        size=field.array_size,
        string_bound=field.string_bound,
        default=field.default,
    )


def _constants(constants: Sequence[Constant]) -> tuple[tuple[str, Any], ...]:
    return tuple((c.name, c.value) for c in constants)


def _collect(
    name: str,
    fields: Sequence[MessageField],
    constants: Sequence[Constant],
    into: dict[str, TypeDef],
) -> None:
    if name in into:
        return
    into[name] = TypeDef(name, tuple(_field(f) for f in fields), _constants(constants))
    for field in fields:
        if not field.builtin and field.resolved:
            _collect(field.base_type, field.fields, field.constants, into)


@cache
def _rosbags_version() -> str:
    try:
        return importlib.metadata.version("rosbags")
    except importlib.metadata.PackageNotFoundError:
        return "none"


_READ: dict[str, dict[str, str]] = {}
"""Standard texts already read in this process, by cache file (every run asks again)."""


def standard_texts(distro: str) -> dict[str, str]:
    """The standard message texts of ``distro`` by type name, cached on disk (and kept in
    memory once read; the caller must not change the mapping)."""
    from skillwright.fileio import write_atomic
    from skillwright.interfaces.rosidl_index import index_fingerprint
    from skillwright.paths import cache_dir

    stem = f"types-{distro}-rosbags-{_rosbags_version()}-index-{index_fingerprint(distro)}"
    path = cache_dir() / "runtime" / f"{stem}.json"
    known = _READ.get(str(path))
    if known is not None:
        return known
    try:
        cached = json.loads(path.read_text(encoding="utf-8"))
        if isinstance(cached, dict) and all(isinstance(v, str) for v in cached.values()):
            _READ[str(path)] = cached
            return cached
    except (OSError, ValueError):
        pass
    from skillwright.interfaces.typestore import store_texts

    texts = store_texts(distro)
    if texts:
        _READ[str(path)] = texts
        # The cache only saves time; a read-only cache folder must not stop a run.
        with contextlib.suppress(OSError):
            write_atomic(path, json.dumps(texts, sort_keys=True))
    return texts


class TypeRegistry:
    """The types of one robot: the inventory's, then the standard ones of its distribution."""

    def __init__(self, inventory: Inventory) -> None:
        self._messages: dict[str, TypeDef] = {}
        self._parts: dict[str, dict[str, str]] = {}
        distro = next((s.ros_distro for s in inventory.sources if s.ros_distro), None)
        self.distro = (distro or "jazzy").strip().lower()
        for interface in inventory.interfaces:
            for role, definition in interface.definitions.items():
                self._add_definition(definition)
                part = _ROLE_PART.get(role)
                if part is not None and interface.kind != "topic":
                    self._parts.setdefault(interface.type_name, {})[part] = definition.type_name
        self._standard: dict[str, str] | None = None
        self._package_names: list[str] | None = None

    def _add_definition(self, definition: MessageDefinition) -> None:
        if definition.fields is not None:
            _collect(definition.type_name, definition.fields, definition.constants, self._messages)

    def _standard_texts(self) -> dict[str, str]:
        if self._standard is None:
            self._standard = standard_texts(self.distro)
            if not self._standard and self.distro != "jazzy":
                self._standard = standard_texts("jazzy")
        return self._standard

    def message(self, name: str) -> TypeDef | None:
        """The message type ``name`` (``pkg/msg/T`` or a part such as ``pkg/srv/T_Request``)."""
        found = self._messages.get(name)
        if found is not None:
            return found
        text = self._standard_texts().get(name)
        if text is None:
            return None
        definition = definition_from_text(name, text)
        if definition.fields is None:
            return None
        _collect(name, definition.fields, definition.constants, self._messages)
        return self._messages.get(name)

    def parts(self, name: str) -> dict[str, str] | None:
        """``{"Request": ..., "Response": ...}`` of a service, ``Goal``/``Result``/``Feedback``
        of an action, or ``None``."""
        known = self._parts.get(name)
        if known is not None:
            return dict(known)
        namespace = name.split("/")[1] if name.count("/") == 2 else ""
        wanted = _SERVICE_PARTS if namespace == "srv" else _ACTION_PARTS
        if namespace not in {"srv", "action"}:
            return None
        found = {part: f"{name}_{part}" for part in wanted}
        if all(self.message(t) is not None for t in found.values()):
            return found
        return None

    def has_package(self, package: str) -> bool:
        """Whether any known type lives in ``package``."""
        prefix = package + "/"
        if any(n.startswith(prefix) for n in self._messages) or any(
            n.startswith(prefix) for n in self._parts
        ):
            return True
        return any(n.startswith(prefix) for n in self._standard_texts())

    def packages(self) -> list[str]:
        """Every package that holds a known type (the inventory's and the standard ones)."""
        if self._package_names is None:
            names = [*self._messages, *self._parts, *self._standard_texts()]
            self._package_names = sorted({n.split("/", 1)[0] for n in names})
        return list(self._package_names)

    def describe_with_nested(self, name: str) -> dict[str, Any]:
        """:meth:`describe` of ``name`` with ``nested``: the answers for every type it is made
        of (nested messages, a service's or an action's parts, and theirs), so the child
        asks once per type it imports."""
        answer = self.describe(name)
        if not answer.get("ok"):
            return answer
        nested: dict[str, dict[str, Any]] = {}
        pending = self._made_of(answer)
        while pending:
            part = pending.pop()
            if part in nested or part == name:
                continue
            described = self.describe(part)
            nested[part] = described
            if described.get("ok"):
                pending.extend(self._made_of(described))
        return {**answer, "nested": nested} if nested else answer

    @staticmethod
    def _made_of(answer: dict[str, Any]) -> list[str]:
        if answer.get("kind") == "message":
            return [spec[1] for spec in answer["fields"] if spec[1] not in BUILTIN_TYPES]
        return list(answer.get("parts", {}).values())

    def describe(self, name: str) -> dict[str, Any]:
        """The child's answer about ``name``: ``ok`` with the type, or ``ok: false`` and why."""
        if name.count("/") != 2:
            return {"ok": False, "error": f"{name!r} is not a full type name (pkg/msg/Type)"}
        namespace = name.split("/")[1]
        if namespace == "msg" or name.rsplit("_", 1)[-1] in {*_SERVICE_PARTS, *_ACTION_PARTS}:
            message = self.message(name)
            if message is not None:
                return {
                    "ok": True,
                    "kind": "message",
                    "name": name,
                    "fields": [f.spec() for f in message.fields],
                    "constants": [list(c) for c in message.constants],
                }
        if namespace in {"srv", "action"}:
            parts = self.parts(name)
            if parts is not None:
                kind = "service" if namespace == "srv" else "action"
                return {"ok": True, "kind": kind, "name": name, "parts": parts}
        return {
            "ok": False,
            "error": (
                f"the robot has no type {name}: it is not among its interfaces' definitions "
                f"nor a standard ROS 2 {self.distro.capitalize()} type"
            ),
        }

    # --- values ----------------------------------------------------------------------

    def default(self, name: str) -> dict[str, Any]:
        """A message of type ``name`` with every field at its default."""
        message = self.message(name)
        if message is None:
            raise KeyError(f"no message type {name}")
        return {f.name: self._field_default(f) for f in message.fields}

    def _field_default(self, field: FieldDef) -> Any:
        if field.array == "none":
            if not field.builtin:
                return self.default(field.base)
            if field.default is not None:
                return _scalar(field.base, field.default)
            return _zero(field.base)
        if field.default is not None and isinstance(field.default, list):
            return [_scalar(field.base, v) for v in field.default]
        if field.array == "fixed" and field.size is not None:
            if not field.builtin:
                return [self.default(field.base) for _ in range(field.size)]
            return [_zero(field.base)] * field.size
        return []

    def conform(self, name: str, value: Any, where: str = "") -> dict[str, Any]:
        """``value`` checked against type ``name``, missing fields filled with defaults.

        Raises ``ValueError`` naming the first field that does not fit.
        """
        budget = [MAX_ELEMENTS]
        return self._conform(name, value, where or name, budget)

    def _conform(self, name: str, value: Any, where: str, budget: list[int]) -> dict[str, Any]:
        message = self.message(name)
        if message is None:
            raise ValueError(f"{where}: no message type {name}")
        if not isinstance(value, dict):
            raise ValueError(f"{where}: expected a {name} message, got {type(value).__name__}")
        known = {f.name for f in message.fields}
        unknown = [k for k in value if k not in known]
        if unknown:
            fields = ", ".join(sorted(known)) or "no fields"
            raise ValueError(f"{where}: {name} has no field {unknown[0]!r} (it has {fields})")
        out: dict[str, Any] = {}
        for field in message.fields:
            if field.name not in value:
                out[field.name] = self._field_default(field)
                continue
            item = value[field.name]
            if field.array == "none":
                if field.builtin and _fits(field.base, item):
                    out[field.name] = item
                else:
                    path = f"{where}.{field.name}"
                    out[field.name] = self._conform_one(field, item, path, budget)
                continue
            path = f"{where}.{field.name}"
            if not isinstance(item, list):
                raise ValueError(f"{path}: expected a list, got {type(item).__name__}")
            if field.array == "fixed" and len(item) != field.size:
                raise ValueError(f"{path}: expected {field.size} elements, got {len(item)}")
            if field.array == "bounded" and field.size is not None and len(item) > field.size:
                raise ValueError(f"{path}: at most {field.size} elements, got {len(item)}")
            budget[0] -= len(item)
            if budget[0] < 0:
                raise ValueError(f"{path}: the message is larger than {MAX_ELEMENTS} elements")
            plain = _builtin_list(field.base, item) if field.builtin else None
            if plain is not None:
                out[field.name] = plain
                continue
            out[field.name] = [
                self._conform_one(field, element, f"{path}[{i}]", budget)
                for i, element in enumerate(item)
            ]
        return out

    def _conform_one(self, field: FieldDef, item: Any, path: str, budget: list[int]) -> Any:
        if not field.builtin:
            return self._conform(field.base, item, path, budget)
        base = field.base
        if base in _FLOATS:
            if isinstance(item, bool) or not isinstance(item, (int, float)):
                raise ValueError(f"{path}: expected a number ({base}), got {type(item).__name__}")
            return float(item)
        if base in _INTEGERS:
            if isinstance(item, bool) or not isinstance(item, int):
                raise ValueError(f"{path}: expected an integer ({base}), got {type(item).__name__}")
            return item
        if base == "bool":
            if not isinstance(item, bool):
                raise ValueError(f"{path}: expected true or false, got {type(item).__name__}")
            return item
        if not isinstance(item, str):
            raise ValueError(f"{path}: expected a string, got {type(item).__name__}")
        if len(item) > 1_000_000:
            raise ValueError(f"{path}: string longer than 1000000 characters")
        return item


def _fits(base: str, item: Any) -> bool:
    """Whether a builtin value is already what :meth:`TypeRegistry._conform_one` makes of it
    (the common case, checked without building the field's path)."""
    kind = type(item)
    if kind is float:
        return base in _FLOATS
    if kind is int:
        return base in _INTEGERS
    if kind is bool:
        return base == "bool"
    return kind is str and base in _STRINGS and len(item) <= 1_000_000


def _builtin_list(base: str, items: list[Any]) -> list[Any] | None:
    """A builtin array as :meth:`TypeRegistry._conform_one` would make it element by
    element, from the set of its elements' types; ``None`` when an element needs that
    look (to convert it, or to name it in the error)."""
    kinds = set(map(type, items))
    if base in _FLOATS:
        if kinds <= {float}:
            return list(items)
        if kinds <= {float, int}:
            return [float(x) for x in items]
    elif base in _INTEGERS:
        if kinds <= {int}:
            return list(items)
    elif base == "bool" and kinds <= {bool}:
        return list(items)
    return None


_REGISTRIES: list[tuple[Inventory, tuple[tuple[str, str, str], ...], TypeRegistry]] = []
"""Type registries of recent inventories (a validation runs one inventory many times)."""


def registry_for(inventory: Inventory) -> TypeRegistry:
    """The type registry of ``inventory``, made once for the runs of the same inventory
    (the same object with the same interfaces)."""
    shape = tuple((i.kind, i.name, i.type_name) for i in inventory.interfaces)
    for known, known_shape, registry in _REGISTRIES:
        if known is inventory and known_shape == shape:
            return registry
    registry = TypeRegistry(inventory)
    _REGISTRIES.append((inventory, shape, registry))
    del _REGISTRIES[:-4]
    return registry


def _zero(base: str) -> Any:
    if base in _FLOATS:
        return 0.0
    if base == "bool":
        return False
    if base in _STRINGS:
        return ""
    return 0


def _scalar(base: str, value: Any) -> Any:
    if base in _FLOATS and isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    return value


MOTION_TYPES: Final = frozenset({"geometry_msgs/msg/Twist", "geometry_msgs/msg/TwistStamped"})
"""Types of a base velocity command."""


def is_zero_motion(message: dict[str, Any]) -> bool:
    """Whether every number in a (Twist-like) message is zero."""
    for value in message.values():
        if isinstance(value, dict):
            if not is_zero_motion(value):
                return False
        elif isinstance(value, float) and not math.isclose(value, 0.0, abs_tol=1e-9):
            return False
    return True
