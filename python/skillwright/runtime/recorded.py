"""Recorded messages for replay and for the simulation's recorded facts: one reader of MCAP
and one of CDR.

* **MCAP** is read by the Rust core (:func:`skillwright.core.read_mcap_messages`), the same
  record decoder discovery uses: front to back, one chunk in memory at a time, the messages
  of a chunk in log-time order, only the topics asked for. A split rosbag2 recording (several
  files) is merged by log time here (:func:`merged_messages`).
* **CDR** is deserialised by rosbags (a dependency already, for its type stores), into a
  type store filled from the robot's own definitions (:class:`MessageDecoder`): the
  inventory's message definitions are what the recording was written with, so they, not a
  distribution's standard ones, say how its bytes are laid out. rosbags handles both byte
  orders of plain CDR (``CDR_LE``, ``CDR_BE``) with alignment relative to the encapsulation
  header, as ROS 2's default middleware writes it; its message objects become the plain
  dicts the simulated graph and the world plug-ins work with.

Why this split rather than one reader for both: the Rust core already owns MCAP (discovery,
bounded decoding, damage reporting) and hands out payloads as bytes without knowing any
message type; deserialising needs the ROS 2 type system, which rosbags implements with
generated per-type code. Doing CDR in Rust would mean a second implementation of the ROS 2
message grammar beside :mod:`skillwright.interfaces.ros2msg`; doing MCAP in rosbags would
mean a second MCAP reader beside discovery's.

rosbags' message grammar has no ``wstring`` (no standard ROS 2 message uses one); a recorded
type with one is refused with :class:`RecordedMessageError`, like any type it cannot lay out.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Any, Final

from skillwright.core import read_mcap_messages
from skillwright.runtime.typesys import FieldDef, TypeRegistry

__all__ = ["MessageDecoder", "RecordedMessage", "RecordedMessageError", "merged_messages"]

RecordedMessage = tuple[int, str, bytes]
"""``(log time in ns, topic, CDR payload)``."""

_ENCAPSULATIONS: Final = frozenset({b"\x00\x00", b"\x00\x01"})
"""``CDR_BE`` and ``CDR_LE``: plain CDR (XCDR1), what ROS 2's default middleware writes."""

Converter = Callable[[Any], Any]


class RecordedMessageError(ValueError):
    """A recorded payload does not decode as its type says (truncated, another type, not
    plain CDR), or its type cannot be laid out (no definition, a field rosbags lacks)."""


def merged_messages(
    paths: Iterable[Path], topics: set[str] | None = None
) -> Iterator[RecordedMessage]:
    """The messages of the MCAP files ``paths`` (a split recording), of ``topics`` only if
    given, in log-time order.

    Every file is opened at once, so a file that is not MCAP raises
    :class:`~skillwright.errors.FileFormatError` here; a record found broken later raises it
    from the iteration, naming the file and the offset.
    """
    readers = [read_mcap_messages(path, topics) for path in paths]
    return heapq.merge(*readers, key=lambda message: message[0])


class MessageDecoder:
    """Decodes the CDR payloads of the registry's types into dicts."""

    def __init__(self, registry: TypeRegistry) -> None:
        self._registry = registry
        self._store: Any = None
        self._converters: dict[str, Converter] = {}
        self._refused: dict[str, str] = {}

    def decode(self, type_name: str, data: bytes) -> dict[str, Any]:
        """The message in ``data`` (with its 4-byte encapsulation header) as a dict."""
        if len(data) < 4:
            raise RecordedMessageError(
                f"{type_name}: {len(data)} bytes, shorter than the CDR header"
            )
        if data[:2] not in _ENCAPSULATIONS:
            raise RecordedMessageError(
                f"{type_name}: encapsulation {data[0]:02x}{data[1]:02x} is not plain CDR"
            )
        convert = self._converter(type_name)
        try:
            message = self._store.deserialize_cdr(data, type_name)
        except Exception as error:  # rosbags' SerdeError, or what its generated code raised
            raise RecordedMessageError(
                f"{type_name}: truncated or not this type ({error})"
            ) from None
        return convert(message)  # type: ignore[no-any-return]

    def _converter(self, type_name: str) -> Converter:
        known = self._converters.get(type_name)
        if known is not None:
            return known
        refused = self._refused.get(type_name)
        if refused is not None:
            raise RecordedMessageError(refused)
        try:
            self._register(type_name)
        except RecordedMessageError as error:
            self._refused[type_name] = str(error)
            raise
        return self._converters[type_name]

    def _register(self, type_name: str) -> None:
        """Puts ``type_name`` and the types it is made of into the store, and makes the
        converters of their message objects to dicts."""
        from rosbags.typesys import Stores, get_types_from_msg, get_typestore

        if self._store is None:  # rosbags is imported by the first run that replays
            self._store = get_typestore(Stores.EMPTY)
        pending, texts = [type_name], {}
        while pending:
            name = pending.pop()
            if name in texts or name in self._converters:
                continue
            message = self._registry.message(name)
            if message is None:
                raise RecordedMessageError(f"no definition of {name} to decode it with")
            wide = [f.name for f in message.fields if f.base == "wstring"]
            if wide:
                raise RecordedMessageError(
                    f"{type_name}: cannot be decoded ({name}.{wide[0]} is a wstring, which "
                    "rosbags does not read)"
                )
            texts[name] = "\n".join(_field_line(field) for field in message.fields)
            pending += [f.base for f in message.fields if not f.builtin]
        types: dict[str, Any] = {}
        try:
            for name, text in texts.items():
                types.update(get_types_from_msg(text, name))
            self._store.register(types)
        except Exception as error:  # rosbags' grammar refused a definition
            raise RecordedMessageError(f"{type_name}: cannot be decoded ({error})") from None
        for name in texts:
            self._make_converter(name)

    def _make_converter(self, type_name: str) -> Converter:
        """The converter of ``type_name``'s message objects, made after those of the types it
        holds (ROS 2 types cannot hold themselves, so this ends)."""
        known = self._converters.get(type_name)
        if known is not None:
            return known
        message = self._registry.message(type_name)
        assert message is not None  # registered from it just before
        plan: list[tuple[str, Converter]] = []
        for field in message.fields:
            if not field.builtin:
                nested = self._make_converter(field.base)
                plan.append((field.name, _each(nested) if field.array != "none" else nested))
            elif field.array != "none":
                plan.append((field.name, _tolist))

        def convert(value: Any) -> dict[str, Any]:
            # rosbags' message objects are dataclasses whose instance dict holds the fields
            # in definition order, and the message type.
            out: dict[str, Any] = value.__dict__.copy()
            del out["__msgtype__"]
            for name, nested in plan:
                out[name] = nested(out[name])
            return out

        self._converters[type_name] = convert
        return convert


def _each(convert: Converter) -> Converter:
    """Converts every element of an array of messages."""
    return lambda items: [convert(item) for item in items]


def _tolist(value: Any) -> Any:
    """A builtin array field as a list (rosbags gives numpy arrays for numeric ones and
    lists for strings)."""
    return value.tolist() if hasattr(value, "tolist") else list(value)


def _field_line(field: FieldDef) -> str:
    """The ros2msg line of ``field``, as rosbags' grammar reads it."""
    base = field.base
    if field.string_bound is not None:
        base += f"<={field.string_bound}"
    suffix = {
        "none": "",
        "fixed": f"[{field.size}]",
        "bounded": f"[<={field.size}]",
        "unbounded": "[]",
    }[field.array]
    return f"{base}{suffix} {field.name}"
