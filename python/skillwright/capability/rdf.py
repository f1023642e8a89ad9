"""Parsing RDF files with rdflib into graphs, with errors that point at the line."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from skillwright.errors import CapabilityError, InputFileError, InputFileNotFoundError

if TYPE_CHECKING:
    from rdflib import Graph

__all__ = ["FORMATS", "guess_format", "parse_graph"]

FORMATS = {
    ".ttl": "turtle",
    ".turtle": "turtle",
    ".n3": "n3",
    ".nt": "nt",
    ".owl": "xml",
    ".rdf": "xml",
    ".xml": "xml",
    ".jsonld": "json-ld",
    ".trig": "trig",
}
"""File suffix -> rdflib parser name; anything else is read as Turtle."""


def guess_format(path: Path) -> str:
    """The rdflib format for ``path`` by its suffix (Turtle when unknown)."""
    return FORMATS.get(path.suffix.lower(), "turtle")


def _read_bytes(path: Path, what: str) -> bytes:
    if not path.exists():
        raise InputFileNotFoundError(f"{what} {path}: no such file; check the path")
    if path.is_dir():
        raise InputFileError(f"{what} {path}: is a folder; give the path of a .ttl file")
    try:
        return path.read_bytes()
    except OSError as error:
        raise InputFileError(f"{what} {path}: cannot be read ({error.strerror})") from error


def _line_and_column(text: bytes | str, index: int) -> tuple[int, int]:
    newline = b"\n" if isinstance(text, bytes) else "\n"
    before = text[:index]
    line = before.count(newline) + 1  # type: ignore[arg-type]
    column = index - (before.rfind(newline) + 1) + 1  # type: ignore[arg-type]
    return line, column


def parse_graph(path: Path, what: str = "capability file") -> Graph:
    """Parses ``path`` into a new graph.

    Raises :class:`CapabilityError` with ``file:line:column`` for syntax errors, and the
    input-file errors for missing or unreadable files. Nothing is fetched: ``owl:imports``
    stay unresolved triples.
    """
    from rdflib import Graph
    from rdflib.plugins.parsers.notation3 import BadSyntax

    data = _read_bytes(path, what)
    fmt = guess_format(path)
    graph = Graph()
    try:
        graph.parse(data=data, format=fmt, publicID=path.resolve().as_uri())
    except BadSyntax as error:
        line, column = _line_and_column(error._str, error._i)
        raise CapabilityError(
            f"{path}:{line}:{column}: Turtle syntax error: {error._why}. "
            "Fix the file at that place (a missing '.', ';' or quote is the usual cause)."
        ) from None
    except UnicodeDecodeError as error:
        line, column = _line_and_column(data, error.start)
        raise CapabilityError(
            f"{path}:{line}:{column}: not valid UTF-8 text; save the file as UTF-8"
        ) from None
    except Exception as error:  # rdflib's parsers raise many unrelated types
        position = ""
        get_line = getattr(error, "getLineNumber", None)
        get_column = getattr(error, "getColumnNumber", None)
        if callable(get_line) and callable(get_column):
            position = f"{get_line()}:{get_column()}:"
        detail = str(error).splitlines()[0] if str(error) else type(error).__name__
        raise CapabilityError(
            f"{path}:{position} cannot be read as {fmt}: {detail}. "
            "Check the file's syntax, or give it a suffix that names its format "
            f"({', '.join(sorted(FORMATS))})."
        ) from None
    return graph
