"""Models in each generation's vocabulary read alike: the capability, its inputs and outputs.

Every model here is our own, written in the terms one ontology version defines (see
:mod:`skillwright.capability.terms` for where each comes from).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.capability import load_capability
from skillwright.capability.terms import INPUT_PROPERTIES, OUTPUT_PROPERTIES, closure, short

HEAD = """\
@prefix ex: <http://example.org/cell#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix CSS: <http://www.w3id.org/hsu-aut/css#> .
@prefix CaSk: <http://www.w3id.org/hsu-aut/cask#> .
@prefix VDI3682: <http://www.w3id.org/hsu-aut/VDI3682#> .
@prefix VDI2206: <http://www.w3id.org/hsu-aut/VDI2206#> .
@prefix DIN: <http://www.w3id.org/hsu-aut/DINEN61360#> .
@prefix Cap19: <http://www.hsu-ifa.de/ontologies/capability-model#> .
@prefix VDI3682old: <http://www.hsu-ifa.de/ontologies/VDI3682#> .
@prefix VDI2206old: <http://www.hsu-ifa.de/ontologies/VDI2206#> .
@prefix DINold: <http://www.hsu-ifa.de/ontologies/DINEN61360#> .
"""


def model(capability_class: str, input_link: str, output_link: str, din: str, state: str) -> str:
    """A drilling capability: a depth (in mm, a DIN EN 61360 Real) goes in, a part comes out."""
    return (
        HEAD
        + f"""
ex:drill a {capability_class} ; rdfs:comment "Drills a hole." ;
    {input_link} ex:depth ;
    {output_link} ex:drilledPart .
ex:depth a {state}Information ; {din}has_Data_Element ex:depth_DE .
ex:depth_DE a {din}Data_Element ;
    {din}has_Type_Description ex:depth_TD ;
    {din}has_Instance_Description ex:depth_ID .
ex:depth_TD a {din}Type_Description ; {din}Unit_of_Measure "mm" ; {din}Definition "Hole depth" .
ex:depth_ID a {din}Instance_Description , {din}Real ;
    {din}Expression_Goal "Requirement" ; {din}Logic_Interpretation "<=" ; {din}Value 40 .
ex:drilledPart a {state}Product .
"""
    )


# (variant, capability class, input link, output link, DIN prefix, state-class prefix)
VARIANTS = [
    ("CaSk 3 with VDI 3682 4", "CaSk:ProvidedCapability", "VDI3682:hasInput", "VDI3682:hasOutput", "DIN:", "VDI3682:"),
    ("CSS links", "CSS:Capability", "CSS:hasInput", "CSS:hasOutput", "DIN:", "VDI3682:"),
    ("CSS links, DIN EN 61360 of hsu-ifa", "CSS:Capability", "CSS:hasInput", "CSS:hasOutput", "DINold:", "VDI3682:"),
    ("the capability model of hsu-ifa", "Cap19:ProvidedCapability", "VDI3682old:hasInput", "VDI3682old:hasOutput", "DINold:", "VDI3682old:"),
    ("VDI 2206 links of hsu-ifa", "Cap19:Capability", "VDI2206old:hasInput", "VDI2206old:hasOutput", "DINold:", "VDI2206old:"),
    ("VDI 2206 links of w3id", "CaSk:ProvidedCapability", "VDI3682:hasInput", "VDI2206:hasOutput", "DIN:", "VDI2206:"),
    ("parallel and alternative links", "Cap19:RequiredCapability", "VDI3682old:hasParallelInput", "VDI3682old:hasAlternativeOutput", "DINold:", "VDI3682old:"),
]  # fmt: skip


@pytest.mark.parametrize(
    ("capability_class", "input_link", "output_link", "din", "state"),
    [v[1:] for v in VARIANTS],
    ids=[v[0] for v in VARIANTS],
)
def test_each_vocabulary_variant_gives_the_capability_its_input_and_output(
    tmp_path: Path, capability_class: str, input_link: str, output_link: str, din: str, state: str
) -> None:
    path = tmp_path / "drill.ttl"
    path.write_text(model(capability_class, input_link, output_link, din, state), encoding="utf-8")
    load = load_capability(path)
    capability = load.capability
    assert capability.name == "drill"
    assert [p.name for p in capability.inputs] == ["depth"]
    assert [p.name for p in capability.outputs] == ["drilledPart"]
    depth = capability.inputs[0]
    assert depth.kind == "Information"
    assert capability.outputs[0].kind == "Product"
    assert depth.element.describe() == "Real [mm] <= 40 (Requirement)"
    assert depth.element.definition == "Hole depth"
    assert load.warnings == []


def test_a_merged_model_of_the_older_namespaces_offers_every_capability(tmp_path: Path) -> None:
    """One file, ten capabilities typed in the capability model CaSk replaced, as RDF/XML."""
    individuals = "".join(
        f"""
  <rdf:Description rdf:about="http://example.org/line#station{i}">
    <rdf:type rdf:resource="http://www.hsu-ifa.de/ontologies/capability-model#ProvidedCapability"/>
    <{"VDI2206" if i % 2 else "VDI3682"}:hasInput rdf:resource="http://example.org/line#in{i}"/>
    <{"VDI2206" if i % 2 else "VDI3682"}:hasOutput rdf:resource="http://example.org/line#out{i}"/>
  </rdf:Description>"""
        for i in range(10)
    )
    path = tmp_path / "line.owl"
    path.write_text(
        f"""<?xml version="1.0"?>
<rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#"
         xmlns:VDI2206="http://www.hsu-ifa.de/ontologies/VDI2206#"
         xmlns:VDI3682="http://www.hsu-ifa.de/ontologies/VDI3682#">{individuals}
</rdf:RDF>
""",
        encoding="utf-8",
    )
    for i in range(10):
        capability = load_capability(path, capability_iri=f"station{i}").capability
        assert [p.name for p in capability.inputs] == [f"in{i}"]
        assert [p.name for p in capability.outputs] == [f"out{i}"]
    load = load_capability(path, capability_iri="station0")
    assert len(load.choices) == 10


def test_a_property_the_model_declares_a_sub_property_of_an_input_link_is_read(
    tmp_path: Path,
) -> None:
    path = tmp_path / "cap.ttl"
    path.write_text(
        HEAD
        + """
ex:hasSetpoint rdfs:subPropertyOf VDI3682:hasInput .
ex:yields owl:equivalentProperty CSS:hasOutput .
ex:heat a CaSk:ProvidedCapability ; rdfs:comment "Heats." ;
    ex:hasSetpoint ex:temperature ; ex:yields ex:warmPart .
""",
        encoding="utf-8",
    )
    capability = load_capability(path).capability
    assert [p.name for p in capability.inputs] == ["temperature"]
    assert [p.name for p in capability.outputs] == ["warmPart"]


def test_an_ontology_given_with_ontology_can_declare_the_links_and_the_class(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("SKILLWRIGHT_CACHE_DIR", str(tmp_path / "cache"))
    ontology = tmp_path / "plant.ttl"
    ontology.write_text(
        HEAD
        + """
<http://example.org/plant> a owl:Ontology .
ex:Skillful owl:equivalentClass CSS:Capability .
ex:consumes owl:equivalentProperty VDI3682:hasInput .
""",
        encoding="utf-8",
    )
    path = tmp_path / "cap.ttl"
    path.write_text(
        HEAD + 'ex:mix a ex:Skillful ; rdfs:comment "Mixes." ; ex:consumes ex:water .\n',
        encoding="utf-8",
    )
    for _ in range(2):  # parsed, then from the cache
        load = load_capability(path, ontologies=[ontology])
        assert load.capability.kinds == ["http://example.org/cell#Skillful"]
        assert [p.name for p in load.capability.inputs] == ["water"]


def test_a_capability_without_inputs_or_outputs_is_told_which_properties_were_looked_for(
    tmp_path: Path,
) -> None:
    path = tmp_path / "cap.ttl"
    path.write_text(
        HEAD
        + """
ex:hasInputs a owl:ObjectProperty .
ex:idle a CaSk:ProvidedCapability ; rdfs:comment "Waits." ; ex:hasInputs ex:signal .
""",
        encoding="utf-8",
    )
    warnings = load_capability(path).warnings
    inputs, outputs = (
        next(w for w in warnings if w.startswith(f"capability <http://example.org/cell#idle> has no {d}s:"))
        for d in ("input", "output")
    )  # fmt: skip
    for warning, looked_for in ((inputs, INPUT_PROPERTIES), (outputs, OUTPUT_PROPERTIES)):
        for iri in looked_for:
            assert (short(iri) if short(iri) != iri else f"<{iri}>") in warning
    assert (
        "VDI3682:hasInput, CSS:hasInput, <http://www.hsu-ifa.de/ontologies/VDI3682#hasInput>"
        in inputs
    )
    # A link whose name says input, in a vocabulary that does not define it as one:
    assert "<http://example.org/cell#hasInputs> links are not inputs" in inputs
    assert "hasInputs" not in outputs


@pytest.mark.parametrize(
    ("axioms", "expected"),
    [
        ([], {"a"}),
        ([("b", "sub", "a"), ("c", "sub", "b")], {"a", "b", "c"}),
        ([("a", "same", "d"), ("e", "sub", "d")], {"a", "d", "e"}),
        ([("a", "sub", "f")], {"a"}),  # a broader term is not an input link
    ],
)
def test_closure_takes_specialisations_and_equivalents_only(
    axioms: list[tuple[str, str, str]], expected: set[str]
) -> None:
    assert closure(["a"], axioms) == expected
