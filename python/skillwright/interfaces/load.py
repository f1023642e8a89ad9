"""One entry point for every interface source a command accepts.

A file is told apart by its content, not its name: JSON (a saved inventory or a
reference-tool report) starts with ``{``; anything else is read as MCAP. A folder is a
rosbag2 recording.
"""

from __future__ import annotations

import json
import threading
from pathlib import Path
from typing import TYPE_CHECKING, Any

from skillwright.cancel import raise_if_cancelled
from skillwright.errors import FileFormatError, InputFileError, InputFileNotFoundError
from skillwright.interfaces.inventory import Inventory

if TYPE_CHECKING:
    from skillwright.interfaces.sources.bag import ReadMode

__all__ = ["discover_path", "is_json_file", "load_inventory", "read_warnings"]

_BOM = b"\xef\xbb\xbf"


def is_json_file(path: Path) -> bool:
    """Whether ``path`` is a file that holds JSON: named ``.json``, or starting with ``{``
    (an MCAP file starts with its magic bytes instead)."""
    if not path.is_file():
        return False
    if path.suffix.lower() == ".json":
        return True
    try:
        with path.open("rb") as stream:
            head = stream.read(256)
    except OSError:
        return False
    return head.removeprefix(_BOM).lstrip().startswith(b"{")


def _read_json(path: Path) -> Any:
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError:
        raise FileFormatError(f"{path}: not UTF-8 text, so not an inventory or report") from None
    except OSError as error:
        raise InputFileError(f"{path}: cannot be read ({error.strerror})") from error
    try:
        return json.loads(text)
    except json.JSONDecodeError as error:
        raise FileFormatError(
            f"{path}:{error.lineno}:{error.colno}: JSON syntax error: {error.msg}"
        ) from None


def _inventory_from_json(path: Path, document: Any) -> Inventory:
    from pydantic import ValidationError

    try:
        return Inventory.model_validate(document)
    except ValidationError as error:
        first = error.errors()[0]
        where = ".".join(str(p) for p in first["loc"])
        raise FileFormatError(
            f"{path}: not a valid inventory at {where}: {first['msg']} "
            f"({error.error_count()} problem(s)); was it written by another version?"
        ) from None


def _read_json_source(
    path: Path, resource_name: str | None, cancel: threading.Event | None
) -> Inventory:
    from skillwright.interfaces.sources.report import inventory_from_report, is_report

    document = _read_json(path)
    raise_if_cancelled(cancel, f"reading {path}")
    if is_report(document):
        return inventory_from_report(document, str(path), resource_name, cancel=cancel)
    if isinstance(document, dict) and "interfaces" in document and "resource" in document:
        inventory = _inventory_from_json(path, document)
        if resource_name:
            inventory.resource.name = resource_name
        return inventory
    raise FileFormatError(
        f"{path}: JSON, but neither a skillwright inventory (no 'resource' and 'interfaces') "
        "nor a report of the reference tool (no 'ros2_control_entities' or 'control_entities'); "
        "make an inventory with `skillwright discover SOURCE -o inventory.json`"
    )


def discover_path(
    source: str | Path,
    mode: ReadMode = "auto",
    resource_name: str | None = None,
    *,
    cancel: threading.Event | None = None,
) -> Inventory:
    """The inventory of a file or folder: saved inventory or report JSON (by content), an
    ``.mcap`` file or a rosbag2 folder. ``mode`` applies to recordings only.

    ``cancel`` is looked at between files and between interfaces; once it is set,
    :class:`~skillwright.errors.OperationCancelledError` is raised (see
    :mod:`skillwright.cancel`).
    """
    raise_if_cancelled(cancel, f"reading {source}")
    path = Path(source)
    if not path.exists():
        raise InputFileNotFoundError(
            f"interface source {path}: no such file or folder; give an .mcap file, a rosbag2 "
            "folder, a report or an inventory .json"
        )
    if is_json_file(path):
        return _read_json_source(path, resource_name, cancel)
    from skillwright.interfaces.sources.bag import discover_bag

    return discover_bag(path, mode, resource_name, cancel=cancel)


def load_inventory(source: str | Path, *, cancel: threading.Event | None = None) -> Inventory:
    """The inventory from a saved inventory or a reference-tool report (JSON, told apart by
    content), an ``.mcap`` file or a rosbag2 folder; ``cancel`` as for :func:`discover_path`."""
    return discover_path(source, cancel=cancel)


def read_warnings(inventory: Inventory) -> list[str]:
    """What reading the inventory's recordings lost, one sentence per file or damaged spot:
    a file skipped, read only up to a byte, or with a damaged record passed over. Every
    command that takes a source says these, so that an interface missing because its
    recording was cut short is not mistaken for one the robot does not have."""
    warnings = []
    for source in inventory.sources:
        for file in source.files:
            if file.read_method == "unreadable" and file.stopped_at is not None:
                warnings.append(f"skipped {file.stopped_at.message}")
            elif file.stopped_at is not None:
                warnings.append(
                    f"{file.path}: read only up to byte {file.stopped_at.offset}: "
                    f"{file.stopped_at.message}; interfaces recorded after it are missing"
                )
            warnings += [f"{file.path}: byte {d.offset}: {d.message}" for d in file.damaged]
    return warnings
