"""Message, service and action classes built from the definitions the host sends.

``from geometry_msgs.msg import Twist`` works in the child because :class:`MessageFinder`
answers for message packages: it asks the host whether the package exists, and a
``pkg.msg`` / ``pkg.srv`` / ``pkg.action`` module asks the host for each type on first
use. Types the robot does not have fail to import, as they would on the robot.

The classes behave like rosidl's generated Python classes where skills notice: keyword
constructor that rejects unknown fields, defaults for every field, assignments checked
with rosidl's messages ("The 'x' field must be of type 'float'"), constants as class
attributes, ``Service.Request``, ``Action.Goal`` and friends. Numeric arrays are plain
lists here (rosidl uses ``array.array`` or numpy arrays; indexing, ``len`` and iteration
behave the same).
"""

from __future__ import annotations

import importlib.machinery
import math
import sys
import types

BUILTINS = {
    "bool",
    "byte",
    "char",
    "float32",
    "float64",
    "int8",
    "uint8",
    "int16",
    "uint16",
    "int32",
    "uint32",
    "int64",
    "uint64",
    "string",
    "wstring",
}
_INT_RANGES = {
    "int8": (-(2**7), 2**7 - 1),
    "uint8": (0, 2**8 - 1),
    "int16": (-(2**15), 2**15 - 1),
    "uint16": (0, 2**16 - 1),
    "int32": (-(2**31), 2**31 - 1),
    "uint32": (0, 2**32 - 1),
    "int64": (-(2**63), 2**63 - 1),
    "uint64": (0, 2**64 - 1),
}
_FLOAT_MAX = {"float32": 3.4028234663852886e38, "float64": 1.7976931348623157e308}
NAMESPACES = ("msg", "srv", "action")


class MessageFieldError(AttributeError):
    """A message has no field of that name (rosidl raises a plain AttributeError)."""

    kind = "field"


class InvalidFieldValue(AssertionError):
    """An assignment rosidl's generated setter would reject."""

    kind = "field"


class UnknownTypeError(ImportError):
    """The robot has no such message, service or action type."""

    kind = "import"


class Field:
    """One field of a message type."""

    __slots__ = ("array", "base", "builtin", "default", "name", "nested", "size", "string_bound")

    def __init__(self, spec: list) -> None:
        self.name, self.base, self.array, self.size, self.string_bound, self.default = spec
        self.builtin = self.base in BUILTINS
        self.nested: type[Message] | None = None

    def fresh_default(self) -> object:
        """The value a new message holds in this field."""
        if self.array == "none":
            if self.nested is not None:
                return self.nested()
            if self.default is not None:
                return _coerce_default(self.base, self.default)
            return _zero(self.base)
        if self.default is not None:
            return [_coerce_default(self.base, value) for value in self.default]
        if self.array == "fixed":
            if self.nested is not None:
                return [self.nested() for _ in range(self.size)]
            return [_zero(self.base)] * self.size
        return []

    def type_text(self) -> str:
        """The type as rosidl's ``get_fields_and_field_types`` shows it."""
        base = self.base
        if not self.builtin:
            package, _, name = base.split("/")
            base = f"{package}/{name}"
        elif self.string_bound is not None:
            base = f"{base}<={self.string_bound}"
        if self.array == "fixed":
            return f"{base}[{self.size}]"
        if self.array == "bounded":
            return f"sequence<{base}, {self.size}>"
        if self.array == "unbounded":
            return f"sequence<{base}>"
        return base

    def check(self, owner: str, value: object) -> object:
        """``value`` as stored, or :class:`InvalidFieldValue` with rosidl's wording; the
        error carries the field (``owner.name``), the type it has and the type of the value
        given, for the run's finding."""
        try:
            return self._check(value)
        except InvalidFieldValue as error:
            error.skillwright_data = {  # type: ignore[attr-defined]
                "field": f"{owner}.{self.name}",
                "expected": self.type_text(),
                "given": self._given(value),
            }
            raise

    def _given(self, value: object) -> str:
        """The type of ``value``; for a sequence, its length or its first element that
        does not fit, with that element's index, type and value."""
        kind = type(value).__name__
        if self.array == "none" or isinstance(value, (str, bytes)):
            return kind
        try:
            items = list(value)  # type: ignore[call-overload]
        except TypeError:
            return kind
        for index, item in enumerate(items):
            try:
                self._check_one(item)
            except InvalidFieldValue:
                return f"{kind} whose element [{index}] is {type(item).__name__} {item!r:.40}"
        return f"{kind} of {len(items)} elements"

    def _check(self, value: object) -> object:
        if self.array == "none":
            return self._check_one(value)
        if isinstance(value, (str, bytes)) and self.base not in {"uint8", "byte", "char"}:
            raise InvalidFieldValue(self._sequence_message())
        try:
            items = list(value)  # type: ignore[call-overload]
        except TypeError:
            raise InvalidFieldValue(self._sequence_message()) from None
        if self.array == "fixed" and len(items) != self.size:
            raise InvalidFieldValue(
                f"The '{self.name}' field must be a set or sequence with length {self.size}"
            )
        if self.array == "bounded" and len(items) > self.size:
            raise InvalidFieldValue(
                f"The '{self.name}' field must be a set or sequence with length <= {self.size}"
            )
        try:
            return [self._check_one(item) for item in items]
        except InvalidFieldValue:
            raise InvalidFieldValue(self._sequence_message()) from None

    def _sequence_message(self) -> str:
        element = self.nested.__name__ if self.nested is not None else _python_type(self.base)
        return (
            f"The '{self.name}' field must be a set or sequence and each value of type '{element}'"
        )

    def _check_one(self, value: object) -> object:
        base = self.base
        if self.nested is not None:
            if not isinstance(value, self.nested):
                raise InvalidFieldValue(
                    f"The '{self.name}' field must be a sub message of type "
                    f"'{self.nested.__name__}'"
                )
            return value
        if base in _FLOAT_MAX:
            if not isinstance(value, float):
                raise InvalidFieldValue(f"The '{self.name}' field must be of type 'float'")
            limit = _FLOAT_MAX[base]
            if (value < -limit or value > limit) and not math.isinf(value):
                raise InvalidFieldValue(
                    f"The '{self.name}' field must be a {base.replace('float', 'float ')} "
                    f"in [{-limit}, {limit}]"
                )
            return value
        if base in _INT_RANGES:
            if not isinstance(value, int):
                raise InvalidFieldValue(f"The '{self.name}' field must be of type 'int'")
            low, high = _INT_RANGES[base]
            if not low <= value <= high:
                raise InvalidFieldValue(
                    f"The '{self.name}' field must be an integer in [{low}, {high}]"
                )
            return value
        if base == "bool":
            if not isinstance(value, bool):
                raise InvalidFieldValue(f"The '{self.name}' field must be of type 'bool'")
            return value
        if base in {"string", "wstring"}:
            if not isinstance(value, str):
                raise InvalidFieldValue(f"The '{self.name}' field must be of type 'str'")
            if self.string_bound is not None and len(value) > self.string_bound:
                raise InvalidFieldValue(
                    f"The '{self.name}' field must be string value not longer than "
                    f"{self.string_bound}"
                )
            return value
        if isinstance(value, (bytes, bytearray)) and len(value) == 1:
            return value[0]
        if isinstance(value, int) and 0 <= value <= 255:
            return value
        raise InvalidFieldValue(f"The '{self.name}' field must be of type 'bytes' or 'int'")


def _python_type(base: str) -> str:
    if base in _FLOAT_MAX:
        return "float"
    if base in _INT_RANGES:
        return "int"
    return {"bool": "bool", "string": "str", "wstring": "str"}.get(base, "bytes")


def _zero(base: str) -> object:
    if base in _FLOAT_MAX:
        return 0.0
    if base == "bool":
        return False
    if base in {"string", "wstring"}:
        return ""
    return 0


def _coerce_default(base: str, value: object) -> object:
    if base in _FLOAT_MAX and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    return value


class Message:
    """Base of every generated message class."""

    __slots__ = ("_values",)
    _type_name = ""
    _fields: tuple[Field, ...] = ()
    _by_name: dict[str, Field] = {}  # noqa: RUF012 - replaced per generated class

    def __init__(self, **kwargs: object) -> None:
        unknown = [name for name in kwargs if name not in self._by_name]
        if unknown:
            raise InvalidFieldValue(
                "Invalid arguments passed to constructor: " + ", ".join(sorted(unknown))
            )
        values = {}
        for field in self._fields:
            if field.name in kwargs:
                values[field.name] = field.check(self._type_name, kwargs[field.name])
            else:
                values[field.name] = field.fresh_default()
        object.__setattr__(self, "_values", values)

    def __getattr__(self, name: str) -> object:
        if name.startswith("__"):
            raise AttributeError(name)
        values = object.__getattribute__(self, "_values")
        if name in values:
            return values[name]
        raise MessageFieldError(self._no_field(name), name=name, obj=self)

    def __setattr__(self, name: str, value: object) -> None:
        field = self._by_name.get(name)
        if field is None:
            raise MessageFieldError(self._no_field(name), name=name, obj=self)
        self._values[name] = field.check(self._type_name, value)

    def __dir__(self) -> list[str]:
        return [*sorted(self._by_name), *super().__dir__()]

    @classmethod
    def _no_field(cls, name: str) -> str:
        names = ", ".join(field.name for field in cls._fields) or "no fields"
        return f"'{cls.__name__}' object has no attribute '{name}' ({cls._type_name} has: {names})"

    @classmethod
    def get_fields_and_field_types(cls) -> dict[str, str]:
        """Field name -> type text, as rosidl's generated classes answer."""
        return {field.name: field.type_text() for field in cls._fields}

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return False
        return self._values == other._values  # type: ignore[attr-defined]

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        inner = ", ".join(f"{name}={value!r}" for name, value in self._values.items())
        return f"{type(self).__module__}.{type(self).__name__}({inner})"

    def __copy__(self) -> Message:
        return from_dict(type(self), to_dict(self))

    def __deepcopy__(self, memo: dict) -> Message:
        return from_dict(type(self), to_dict(self))


def to_dict(message: Message) -> dict:
    """The message as plain data for the host."""
    out = {}
    for field in message._fields:
        value = message._values[field.name]
        if field.nested is not None:
            value = [to_dict(v) for v in value] if field.array != "none" else to_dict(value)
        elif field.array != "none":
            value = list(value)
        out[field.name] = value
    return out


def from_dict(cls: type[Message], data: dict) -> Message:
    """A message of ``cls`` from the host's plain data (the host conformed it to the type)."""
    message = cls.__new__(cls)
    values = {}
    for field in cls._fields:
        if field.name not in data:
            values[field.name] = field.fresh_default()
            continue
        value = data[field.name]
        if field.nested is not None:
            if field.array != "none":
                value = [from_dict(field.nested, v) for v in value]
            else:
                value = from_dict(field.nested, value)
        elif field.base in _FLOAT_MAX:
            value = [float(v) for v in value] if field.array != "none" else float(value)
        elif field.array != "none":
            value = list(value)
        values[field.name] = value
    object.__setattr__(message, "_values", values)
    return message


def _reader(name: str) -> property:
    """Reading field ``name``: a property, because falling through to ``__getattr__`` first
    raises (and drops) an AttributeError, which made every field access cost microseconds
    (a skill reads fields in its loops and callbacks). Writes go through ``__setattr__``."""

    def read(message: Message) -> object:
        return message._values[name]

    read.__name__ = name
    return property(read)


class TypeCatalog:
    """The classes built so far, and the host's answers about types and packages.

    The host answers a type with the types it is made of (nested messages, a service's
    or an action's parts) in the same reply, and names the robot's message packages in
    its answer to ``hello``, so a skill's imports cost one exchange per imported type.
    """

    def __init__(self, ask: object) -> None:
        self._ask = ask  # callable(op, **fields) -> dict
        self._classes: dict[str, object] = {}
        self._packages: dict[str, bool] = {}
        self._all_packages = False
        self._answers: dict[str, dict] = {}

    def know_packages(self, packages: list) -> None:
        """The robot's message packages, all of them (no need to ask about others)."""
        self._packages = {str(p): True for p in packages}
        self._all_packages = True

    def has_package(self, package: str) -> bool:
        """Whether the robot has message package ``package``."""
        if package not in self._packages:
            if self._all_packages:
                return False
            reply = self._ask("package", name=package)
            self._packages[package] = bool(reply.get("ok"))
        return self._packages[package]

    def get(self, type_name: str) -> object:
        """The class of ``pkg/msg/T`` (a message), ``pkg/srv/T`` or ``pkg/action/T``."""
        found = self._classes.get(type_name)
        if found is not None:
            return found
        reply = self._answers.pop(type_name, None)
        if reply is None:
            reply = self._ask("type", name=type_name)
            nested = reply.pop("nested", None)
            if isinstance(nested, dict):
                self._answers.update(nested)
        if not reply.get("ok"):
            raise UnknownTypeError(str(reply.get("error") or f"no type {type_name}"))
        package, namespace, name = type_name.split("/")
        module = f"{package}.{namespace}"
        kind = reply["kind"]
        if kind == "message":
            cls = self._message_class(type_name, name, module, reply)
        else:
            attributes: dict[str, object] = {"_type_name": type_name, "__module__": module}
            for part, part_type in reply["parts"].items():
                attributes[part] = self.get(part_type)
            cls = type(name, (), attributes)
        self._classes[type_name] = cls
        return cls

    def _message_class(self, type_name: str, name: str, module: str, reply: dict) -> type:
        fields = tuple(Field(spec) for spec in reply["fields"])
        attributes: dict[str, object] = {
            "__slots__": (),
            "__module__": module,
            "_type_name": type_name,
            "_fields": fields,
            "_by_name": {field.name: field for field in fields},
        }
        for field in fields:
            attributes[field.name] = _reader(field.name)
        for constant, value in reply.get("constants", []):
            attributes[constant] = value
        cls = type(name, (Message,), attributes)
        # Registered before the nested types are built: a type may (indirectly) refer to
        # itself through a sequence.
        self._classes[type_name] = cls
        for field in fields:
            if not field.builtin:
                field.nested = self.get(field.base)  # type: ignore[assignment]
        return cls


class _PackageLoader:
    """Creates the package and namespace modules (a loader, without importlib.abc's import cost)."""

    def __init__(self, catalog: TypeCatalog) -> None:
        self._catalog = catalog

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        module = types.ModuleType(spec.name)
        parts = spec.name.split(".")
        if len(parts) == 2:
            catalog = self._catalog
            package, namespace = parts

            def lookup(name: str) -> object:
                if name.startswith("__"):
                    raise AttributeError(name)
                try:
                    value = catalog.get(f"{package}/{namespace}/{name}")
                except UnknownTypeError as error:
                    raise AttributeError(str(error), name=name, obj=module) from None
                setattr(module, name, value)
                return value

            module.__getattr__ = lookup  # type: ignore[method-assign]
        return module

    def exec_module(self, module: types.ModuleType) -> None:
        return None


class MessageFinder:
    """Finds ``pkg``, ``pkg.msg``, ``pkg.srv`` and ``pkg.action`` for the robot's packages."""

    def __init__(self, catalog: TypeCatalog) -> None:
        self._catalog = catalog
        self._loader = _PackageLoader(catalog)

    def find_spec(
        self, fullname: str, path: object = None, target: object = None
    ) -> importlib.machinery.ModuleSpec | None:
        parts = fullname.split(".")
        if len(parts) > 2 or (len(parts) == 2 and parts[1] not in NAMESPACES):
            return None
        if not parts[0].isidentifier() or not self._catalog.has_package(parts[0]):
            return None
        spec = importlib.machinery.ModuleSpec(fullname, self._loader, is_package=len(parts) == 1)
        if len(parts) == 1:
            spec.submodule_search_locations = []
        return spec


def install(catalog: TypeCatalog) -> None:
    """Makes the robot's message packages importable."""
    sys.meta_path.append(MessageFinder(catalog))
