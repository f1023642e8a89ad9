"""Parsing RDF files with rdflib into graphs, with errors that point at the line.

Three things rdflib leaves to its caller are done here:

* **The syntax.** rdflib picks a parser by the name it is given; we give it the one the
  suffix names (:data:`FORMATS`). When that parser fails, the content decides: OWL files
  saved from an editor as Turtle keep their ``.owl`` suffix, and a Turtle parser fed
  RDF/XML fails just as surely. :func:`sniff_format` tells Turtle, RDF/XML and JSON-LD apart
  by their first significant characters, and a file read in another syntax than its suffix
  names says so in a warning.
* **Literals that do not match their datatype** (``"Value of A"^^xsd:int``). RDF keeps them
  (an *ill-typed* literal has no value, only its text); rdflib logs a warning with a Python
  traceback for each one it cannot convert. Its log records go to :class:`_RdflibLog`, never
  to the terminal, and each ill-typed literal of the graph becomes one warning naming the
  file, the line it is first written on, the literal and its datatype.
* **Other rdflib log records and Python warnings** become one-line warnings, without
  tracebacks.
"""

from __future__ import annotations

import logging
import os
import re
import threading
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from skillwright.errors import CapabilityError, InputFileError, InputFileNotFoundError

if TYPE_CHECKING:
    from rdflib import Graph, Literal

__all__ = [
    "FORMATS",
    "ParsedGraph",
    "captured_rdflib_log",
    "guess_format",
    "parse_graph",
    "sniff_format",
]

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

SYNTAX_NAMES = {
    "turtle": "Turtle",
    "n3": "N3",
    "nt": "N-Triples",
    "xml": "RDF/XML",
    "json-ld": "JSON-LD",
    "trig": "TriG",
}
"""rdflib parser name -> the syntax's own name, for messages."""

_XSD = "http://www.w3.org/2001/XMLSchema#"


@dataclass
class ParsedGraph:
    """A parsed file: the graph, the syntax it was read in and what to warn about."""

    graph: Graph
    syntax: str
    """The rdflib parser that read it (``turtle``, ``xml``, ``json-ld``, ...)."""
    warnings: list[str] = field(default_factory=list)


def guess_format(path: Path) -> str:
    """The rdflib format for ``path`` by its suffix (Turtle when unknown)."""
    return FORMATS.get(path.suffix.lower(), "turtle")


_BOM = b"\xef\xbb\xbf"


def sniff_format(data: bytes) -> str:
    """The syntax the content looks like: ``xml``, ``json-ld`` or ``turtle``.

    RDF/XML starts with an XML declaration, a comment or an element (``<?xml``, ``<!--``,
    ``<rdf:RDF``); JSON-LD is a JSON object or array. Everything else is taken for Turtle,
    whose documents start with directives, comments or triples, and whose only leading
    ``<`` is that of an IRI followed by white space or a name character.
    """
    text = data.removeprefix(_BOM).lstrip()
    if text[:1] in (b"{", b"["):
        return "json-ld"
    if re.match(rb"<(\?xml|!--|!DOCTYPE|[A-Za-z_][\w.-]*(:[\w.-]+)?[\s/>])", text):
        return "xml"
    return "turtle"


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


class _RdflibLog(logging.Handler):
    """Takes every record of the ``rdflib`` loggers, so none reaches the terminal.

    While :func:`captured_rdflib_log` is active in a thread, that thread's records are kept for it;
    others are passed to skillwright's logger as one line each, their tracebacks dropped.
    """

    def __init__(self) -> None:
        super().__init__(logging.DEBUG)
        self.local = threading.local()

    def emit(self, record: logging.LogRecord) -> None:
        kept: list[logging.LogRecord] | None = getattr(self.local, "records", None)
        if kept is not None:
            kept.append(record)
        elif record.levelno >= logging.WARNING:
            logging.getLogger("skillwright.rdf").warning("rdflib: %s", _first_line(record))


def _first_line(record: logging.LogRecord) -> str:
    lines = record.getMessage().splitlines()
    return lines[0] if lines else record.levelname.lower()


_HANDLER = _RdflibLog()


def _install_handler() -> None:
    import rdflib  # its import may add a stream handler, replaced here

    logger = logging.getLogger(rdflib.__name__)
    if _HANDLER not in logger.handlers:
        for handler in list(logger.handlers):
            logger.removeHandler(handler)
        logger.addHandler(_HANDLER)
        logger.propagate = False


@contextmanager
def captured_rdflib_log() -> Iterator[list[logging.LogRecord]]:
    """Keeps the rdflib log records of this thread while the block runs (none reaches the
    terminal, in this thread or another)."""
    _install_handler()
    records: list[logging.LogRecord] = []
    outer = getattr(_HANDLER.local, "records", None)
    _HANDLER.local.records = records
    try:
        yield records
    finally:
        _HANDLER.local.records = outer


_PARSING = threading.Lock()
"""Held while a parser runs: catching warnings swaps process-wide state, so two threads
(the TUI's workers) must not do it at once."""


def _parse(data: bytes, fmt: str, path: Path, notes: list[str]) -> Graph:
    """Parses with one parser, literals kept in the lexical form the file writes (rdflib
    would rewrite an ill-typed ``"maybe"^^xsd:boolean`` as ``"false"``; values are the same
    either way). The Python warnings rdflib issues meanwhile go to ``notes``, except its
    deprecations and those about literals (:func:`_literal_warnings` reports each of these
    with its place); those of other code running meanwhile are issued again."""
    import rdflib

    graph = rdflib.Graph()
    with _PARSING, warnings.catch_warnings(record=True) as issued:
        warnings.simplefilter("always")
        normalize = rdflib.NORMALIZE_LITERALS
        rdflib.NORMALIZE_LITERALS = False
        try:
            graph.parse(data=data, format=fmt, publicID=path.resolve().as_uri())
        finally:
            rdflib.NORMALIZE_LITERALS = normalize
            ours = [w for w in issued if f"{os.sep}rdflib{os.sep}" in w.filename]
            others = [w for w in issued if w not in ours]
    for w in others:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    notes += [
        f"{path}: rdflib: {str(w.message).splitlines()[0]}"
        for w in ours
        if not issubclass(w.category, DeprecationWarning)
        and not w.filename.endswith(f"{os.sep}rdflib{os.sep}term.py")
        and str(w.message)
    ]
    return graph


def _syntax_error(error: Exception, data: bytes, fmt: str, path: Path) -> CapabilityError:
    """The message for a parser's failure, at the line and column when it says them."""
    from rdflib.plugins.parsers.notation3 import BadSyntax

    if isinstance(error, BadSyntax):
        line, column = _line_and_column(error._str, error._i)
        return CapabilityError(
            f"{path}:{line}:{column}: {SYNTAX_NAMES.get(fmt, fmt)} syntax error: {error._why}. "
            "Fix the file at that place (a missing '.', ';' or quote is the usual cause)."
        )
    if isinstance(error, UnicodeDecodeError):
        line, column = _line_and_column(data, error.start)
        return CapabilityError(
            f"{path}:{line}:{column}: not valid UTF-8 text; save the file as UTF-8"
        )
    position = ""
    get_line = getattr(error, "getLineNumber", None)
    get_column = getattr(error, "getColumnNumber", None)
    if callable(get_line) and callable(get_column):
        position = f"{get_line()}:{get_column()}:"
    detail = str(error).splitlines()[0] if str(error) else type(error).__name__
    return CapabilityError(
        f"{path}:{position} cannot be read as {fmt}: {detail}. "
        "Check the file's syntax, or give it a suffix that names its format "
        f"({', '.join(sorted(FORMATS))})."
    )


def _literal_line(data: bytes, literal: Literal) -> int | None:
    """The line where ``literal``'s text is first written, quoted as Turtle, N-Triples and
    JSON-LD write it or as RDF/XML element content; ``None`` when it cannot be found."""
    text = str(literal).encode("utf-8")
    for pattern in (b'"' + text + b'"', b"'" + text + b"'", b">" + text + b"<"):
        index = data.find(pattern)
        if index >= 0:
            return _line_and_column(data, index)[0]
    return None


def _literal_warnings(graph: Graph, data: bytes, path: Path) -> list[str]:
    from rdflib import Literal, URIRef

    def named(term: object) -> str:
        return f"<{term}>" if isinstance(term, URIRef) else "a blank node"

    ill_typed = sorted(
        {o for o in graph.objects() if isinstance(o, Literal) and o.ill_typed},
        key=lambda o: (str(o.datatype), str(o)),
    )
    found = []
    for literal in ill_typed:
        datatype = str(literal.datatype)
        name = "xsd:" + datatype[len(_XSD) :] if datatype.startswith(_XSD) else f"<{datatype}>"
        line = _literal_line(data, literal)
        where = f"{path}:{line}" if line is not None else str(path)
        subject, predicate = sorted(graph.subject_predicates(literal), key=str)[0]
        found.append(
            f'{where}: literal "{literal}"^^{name} (the {named(predicate)} of '
            f"{named(subject)}) is not a valid {name}; it is read as the text it is"
        )
    return found


def parse_graph(path: Path, what: str = "capability file") -> ParsedGraph:
    """Parses ``path`` into a new graph, in the syntax its suffix names or else its content.

    Raises :class:`CapabilityError` with ``file:line:column`` for syntax errors, and the
    input-file errors for missing or unreadable files. Nothing is fetched: ``owl:imports``
    stay unresolved triples. rdflib's log records never reach the terminal; the warnings
    say what they were about (see the module docstring).
    """
    data = _read_bytes(path, what)
    by_suffix = guess_format(path)
    by_content = sniff_format(data)
    notes: list[str] = []
    with captured_rdflib_log() as records:
        try:
            graph = _parse(data, by_suffix, path, notes)
            syntax = by_suffix
        except Exception as error:  # rdflib's parsers raise many unrelated types
            suffix_error = _syntax_error(error, data, by_suffix, path)
            notes.clear()  # what the failed parser said is not about the graph read
            records.clear()
            if by_content == by_suffix or (by_suffix in ("n3", "trig") and by_content == "turtle"):
                raise suffix_error from None
            try:
                graph = _parse(data, by_content, path, notes)
            except Exception as content_error:  # as above
                message = str(_syntax_error(content_error, data, by_content, path))
                raise CapabilityError(
                    f"{message} (read as {SYNTAX_NAMES[by_content]}, which its content looks "
                    f"like; as {SYNTAX_NAMES[by_suffix]}, which its suffix names, it fails too)"
                ) from None
            syntax = by_content
            suffix = path.suffix.lower()
            told = (
                f"its suffix {path.suffix} names {SYNTAX_NAMES[by_suffix]}"
                if suffix in FORMATS
                else f"read as {SYNTAX_NAMES[by_suffix]}, the default, it fails"
            )
            notes.append(
                f"{path}: read as {SYNTAX_NAMES[by_content]}, which its content is; {told}"
            )
    notes += _literal_warnings(graph, data, path)
    for record in records:
        if record.levelno >= logging.WARNING and "Failed to convert Literal" not in (
            record.getMessage()
        ):
            notes.append(f"{path}: rdflib: {_first_line(record)}")
    return ParsedGraph(graph=graph, syntax=syntax, warnings=notes)
