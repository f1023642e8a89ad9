"""The class and property hierarchy of ontologies the user supplies with ``--ontology``.

Capability models import their ontologies (CaSk, CSS, ...) with ``owl:imports``, which
skillwright never fetches. A user can give local copies instead; from them we need only
the vocabulary (sub-class, sub-property and equivalence axioms, labels), not their thousands of
individuals. Parsing CaSk's 2.7 MB Turtle with rdflib takes seconds, so the vocabulary
part is cached as N-Triples keyed by the file's SHA-256 and reused on later runs.
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING

from skillwright.cancel import raise_if_cancelled
from skillwright.capability.rdf import captured_rdflib_log, parse_graph
from skillwright.fileio import write_atomic
from skillwright.paths import cache_dir

if TYPE_CHECKING:
    from rdflib import Graph

__all__ = ["Vocabulary", "load_vocabulary"]

# Bump when the choice of kept triples changes, so old cache entries are not reused.
_SUBSET_VERSION = "2"


class Vocabulary:
    """The vocabulary triples of the supplied ontologies, the ontology IRIs they declare
    and what parsing them had to warn about (nothing when read from the cache)."""

    def __init__(self, graph: Graph, ontology_iris: set[str], warnings: list[str]) -> None:
        self.graph = graph
        self.ontology_iris = ontology_iris
        self.warnings = warnings


def _subset(full: Graph) -> Graph:
    from rdflib import OWL, RDF, RDFS, Graph

    keep = {
        RDFS.subClassOf,
        RDFS.subPropertyOf,
        OWL.equivalentClass,
        OWL.equivalentProperty,
        RDFS.label,
        OWL.versionIRI,
    }
    subset = Graph()
    for triple in full:
        predicate = triple[1]
        if predicate in keep or (predicate == RDF.type and triple[2] == OWL.Ontology):
            subset.add(triple)
    return subset


def _load_one(path: Path) -> tuple[Graph, list[str]]:
    from rdflib import Graph

    from skillwright.core import sha256_file

    digest = sha256_file(path)
    cached = cache_dir() / "ontologies" / f"{digest}-v{_SUBSET_VERSION}.nt"
    if cached.is_file():
        graph = Graph()
        try:
            with captured_rdflib_log():
                graph.parse(cached, format="nt")
        except Exception:  # a damaged cache entry is rebuilt, never fatal
            cached.unlink(missing_ok=True)
        else:
            return graph, []
    parsed = parse_graph(path, what="ontology file")
    subset = _subset(parsed.graph)
    with contextlib.suppress(OSError):  # an unwritable cache only costs speed next time
        write_atomic(cached, subset.serialize(format="nt", encoding="utf-8"))
    return subset, parsed.warnings


def load_vocabulary(paths: Iterable[Path], *, cancel: threading.Event | None = None) -> Vocabulary:
    """Reads the vocabulary of each ontology file (cached after the first read).

    ``cancel`` is looked at before each file (see :mod:`skillwright.cancel`).
    """
    from rdflib import OWL, RDF, Graph

    merged = Graph()
    warnings: list[str] = []
    for path in paths:
        raise_if_cancelled(cancel, "reading the ontologies")
        graph, notes = _load_one(path)
        warnings += notes
        for triple in graph:
            merged.add(triple)
    iris = {str(s) for s in merged.subjects(RDF.type, OWL.Ontology)}
    iris |= {str(o) for o in merged.objects(None, OWL.versionIRI)}
    return Vocabulary(merged, iris, warnings)
