"""The commands that take a capability, a spec and interfaces name them the same way."""

from __future__ import annotations

from pathlib import Path

import click
import pytest
from click.testing import CliRunner

from skillwright.cli import COMMANDS, main


@pytest.mark.parametrize("name", ["check", "retrieve", "generate"])
def test_capability_spec_and_interfaces_options_agree(name: str) -> None:
    assert name in COMMANDS
    command = main.get_command(click.Context(main), name)
    assert command is not None
    options = {p.name: p for p in command.params if isinstance(p, click.Option)}
    assert options["capability_file"].opts == ["--capability"]
    assert options["capability_iri"].opts == ["--capability-iri"]
    assert options["spec_file"].opts == ["--spec"]
    assert options["source"].opts == ["--interfaces"]
    assert options["capability_file"].required


def test_every_command_that_reads_a_capability_takes_its_ontologies(tmp_path: Path) -> None:
    """A model typed with a domain class declared in an imported ontology reads in
    retrieve (as in check, run, validate and generate) once --ontology gives the copy."""
    from tests.conftest import SHIPPED_CAPABILITIES

    ontology = tmp_path / "robot-ontology.ttl"
    ontology.write_text(
        "@prefix ex: <http://example.org/robot/> .\n"
        "@prefix CaSk: <http://www.w3id.org/hsu-aut/cask#> .\n"
        "@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .\n"
        "ex:DriveCapability rdfs:subClassOf CaSk:ProvidedCapability .\n",
        encoding="utf-8",
    )
    shipped = (SHIPPED_CAPABILITIES / "move-forward.ttl").read_text(encoding="utf-8")
    assert shipped.count("CaSk:ProvidedCapability") == 1
    model = tmp_path / "move-forward.ttl"
    model.write_text(
        "@prefix ex: <http://example.org/robot/> .\n"
        + shipped.replace("CaSk:ProvidedCapability", "ex:DriveCapability"),
        encoding="utf-8",
    )
    arguments = [
        "retrieve",
        "--capability",
        str(model),
        "--interfaces",
        str(SHIPPED_CAPABILITIES / "recordings" / "mr1"),
        "--json",
    ]
    without = CliRunner().invoke(main, arguments)
    assert without.exit_code == 2
    assert "given as --ontology FILE" in without.stderr
    given = CliRunner().invoke(main, [*arguments, "--ontology", str(ontology)])
    assert given.exit_code == 0, given.output
    for command in ("check", "run", "validate", "generate"):
        assert "--ontology" in CliRunner().invoke(main, [command, "--help"]).output
