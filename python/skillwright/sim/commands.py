"""``skillwright validate``: check a skill's behaviour in the MuJoCo simulation of the robot."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING

import click

from skillwright.cli_options import (
    bind_option,
    capability_options,
    interfaces_option,
    isolation_option,
    spec_option,
    warn_unisolated,
)
from skillwright.validation.commands import selection_options

if TYPE_CHECKING:
    from rich.console import Console

    from skillwright.capability.model import Capability
    from skillwright.interfaces.inventory import Inventory
    from skillwright.rules.finding import Finding
    from skillwright.rules.settings import Selection
    from skillwright.sim.report import ValidationProgress, ValidationReport

__all__ = ["print_report", "validate"]

_MARKS = {True: "[green]pass[/]", False: "[red]FAIL[/]", None: "[dim]n/a[/]"}


class _Progress:
    def __init__(self, console: Console) -> None:
        self.console = console

    def __call__(self, progress: ValidationProgress) -> None:
        if progress.event == "scenario-start":
            self.console.print(
                f"[bold]scenario {progress.index + 1}/{progress.total}: {progress.scenario}[/]",
                highlight=False,
            )
        elif progress.event == "episode-start":
            what = "run" if progress.episode == "normal" else "run stopped during execute"
            self.console.print(f"  {what} ...", style="dim", highlight=False)
        elif progress.event == "state-end" and progress.state:
            self.console.print(
                f"    {progress.state} ended at {progress.virtual_time:.2f} s",
                style="dim",
                highlight=False,
            )


def print_report(console: Console, report: ValidationReport) -> None:
    """Verdicts per scenario and run, artefacts, findings and a summary line."""
    from rich.markup import escape
    from rich.table import Table

    from skillwright.validation.commands import print_findings

    for capability_name, skill_name in report.binding.items():
        if capability_name != skill_name:
            console.print(f"bound: {escape(skill_name)} is {escape(capability_name)}")
    for scenario in report.scenarios:
        inputs = ", ".join(f"{k}={v}" for k, v in scenario.inputs.items())
        console.print(
            f"[bold]{escape(scenario.name)}[/] in {escape(scenario.world)}"
            + (f" ({escape(inputs)})" if inputs else ""),
            highlight=False,
        )
        for episode in scenario.episodes:
            what = "run" if episode.episode == "normal" else "run stopped during execute"
            speed = f", {episode.speed:.1f}x real time" if episode.speed else ""
            table = Table(
                title=f"{what}: {episode.ended}, {episode.virtual_seconds:.1f} s simulated in "
                f"{episode.wall_seconds:.1f} s{speed}",
                title_justify="left",
                show_edge=False,
            )
            table.add_column("oracle", overflow="fold")
            table.add_column("", width=4)
            table.add_column("verdict", overflow="fold")
            for verdict in episode.verdicts:
                table.add_row(
                    escape(verdict.oracle), _MARKS[verdict.passed], escape(verdict.message)
                )
            console.print(table)
        for label, path in (("plot", scenario.plot), ("trace", scenario.trace)):
            if path:
                console.print(f"  {label}: {escape(path)}", highlight=False)
    print_findings(console, report.skill, report.findings)
    for note in report.notes:
        console.print(f"note: {escape(note)}", style="dim", highlight=False)
    failed = report.failed_oracles()
    errors = sum(f.severity == "error" for f in report.findings)
    outcome = "[green]passed[/]" if report.passed else "[red]failed[/]"
    console.print(
        f"{escape(report.skill)}: behaviour {outcome}: {len(report.scenarios)} scenario(s), "
        f"{len(failed)} oracle(s) failed, {errors} error(s) in {report.wall_seconds:.1f} s",
        highlight=False,
    )


def _stage_of(finding: Finding) -> str | None:
    from skillwright.rules.registry import rule_of

    rule = rule_of(finding)
    return None if rule is None else rule.stage


def _static_checks_first(
    skill_file: Path,
    capability: Capability,
    spec_file: Path,
    inventory: Inventory,
    as_json: bool,
    selection: Selection,
) -> None:
    """With ``--spec``: the static checks, and exit 1 without running when they fail."""
    from skillwright.console import out_console, print_model_json
    from skillwright.errors import InputFileError
    from skillwright.spec.loader import load_spec
    from skillwright.validation.catalog import catalog_from_inventory
    from skillwright.validation.commands import print_findings
    from skillwright.validation.static import check_skill

    try:
        text = skill_file.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise InputFileError(f"skill file {skill_file}: cannot be read as UTF-8 text") from error
    static = check_skill(
        text,
        capability=capability,
        spec=load_spec(spec_file),
        catalog=catalog_from_inventory(inventory),
        path=str(skill_file),
    )
    static = static.model_copy(update={"findings": selection.filter(static.findings)})
    if not static.passed:
        if as_json:
            print_model_json(static)
        else:
            print_findings(out_console(), static.path, static.findings)
            out_console().print(
                f"{skill_file}: the static checks failed; the skill was not run",
                highlight=False,
            )
        sys.exit(1)


@click.command("validate")
@click.argument("skill_file", type=click.Path(path_type=Path))
@capability_options
@spec_option(
    required=False,
    extra_help=" With it, the static checks run first and a skill that fails them is not run.",
)
@interfaces_option(required=True, extra_help=" A recording also gives the lidar's geometry.")
@click.option(
    "--scenario",
    "scenario_file",
    type=click.Path(path_type=Path),
    help="A scenario file (YAML). Default: the shipped one for the capability, else one "
    "derived from the capability model.",
)
@click.option("--only", multiple=True, metavar="NAME", help="Run only this scenario (repeatable).")
@click.option(
    "-o",
    "--output",
    "output_dir",
    type=click.Path(path_type=Path),
    help="Folder for plots, traces and saved maps (default: validation/<skill file's name>).",
)
@click.option("--no-plot", is_flag=True, help="Do not draw the trajectory plots.")
@bind_option
@selection_options
@click.option("--json", "as_json", is_flag=True, help="Print the report as JSON on stdout.")
@isolation_option
def validate(
    skill_file: Path,
    capability_file: Path,
    capability_iri: str | None,
    ontology_files: tuple[Path, ...],
    spec_file: Path | None,
    source: Path,
    scenario_file: Path | None,
    only: tuple[str, ...],
    output_dir: Path | None,
    no_plot: bool,
    bind: dict[str, str],
    select: tuple[str, ...],
    ignore: tuple[str, ...],
    as_json: bool,
    unisolated: bool,
) -> None:
    """Run SKILL_FILE in the MuJoCo simulation of the robot and judge its behaviour.

    For each scenario of the capability the skill runs in the sandbox, in virtual time, with
    the robot simulated in MuJoCo (once normally, and once stopped during execute when it
    moves the robot). Oracles derived from the capability model judge each run on the
    simulator's ground truth: its constraints, its outputs, the resource's limits, contacts,
    the base at rest. --select and --ignore (and the project's [tool.skillwright]) choose the
    static and run rules reported; every oracle's verdict is. Exit status 0 when every
    oracle passes, 1 when one fails, 2 for bad input, 130 when interrupted.
    """
    from skillwright.capability.reader import load_capability
    from skillwright.console import err_console, out_console
    from skillwright.errors import GenerationCancelledError
    from skillwright.interfaces.load import discover_path, is_json_file
    from skillwright.rules.settings import project_selection
    from skillwright.runtime.run import read_skill_file
    from skillwright.sim.scenario import scenarios_for
    from skillwright.sim.validate import validate_skill

    read_skill_file(skill_file)  # a folder, a missing or unreadable file: said before anything
    if unisolated:
        warn_unisolated()
    selection = project_selection(skill_file).narrowed(select, ignore)
    capability = load_capability(
        capability_file, capability_iri=capability_iri, ontologies=ontology_files
    ).capability
    inventory = discover_path(source)
    from skillwright.sim.bindings import bind_interfaces

    localised = bind_interfaces(inventory).has_localisation
    chosen = scenarios_for(capability, scenario_file, localised=localised)
    unknown = [name for name in only if name not in {s.name for s in chosen.scenarios}]
    if unknown:
        from skillwright.errors import InvalidArgumentError

        names = ", ".join(s.name for s in chosen.scenarios)
        raise InvalidArgumentError(
            f"--only {unknown[0]}: {chosen.source} has no such scenario ({names})"
        )
    if spec_file is not None:
        _static_checks_first(skill_file, capability, spec_file, inventory, as_json, selection)
    folder = output_dir if output_dir is not None else Path("validation") / skill_file.stem
    try:
        report = validate_skill(
            skill_file,
            capability,
            inventory,
            scenarios=chosen,
            recording=None if is_json_file(source) else source,
            output_dir=folder,
            only=list(only) or None,
            plot=not no_plot,
            on_progress=None if as_json else _Progress(err_console()),
            isolated=not unisolated,
            bind=bind,
        )
    except KeyboardInterrupt:
        raise GenerationCancelledError(
            "validation interrupted; the sandboxed process was killed"
        ) from None
    kept = [f for f in report.findings if _stage_of(f) == "simulation" or selection.keeps(f)]
    report = report.model_copy(update={"findings": kept})
    if as_json:
        import json

        document = {"passed": report.passed, **report.model_dump(mode="json")}
        sys.stdout.write(json.dumps(document, indent=2) + "\n")
    else:
        print_report(out_console(), report)
    if not report.passed:
        sys.exit(1)
