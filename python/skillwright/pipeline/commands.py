"""``skillwright generate``: the whole pipeline from the command line."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING

import click

from skillwright.cli_options import (
    capability_options,
    dense_option,
    interfaces_option,
    isolation_option,
    spec_option,
    warn_unisolated,
)
from skillwright.pipeline.verdict import (
    Verdict,
    behaviour_verdict,
    checks_verdict,
    overall,
    stage_verdicts,
)
from skillwright.validation.commands import selection_options

if TYPE_CHECKING:
    from rich.console import Console

    from skillwright.pipeline.events import AttemptFinished, Event, ModelWaiting
    from skillwright.pipeline.run import Outcome

__all__ = ["generate"]


class _Progress:
    """Prints the engine's events on stderr: one line per stage, a live token count."""

    def __init__(self, console: Console) -> None:
        self.console = console
        self.chunks = 0
        self.live = console.is_terminal
        self.open_line = False
        """A line ended in a carriage return (a live count) is on the terminal."""
        self.waited: tuple[int, int] | None = None
        """Place in line and minute of waiting of the last wait line printed (on a terminal
        the wait line is rewritten in place instead)."""

    def end_line(self) -> None:
        """Ends a live count's line, so what is printed next starts on a line of its own."""
        if self.open_line:
            self.console.print()
            self.open_line = False

    def __call__(self, event: Event) -> None:
        from skillwright.pipeline.events import ModelWaiting

        if isinstance(event, ModelWaiting):
            self._waiting(event)
            return
        if self.waited is not None:
            # The wait is over: its last line stays, what comes next starts below it.
            self.end_line()
            self.waited = None
        self.open_line = False
        self._show(event)

    def _waiting(self, event: ModelWaiting) -> None:
        """Another generation holds the model: one line, rewritten on a terminal; elsewhere
        printed again when the place in line changes and once a minute."""
        key = (event.place, int(event.seconds // 60))
        if self.live:
            self.console.print(
                # Padded: a shorter line must cover the one it rewrites.
                f"  {event.message}".ljust(self.console.width - 1),
                end="\r",
                style="yellow",
                highlight=False,
                markup=False,
                no_wrap=True,
                overflow="ellipsis",
            )
            self.open_line = True
        elif key != self.waited:
            self.console.print(
                f"  {event.message}", style="yellow", highlight=False, markup=False, soft_wrap=True
            )
        self.waited = key

    def _show(self, event: Event) -> None:
        from skillwright.pipeline.events import (
            AttemptFinished,
            AttemptStarted,
            GenerationStats,
            Notice,
            PrefixCacheStatus,
            StageFinished,
            StageStarted,
            TokenChunk,
        )

        if isinstance(event, StageStarted):
            self.console.print(f"[bold]{event.stage}[/]: {event.detail} ...", highlight=False)
        elif isinstance(event, StageFinished):
            detail = f" — {event.detail}" if event.detail else ""
            self.console.print(
                f"  done in {event.seconds:.2f} s{detail}", style="dim", highlight=False
            )
        elif isinstance(event, Notice):
            style = "yellow" if event.level == "warning" else "cyan"
            self.console.print(f"[{style}]{event.level}[/]: {event.message}", highlight=False)
        elif isinstance(event, PrefixCacheStatus):
            self.console.print(f"  prefix cache: {event.status}", style="dim")
        elif isinstance(event, AttemptStarted):
            self.chunks = 0
            what = "repairing" if event.number > 1 else "writing"
            self.console.print(
                f"  {what} {event.target} (answer {event.number}) ...",
                end="\r" if self.live else "\n",
                style="dim",
                highlight=False,
            )
            self.open_line = self.live
        elif isinstance(event, AttemptFinished):
            self.console.print(_attempt_line(event), highlight=False, markup=False)
        elif isinstance(event, TokenChunk):
            self.chunks += 1
            if self.live and self.chunks % 8 == 0:
                self.console.print(f"  {self.chunks} tokens ...", end="\r", style="dim")
            self.open_line = self.live
        elif isinstance(event, GenerationStats):
            rate = f", {event.tokens_per_second:.1f} tokens/s" if event.tokens_per_second else ""
            self.console.print(
                f"  prompt {event.prompt_tokens} tokens, answer {event.completion_tokens} "
                f"tokens{rate}",
                style="dim",
                highlight=False,
            )


def _attempt_line(event: AttemptFinished) -> str:
    attempt = event.attempt
    if attempt.finish == "fixed":
        return (
            f"  {attempt.target} answer {attempt.number}: {Verdict.FIXED.word} with the checks' "
            "suggestions (no model time)"
        )
    verdict = "ok" if attempt.finish == "stop" else attempt.finish
    note = f" — {attempt.note}" if attempt.note else ""
    return (
        f"  {attempt.target} answer {attempt.number}: {verdict}, "
        f"{attempt.completion_tokens or 0} tokens in {attempt.seconds:.1f} s{note}"
    )


def _summary(outcome: Outcome) -> None:
    from rich.table import Table

    from skillwright.console import out_console
    from skillwright.validation.commands import print_findings

    console = out_console()
    record = outcome.record
    table = Table(title="Retrieved interfaces", title_justify="left")
    for column in ("name", "kind", "type", "score", "reason"):
        table.add_column(column, overflow="fold")
    for hit in record.retrieval.hits:
        score = f"{hit.score:.3f}" if hit.score is not None else "pinned" if hit.pinned else "added"
        reason = hit.reason
        if hit.judgement is not None:
            verdict = {True: "needed", False: "not needed", None: "no verdict"}[hit.needed]
            reason += f"; model: {verdict}: {hit.judgement}"
        if hit.set_aside:
            reason += "; set aside (a weak score): not given to the skill"
        table.add_row(hit.name, hit.kind, hit.type_name, score, reason)
    console.print(table)
    print_findings(console, outcome.skill_path, outcome.report.findings)
    for note in record.notes:
        console.print(f"note: {note}", style="yellow", highlight=False, markup=False)
    checks = record.checks
    verdict = checks_verdict(checks).verdict.markup()
    what = "skeleton" if record.model is None else f"skill written by {record.model.id}"
    console.print(
        f"{what}: {outcome.skill_path}\nchecks {verdict}: {checks.errors} error(s), "
        f"{checks.warnings} warning(s)\nrecord: {outcome.record_path}",
        highlight=False,
    )
    _behaviour_summary(console, outcome)
    console.print(f"verdict: {overall(stage_verdicts(record)).markup()}", highlight=False)
    for backup in outcome.backups:
        console.print(f"earlier version kept in {backup}", style="dim", highlight=False)


def _behaviour_summary(console: Console, outcome: Outcome) -> None:
    from rich.markup import escape

    from skillwright.validation.commands import print_findings

    record = outcome.record
    run, simulation = record.run, record.simulation
    for name, part in (("run", run), ("simulation", simulation)):
        if part is not None and part.skipped is not None:
            given = behaviour_verdict(part, record.checks.passed).verdict
            console.print(f"{name} {given.markup()}: {escape(part.skipped)}", highlight=False)
    if run is not None and run.skipped is None:
        print_findings(console, outcome.skill_path, run.findings)
        verdict = behaviour_verdict(run, record.checks.passed).verdict.markup()
        console.print(
            f"run {verdict}: {run.errors} error(s), {run.warnings} warning(s) "
            f"(world: {run.world or 'none'})",
            highlight=False,
        )
    if simulation is not None and simulation.skipped is None:
        failed = [v for v in simulation.verdicts if v.passed is False]
        for verdict_record in failed:
            console.print(
                f"  ✗ {simulation.verdict_place(verdict_record)} {verdict_record.oracle}: "
                f"{verdict_record.message}",
                highlight=False,
                markup=False,
            )
        judged = sum(v.passed is not None for v in simulation.verdicts)
        verdict = behaviour_verdict(simulation, record.checks.passed).verdict.markup()
        plot = f"; plot: {outcome.out_dir / simulation.plot}" if simulation.plot else ""
        console.print(
            f"simulation {verdict} in {simulation.where}: {judged - len(failed)}/{judged} "
            f"verdicts passed{plot}",
            highlight=False,
        )


@click.command("generate")
@capability_options
@spec_option(required=True)
@interfaces_option(required=True)
@click.option("--model", "model_id", metavar="ID", help="Model id or alias from models.toml.")
@click.option("--skeleton", is_flag=True, help="Write the skeleton only; no model.")
@click.option("-k", "k", default=4, show_default=True, help="Interfaces to retrieve.")
@click.option(
    "--min-share",
    default=0.1,
    show_default=True,
    type=click.FloatRange(0.0, 1.0),
    help="Set aside a retrieved interface scoring under this share of the best one's score "
    "(the record keeps it; the skill does not get it). 0 gives all k.",
)
@click.option(
    "--pin", multiple=True, metavar="NAME", help="Always give this interface (repeatable)."
)
@click.option(
    "--drop", multiple=True, metavar="NAME", help="Never give this interface (repeatable)."
)
@click.option("--all", "include_all", is_flag=True, help="Let retrieval pick infrastructure too.")
@dense_option
@click.option(
    "--rerank",
    is_flag=True,
    help="Have the generation model judge the best 8 candidates after ranking (needed or not, "
    "with a reason); the model is then loaded during retrieval. Answers are cached.",
)
@click.option(
    "--attempts",
    default=3,
    show_default=True,
    type=click.IntRange(1, 10),
    help="Answers the model may give per method: the first, then repairs from the findings "
    "(and one more for the run's and simulation's findings once the static checks pass).",
)
@click.option(
    "--candidates",
    default=1,
    show_default=True,
    type=click.IntRange(1, 8),
    help="Candidate skills of the first round: each state is asked for this many answers at "
    "once (the greedy one and sampled ones; a local model decodes them in one batch), every "
    "distinct candidate is judged by the checks, the run and the simulation, and repair "
    "starts from the best. The record keeps every candidate's verdict.",
)
@click.option(
    "--no-run",
    is_flag=True,
    help="Do not run the skill in the sandbox after the static checks (stage `run`).",
)
@click.option(
    "--no-sim",
    is_flag=True,
    help="Do not validate the skill in MuJoCo after the static checks (stage `simulate`).",
)
@click.option(
    "--scenario",
    "scenario_file",
    type=click.Path(path_type=Path),
    help="A scenario file (YAML) for the run and the simulation (the run takes its first "
    "scenario). Default: the shipped one for the capability, else scenarios derived from the "
    "capability model.",
)
@click.option(
    "-o",
    "--output",
    "out_dir",
    type=click.Path(path_type=Path),
    help="Output folder (default: generated/<skill name>).",
)
@click.option(
    "--models",
    "models_file",
    type=click.Path(path_type=Path),
    help="A models.toml to use instead of the usual ones.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the record as JSON on stdout.")
@selection_options
@isolation_option
def generate(
    capability_file: Path,
    capability_iri: str | None,
    ontology_files: tuple[Path, ...],
    spec_file: Path,
    source: Path,
    model_id: str | None,
    skeleton: bool,
    k: int,
    min_share: float,
    pin: tuple[str, ...],
    drop: tuple[str, ...],
    include_all: bool,
    dense: bool,
    rerank: bool,
    attempts: int,
    candidates: int,
    no_run: bool,
    no_sim: bool,
    scenario_file: Path | None,
    out_dir: Path | None,
    models_file: Path | None,
    as_json: bool,
    select: tuple[str, ...],
    ignore: tuple[str, ...],
    unisolated: bool,
) -> None:
    """Write a skill for a capability and a specification from the robot's interfaces.

    Stages: inputs, retrieval, skeleton, model, generation (the model writes each state,
    then repairs what the checks find), checks, run (the states in the sandbox against the
    simulated graph), simulate (MuJoCo, every scenario of the capability and its oracles),
    outputs (progress on stderr). Run and simulate follow only static checks without
    errors; their findings also go back to the model. Without an installed model the
    skeleton is written and said so.
    Exit status 0 when the checks, the run and the simulation pass, 1 when they find
    problems, 2 for bad input, 130 when interrupted (Ctrl-C; one line says what was kept).
    """
    from skillwright.console import err_console, print_model_json
    from skillwright.errors import GenerationCancelledError, InvalidArgumentError
    from skillwright.pipeline.run import GenerationRequest, run_generation

    progress = _Progress(err_console())
    outcome: Outcome | None = None
    try:
        if skeleton and model_id is not None:
            raise InvalidArgumentError("--skeleton and --model exclude each other; choose one")
        if skeleton and candidates > 1:
            raise InvalidArgumentError("--candidates needs the model that --skeleton leaves out")
        if skeleton and rerank:
            raise InvalidArgumentError("--rerank needs the model that --skeleton leaves out")
        if out_dir is None:
            from skillwright.spec.loader import load_spec

            out_dir = Path("generated") / load_spec(spec_file).name
        request = GenerationRequest(
            capability=capability_file,
            spec=spec_file,
            interfaces=source,
            out_dir=out_dir,
            capability_iri=capability_iri,
            ontologies=ontology_files,
            model=model_id,
            skeleton=skeleton,
            k=k,
            min_share=min_share,
            include_infrastructure=include_all,
            pinned=pin,
            dropped=drop,
            models_file=models_file,
            dense=dense,
            rerank=rerank,
            attempts=attempts,
            candidates=candidates,
            run=not no_run,
            simulate=not no_sim,
            scenario=scenario_file,
            isolated=not unisolated,
            select=select,
            ignore=ignore,
        )
        if unisolated and not (no_run and no_sim):
            warn_unisolated()
        outcome = run_generation(request, on_event=progress)
        if as_json:
            print_model_json(outcome.record)
        else:
            _summary(outcome)
    except KeyboardInterrupt:
        # run_generation turns an interrupt in its stages into a GenerationCancelledError;
        # this one came before them (reading the specification) or after (the summary).
        progress.end_line()
        if outcome is None:
            raise GenerationCancelledError(
                "generation interrupted before its first stage; nothing was written"
            ) from None
        raise GenerationCancelledError(
            f"generation interrupted after writing {outcome.out_dir}: its files are complete"
        ) from None
    except GenerationCancelledError:
        progress.end_line()
        raise
    if not outcome.passed:
        sys.exit(1)
