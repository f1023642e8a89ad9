"""ROS 2 ``.msg`` / ``.srv`` definition text into field trees.

A ``ros2msg`` schema in an MCAP file is the main definition followed by the definitions
it depends on, each after a line of ``=`` signs and a ``MSG: pkg/Type`` line. Types are
named ``pkg/Type`` or ``pkg/msg/Type``; both mean the same and are normalised to the
latter. rosbag2 records services with the raw ``.srv`` text (request ``---`` response)
as the schema of their ``_service_event`` topic; :func:`split_service` handles that.

The grammar follows rosidl's: ``TYPE NAME [DEFAULT]`` fields, ``TYPE NAME=VALUE``
constants, ``#`` comments (not inside quoted strings), bounded strings
``string<=10``, and arrays ``T[]``, ``T[3]``, ``T[<=5]``.
"""

from __future__ import annotations

import ast
import itertools
import re
from dataclasses import dataclass, field

from skillwright.interfaces.inventory import ArrayKind, Constant, MessageDefinition, MessageField

__all__ = [
    "BUILTIN_TYPES",
    "Block",
    "definition_from_text",
    "find_block",
    "normalize_type_name",
    "parse_blocks",
    "split_action",
    "split_service",
]

BUILTIN_TYPES = frozenset(
    {
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
)
_INTEGER_TYPES = frozenset(t for t in BUILTIN_TYPES if "int" in t) | {"byte", "char"}
_FLOAT_TYPES = frozenset({"float32", "float64"})
_STRING_TYPES = frozenset({"string", "wstring"})

# The nesting depth at which expansion stops; real ROS 2 messages stay far below it and
# a (malformed) self-referencing definition must not recurse forever.
_MAX_DEPTH = 24

_SEPARATOR = re.compile(r"^={3,}\s*$")
_MSG_LINE = re.compile(r"^MSG:\s*(\S+)\s*$")
_TYPE = re.compile(
    r"^(?P<base>[A-Za-z][A-Za-z0-9_]*(?:/[A-Za-z][A-Za-z0-9_]*){0,2})"
    r"(?:<=(?P<string_bound>\d+))?"
    r"(?:\[(?P<array>(?:<=)?\d*)\])?$"
)
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
_CONSTANT = re.compile(r"^(?P<name>[A-Za-z][A-Za-z0-9_]*)\s*=\s*(?P<value>.*)$")


def normalize_type_name(name: str, package: str | None = None) -> str:
    """``pkg/Type`` -> ``pkg/msg/Type``; a bare ``Type`` takes ``package`` (ROS 1
    ``Header`` means ``std_msgs/msg/Header``); full names are returned unchanged."""
    parts = name.split("/")
    if len(parts) == 3:
        return name
    if len(parts) == 2:
        return f"{parts[0]}/msg/{parts[1]}"
    if name == "Header":
        return "std_msgs/msg/Header"
    return f"{package}/msg/{name}" if package else name


def _package_of(type_name: str) -> str | None:
    return type_name.split("/", 1)[0] if "/" in type_name else None


@dataclass
class Block:
    """One message definition of a schema: its type name and text."""

    type_name: str
    text: str
    fields: list[tuple[str, str, str | None]] = field(default_factory=list)
    """``(type, name, default text)`` per field."""
    constants: list[Constant] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)


def parse_blocks(type_name: str, text: str) -> tuple[Block, dict[str, Block]]:
    """Splits a schema into its main block and its dependency blocks (by full type name)."""
    chunks: list[list[str]] = [[]]
    for line in text.splitlines():
        if _SEPARATOR.match(line.strip()):
            chunks.append([])
        else:
            chunks[-1].append(line)
    main = _parse_block(normalize_type_name(type_name), "\n".join(chunks[0]))
    dependencies: dict[str, Block] = {}
    for lines in chunks[1:]:
        body = list(lines)
        while body and not body[0].strip():
            body.pop(0)
        match = _MSG_LINE.match(body[0].strip()) if body else None
        if match is None:
            main.errors.append("a dependency block has no `MSG: pkg/Type` line; it is ignored")
            continue
        name = normalize_type_name(match.group(1))
        dependencies[name] = _parse_block(name, "\n".join(body[1:]))
    return main, dependencies


def _unquoted_positions(text: str, targets: str) -> list[int]:
    """Indexes of the characters in ``targets`` that stand outside quoted strings."""
    found: list[int] = []
    quote: str | None = None
    escaped = False
    for index, char in enumerate(text):
        if escaped:
            escaped = False
        elif char == "\\":
            escaped = True
        elif quote is not None:
            if char == quote:
                quote = None
        elif char in "'\"":
            quote = char
        elif char in targets:
            found.append(index)
    return found


def _strip_comment(line: str) -> str:
    """Removes a ``#`` comment, leaving ``#`` inside quoted strings alone."""
    hashes = _unquoted_positions(line, "#")
    return line[: hashes[0]] if hashes else line


def _parse_block(type_name: str, text: str) -> Block:
    block = Block(type_name=type_name, text=text)
    for number, raw_line in enumerate(text.splitlines(), start=1):
        line = _strip_comment(raw_line).strip()
        if not line:
            continue
        parts = line.split(None, 1)
        if len(parts) < 2:
            block.errors.append(f"{type_name} line {number}: {raw_line.strip()!r} has no name")
            continue
        type_text, rest = parts
        constant = _CONSTANT.match(rest)
        if constant is not None:
            base = _TYPE.match(type_text)
            if base is None:
                block.errors.append(f"{type_name} line {number}: bad type {type_text!r}")
                continue
            block.constants.append(
                Constant(
                    name=constant.group("name"),
                    type=type_text,
                    value=_parse_scalar(constant.group("value").strip(), base.group("base")),
                )
            )
            continue
        name_and_default = rest.split(None, 1)
        name = name_and_default[0]
        if not _NAME.match(name):
            block.errors.append(f"{type_name} line {number}: bad field name {name!r}")
            continue
        default = name_and_default[1].strip() if len(name_and_default) > 1 else None
        block.fields.append((type_text, name, default))
    return block


def _unquote(text: str) -> str:
    if len(text) >= 2 and text[0] == text[-1] and text[0] in "'\"":
        try:
            value = ast.literal_eval(text)
        except (ValueError, SyntaxError):
            return text[1:-1]
        return value if isinstance(value, str) else text[1:-1]
    return text


def _parse_scalar(text: str, base: str) -> str | int | float | bool:
    """A constant or default value parsed according to its builtin type."""
    if base in _STRING_TYPES:
        return _unquote(text)
    if base == "bool":
        lowered = text.lower()
        if lowered in {"true", "1"}:
            return True
        if lowered in {"false", "0"}:
            return False
        return text
    try:
        if base in _INTEGER_TYPES:
            return int(text, 0)
        if base in _FLOAT_TYPES:
            return float(text)
    except ValueError:
        return text
    return text


def _split_array_literal(text: str) -> list[str]:
    """``[1, 2]`` or ``["a", 'b,c']`` into element texts, honouring quotes."""
    inner = text.strip()
    if inner.startswith("[") and inner.endswith("]"):
        inner = inner[1:-1]
    if not inner.strip():
        return []
    bounds = [-1, *_unquoted_positions(inner, ","), len(inner)]
    return [inner[a + 1 : b].strip() for a, b in itertools.pairwise(bounds)]


def _field(
    type_text: str,
    name: str,
    default: str | None,
    *,
    package: str | None,
    dependencies: dict[str, Block],
    notes: list[str],
    depth: int,
) -> MessageField:
    match = _TYPE.match(type_text)
    if match is None:
        notes.append(f"field {name!r}: type {type_text!r} is not a ROS 2 type")
        return MessageField(
            name=name, type=type_text, base_type=type_text, builtin=False, resolved=False
        )
    base = match.group("base")
    builtin = base in BUILTIN_TYPES
    base_type = base if builtin else normalize_type_name(base, package)
    array_text = match.group("array")
    array: ArrayKind = "none"
    array_size: int | None = None
    if array_text is not None:
        if array_text == "":
            array = "unbounded"
        elif array_text.startswith("<="):
            array, array_size = "bounded", int(array_text[2:])
        else:
            array, array_size = "fixed", int(array_text)
    string_bound = match.group("string_bound")
    parsed_default: object = None
    if default is not None:
        if array == "none":
            parsed_default = _parse_scalar(default, base)
        else:
            parsed_default = [_parse_scalar(item, base) for item in _split_array_literal(default)]
    result = MessageField(
        name=name,
        type=type_text,
        base_type=base_type,
        builtin=builtin,
        array=array,
        array_size=array_size,
        string_bound=int(string_bound) if string_bound is not None else None,
        default=parsed_default,  # type: ignore[arg-type]  # scalars and lists of them
    )
    if builtin:
        return result
    nested = find_block(dependencies, base_type)
    if nested is not None:
        # A bare `Goal` inside `pkg/action/...` lives in pkg/action, not pkg/msg.
        result.base_type = nested.type_name
    if nested is None:
        result.resolved = False
        notes.append(f"field {name!r}: definition of {base_type} is not in the schema")
        return result
    if depth >= _MAX_DEPTH:
        result.resolved = False
        notes.append(f"field {name!r}: nesting deeper than {_MAX_DEPTH} levels, not expanded")
        return result
    result.fields = _fields(nested, dependencies, notes, depth + 1)
    result.constants = list(nested.constants)
    return result


def find_block(blocks: dict[str, Block], type_name: str) -> Block | None:
    """The block defining ``type_name``; ``pkg/msg/T``, ``pkg/srv/T`` and ``pkg/action/T``
    are tried in that order when the exact name is absent (schemas name a type by any)."""
    exact = blocks.get(type_name)
    if exact is not None:
        return exact
    parts = type_name.split("/")
    if len(parts) < 2:
        return None
    package, name = parts[0], parts[-1]
    for namespace in ("msg", "srv", "action"):
        candidate = blocks.get(f"{package}/{namespace}/{name}")
        if candidate is not None:
            return candidate
    return None


def _fields(
    block: Block, dependencies: dict[str, Block], notes: list[str], depth: int
) -> list[MessageField]:
    package = _package_of(block.type_name)
    return [
        _field(
            type_text,
            name,
            default,
            package=package,
            dependencies=dependencies,
            notes=notes,
            depth=depth,
        )
        for type_text, name, default in block.fields
    ]


def definition_from_text(
    type_name: str,
    text: str,
    *,
    extra_dependencies: dict[str, Block] | None = None,
    encoding: str = "ros2msg",
) -> MessageDefinition:
    """The :class:`MessageDefinition` of ``type_name`` from ros2msg ``text``.

    ``extra_dependencies`` supplies blocks defined elsewhere (e.g. the other half of a
    service schema). Problems never raise: they become ``notes`` and unresolved fields.
    """
    main, dependencies = parse_blocks(type_name, text)
    if extra_dependencies:
        dependencies = {**extra_dependencies, **dependencies}
    notes: list[str] = list(main.errors)
    for block in dependencies.values():
        notes.extend(block.errors)
    fields = _fields(main, dependencies, notes, 0)
    return MessageDefinition(
        type_name=normalize_type_name(type_name),
        encoding=encoding,
        raw=text,
        fields=fields,
        constants=main.constants,
        notes=list(dict.fromkeys(notes)),
    )


def split_action(text: str) -> tuple[str, str, str] | None:
    """Goal, result and feedback text of a raw ``.action`` definition (two top-level
    ``---`` lines, optionally after an ``ACTION:`` header line), or ``None``."""
    main_lines: list[str] = []
    for line in text.splitlines():
        if _SEPARATOR.match(line.strip()):
            break
        if not main_lines and line.startswith("ACTION:"):
            continue
        main_lines.append(line)
    cuts = [i for i, line in enumerate(main_lines) if line.strip() == "---"]
    if len(cuts) != 2:
        return None
    first, second = cuts
    return (
        "\n".join(main_lines[:first]),
        "\n".join(main_lines[first + 1 : second]),
        "\n".join(main_lines[second + 1 :]),
    )


def split_service(text: str) -> tuple[str, str] | None:
    """Request and response text of a raw ``.srv`` definition, or ``None`` when ``text``
    has no ``---`` line at top level (it is an expanded message instead)."""
    main_lines: list[str] = []
    for line in text.splitlines():
        if _SEPARATOR.match(line.strip()):
            break  # dependency blocks start; a .srv split must come before them
        main_lines.append(line)
    for index, line in enumerate(main_lines):
        if line.strip() == "---":
            return "\n".join(main_lines[:index]), "\n".join(main_lines[index + 1 :])
    return None
