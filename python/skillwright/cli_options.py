"""Options several commands share, declared once so their names and meaning agree."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import click

__all__ = ["capability_options", "dense_option", "interfaces_option", "spec_option"]

F = TypeVar("F", bound=Callable[..., object])

INTERFACES_HELP = (
    "The robot's interfaces: an .mcap file, a rosbag2 folder, a reference-tool report or a "
    "saved inventory .json."
)


def dense_option(function: F) -> F:
    """``--dense/--no-dense`` (as ``dense``, off by default)."""
    return click.option(
        "--dense/--no-dense",
        default=False,
        help="Mix a share of embedding similarity (the local all-MiniLM-L6-v2) into the "
        "ranking. Off by default: on eight labelled sets it found no needed interface in the "
        "first 4 that the lexical ranking missed, lost four, and costs about a second per "
        "capability.",
    )(function)


def capability_options(function: F) -> F:
    """``--capability FILE`` (required, as ``capability_file``) and ``--capability-iri IRI``."""
    function = click.option(
        "--capability-iri", metavar="IRI", help="Which capability, when the file holds several."
    )(function)
    return click.option(
        "--capability",
        "capability_file",
        required=True,
        type=click.Path(path_type=Path),
        help="The capability model (Turtle or another RDF syntax).",
    )(function)


def spec_option(*, required: bool, extra_help: str = "") -> Callable[[F], F]:
    """``--spec FILE`` (as ``spec_file``)."""
    return click.option(
        "--spec",
        "spec_file",
        required=required,
        type=click.Path(path_type=Path),
        help=f"The skill specification (JSON or YAML).{extra_help}",
    )


def interfaces_option(*, required: bool, extra_help: str = "") -> Callable[[F], F]:
    """``--interfaces SOURCE`` (as ``source``)."""
    return click.option(
        "--interfaces",
        "source",
        required=required,
        type=click.Path(path_type=Path),
        help=INTERFACES_HELP + extra_help,
    )
