"""Reading capability models: the paper's nine, our own, and every kind of bad input."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest

from skillwright.capability import Capability, load_capability
from skillwright.errors import (
    CapabilityError,
    CapabilitySelectionError,
    InputFileError,
    InputFileNotFoundError,
    OperationCancelledError,
)
from tests.conftest import SHIPPED_CAPABILITIES

PREFIXES = """\
@prefix ex: <http://example.org/robot/> .
@prefix CSS: <http://www.w3id.org/hsu-aut/css#> .
@prefix CaSk: <http://www.w3id.org/hsu-aut/cask#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
@prefix VDI3682: <http://www.w3id.org/hsu-aut/VDI3682#> .
@prefix DINEN61360: <http://www.w3id.org/hsu-aut/DINEN61360#> .
@prefix openmath: <http://openmath.org/vocab/math#> .
"""

# name -> (inputs, outputs, constraint texts) as the paper's models state them
PAPER_MODELS = {
    "collision-avoidance": (
        ["inObstacleDistance", "inTime", "inVelocity"],
        ["outObstacleDegree", "outObstacleDistance", "outTime", "outVelocity"],
        ["outTime <= inTime"],
    ),
    "get-distance-to-nearest-object": ([], ["outDegree", "outDistance"], []),
    "get-position": ([], ["outPosition"], ["positionX = outPositionX", "positionY = outPositionY"]),
    "mapping": (["inDistance"], ["outMap"], []),
    "move-forward": (
        ["inDistance", "inTime"],
        ["outDistance", "outTime", "outVelocity"],
        ["inDistance = outDistance", "inTime = outTime"],
    ),
    "move-to-point": (
        ["inPosition"],
        ["outPosition"],
        ["inPositionX = outPositionX", "inPositionY = outPositionY", "inPositionZ = outPositionZ"],
    ),
    "navigate-to-point": (
        ["inPosition"],
        ["outPosition"],
        ["inPositionX = outPositionX", "inPositionY = outPositionY"],
    ),
    "rotate": (
        ["inDegree", "inVelocity"],
        ["outDegree", "outVelocity"],
        ["outDegree = (inDegree + degree) mod 360"],
    ),
    "set-velocity": (["inVelocity"], ["outVelocity"], ["inVelocity = outVelocity"]),
}


def write(tmp_path: Path, body: str, name: str = "cap.ttl") -> Path:
    path = tmp_path / name
    path.write_text(PREFIXES + body, encoding="utf-8")
    return path


def load_paper(shared_data: Path, name: str) -> Capability:
    path = shared_data / "cap2skill" / "capability-models" / f"{name}.ttl"
    return load_capability(path).capability


@pytest.mark.parametrize("name", sorted(PAPER_MODELS))
def test_each_paper_model_loads_with_its_parameters_and_constraints(
    shared_data: Path, name: str
) -> None:
    capability = load_paper(shared_data, name)
    inputs, outputs, constraints = PAPER_MODELS[name]
    assert [p.name for p in capability.inputs] == inputs
    assert [p.name for p in capability.outputs] == outputs
    assert [c.text for c in capability.constraints] == constraints
    assert capability.kinds == ["CaSk:ProvidedCapability"]
    assert capability.comment
    assert capability.comment.startswith("I am a")
    assert capability.resource is not None
    for parameter in (*capability.inputs, *capability.outputs):
        for component in parameter.components:
            assert component.data_type in {"Real", "String"}, parameter.name


def test_move_forward_has_units_types_constraints_and_the_velocity_limit(
    shared_data: Path,
) -> None:
    capability = load_paper(shared_data, "move-forward")
    assert capability.name == "moveForward"
    assert capability.label == "Move forward"
    assert capability.iri.endswith("/capabilities/moveForward/moveForward")
    units = {p.name: (p.element.unit, p.element.data_type) for p in capability.inputs}
    assert units == {"inDistance": ("m", "Real"), "inTime": ("s", "Real")}
    velocity = capability.outputs[2]
    assert (velocity.element.unit, velocity.element.value) == ("m/s", 0.0)
    assert velocity.element.expression_goal == "Assurance"
    assert [c.relation for c in capability.constraints] == ["=", "="]
    refs = [a.refers_to for a in capability.constraints[0].expression.arguments]
    assert refs == [capability.inputs[0].element.iri, capability.outputs[0].element.iri]
    assert capability.resource is not None
    assert capability.resource.name == "neobotixMMO700"
    limits = [limit for p in capability.resource.properties for limit in p.limits()]
    assert limits == ["velocity <= 0.8 m/s"]


def test_rotate_constraint_keeps_its_nested_applications(shared_data: Path) -> None:
    constraint = load_paper(shared_data, "rotate").constraints[0]
    outer = constraint.expression
    assert outer.operator == "http://www.openmath.org/cd/relation1#eq"
    modulo = outer.arguments[1]
    assert modulo.operator == "http://www.openmath.org/cd/arith1#mod"
    assert [a.kind for a in modulo.arguments] == ["application", "literal"]
    assert modulo.arguments[1].text == "360"


def test_get_position_output_has_x_and_y_components(shared_data: Path) -> None:
    output = load_paper(shared_data, "get-position").outputs[0]
    assert [c.name for c in output.components] == ["outPositionX", "outPositionY"]
    assert all(c.unit == "m" for c in output.components)


def test_collision_avoidance_minimum_distance_is_a_requirement_input(shared_data: Path) -> None:
    capability = load_paper(shared_data, "collision-avoidance")
    distance = capability.inputs[0].element
    assert (distance.unit, distance.expression_goal, distance.value) == ("m", "Requirement", None)


@pytest.mark.parametrize("path", sorted(SHIPPED_CAPABILITIES.glob("*.ttl")), ids=lambda p: p.stem)
def test_each_shipped_model_loads_cleanly(path: Path) -> None:
    load = load_capability(path)
    capability = load.capability
    no_inputs = f"capability <{capability.iri}> has no inputs: "
    rest = [w for w in load.warnings if "owl:imports" not in w and not w.startswith(no_inputs)]
    assert rest == []
    # The two that only read a sensor have no inputs, and are told so.
    told = any(w.startswith(no_inputs) for w in load.warnings)
    assert told == (not PAPER_MODELS[path.stem][0])
    assert capability.comment
    assert capability.outputs
    for parameter in (*capability.inputs, *capability.outputs):
        for component in parameter.components:
            assert component.unit, (path.name, component.name)
            assert component.data_type, (path.name, component.name)


def test_shipped_models_cover_the_nine_paper_capabilities() -> None:
    assert {p.stem for p in SHIPPED_CAPABILITIES.glob("*.ttl")} == set(PAPER_MODELS)


def test_missing_file_is_reported_by_path(tmp_path: Path) -> None:
    with pytest.raises(InputFileNotFoundError, match=r"capability file .*nope\.ttl: no such file"):
        load_capability(tmp_path / "nope.ttl")


def test_folder_is_rejected(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match="is a folder"):
        load_capability(tmp_path)


def test_turtle_syntax_error_names_line_and_column(tmp_path: Path) -> None:
    path = write(tmp_path, 'ex:cap a CaSk:ProvidedCapability ;\n    rdfs:comment "open .\n')
    line = PREFIXES.count("\n") + 2
    with pytest.raises(CapabilityError, match=rf"cap\.ttl:{line}:\d+: Turtle syntax error"):
        load_capability(path)


def test_non_utf8_file_is_reported(tmp_path: Path) -> None:
    path = tmp_path / "latin1.ttl"
    path.write_bytes(PREFIXES.encode() + 'ex:a rdfs:comment "Gr\xfc\xdfe" .\n'.encode("latin-1"))
    with pytest.raises(CapabilityError, match=r"latin1\.ttl"):
        load_capability(path)


def test_file_without_capability_says_what_it_looked_for(tmp_path: Path) -> None:
    path = write(tmp_path, "ex:thing a VDI3682:ProcessOperator .\n")
    with pytest.raises(CapabilityError, match=r"no capability found.*CaSk:ProvidedCapability"):
        load_capability(path)


TWO_CAPABILITIES = """
ex:drive a CaSk:ProvidedCapability ; rdfs:comment "Drives." .
ex:grip a CSS:Capability ; rdfs:comment "Grips." .
"""


def test_several_capabilities_are_listed_and_one_must_be_chosen(tmp_path: Path) -> None:
    path = write(tmp_path, TWO_CAPABILITIES)
    with pytest.raises(CapabilityError, match="holds 2 capabilities") as info:
        load_capability(path)
    message = str(info.value)
    assert "http://example.org/robot/drive" in message
    assert "http://example.org/robot/grip" in message
    assert "--capability" in message


@pytest.mark.parametrize("wanted", ["http://example.org/robot/grip", "grip"])
def test_capability_option_selects_by_iri_or_local_name(tmp_path: Path, wanted: str) -> None:
    load = load_capability(write(tmp_path, TWO_CAPABILITIES), capability_iri=wanted)
    assert load.capability.name == "grip"
    assert load.capability.kinds == ["CSS:Capability"]
    assert load.others == ["http://example.org/robot/drive"]


def test_unknown_selection_lists_the_capabilities(tmp_path: Path) -> None:
    path = write(tmp_path, TWO_CAPABILITIES)
    with pytest.raises(CapabilityError, match="is not one of the capabilities"):
        load_capability(path, capability_iri="weld")


def test_missing_comment_is_a_warning_not_an_error(tmp_path: Path) -> None:
    load = load_capability(write(tmp_path, "ex:cap a CaSk:RequiredCapability .\n"))
    assert load.capability.comment is None
    assert any("no rdfs:comment" in w for w in load.warnings)


def test_dangling_references_are_warnings(tmp_path: Path) -> None:
    body = """
ex:cap a CaSk:ProvidedCapability ; rdfs:comment "c" ;
    VDI3682:hasInput ex:ghostInput ;
    CSS:isRestrictedBy ex:limit .
ex:limit a openmath:Application ;
    openmath:operator <http://www.openmath.org/cd/relation1#leq> ;
    openmath:arguments ( ex:ghostInput ex:nowhere_ID ) .
"""
    load = load_capability(write(tmp_path, body))
    assert load.capability.inputs[0].name == "ghostInput"
    assert load.capability.constraints[0].text == "ghostInput <= nowhere"
    assert any("input <http://example.org/robot/ghostInput>" in w for w in load.warnings)
    assert any("refers to <http://example.org/robot/nowhere_ID>" in w for w in load.warnings)


def test_owl_imports_are_never_fetched_and_said_once(tmp_path: Path) -> None:
    body = """
<http://example.org/robot> a owl:Ontology ;
    owl:imports <http://example.org/a>, <http://example.org/b> .
ex:cap a CaSk:ProvidedCapability ; rdfs:comment "c" .
"""
    load = load_capability(write(tmp_path, body))
    notes = [w for w in load.warnings if "owl:imports" in w]
    assert len(notes) == 1
    assert "<http://example.org/a>" in notes[0]
    assert "<http://example.org/b>" in notes[0]


def test_cyclic_argument_list_is_an_error_not_a_hang(tmp_path: Path) -> None:
    body = """
ex:cap a CaSk:ProvidedCapability ; rdfs:comment "c" ; CSS:isRestrictedBy ex:loop .
ex:loop a openmath:Application ;
    openmath:operator <http://www.openmath.org/cd/relation1#eq> ;
    openmath:arguments ( ex:loop ) .
"""
    with pytest.raises(CapabilityError, match="nests deeper than 32"):
        load_capability(write(tmp_path, body))


def test_rdf_xml_files_are_read_too(tmp_path: Path) -> None:
    path = tmp_path / "cap.owl"
    path.write_text(
        """<?xml version="1.0"?>
<rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#"
         xmlns:rdfs="http://www.w3.org/2000/01/rdf-schema#">
  <rdf:Description rdf:about="http://example.org/robot/weld">
    <rdf:type rdf:resource="http://www.w3id.org/hsu-aut/cask#ProvidedCapability"/>
    <rdfs:comment>Welds.</rdfs:comment>
  </rdf:Description>
</rdf:RDF>
""",
        encoding="utf-8",
    )
    assert load_capability(path).capability.comment == "Welds."


def test_broken_rdf_xml_names_line_and_column(tmp_path: Path) -> None:
    path = tmp_path / "cap.owl"
    path.write_text('<?xml version="1.0"?>\n<rdf:RDF>\n  <oops\n</rdf:RDF>\n', encoding="utf-8")
    with pytest.raises(CapabilityError, match=r"cap\.owl:\d+:\d+: cannot be read as xml"):
        load_capability(path)


ONTOLOGY = (
    PREFIXES
    + """
<http://example.org/robot-ontology> a owl:Ontology .
ex:WeldingCapability rdfs:subClassOf CaSk:ProvidedCapability .
"""
)


def test_subclass_from_a_local_ontology_is_recognised_and_cached(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("SKILLWRIGHT_CACHE_DIR", str(tmp_path / "cache"))
    ontology = tmp_path / "robot-ontology.ttl"
    ontology.write_text(ONTOLOGY, encoding="utf-8")
    body = """
<http://example.org/robot/model> a owl:Ontology ; owl:imports <http://example.org/robot-ontology> .
ex:weld a ex:WeldingCapability ; rdfs:comment "Welds." .
"""
    path = write(tmp_path, body)
    with pytest.raises(CapabilityError, match="no capability found"):
        load_capability(path)

    load = load_capability(path, ontologies=[ontology])
    assert load.capability.kinds == ["http://example.org/robot/WeldingCapability"]
    assert not any("owl:imports" in w for w in load.warnings)
    cached = list((tmp_path / "cache" / "ontologies").glob("*.nt"))
    assert len(cached) == 1

    cached[0].write_text("this is < not n-triples", encoding="utf-8")
    again = load_capability(path, ontologies=[ontology])
    assert again.capability.name == "weld"
    assert "WeldingCapability" in cached[0].read_text(encoding="utf-8")


def test_cask_ontology_alongside_a_model_loads(
    shared_data: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("SKILLWRIGHT_CACHE_DIR", str(tmp_path / "cache"))
    model = shared_data / "cap2skill" / "capability-models" / "move-forward.ttl"
    cask = shared_data / "ontologies" / "cask.ttl"
    load = load_capability(model, ontologies=[cask])
    assert load.capability.name == "moveForward"
    # the model imports CaSk 2.5.4; the file given is CaSk 3.0.1, so that import stays open
    assert any("cask/2.5.4" in w for w in load.warnings)


def test_a_cancelled_read_stops_before_parsing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.capability import reader

    parsed: list[Path] = []
    monkeypatch.setattr(reader, "parse_graph", parsed.append)
    cancel = threading.Event()
    cancel.set()
    with pytest.raises(OperationCancelledError, match="cancelled"):
        load_capability(write(tmp_path, TWO_CAPABILITIES), cancel=cancel)
    assert parsed == []


def test_cancel_during_parsing_stops_before_the_ontologies_are_read(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.capability import reader, vocabulary

    monkeypatch.setenv("SKILLWRIGHT_CACHE_DIR", str(tmp_path / "cache"))
    ontology = tmp_path / "robot-ontology.ttl"
    ontology.write_text(ONTOLOGY, encoding="utf-8")
    cancel = threading.Event()
    real_parse = reader.parse_graph

    def parse_then_cancel(path: Path) -> object:
        graph = real_parse(path)
        cancel.set()  # the user presses Esc while the file is being parsed
        return graph

    read: list[Path] = []
    monkeypatch.setattr(reader, "parse_graph", parse_then_cancel)
    monkeypatch.setattr(vocabulary, "_load_one", lambda path: read.append(path) or ([], []))
    with pytest.raises(OperationCancelledError):
        load_capability(write(tmp_path, TWO_CAPABILITIES), ontologies=[ontology], cancel=cancel)
    assert read == []


def test_the_vocabulary_stops_between_ontology_files(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.capability import vocabulary

    cancel = threading.Event()
    read: list[Path] = []

    def load_one(path: Path) -> tuple[list[object], list[str]]:
        read.append(path)
        cancel.set()
        return [], []

    monkeypatch.setattr(vocabulary, "_load_one", load_one)
    with pytest.raises(OperationCancelledError, match="reading the ontologies cancelled"):
        vocabulary.load_vocabulary([tmp_path / "a.ttl", tmp_path / "b.ttl"], cancel=cancel)
    assert read == [tmp_path / "a.ttl"]


def test_a_file_with_several_capabilities_offers_them_to_choose_from(tmp_path: Path) -> None:
    path = write(tmp_path, TWO_CAPABILITIES)
    with pytest.raises(CapabilitySelectionError) as info:
        load_capability(path)
    expected = [
        ("http://example.org/robot/drive", "drive", "Drive"),
        ("http://example.org/robot/grip", "grip", "Grip"),
    ]
    assert [(c.iri, c.name, c.label) for c in info.value.choices] == expected
    with pytest.raises(CapabilitySelectionError, match="is not one of") as again:
        load_capability(path, capability_iri="weld")
    assert again.value.choices == info.value.choices
    load = load_capability(path, capability_iri="grip")
    assert load.choices == info.value.choices


def test_a_file_with_one_capability_offers_just_that_one(tmp_path: Path) -> None:
    load = load_capability(SHIPPED_CAPABILITIES / "rotate.ttl")
    assert [(c.name, c.label) for c in load.choices] == [("rotate", load.capability.label)]


def test_the_messages_say_how_the_caller_gives_an_ontology(tmp_path: Path) -> None:
    """The CLI gives a local ontology with --ontology FILE, the TUI from its ontologies
    folder: each message says it the caller's way."""
    body = """
<http://example.org/robot/model> a owl:Ontology ; owl:imports <http://example.org/robot-ontology> .
ex:weld a ex:WeldingCapability .
"""
    path = write(tmp_path, body)
    with pytest.raises(CapabilityError, match=r"in an ontology, given as --ontology FILE"):
        load_capability(path)
    with pytest.raises(CapabilityError, match=r"given as a file in /w/ontologies"):
        load_capability(path, ontology_hint="a file in /w/ontologies")
