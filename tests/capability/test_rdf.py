"""Parsing RDF: the syntax by suffix or content, ill-typed literals, rdflib's log kept quiet."""

from __future__ import annotations

import json
import logging
import subprocess
import sys
from pathlib import Path

import pytest

from skillwright.capability import load_capability
from skillwright.capability.rdf import captured_rdflib_log, parse_graph, sniff_format
from skillwright.errors import CapabilityError

TURTLE = """\
@prefix CaSk: <http://www.w3id.org/hsu-aut/cask#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
<http://example.org/weld> a CaSk:ProvidedCapability ; rdfs:comment "Welds." .
"""

RDF_XML = """<?xml version="1.0"?>
<rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#"
         xmlns:rdfs="http://www.w3.org/2000/01/rdf-schema#">
  <rdf:Description rdf:about="http://example.org/weld">
    <rdf:type rdf:resource="http://www.w3id.org/hsu-aut/cask#ProvidedCapability"/>
    <rdfs:comment>Welds.</rdfs:comment>
  </rdf:Description>
</rdf:RDF>
"""

JSON_LD = json.dumps(
    {
        "@id": "http://example.org/weld",
        "@type": "http://www.w3id.org/hsu-aut/cask#ProvidedCapability",
        "http://www.w3.org/2000/01/rdf-schema#comment": "Welds.",
    }
)


@pytest.mark.parametrize(
    ("data", "expected"),
    [
        (TURTLE, "turtle"),
        ("# a comment\n<http://a> <http://b> <http://c> .\n", "turtle"),
        ("PREFIX ex: <http://example.org/>\nex:a ex:b ex:c .\n", "turtle"),
        (RDF_XML, "xml"),
        ("\ufeff<rdf:RDF xmlns:rdf='http://www.w3.org/1999/02/22-rdf-syntax-ns#'/>", "xml"),
        ("<!-- saved by an editor -->\n<rdf:RDF/>", "xml"),
        (JSON_LD, "json-ld"),
        ("  [ {} ]", "json-ld"),
    ],
)
def test_the_content_tells_its_syntax(data: str, expected: str) -> None:
    assert sniff_format(data.encode("utf-8")) == expected


@pytest.mark.parametrize(
    ("name", "content", "told"),
    [
        ("model.owl", TURTLE, "read as Turtle, which its content is; its suffix .owl names RDF/XML"),
        ("model.ttl", RDF_XML, "read as RDF/XML, which its content is; its suffix .ttl names Turtle"),
        ("model.OWL", JSON_LD, "read as JSON-LD, which its content is; its suffix .OWL names RDF/XML"),
        ("model.nt", TURTLE, "read as Turtle, which its content is; its suffix .nt names N-Triples"),
        ("model.txt", RDF_XML, "read as RDF/XML, which its content is; read as Turtle, the default, it fails"),
    ],
)  # fmt: skip
def test_a_file_whose_suffix_names_another_syntax_is_read_by_its_content_and_says_so(
    tmp_path: Path, name: str, content: str, told: str
) -> None:
    path = tmp_path / name
    path.write_text(content, encoding="utf-8")
    load = load_capability(path)
    assert load.capability.comment == "Welds."
    assert [w for w in load.warnings if "read as" in w] == [f"{path}: {told}"]


def test_a_file_in_the_syntax_its_suffix_names_says_nothing_about_it(tmp_path: Path) -> None:
    path = tmp_path / "model.owl"
    path.write_text(RDF_XML, encoding="utf-8")
    parsed = parse_graph(path)
    assert (parsed.syntax, parsed.warnings) == ("xml", [])


def test_broken_turtle_in_an_owl_file_is_reported_as_turtle_at_its_line(tmp_path: Path) -> None:
    path = tmp_path / "model.owl"
    path.write_text(TURTLE + '<http://example.org/x> rdfs:comment "open .\n', encoding="utf-8")
    with pytest.raises(CapabilityError) as info:
        load_capability(path)
    message = str(info.value)
    assert message.startswith(f"{path}:4:")
    assert "Turtle syntax error" in message
    assert "as RDF/XML, which its suffix names, it fails too" in message
    assert "\n" not in message


ILL_TYPED = """\
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .
@prefix CaSk: <http://www.w3id.org/hsu-aut/cask#> .
@prefix VDI3682: <http://www.w3id.org/hsu-aut/VDI3682#> .
@prefix DINEN61360: <http://www.w3id.org/hsu-aut/DINEN61360#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
<http://example.org/add> a CaSk:ProvidedCapability ; rdfs:comment "Adds." ;
    VDI3682:hasInput <http://example.org/a> .
<http://example.org/a> DINEN61360:has_Data_Element <http://example.org/a_DE> .
<http://example.org/a_DE> DINEN61360:has_Instance_Description <http://example.org/a_ID> .
<http://example.org/a_ID> DINEN61360:Value "Value of A"^^xsd:int .
<http://example.org/b_ID> DINEN61360:Value "Value of A"^^xsd:int .
<http://example.org/c_ID> DINEN61360:Value "1.5e"^^xsd:double .
"""


def test_each_ill_typed_literal_is_one_warning_with_its_line_and_datatype(tmp_path: Path) -> None:
    path = tmp_path / "add.ttl"
    path.write_text(ILL_TYPED, encoding="utf-8")
    load = load_capability(path)
    literals = [w for w in load.warnings if "literal" in w]
    assert literals == [
        f'{path}:12: literal "1.5e"^^xsd:double (the <http://www.w3id.org/hsu-aut/DINEN61360#Value>'
        " of <http://example.org/c_ID>) is not a valid xsd:double; it is read as the text it is",
        f'{path}:10: literal "Value of A"^^xsd:int (the <http://www.w3id.org/hsu-aut/DINEN61360#Value>'
        " of <http://example.org/a_ID>) is not a valid xsd:int; it is read as the text it is",
    ]
    assert load.capability.inputs[0].element.value == "Value of A"


def test_an_ill_typed_literal_in_rdf_xml_is_found_at_its_line(tmp_path: Path) -> None:
    path = tmp_path / "m.owl"
    path.write_text(
        RDF_XML.replace(
            "<rdfs:comment>Welds.</rdfs:comment>",
            "<rdfs:comment>Welds.</rdfs:comment>\n    <rdfs:label rdf:datatype="
            '"http://www.w3.org/2001/XMLSchema#boolean">maybe</rdfs:label>',
        ),
        encoding="utf-8",
    )
    warnings = load_capability(path).warnings
    assert any(w.startswith(f'{path}:7: literal "maybe"^^xsd:boolean') for w in warnings)


def test_rdflib_records_are_kept_for_the_parse_and_never_printed(
    caplog: pytest.LogCaptureFixture, capfd: pytest.CaptureFixture[str]
) -> None:
    rdflib_log = logging.getLogger("rdflib.term")
    with captured_rdflib_log() as records:
        try:
            int("x")
        except ValueError:
            rdflib_log.warning("inside", exc_info=True)
    assert [r.getMessage() for r in records] == ["inside"]
    with caplog.at_level(logging.WARNING, logger="skillwright"):
        try:
            int("y")
        except ValueError:
            rdflib_log.warning("outside\nsecond line", exc_info=True)
    # (pytest's caplog also listens on non-propagating loggers such as rdflib's)
    ours = [r for r in caplog.records if r.name.startswith("skillwright")]
    assert [(r.name, r.getMessage(), r.exc_info) for r in ours] == [
        ("skillwright.rdf", "rdflib: outside", None)
    ]
    assert "Traceback" not in capfd.readouterr().err


def test_capability_show_prints_warnings_and_no_traceback(tmp_path: Path) -> None:
    path = tmp_path / "add.owl"
    path.write_text(ILL_TYPED, encoding="utf-8")
    result = subprocess.run(
        [sys.executable, "-m", "skillwright", "capability", "show", str(path)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
        env={"COLUMNS": "400", "PATH": "/usr/bin:/bin"},
    )
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr
    assert "Failed to convert" not in result.stderr
    lines = result.stderr.splitlines()
    assert lines[0] == (
        f"warning: {path}: read as Turtle, which its content is; its suffix .owl names RDF/XML"
    )
    assert sum('literal "Value of A"^^xsd:int' in line for line in lines) == 1
    assert sum('literal "1.5e"^^xsd:double' in line for line in lines) == 1
