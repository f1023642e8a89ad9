"""``skillwright run``: run a skill's states in the sandbox against a simulated graph."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING

import click

from skillwright.cli_options import (
    bind_option,
    interfaces_option,
    isolation_option,
    optional_capability_options,
    warn_unisolated,
)
from skillwright.validation.commands import selection_options

if TYPE_CHECKING:
    from rich.console import Console

    from skillwright.runtime.report import RunProgress, RunReport

__all__ = ["parse_inputs", "run"]


def _value(text: str) -> float | int | bool | str:
    lowered = text.strip().lower()
    if lowered in {"true", "false"}:
        return lowered == "true"
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


def parse_inputs(values: tuple[str, ...]) -> dict[str, float | int | bool | str]:
    """``("inDistance=1.0", "a=1 b=true")`` -> ``{"inDistance": 1.0, "a": 1, "b": True}``."""
    from skillwright.errors import InvalidArgumentError

    inputs: dict[str, float | int | bool | str] = {}
    for value in values:
        for pair in value.split():
            name, sep, text = pair.partition("=")
            if not sep or not name:
                raise InvalidArgumentError(
                    f"--inputs {pair!r}: write each input as NAME=VALUE, e.g. inDistance=1.0"
                )
            inputs[name] = _value(text)
    return inputs


class _Progress:
    def __init__(self, console: Console) -> None:
        self.console = console

    def __call__(self, progress: RunProgress) -> None:
        if progress.event == "episode-start":
            what = (
                "normal run" if progress.episode == "normal" else "run with a Stop during execute"
            )
            self.console.print(f"[bold]{what}[/] ...", highlight=False)
        elif progress.event == "state-end":
            self.console.print(
                f"  {progress.state}: {progress.detail} at {progress.virtual_time:.2f} s",
                style="dim",
                highlight=False,
            )


def _summary(console: Console, path: Path, report: RunReport) -> None:
    from rich.markup import escape

    from skillwright.validation.commands import print_findings

    trace = report.trace
    for episode in trace.episodes:
        states = ", ".join(
            f"{s.name} {s.outcome}" + (f" ({s.detail})" if s.detail else "")
            for s in episode.states
            if s.outcome != "absent"
        )
        published: dict[str, int] = {}
        for event in episode.events:
            if event["kind"] == "publish":
                published[event["topic"]] = published.get(event["topic"], 0) + 1
        sent = ", ".join(f"{count} on {topic}" for topic, count in sorted(published.items()))
        console.print(
            f"{episode.name} run: {states or 'no state ran'}; {episode.virtual_seconds:.2f} s "
            f"simulated in {episode.wall_seconds:.2f} s" + (f"; published {sent}" if sent else ""),
            highlight=False,
            markup=False,
            soft_wrap=True,
        )
        if episode.outputs:
            shown = ", ".join(f"{k} = {v}" for k, v in episode.outputs.items())
            console.print(f"  outputs: {escape(shown)}", highlight=False, soft_wrap=True)
    print_findings(console, path, report.findings)
    errors = sum(f.severity == "error" for f in report.findings)
    warnings = len(report.findings) - errors
    verdict = "[green]passed[/]" if report.passed else "[red]failed[/]"
    isolation = trace.episodes[0].isolation if trace.episodes else {}
    namespaces = isolation.get("namespaces", "not started")
    console.print(
        f"{escape(str(path))}: run {verdict}, {errors} error(s), {warnings} warning(s) "
        f"(world: {trace.world or 'none'}; sandbox namespaces: {namespaces})",
        highlight=False,
        soft_wrap=True,
    )


def _binding_lines(console: Console, report: RunReport) -> None:
    """One line per input or output bound under another name than the capability's."""
    for capability_name, skill_name in report.trace.binding.items():
        if capability_name != skill_name:
            console.print(f"bound: {skill_name} is {capability_name}", highlight=False)


@click.command("run")
@click.argument("skill_file", type=click.Path(path_type=Path))
@interfaces_option(required=True, extra_help=" A recording is also replayed during the run.")
@click.option(
    "-i",
    "--inputs",
    "input_values",
    multiple=True,
    metavar="NAME=VALUE",
    help="A skill input, by the skill's name or, with --capability, the capability's "
    "(repeatable; several may share one value, separated by spaces).",
)
@optional_capability_options
@bind_option
@click.option(
    "--scenario",
    "scenario_file",
    type=click.Path(path_type=Path),
    help="A scenario (YAML): inputs, world, scripted topics, services and actions, deadlines.",
)
@click.option(
    "--world",
    type=click.Choice(["none", "kinematic"]),
    help="The simulated world: `kinematic` moves the base and arm as commanded; `none` "
    "replays the recording only. Default: the scenario's, else none.",
)
@click.option(
    "-o",
    "--output",
    "out_file",
    type=click.Path(path_type=Path),
    help="Also write the report (findings and trace) as JSON to this file.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the report as JSON on stdout.")
@selection_options
@isolation_option
def run(
    skill_file: Path,
    source: Path,
    input_values: tuple[str, ...],
    capability_file: Path | None,
    capability_iri: str | None,
    ontology_files: tuple[Path, ...],
    bind: dict[str, str],
    scenario_file: Path | None,
    world: str | None,
    out_file: Path | None,
    as_json: bool,
    select: tuple[str, ...],
    ignore: tuple[str, ...],
    unisolated: bool,
) -> None:
    """Run SKILL_FILE's PackML states in a sandbox against the robot's simulated graph.

    The skill runs in a sandbox the kernel enforces (its own user, mount, PID and network
    namespaces, a read-only root, seccomp; see the README), with time, memory and file
    limits, in virtual time: starting, execute, completing and resetting, and, when it
    moved the robot, a second time with a Stop during execute. Everything it publishes,
    calls and logs is traced; problems are reported at their line in SKILL_FILE. A state
    whose wait gave up ("within 2 s") runs once more with the wait allowed longer, to tell
    a timeout too short for the motion (the finding gives a measured one) from a wait for
    what never happens; then, and for a loop that ran into the state's deadline, the
    comparison the loop waits on is logged on every pass of that second run, to say why it
    never held (it steps over its goal, never changes, or moves away). With --capability,
    inputs may be given by the capability's names: the skill's parameters are bound to them
    by name, else by what their names and descriptions mean, else by --bind; the binding is
    printed and kept in the report. Exit status 0 when the run finds no error, 1 when it
    does, 2 for bad input, 130 when interrupted.
    """
    from skillwright.console import err_console, out_console, print_model_json
    from skillwright.errors import GenerationCancelledError
    from skillwright.interfaces.load import discover_path, is_json_file
    from skillwright.rules.settings import project_selection
    from skillwright.runtime.run import run_skill
    from skillwright.runtime.scenario import RunScenario, load_scenario
    from skillwright.runtime.waits import probe_waits

    if unisolated:
        warn_unisolated()
    selection = project_selection(skill_file).narrowed(select, ignore)
    inputs = parse_inputs(input_values)
    scenario = load_scenario(scenario_file) if scenario_file is not None else None
    inventory = discover_path(source)
    recording = None if is_json_file(source) else source
    capability = None
    if capability_file is not None:
        from skillwright.capability.reader import load_capability

        capability = load_capability(
            capability_file, capability_iri=capability_iri, ontologies=ontology_files
        ).capability
    try:

        def run_once(source_text: str | None, progress: _Progress | None = None) -> RunReport:
            return run_skill(
                skill_file,
                inventory,
                inputs=inputs,
                scenario=scenario,
                world=world,
                recording=recording,
                source=source_text,
                on_progress=progress,
                isolated=not unisolated,
                capability=capability,
                bindings=bind,
            )

        report = run_once(None, None if as_json else _Progress(err_console()))
        deadline = (scenario or RunScenario()).deadlines.state
        report = probe_waits(report, skill_file.read_text(encoding="utf-8"), run_once, deadline)
        report = report.model_copy(update={"findings": selection.filter(report.findings)})
    except KeyboardInterrupt:
        raise GenerationCancelledError(
            "run interrupted; the sandboxed process was killed"
        ) from None
    if out_file is not None:
        from skillwright.fileio import write_atomic

        write_atomic(out_file, report.model_dump_json(indent=2) + "\n")
    if as_json:
        print_model_json(report)
    else:
        _binding_lines(err_console(), report)
        _summary(out_console(), skill_file, report)
    if not report.passed:
        sys.exit(1)
