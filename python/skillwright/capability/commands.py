"""``skillwright capability ...``: read and show capability models."""

from __future__ import annotations

from pathlib import Path

import click

__all__ = ["capability"]


@click.group()
def capability() -> None:
    """Read capability models (OWL/Turtle, CaSk ontology family)."""


@capability.command("show")
@click.argument("file", type=click.Path(path_type=Path))
@click.option(
    "--capability",
    "capability_iri",
    metavar="IRI",
    help="Which capability, when the file holds several (full IRI or local name).",
)
@click.option(
    "--ontology",
    "ontologies",
    multiple=True,
    type=click.Path(path_type=Path),
    metavar="FILE",
    help="Local copy of an imported ontology (repeatable); imports are never fetched.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the capability document as JSON.")
def show(
    file: Path, capability_iri: str | None, ontologies: tuple[Path, ...], as_json: bool
) -> None:
    """Summarise the capability in FILE: inputs, outputs, constraints, resource limits."""
    from skillwright.capability.reader import load_capability
    from skillwright.console import err_console, out_console, print_model_json

    load = load_capability(file, capability_iri=capability_iri, ontologies=ontologies)
    for warning in load.warnings:
        err_console().print(f"[yellow]warning:[/] {warning}", markup=True, highlight=False)
    if as_json:
        print_model_json(load)
        return
    from skillwright.capability.render import render_capability

    out_console().print(render_capability(load))
