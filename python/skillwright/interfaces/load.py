"""One entry point for every interface source a command accepts."""

from __future__ import annotations

import json
from pathlib import Path

from skillwright.errors import FileFormatError, InputFileError, InputFileNotFoundError
from skillwright.interfaces.inventory import Inventory

__all__ = ["load_inventory"]


def _read_inventory_json(path: Path) -> Inventory:
    from pydantic import ValidationError

    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise FileFormatError(f"{path}: not UTF-8 text, so not an inventory") from None
    except OSError as error:
        raise InputFileError(f"{path}: cannot be read ({error.strerror})") from error
    try:
        document = json.loads(text)
    except json.JSONDecodeError as error:
        raise FileFormatError(
            f"{path}:{error.lineno}:{error.colno}: JSON syntax error: {error.msg}"
        ) from None
    if not (isinstance(document, dict) and "interfaces" in document and "resource" in document):
        raise FileFormatError(
            f"{path}: JSON, but not a skillwright inventory (no 'resource' and 'interfaces'); "
            "make one with `skillwright discover SOURCE -o inventory.json`"
        )
    try:
        return Inventory.model_validate(document)
    except ValidationError as error:
        first = error.errors()[0]
        where = ".".join(str(p) for p in first["loc"])
        raise FileFormatError(
            f"{path}: not a valid inventory at {where}: {first['msg']} "
            f"({error.error_count()} problem(s)); was it written by another version?"
        ) from None


def load_inventory(source: str | Path) -> Inventory:
    """The inventory from a saved inventory (``.json``), an ``.mcap`` file or a rosbag2 folder."""
    path = Path(source)
    if not path.exists():
        raise InputFileNotFoundError(
            f"interface source {path}: no such file or folder; give an .mcap file, a rosbag2 "
            "folder or an inventory .json"
        )
    if path.is_file() and path.suffix.lower() == ".json":
        return _read_inventory_json(path)
    from skillwright.interfaces.sources.bag import discover_bag

    return discover_bag(path)
