"""The reference tool's interface reports: read them as inventories, write inventories as them.

LLMCap2Skill (the paper's tool) saves what it discovers on a live ROS 2 system as JSON, in
three shapes, and all are read here as they are:

* the raw report: ``{"timestamp", "ros2_control_entities": {"topics": [...], "services":
  [...], "actions": [...]}}``;
* the report after its relevance filter: ``{"ros2_control_entities": [...]}``, one flat
  list whose entries also carry a ``description``;
* what its REST service's ``/generate-system-report/`` answers (saved as
  ``api_documentation.json``): ``{"control_entities": [...]}``, the same flat list, every entry
  with a ``description`` (empty where none was written).

An entry is ``{"name", "type", "interfaces": [{"name": "pkg/msg/T", "details": TEXT}],
"description"?}``. ``details`` is what ``ros2 interface show`` prints: the definition with
every nested type expanded below its field one tab deeper, comments only at the top level,
services split at ``---`` and actions at two ``---`` lines. Import turns that text back
into our definitions (main block plus ``MSG:`` blocks, field tree, constants, defaults);
export prints definitions the way ``ros2 interface show`` does, so report → inventory →
report gives back the same text, and a recording can be handed to a team using that tool.
"""

from __future__ import annotations

import json
import re
import threading
from collections.abc import Iterator
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Final

from skillwright.cancel import raise_if_cancelled
from skillwright.errors import FileFormatError, InputFileError
from skillwright.interfaces.infrastructure import classify
from skillwright.interfaces.inventory import (
    Description,
    Interface,
    InterfaceKind,
    Inventory,
    MessageDefinition,
    MessageField,
    Resource,
    Source,
)
from skillwright.interfaces.ros2msg import (
    BUILTIN_TYPES,
    Block,
    definition_from_text,
    find_block,
    normalize_type_name,
    parse_blocks,
)
from skillwright.interfaces.sources import InterfaceSource
from skillwright.interfaces.typestore import fill_missing_definitions, filled_note

__all__ = [
    "DESCRIPTION_HEADINGS",
    "ReportSource",
    "definitions_from_details",
    "description_from_text",
    "description_to_text",
    "details_from_definitions",
    "interface_type_name",
    "inventory_from_report",
    "is_report",
    "read_report",
    "report_from_inventory",
    "report_text",
]

SECTIONS: Final[dict[str, InterfaceKind]] = {
    "topics": "topic",
    "services": "service",
    "actions": "action",
}
"""Keys of the raw report's ``ros2_control_entities`` and the interface kind of each."""

ROLES: Final[dict[InterfaceKind, tuple[str, ...]]] = {
    "topic": ("message",),
    "service": ("request", "response"),
    "action": ("goal", "result", "feedback"),
}
"""Definition roles of each kind, in the order ``details`` shows them."""

_SUFFIX = {
    "message": "",
    "request": "_Request",
    "response": "_Response",
    "goal": "_Goal",
    "result": "_Result",
    "feedback": "_Feedback",
}
_NAMESPACE: dict[InterfaceKind, str] = {"topic": "msg", "service": "srv", "action": "action"}
_KIND_ORDER = {"topic": 0, "service": 1, "action": 2}

DETAILS_ROLE: Final = "details"
"""Role under which ``details`` text that could not be split is kept whole."""
DETAILS_ENCODING: Final = "ros2-interface-show"
"""Encoding recorded for such text: ``ros2 interface show`` output, not a ``.msg`` file."""

DESCRIPTION_HEADINGS: Final = (
    ("purpose", "Purpose of the ROS2 Element:"),
    ("module", "Mobile Robot Module:"),
    ("tasks", "Relevance for Specific Tasks:"),
    ("used_by", "Usage in the ROS2 System:"),
    ("key_fields", "Key Fields:"),
)
"""The sections of the reference tool's descriptions (the last one is ours), in order."""

_SEPARATOR_LINE = "=" * 80
_SEPARATOR = re.compile(r"^={3,}\s*$")
_TYPE_TOKEN = re.compile(
    r"^(?P<base>[A-Za-z][A-Za-z0-9_]*(?:/[A-Za-z][A-Za-z0-9_]*){0,2})"
    r"(?:<=\d+)?(?:\[(?:<=)?\d*\])?$"
)
# rosidl removes a lone "[unit]" from a comment before it compares comment and line.
_UNIT = re.compile(r"(\s*\[([^,\]]+)\])")
# Nesting deeper than this is malformed input (a type containing itself), not ROS 2.
_MAX_DEPTH = 24


# --- details text -> definitions -------------------------------------------------------


def _field_line(line: str) -> tuple[str, str] | None:
    """``(type, name)`` of a field line as rosidl reads it; ``None`` for blank lines,
    comments and constants (``TYPE NAME=VALUE``)."""
    index = line.find("#")
    content = (line[:index] if index >= 0 else line).replace("\t", " ").strip()
    type_text, _, rest = content.partition(" ")
    rest = rest.strip()
    if not rest or "=" in rest:
        return None
    return type_text, rest.split(None, 1)[0]


def _nested_type(line: str, package: str) -> str | None:
    """The full message type a field line refers to, or ``None`` (builtin, not a field)."""
    parsed = _field_line(line)
    if parsed is None:
        return None
    match = _TYPE_TOKEN.match(parsed[0])
    if match is None or match.group("base") in BUILTIN_TYPES:
        return None
    return normalize_type_name(match.group("base"), package)


@dataclass
class _ShownLines:
    """The lines of one part of ``details`` as (tab depth, text), and a read position."""

    items: list[tuple[int, str]]
    position: int = 0

    def next_depth(self) -> int:
        """Depth of the next non-blank line, -1 at the end."""
        for depth, text in self.items[self.position :]:
            if text.strip():
                return depth
        return -1


@dataclass
class _Collected:
    blocks: dict[str, str]
    notes: list[str]


def _take_block(lines: _ShownLines, depth: int, type_name: str, found: _Collected) -> list[str]:
    """The lines of the block at ``depth``; nested blocks below them go to ``found``."""
    own: list[str] = []
    package = type_name.split("/", 1)[0]
    while lines.position < len(lines.items):
        line_depth, text = lines.items[lines.position]
        if not text.strip():
            # A blank line inside a nested block belongs to it only if the block goes on
            # after it; otherwise it is the outer block's (ros2 shows nested blank lines
            # only with --all-comments).
            if depth > 0 and lines.next_depth() < depth:
                break
            own.append("")
            lines.position += 1
            continue
        if line_depth < depth:
            break
        lines.position += 1
        if line_depth > depth:
            own.append("\t" * (line_depth - depth) + text)
            found.notes.append(
                f"{type_name}: line {text.strip()!r} is indented deeper than a nested type; "
                "kept as written"
            )
            continue
        own.append(text)
        nested = _nested_type(text, package)
        if nested is not None:
            # `ros2 interface show` expands every nested type (it fails on unknown ones),
            # so a nested type with no lines below it is an empty message (std_msgs/Empty).
            child = ""
            if lines.next_depth() > depth:
                child = "\n".join(_take_block(lines, depth + 1, nested, found))
            known = found.blocks.setdefault(nested, child)
            if known != child:
                found.notes.append(
                    f"{nested} is shown differently in two places; the first is kept"
                )
    return own


def _ros2msg_text(type_name: str, items: list[tuple[int, str]]) -> tuple[str, list[str]]:
    """ros2msg text (main block, then ``MSG:`` blocks) of one part of ``details``."""
    found = _Collected(blocks={}, notes=[])
    lines = _ShownLines(items)
    main = _take_block(lines, 0, type_name, found)
    pieces = ["\n".join(main)]
    for nested, text in found.blocks.items():
        pieces.append(f"{_SEPARATOR_LINE}\nMSG: {nested}\n{text}")
    return "\n".join(pieces), found.notes


def _shown_items(details: str) -> list[tuple[int, str]]:
    items = []
    for line in details.replace("\r\n", "\n").split("\n"):
        text = line.lstrip("\t")
        items.append((len(line) - len(text), text))
    return items


def interface_type_name(kind: InterfaceKind, name: str) -> str:
    """A report's type name in full: ``pkg/T`` of a service is ``pkg/srv/T``."""
    parts = name.split("/")
    if len(parts) == 2:
        return f"{parts[0]}/{_NAMESPACE[kind]}/{parts[1]}"
    return name


def definitions_from_details(
    kind: InterfaceKind, type_name: str, details: str
) -> tuple[dict[str, MessageDefinition], list[str]]:
    """Definitions by role from ``ros2 interface show`` text, and notes for the interface.

    When the text does not split into the parts ``kind`` needs (one for a topic, request
    and response for a service, goal, result and feedback for an action), it is kept
    whole under the role ``details`` so that nothing is lost, with a note.
    """
    items = _shown_items(details)
    parts: list[list[tuple[int, str]]] = [[]]
    for depth, text in items:
        if depth == 0 and text.strip() == "---":
            parts.append([])
        else:
            parts[-1].append((depth, text))
    roles = ROLES[kind]
    if len(parts) != len(roles):
        note = (
            f"the definition of {type_name} has {len(parts)} part(s) between `---` lines, a "
            f"{kind} has {len(roles)}; kept as shown, without a field tree"
        )
        return {
            DETAILS_ROLE: MessageDefinition(
                type_name=type_name, encoding=DETAILS_ENCODING, raw=details, notes=[note]
            )
        }, [note]
    definitions: dict[str, MessageDefinition] = {}
    for role, part in zip(roles, parts, strict=True):
        part_type = type_name + _SUFFIX[role]
        text, notes = _ros2msg_text(part_type, part)
        definition = definition_from_text(part_type, text)
        definition.notes = list(dict.fromkeys([*notes, *definition.notes]))
        definitions[role] = definition
    return definitions, []


# --- definitions -> details text -------------------------------------------------------


def _processed_comment(comment: str) -> str:
    """A comment as rosidl keeps it: ``#`` stripped, a lone ``[unit]`` removed, dedented."""
    text = comment.lstrip("#")
    units = _UNIT.findall(text)
    if len(units) == 1:
        text = text.replace(units[0][0], "")
    return text.strip()


def _shown_nested(line: str) -> str | None:
    """A line of a nested type as ``ros2 interface show`` prints it, or ``None`` when it
    leaves it out (blank lines and comments).

    This follows ros2cli's rules exactly, including two of its quirks that real reports
    carry: a comment that rosidl reduces to nothing (``#``, ``##``) is printed, and a
    trailing comment is cut one character late, so ``x  # text`` prints as ``x  #``.
    Applied to its own output it changes nothing, which keeps round trips exact.
    """
    if not line.strip():
        return None
    if line.startswith("#"):
        return None if _processed_comment(line) else line
    index = line.find("#")
    if index < 0 or not line[:index].strip():
        return line  # no comment, or an indented comment line, printed as it stands
    if _field_line(line) is None:
        return line  # a constant: ros2cli strips trailing comments of fields only
    comment = _processed_comment(line[index:])
    if not comment:
        return line
    return line[: line.find(comment) - 1].strip()


def _value_text(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_value_text(v) for v in value) + "]"
    return str(value)


def _render_nested(
    field: MessageField, blocks: dict[str, Block], depth: int, out: list[str]
) -> None:
    if depth > _MAX_DEPTH:
        return
    block = find_block(blocks, field.base_type)
    if block is not None:
        _render_block(block.text.split("\n"), field.fields, blocks, depth, out)
        return
    # The source kept only the field tree (e.g. one half of a service schema): print it.
    indent = "\t" * depth
    for constant in field.constants:
        out.append(f"{indent}{constant.type} {constant.name}={_value_text(constant.value)}")
    for child in field.fields:
        default = "" if child.default is None else f" {_value_text(child.default)}"
        out.append(f"{indent}{child.type} {child.name}{default}")
        if not child.builtin:
            _render_nested(child, blocks, depth + 1, out)


def _render_block(
    lines: list[str],
    fields: list[MessageField] | None,
    blocks: dict[str, Block],
    depth: int,
    out: list[str],
) -> None:
    by_name = {f.name: f for f in fields or []}
    for raw_line in lines:
        line = raw_line.rstrip()
        shown = line if depth == 0 else _shown_nested(line)
        if shown is None:
            continue
        out.append("\t" * depth + shown if shown else "")
        parsed = _field_line(line)
        field = by_name.get(parsed[1]) if parsed is not None else None
        if field is not None and not field.builtin:
            _render_nested(field, blocks, depth + 1, out)


def _main_lines(raw: str) -> list[str]:
    lines = raw.split("\n")
    for index, line in enumerate(lines):
        if _SEPARATOR.match(line.strip()):
            return lines[:index]
    return lines


def details_from_definitions(
    kind: InterfaceKind, definitions: dict[str, MessageDefinition]
) -> str | None:
    """The ``ros2 interface show`` text of an interface's definitions, or ``None`` when
    they are incomplete (a role missing) or not ros2msg text."""
    kept = definitions.get(DETAILS_ROLE)
    if kept is not None:
        return kept.raw
    out: list[str] = []
    for number, role in enumerate(ROLES[kind]):
        definition = definitions.get(role)
        if definition is None or definition.encoding != "ros2msg" or definition.fields is None:
            return None
        if number:
            out.append("---")
        _, blocks = parse_blocks(definition.type_name, definition.raw)
        _render_block(_main_lines(definition.raw), definition.fields, blocks, 0, out)
    # The reference tool stores `ros2 interface show`'s output stripped.
    return "\n".join(out).strip()


# --- descriptions ----------------------------------------------------------------------

_HEADING_KEYS = {
    re.sub(r"\W+", " ", heading).strip().casefold(): key for key, heading in DESCRIPTION_HEADINGS
}


def _heading_key(line: str) -> str | None:
    text = line.strip().strip("#*_ ").strip()
    if not text.endswith(":"):
        return None
    return _HEADING_KEYS.get(re.sub(r"\W+", " ", text).strip().casefold())


def description_from_text(text: str) -> Description:
    """A report's free-text description in our structure (engine ``report``).

    The reference tool's descriptions have four sections, each a list of ``-`` items:
    purpose, module, tasks, usage. Items of the first two are joined into one text, the
    others become list entries. Text outside the known sections is kept in the purpose.
    """
    sections: dict[str, list[str]] = {}
    extra: list[str] = []
    current: list[str] = extra
    new_item = True
    for raw_line in text.replace("\r\n", "\n").split("\n"):
        line = raw_line.strip()
        if not line:
            new_item = True
            continue
        key = _heading_key(line)
        if key is not None:
            current = sections.setdefault(key, [])
            new_item = True
            continue
        bullet = re.match(r"^[-*\u2022]\s*(.*)$", line)
        if bullet is not None:
            current.append(bullet.group(1).strip())
            new_item = False
        elif new_item or not current:
            current.append(line)
            new_item = False
        else:
            current[-1] = f"{current[-1]} {line}"
    purpose = " ".join([*sections.get("purpose", []), *extra])
    return Description(
        purpose=purpose,
        module=" ".join(sections.get("module", [])) or "other",
        tasks=sections.get("tasks", []),
        used_by=sections.get("used_by", []),
        key_fields=sections.get("key_fields", []),
        engine="report",
    )


def description_to_text(description: Description) -> str:
    """Our description in the reference tool's section layout (plus ``Key Fields:``)."""
    values: dict[str, list[str]] = {
        "purpose": [description.purpose] if description.purpose else [],
        "module": [description.module] if description.module else [],
        "tasks": description.tasks,
        "used_by": description.used_by,
        "key_fields": description.key_fields,
    }
    blocks = []
    for key, heading in DESCRIPTION_HEADINGS:
        if key == "key_fields" and not values[key]:
            continue
        blocks.append("\n".join([heading, *(f"    - {item}" for item in values[key])]))
    return "\n\n".join(blocks)


# --- import ----------------------------------------------------------------------------


REPORT_KEYS: Final = ("ros2_control_entities", "control_entities")
"""The key of a report's entries: the saved report's, the REST service's answer's."""


def _report_key(document: object) -> str | None:
    if not isinstance(document, dict):
        return None
    return next((key for key in REPORT_KEYS if key in document), None)


def is_report(document: object) -> bool:
    """Whether a parsed JSON document is a reference-tool report (by its content)."""
    return _report_key(document) is not None


def _entries(
    document: dict[str, Any], where: str
) -> Iterator[tuple[str, InterfaceKind | None, object]]:
    """``(JSON path, kind of its section or None, entry)`` for every entry."""
    key = _report_key(document)
    assert key is not None
    entities = document[key]
    if key == "control_entities" and not isinstance(entities, list):
        raise FileFormatError(f"{where}: control_entities: expected a list of entries")
    if isinstance(entities, dict):
        for section, items in entities.items():
            kind = SECTIONS.get(section)
            path = f"ros2_control_entities.{section}"
            if kind is None:
                raise FileFormatError(
                    f"{where}: {path}: unknown section; a report has topics, services and actions"
                )
            if not isinstance(items, list):
                raise FileFormatError(f"{where}: {path}: expected a list of entries")
            for index, entry in enumerate(items):
                yield f"{path}[{index}]", kind, entry
    elif isinstance(entities, list):
        for index, entry in enumerate(entities):
            yield f"{key}[{index}]", None, entry
    else:
        raise FileFormatError(
            f"{where}: ros2_control_entities: expected an object with topics, services and "
            "actions, or a list of entries"
        )


def _text(entry: dict[str, Any], key: str, where: str, path: str) -> str:
    value = entry.get(key)
    if not isinstance(value, str) or not value:
        raise FileFormatError(
            f"{where}: {path}.{key}: expected a non-empty string, found {json.dumps(value)}"
        )
    return value


def _interfaces_of(
    entry: dict[str, Any], kind: InterfaceKind, name: str, where: str, path: str
) -> list[Interface]:
    interfaces = entry.get("interfaces")
    if not isinstance(interfaces, list):
        raise FileFormatError(
            f"{where}: {path}.interfaces: expected a list of {{name, details}} objects"
        )
    description_text = entry.get("description")
    if description_text is not None and not isinstance(description_text, str):
        raise FileFormatError(f"{where}: {path}.description: expected a string")
    description = description_from_text(description_text) if description_text else None
    result: list[Interface] = []
    for index, item in enumerate(interfaces):
        item_path = f"{path}.interfaces[{index}]"
        if not isinstance(item, dict):
            raise FileFormatError(f"{where}: {item_path}: expected an object {{name, details}}")
        type_name = interface_type_name(kind, _text(item, "name", where, item_path))
        details = item.get("details")
        if details is not None and not isinstance(details, str):
            raise FileFormatError(f"{where}: {item_path}.details: expected a string or null")
        notes: list[str] = []
        definitions: dict[str, MessageDefinition] = {}
        if details and details.strip():
            definitions, notes = definitions_from_details(kind, type_name, details)
        else:
            notes.append(f"the report gives no definition of {type_name}")
        namespace = type_name.split("/")[1] if type_name.count("/") == 2 else None
        if namespace is not None and namespace != _NAMESPACE[kind]:
            notes.append(f"a {kind} of type {type_name}, expected a {_NAMESPACE[kind]} type")
        if len(interfaces) > 1:
            notes.append(f"{name}: the report gives it {len(interfaces)} types")
        result.append(
            Interface(
                name=name,
                kind=kind,
                type_name=type_name,
                definitions=definitions,
                infrastructure=classify(kind, name, type_name),
                description=description.model_copy(deep=True) if description else None,
                notes=notes,
            )
        )
    return result


def inventory_from_report(
    document: object,
    where: str,
    resource_name: str | None = None,
    *,
    cancel: threading.Event | None = None,
) -> Inventory:
    """The inventory of a parsed report; ``where`` names the file in error messages.

    Raises :class:`FileFormatError` naming the file and the JSON path of the bad entry.
    ``cancel`` is looked at before each entry (see :mod:`skillwright.cancel`).
    """
    if not is_report(document):
        raise FileFormatError(
            f"{where}: not a reference-tool report (no 'ros2_control_entities' or "
            "'control_entities')"
        )
    assert isinstance(document, dict)
    interfaces: list[Interface] = []
    for path, section_kind, entry in _entries(document, where):
        raise_if_cancelled(cancel, f"reading {where}")
        if not isinstance(entry, dict):
            raise FileFormatError(f"{where}: {path}: expected an object {{name, type, interfaces}}")
        name = _text(entry, "name", where, path)
        kind_text = entry.get("type", section_kind)
        if kind_text not in ROLES:
            raise FileFormatError(
                f"{where}: {path}.type: {json.dumps(kind_text)} is not topic, service or action"
            )
        kind: InterfaceKind = kind_text
        if section_kind is not None and kind != section_kind:
            raise FileFormatError(
                f"{where}: {path}.type: a {kind} in the {section_kind}s section; move the "
                "entry or correct its type"
            )
        interfaces.extend(_interfaces_of(entry, kind, name, where, path))
    # Stable: types of one name keep the report's order, so export gives them back as read.
    interfaces.sort(key=lambda i: (_KIND_ORDER[i.kind], i.name))
    # Entries without details still name their type; the report says nothing of the distro.
    filled = fill_missing_definitions(interfaces, cancel=cancel)
    timestamp = document.get("timestamp")
    described = sum(i.description is not None for i in interfaces)
    notes = []
    if described:
        notes.append(f"{described} description(s) from the report (engine `report`)")
    if filled:
        notes.append(filled_note(filled))
    return Inventory(
        resource=Resource(name=resource_name or Path(where).stem),
        sources=[
            Source(
                kind="report",
                location=where,
                captured_at=timestamp if isinstance(timestamp, str) else None,
                notes=notes,
            )
        ],
        interfaces=interfaces,
    )


def read_report(path: str | Path, resource_name: str | None = None) -> Inventory:
    """The inventory of a report file (either shape)."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise FileFormatError(f"{path}: not UTF-8 text, so not a report") from None
    except OSError as error:
        raise InputFileError(f"{path}: cannot be read ({error.strerror})") from error
    try:
        document = json.loads(text)
    except json.JSONDecodeError as error:
        raise FileFormatError(
            f"{path}:{error.lineno}:{error.colno}: JSON syntax error: {error.msg}"
        ) from None
    return inventory_from_report(document, str(path), resource_name)


@dataclass
class ReportSource(InterfaceSource):
    """Interfaces listed in a reference-tool report file."""

    path: Path
    resource_name: str | None = None

    kind = "report"

    def discover(self) -> Inventory:
        """Reads the report (see :func:`read_report`)."""
        return read_report(self.path, self.resource_name)


# --- export ----------------------------------------------------------------------------


def _timestamp(inventory: Inventory) -> str:
    for source in inventory.sources:
        if source.captured_at:
            return source.captured_at
    for source in inventory.sources:
        if source.start_time_ns is not None:
            moment = datetime.fromtimestamp(source.start_time_ns / 1e9, tz=UTC)
            return moment.strftime("%Y-%m-%d %H:%M:%S")
    # The reference tool stamps a report with the local time it was made.
    return datetime.now().astimezone().strftime("%Y-%m-%d %H:%M:%S")


def report_from_inventory(inventory: Inventory) -> tuple[dict[str, Any], list[str]]:
    """The raw report shape of ``inventory`` and notes on what it could not carry.

    Entries get a ``description`` (in the reference tool's section layout) when the
    inventory has one. Interfaces sharing a kind and name become one entry with several
    ``interfaces``. A definition that cannot be shown as ``ros2 interface show`` would
    (incomplete, or not ros2msg) leaves ``details`` empty, as the reference tool does
    when that command fails.
    """
    sections: dict[str, list[dict[str, Any]]] = {section: [] for section in SECTIONS}
    section_of = {kind: section for section, kind in SECTIONS.items()}
    entries: dict[tuple[str, str], dict[str, Any]] = {}
    notes: list[str] = []
    for interface in inventory.interfaces:
        if not interface.type_name:
            # A report entry needs a type name; an empty one would not read back.
            notes.append(f"{interface.kind} {interface.name}: type unknown; left out")
            continue
        key = (interface.kind, interface.name)
        entry = entries.get(key)
        if entry is None:
            entry = {"name": interface.name, "type": interface.kind}
            if interface.description is not None:
                entry["description"] = description_to_text(interface.description)
            entry["interfaces"] = []
            entries[key] = entry
            sections[section_of[interface.kind]].append(entry)
        details = details_from_definitions(interface.kind, interface.definitions)
        if details is None:
            notes.append(
                f"{interface.kind} {interface.name}: no complete ros2msg definition of "
                f"{interface.type_name or 'its type'}; its details are left empty"
            )
        entry["interfaces"].append({"name": interface.type_name, "details": details or ""})
    return {"timestamp": _timestamp(inventory), "ros2_control_entities": sections}, notes


def report_text(inventory: Inventory) -> tuple[str, list[str]]:
    """:func:`report_from_inventory` as JSON text, laid out as the reference tool writes it."""
    document, notes = report_from_inventory(inventory)
    return json.dumps(document, indent=4), notes
