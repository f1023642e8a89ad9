"""Decoding ROS 2 messages from CDR (what rosbag2 records) into plain dicts.

Plain (XCDR1) CDR as ROS 2's default middleware writes it: a 4-byte encapsulation header
(representation ``CDR_BE`` 0x0000 or ``CDR_LE`` 0x0001, two option bytes), then the
fields in order, each primitive aligned to its size relative to the end of the header;
strings and sequences are a ``uint32`` length (strings count their terminating NUL)
followed by the elements. Decoding plans are built once per type from the
:class:`~skillwright.runtime.typesys.TypeRegistry`, so replaying a recording costs one
``struct`` call per run of primitives.
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from typing import Any, Final

from skillwright.runtime.typesys import TypeRegistry

__all__ = ["CdrDecoder", "CdrError"]

_PRIMITIVES: Final = {
    "bool": ("?", 1),
    "byte": ("B", 1),
    "char": ("B", 1),
    "int8": ("b", 1),
    "uint8": ("B", 1),
    "int16": ("h", 2),
    "uint16": ("H", 2),
    "int32": ("i", 4),
    "uint32": ("I", 4),
    "int64": ("q", 8),
    "uint64": ("Q", 8),
    "float32": ("f", 4),
    "float64": ("d", 8),
}

Reader = Callable[[bytes, int, str], tuple[Any, int]]


class CdrError(ValueError):
    """The bytes do not decode as the type says (truncated, or another type)."""


def _align(offset: int, size: int) -> int:
    # Offsets here count from the start of the payload (after the 4-byte header).
    return offset + (-offset % size)


class CdrDecoder:
    """Decodes messages of the registry's types."""

    def __init__(self, registry: TypeRegistry) -> None:
        self._registry = registry
        self._plans: dict[str, list[tuple[str, Reader]]] = {}

    def decode(self, type_name: str, data: bytes) -> dict[str, Any]:
        """The message in ``data`` (with its encapsulation header) as a dict."""
        if len(data) < 4:
            raise CdrError(f"{type_name}: {len(data)} bytes, shorter than the CDR header")
        if data[1] not in (0, 1):
            raise CdrError(
                f"{type_name}: encapsulation {data[0]:02x}{data[1]:02x} is not plain CDR"
            )
        endian = "<" if data[1] == 1 else ">"
        try:
            value, _ = self._struct(type_name)(memoryview(data)[4:], 0, endian)  # type: ignore[arg-type]
        except (struct.error, IndexError, UnicodeDecodeError) as error:
            raise CdrError(f"{type_name}: truncated or not this type ({error})") from None
        return value  # type: ignore[no-any-return]

    def _struct(self, type_name: str) -> Reader:
        def read(data: bytes, offset: int, endian: str) -> tuple[Any, int]:
            plan = self._plan(type_name)
            out: dict[str, Any] = {}
            for name, reader in plan:
                out[name], offset = reader(data, offset, endian)
            return out, offset

        return read

    def _plan(self, type_name: str) -> list[tuple[str, Reader]]:
        plan = self._plans.get(type_name)
        if plan is not None:
            return plan
        message = self._registry.message(type_name)
        if message is None:
            raise CdrError(f"no definition of {type_name} to decode it with")
        plan = []
        self._plans[type_name] = plan
        for field in message.fields:
            element = self._element(field.base)
            if field.array == "none":
                plan.append((field.name, element))
            elif field.array == "fixed":
                plan.append((field.name, self._array(field.base, element, field.size)))
            else:
                plan.append((field.name, self._array(field.base, element, None)))
        return plan

    def _element(self, base: str) -> Reader:
        if base in _PRIMITIVES:
            code, size = _PRIMITIVES[base]

            def primitive(data: bytes, offset: int, endian: str) -> tuple[Any, int]:
                offset = _align(offset, size)
                (value,) = struct.unpack_from(endian + code, data, offset)
                return value, offset + size

            return primitive
        if base == "string":
            return _string
        if base == "wstring":
            return _wstring
        return self._struct(base)

    def _array(self, base: str, element: Reader, size: int | None) -> Reader:
        primitive = _PRIMITIVES.get(base)

        def array(data: bytes, offset: int, endian: str) -> tuple[Any, int]:
            count = size
            if count is None:
                offset = _align(offset, 4)
                (count,) = struct.unpack_from(endian + "I", data, offset)
                offset += 4
                if count > len(data):
                    raise CdrError(f"a sequence of {count} elements in {len(data)} bytes")
            if primitive is not None:
                code, width = primitive
                if count:
                    offset = _align(offset, width)
                values = list(struct.unpack_from(f"{endian}{count}{code}", data, offset))
                return values, offset + count * width
            values = []
            for _ in range(count):
                value, offset = element(data, offset, endian)
                values.append(value)
            return values, offset

        return array


def _string(data: bytes, offset: int, endian: str) -> tuple[str, int]:
    offset = _align(offset, 4)
    (length,) = struct.unpack_from(endian + "I", data, offset)
    offset += 4
    raw = bytes(data[offset : offset + length])
    if len(raw) != length:
        raise CdrError("a string runs past the end of the message")
    return raw.rstrip(b"\x00").decode("utf-8", "replace"), offset + length


def _wstring(data: bytes, offset: int, endian: str) -> tuple[str, int]:
    offset = _align(offset, 4)
    (length,) = struct.unpack_from(endian + "I", data, offset)
    offset += 4
    raw = bytes(data[offset : offset + 4 * length])
    codec = "utf-32-le" if endian == "<" else "utf-32-be"
    return raw.decode(codec, "replace").rstrip("\x00"), offset + 4 * length
