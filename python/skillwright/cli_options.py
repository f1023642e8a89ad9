"""Options several commands share, declared once so their names and meaning agree."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import click

__all__ = [
    "bind_option",
    "capability_options",
    "dense_option",
    "interfaces_option",
    "isolation_option",
    "optional_capability_options",
    "spec_option",
    "warn_unisolated",
]

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


def isolation_option(function: F) -> F:
    """``--unsafe-no-isolation`` (as ``unisolated``): skills run without the kernel sandbox."""
    return click.option(
        "--unsafe-no-isolation",
        "unisolated",
        is_flag=True,
        help="Run skills WITHOUT the kernel sandbox (their own user, mount, PID and network "
        "namespaces, a read-only root, seccomp): only the audit hook, the resource limits "
        "and what the process can do to itself (Landlock, seccomp) remain, and the skill can "
        "reach your files. Only for a machine whose kernel refuses user namespaces, and only "
        "for code you have read. The record says so.",
    )(function)


def warn_unisolated() -> None:
    """The warning every command that runs a skill without isolation prints first."""
    from skillwright.console import err_console

    err_console().print(
        "[bold red]warning:[/] --unsafe-no-isolation: the skill runs without the kernel "
        "sandbox and can read and change what your user can",
        highlight=False,
    )


def _capability(*, required: bool) -> Callable[[F], F]:
    def decorate(function: F) -> F:
        function = click.option(
            "--ontology",
            "ontology_files",
            multiple=True,
            type=click.Path(path_type=Path),
            help="A local copy of an ontology the model imports (repeatable): its classes "
            "and properties let domain-specific capabilities, inputs and outputs be read.",
        )(function)
        function = click.option(
            "--capability-iri",
            metavar="IRI",
            help="Which capability, when the file holds several.",
        )(function)
        return click.option(
            "--capability",
            "capability_file",
            required=required,
            type=click.Path(path_type=Path),
            help="The capability model (Turtle or another RDF syntax)."
            + ("" if required else " With it, inputs may be given by its names."),
        )(function)

    return decorate


def capability_options(function: F) -> F:
    """``--capability FILE`` (required, as ``capability_file``), ``--capability-iri IRI`` and
    ``--ontology FILE ...`` (as ``ontology_files``)."""
    return _capability(required=True)(function)


def optional_capability_options(function: F) -> F:
    """``--capability FILE`` (optional, as ``capability_file``), ``--capability-iri IRI`` and
    ``--ontology FILE ...`` (as ``ontology_files``)."""
    return _capability(required=False)(function)


def _bindings(_: click.Context, __: click.Parameter, values: tuple[str, ...]) -> dict[str, str]:
    pairs: dict[str, str] = {}
    for value in values:
        skill_name, equals, capability_name = value.partition("=")
        if not equals or not skill_name.strip() or not capability_name.strip():
            raise click.BadParameter(
                f"{value!r} is not SKILL_NAME=CAPABILITY_NAME (e.g. --bind distance=inDistance)"
            )
        pairs[skill_name.strip()] = capability_name.strip()
    return pairs


def bind_option(function: F) -> F:
    """``--bind SKILL_NAME=CAPABILITY_NAME`` (repeatable, as ``bind``, a dict)."""
    return click.option(
        "--bind",
        "bind",
        multiple=True,
        metavar="NAME=CAPABILITY_NAME",
        callback=_bindings,
        help="Bind the skill's parameter or output NAME to the capability's input or output "
        "(repeatable); others bind by name, else by their meaning (name, description, unit).",
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
