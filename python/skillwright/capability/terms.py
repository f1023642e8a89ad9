"""The terms the capability reader looks for, in every form the CaSk family has given them.

Capability models are written against the ontologies of their day, and those moved: the
ontology design patterns of VDI 3682, VDI 2206 and DIN EN 61360 were first published under
``http://www.hsu-ifa.de/ontologies/`` and later under ``http://www.w3id.org/hsu-aut/``
(CaSk 2.2.0 imports ``VDI3682.owl`` v3.0.1 and ``DINEN61360.owl`` v1.4.2 from the first,
CaSk 2.5 and 3.0 import ``VDI3682/4.0.1`` and ``DINEN61360/2.0.3`` from the second), and
CaSk itself replaced the *capability model* of ``http://www.hsu-ifa.de/ontologies/
capability-model#``. The local names stayed the same. Each tuple below lists the current
term first and then the earlier or equivalent ones, each with the ontology that defines it,
so a model of any generation reads alike.

Beyond these, the reader follows ``rdfs:subPropertyOf``, ``owl:equivalentProperty``,
``rdfs:subClassOf`` and ``owl:equivalentClass`` axioms that the model or an ``--ontology``
states about them (:func:`closure`).
"""

from __future__ import annotations

from collections.abc import Iterable

__all__ = [
    "CAPABILITY_CLASSES",
    "CASK",
    "CSS",
    "DIN",
    "DIN_NAMESPACES",
    "INPUT_PROPERTIES",
    "OM",
    "OUTPUT_PROPERTIES",
    "PREFIXES",
    "STATE_CLASSES",
    "VDI3682",
    "VDI3682_NAMESPACES",
    "closure",
    "short",
]

CSS = "http://www.w3id.org/hsu-aut/css#"
CASK = "http://www.w3id.org/hsu-aut/cask#"
VDI3682 = "http://www.w3id.org/hsu-aut/VDI3682#"
VDI2206 = "http://www.w3id.org/hsu-aut/VDI2206#"
DIN = "http://www.w3id.org/hsu-aut/DINEN61360#"
OM = "http://openmath.org/vocab/math#"

CAPABILITY_MODEL_HSU_IFA = "http://www.hsu-ifa.de/ontologies/capability-model#"
"""The capability model 1.0.0 (``capability-model/1.0.0#``) that CaSk replaced; it
defines the ``Capability``, ``ProvidedCapability`` and ``RequiredCapability`` classes that
CaSk took over."""
VDI3682_HSU_IFA = "http://www.hsu-ifa.de/ontologies/VDI3682#"
"""The VDI 3682 design pattern up to v3.0.1 (imported so by CaSk 2.2.0)."""
VDI2206_HSU_IFA = "http://www.hsu-ifa.de/ontologies/VDI2206#"
"""The VDI 2206 design pattern up to v1.4.2 (imported so by CaSk 2.2.0)."""
DIN_HSU_IFA = "http://www.hsu-ifa.de/ontologies/DINEN61360#"
"""The DIN EN 61360 design pattern up to v1.4.2 (imported so by CaSk 2.2.0)."""

CAPABILITY_CLASSES = (
    f"{CASK}ProvidedCapability",
    f"{CASK}RequiredCapability",
    f"{CSS}Capability",
    # The capability model that CaSk replaced defines the same three classes.
    f"{CAPABILITY_MODEL_HSU_IFA}ProvidedCapability",
    f"{CAPABILITY_MODEL_HSU_IFA}RequiredCapability",
    f"{CAPABILITY_MODEL_HSU_IFA}Capability",
)
"""Classes whose individuals are capabilities (subclasses are found by :func:`closure`)."""

INPUT_PROPERTIES = (
    # VDI 3682 (4.x): a process operator's input; CaSk 3 models use it on the capability.
    f"{VDI3682}hasInput",
    # CSS: a process's input; CaSk 2.2.0 declares VDI3682:hasInput owl:equivalentProperty
    # CSS:hasInput, so a capability's CSS:hasInput is the same link.
    f"{CSS}hasInput",
    # VDI 3682 up to v3.0.1, and its sub-properties for alternative and parallel inputs.
    f"{VDI3682_HSU_IFA}hasInput",
    f"{VDI3682_HSU_IFA}hasAlternativeInput",
    f"{VDI3682_HSU_IFA}hasParallelInput",
    # VDI 2206: CaSk 2.2.0 declares VDI2206:hasInput owl:equivalentProperty VDI3682:hasInput;
    # the pattern moved to w3id.org/hsu-aut with VDI 3682 (CaSk 2.5 imports VDI2206/2.0.0).
    f"{VDI2206_HSU_IFA}hasInput",
    f"{VDI2206}hasInput",
)
"""Properties that link a capability to an input, the current one first."""

OUTPUT_PROPERTIES = (
    f"{VDI3682}hasOutput",
    # CaSk 2.2.0: VDI3682:hasOutput owl:equivalentProperty CSS:hasOutput.
    f"{CSS}hasOutput",
    f"{VDI3682_HSU_IFA}hasOutput",
    f"{VDI3682_HSU_IFA}hasAlternativeOutput",
    f"{VDI3682_HSU_IFA}hasParallelOutput",
    # CaSk 2.2.0: VDI2206:hasOutput owl:equivalentProperty VDI3682:hasOutput.
    f"{VDI2206_HSU_IFA}hasOutput",
    f"{VDI2206}hasOutput",
)
"""Properties that link a capability to an output, the current one first."""

VDI3682_NAMESPACES = (VDI3682, VDI3682_HSU_IFA)
"""Namespaces of VDI 3682's ``isCharacterizedBy`` and its state classes."""

STATE_CLASSES = {
    f"{ns}{name}": name
    # VDI 3682's states; CaSk 3.0.1 (and 2.2.0 for the older namespace) declares VDI 2206's
    # Energy, Information and Product owl:equivalentClass VDI 3682's.
    for ns in (*VDI3682_NAMESPACES, VDI2206, VDI2206_HSU_IFA)
    for name in ("Product", "Information", "Energy")
} | {
    # CaSk 3.0.1: VDI2206:Product owl:equivalentClass VDI3682:Product, CSS:Product.
    f"{CSS}Product": "Product"
}
"""Classes of an input or output -> its VDI 3682 kind (Product, Information or Energy)."""

DIN_NAMESPACES = (DIN, DIN_HSU_IFA)
"""Namespaces of the DIN EN 61360 data element properties and data type classes."""

PREFIXES = {
    CSS: "CSS:",
    CASK: "CaSk:",
    VDI3682: "VDI3682:",
    VDI2206: "VDI2206:",
    DIN: "DINEN61360:",
    OM: "openmath:",
}
"""Namespaces shown by their usual prefix; terms of the older namespaces stay full IRIs."""


def short(iri: str) -> str:
    """``http://www.w3id.org/hsu-aut/css#Capability`` -> ``CSS:Capability``; other IRIs
    as they are."""
    for namespace, prefix in PREFIXES.items():
        if iri.startswith(namespace):
            return prefix + iri[len(namespace) :]
    return iri


def closure(terms: Iterable[str], axioms: Iterable[tuple[str, str, str]]) -> set[str]:
    """``terms`` and every term the axioms make a specialisation or an equivalent of one.

    ``axioms`` are ``(subject, relation, object)`` with relation ``sub`` (subject is a
    sub-class or sub-property of object) or ``same`` (the two are equivalent, either way).
    """
    found = set(terms)
    edges: list[tuple[str, str]] = []
    for subject, relation, obj in axioms:
        edges.append((subject, obj))
        if relation == "same":
            edges.append((obj, subject))
    changed = True
    while changed:
        changed = False
        for narrower, broader in edges:
            if broader in found and narrower not in found:
                found.add(narrower)
                changed = True
    return found
