"""``skillwright check``: run the static checks on a skill file."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import click

from skillwright.cli_options import capability_options, interfaces_option, spec_option

if TYPE_CHECKING:
    from rich.console import Console

    from skillwright.rules.finding import Finding

__all__ = ["check", "print_findings"]


def print_findings(console: Console, path: object, findings: Sequence[Finding]) -> None:
    """Prints findings compiler-style: ``path:line:col: severity [check] message``, one line
    each whatever the terminal's width (editors and CI logs parse these lines)."""
    from rich.markup import escape

    for finding in findings:
        style = "red" if finding.severity == "error" else "yellow"
        console.print(
            f"{escape(str(path))}:{finding.line}:{finding.column}: [{style}]{finding.severity}[/] "
            f"{escape(f'[{finding.check}]')} {escape(finding.message)}",
            highlight=False,
            soft_wrap=True,
        )


@click.command("check")
@click.argument("skill_file", type=click.Path(path_type=Path))
@capability_options
@spec_option(required=True)
@interfaces_option(required=False, extra_help=" Without it, interface grounding is not checked.")
@click.option(
    "--retrieved",
    multiple=True,
    metavar="NAME",
    help="An interface retrieval chose (repeatable): enables the used-versus-retrieved check.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the report as JSON.")
def check(
    skill_file: Path,
    capability_file: Path,
    capability_iri: str | None,
    spec_file: Path,
    source: Path | None,
    retrieved: tuple[str, ...],
    as_json: bool,
) -> None:
    """Check SKILL_FILE statically against its capability, spec and the robot's interfaces.

    Exit status 0 when no check fails, 1 when a check finds an error, 2 for bad input.
    """
    from skillwright.capability.reader import load_capability
    from skillwright.console import out_console, print_model_json
    from skillwright.errors import InputFileError, InputFileNotFoundError
    from skillwright.spec.loader import load_spec
    from skillwright.validation.static import check_skill

    if not skill_file.is_file():
        raise InputFileNotFoundError(f"skill file {skill_file}: no such file; check the path")
    try:
        source_text = skill_file.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise InputFileError(f"skill file {skill_file}: cannot be read as UTF-8 text") from error
    capability = load_capability(capability_file, capability_iri=capability_iri).capability
    skill_spec = load_spec(spec_file)
    catalog = None
    if source is not None:
        from skillwright.console import warn
        from skillwright.interfaces.load import load_inventory, read_warnings
        from skillwright.validation.catalog import catalog_from_inventory

        inventory = load_inventory(source)
        warn(read_warnings(inventory))
        catalog = catalog_from_inventory(inventory)
    report = check_skill(
        source_text,
        capability=capability,
        spec=skill_spec,
        catalog=catalog,
        retrieved=retrieved,
        path=str(skill_file),
    )
    if as_json:
        print_model_json(report)
    else:
        console = out_console()
        print_findings(console, report.path, report.findings)
        errors = sum(f.severity == "error" for f in report.findings)
        warnings = len(report.findings) - errors
        verdict = "passed" if report.passed else "failed"
        grounding = "" if catalog is not None else " (interfaces not checked: no --interfaces)"
        console.print(
            f"{report.path}: {verdict}, {errors} error(s), {warnings} warning(s){grounding}",
            soft_wrap=True,
            highlight=False,
        )
    if not report.passed:
        sys.exit(1)
