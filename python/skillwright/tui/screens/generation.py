"""The Generation tab: run :func:`skillwright.pipeline.run_generation` and watch it work.

Each stage's start and end, every answer the model starts and how it ended (the model
writes one method at a time and repairs what the checks find), the run's and the
simulation's verdicts with the plot's file (their findings join the list), the prefix cache,
throughput and every streamed token arrive as pipeline events, posted from the worker
thread. Esc sets the pipeline's cancel event; the pipeline then stops and writes nothing.
The result folder and record are the pipeline's, exactly as in headless mode.
"""

from __future__ import annotations

import threading
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rich.text import Text
from textual import on, work
from textual.app import ComposeResult, SystemCommand
from textual.containers import Horizontal, Vertical, VerticalScroll
from textual.widgets import Button, OptionList, Select, Static
from textual.widgets.option_list import Option
from textual.worker import Worker

from skillwright.errors import SkillwrightError
from skillwright.tui.messages import GenerationEvent, GenerationFinished, JobFailed, ModelsListed
from skillwright.tui.screens.base import Pane
from skillwright.tui.widgets.code_view import CodeView

if TYPE_CHECKING:
    from skillwright.rules.finding import Finding

__all__ = ["SKELETON", "GenerationPane"]

SKELETON = "skeleton"
"""Value of the model selector that asks for the deterministic skeleton only."""

_IDLE = "Ctrl+G generates a skill from the current inputs."
_ICONS = {"pending": "·", "running": "…", "done": "✓", "skipped": "-"}


class GenerationPane(Pane):
    """Model choice, stage progress, the streamed code and the check findings."""

    job = "generation"
    primary = "#generation-code"

    def __init__(self) -> None:
        super().__init__(id="generation-pane")
        self._worker: Worker[None] | None = None
        self._cancel: threading.Event | None = None
        self.stages: dict[str, tuple[str, str]] = {}
        """Stage -> (state, text shown after it)."""
        self.findings: list[Finding] = []
        self.outcome: Any = None
        """The last pipeline ``Outcome``."""
        self._stats: list[str] = []
        self.attempts: list[str] = []
        """One line per answer of the model: method, answer number, how it ended."""
        self.streamed = ""
        """Everything the model wrote in the current run."""

    def compose(self) -> ComposeResult:
        with Horizontal(id="generation-bar", classes="bar"):
            yield Select[str]([], prompt="model", id="generation-model", compact=True)
            yield Button("Generate ^G", id="generation-start", variant="primary", compact=True)
            yield Button("Cancel Esc", id="generation-cancel", compact=True)
        with Horizontal(id="generation-body"):
            with VerticalScroll(id="generation-side"):
                yield Static(_IDLE, id="generation-stages", markup=False)
                yield Static("", id="generation-attempts", markup=False)
                yield Static("", id="generation-behaviour", markup=False)
                yield Static("", id="generation-stats", markup=False)
            with Vertical(id="generation-main"):
                yield CodeView(id="generation-code")
                yield OptionList(id="generation-findings")
        yield Static("", id="generation-status", markup=False)

    def on_mount(self) -> None:
        self.query_one("#generation-cancel").disabled = True
        self.query_one("#generation-findings").display = False
        self._list_models()

    # --- models ---------------------------------------------------------------------------------
    @work(thread=True, group="models", exit_on_error=False)
    def _list_models(self) -> None:
        from skillwright.llm.config import LlamaCppModel, load_registry

        try:
            registry = load_registry(self.sw.models_file)
        except SkillwrightError as error:
            self.fail(str(error))
            self.post_message(ModelsListed([("skeleton only (no model)", SKELETON)], None))
            return
        options = []
        for entry in registry.llms.values():
            label = entry.id
            if isinstance(entry, LlamaCppModel) and not registry.resolve(entry.file).is_file():
                label += " (file missing)"
            options.append((label, entry.id))
        options.append(("skeleton only (no model)", SKELETON))
        self.post_message(ModelsListed(options, registry.defaults.generation))

    def on_models_listed(self, message: ModelsListed) -> None:
        options, default = message.options, message.default
        select = self.query_one("#generation-model", Select)
        ids = [value for _label, value in options]
        session = self.sw.session
        chosen = SKELETON if session.skeleton else session.model or default
        with self.prevent(Select.Changed):
            select.set_options(options)
            if chosen in ids:
                select.value = chosen

    @on(Select.Changed, "#generation-model")
    def _model_chosen(self, event: Select.Changed) -> None:
        if event.value == SKELETON:
            self.sw.update_session(skeleton=True)
        elif isinstance(event.value, str):
            self.sw.update_session(model=event.value, skeleton=False)

    # --- running ----------------------------------------------------------------------------------
    @property
    def running(self) -> bool:
        """True while a generation worker runs."""
        return self._worker is not None and self._worker.is_running

    @on(Button.Pressed, "#generation-start")
    def start(self) -> None:
        """Checks the inputs are there, then runs the pipeline in a worker."""
        if self.running:
            self.notify("a generation is running; Esc cancels it", title="Generation", markup=False)
            return
        loaded, session = self.sw.loaded, self.sw.session
        if loaded.capability_path is None or loaded.capability is None:
            self.fail("choose a capability first (Capability tab, F2)")
            return
        if loaded.inventory_source is None:
            self.fail("load the robot's interfaces first (Interfaces tab, F4)")
            return
        spec_path = self.sw.spec_pane().saved_path()
        spec = self.sw.spec_pane().spec
        if spec_path is None or spec is None:
            return
        known = {i.name for i in loaded.inventory.interfaces} if loaded.inventory else set()
        stale = [n for n in (*session.pinned, *session.dropped) if n not in known]
        if stale:
            self.notify(
                f"not in this inventory, so not pinned or dropped: {', '.join(stale)}",
                title="Generation",
                severity="warning",
                markup=False,
            )
        out_dir = self.sw.workspace.new_result_dir(spec.name)
        request = {
            "capability": loaded.capability_path,
            "spec": spec_path,
            "interfaces": loaded.inventory_source,
            "out_dir": out_dir,
            "capability_iri": session.capability_iri,
            "model": None if session.skeleton else session.model,
            "skeleton": session.skeleton,
            "k": session.k,
            "include_infrastructure": session.show_infrastructure,
            "pinned": tuple(n for n in session.pinned if n in known),
            "dropped": tuple(n for n in session.dropped if n in known),
            "models_file": self.sw.models_file,
            "dense": session.dense,
            "attempts": session.attempts,
        }
        self._reset()
        self._cancel = threading.Event()
        self.query_one("#generation-start").disabled = True
        self.query_one("#generation-cancel").disabled = False
        self.query_one("#generation-status", Static).update(
            f"generating {spec.name} into {self.sw.workspace.relative(out_dir)} …"
        )
        self._worker = self._generate(request, self._cancel)

    @work(thread=True, exclusive=True, group="generation", exit_on_error=False)
    def _generate(self, request: dict[str, Any], cancel: threading.Event) -> None:
        # The whole pipeline (rdflib, NumPy, the embedder, llama.cpp) loads here.
        from skillwright.pipeline import GenerationRequest, run_generation
        from skillwright.pipeline.events import ChunkBatcher

        def post(event: object) -> None:
            self.post_message(GenerationEvent(event))

        batcher = ChunkBatcher(post)
        try:
            outcome = run_generation(GenerationRequest(**request), on_event=batcher, cancel=cancel)
        except SkillwrightError as error:
            batcher.flush()
            self.fail(str(error), cancelled=cancel.is_set())
            return
        batcher.flush()
        self.post_message(GenerationFinished(outcome))

    @on(Button.Pressed, "#generation-cancel")
    def _cancel_pressed(self) -> None:
        self.cancel_job()

    def cancel_job(self) -> bool:
        if not self.running or self._cancel is None:
            return False
        self._cancel.set()
        self.query_one("#generation-status", Static).update("cancelling …")
        return True

    def _reset(self) -> None:
        self.stages = {}
        self._stats = []
        self.attempts = []
        self.findings = []
        self.outcome = None
        self.streamed = ""
        self.query_one("#generation-behaviour", Static).update("")
        self.query_one(CodeView).show("")
        findings = self.query_one("#generation-findings", OptionList)
        findings.clear_options()
        findings.display = False
        self._show_stages()

    def _finish_ui(self) -> None:
        self.query_one("#generation-start").disabled = False
        self.query_one("#generation-cancel").disabled = True

    # --- events -----------------------------------------------------------------------------------
    def on_generation_event(self, message: GenerationEvent) -> None:
        from skillwright.pipeline import events

        event = message.event
        if isinstance(event, events.TokenChunk):
            self.streamed += event.text
            self.query_one(CodeView).append(event.text)
            return
        if isinstance(event, events.AttemptStarted):
            what = "repairing" if event.number > 1 else "writing"
            self.attempts.append(f"… {event.target} #{event.number} {what}")
            gap = "\n" if self.streamed else ""
            self.query_one(CodeView).append(
                f"{gap}# {what} {event.target} (answer {event.number})\n"
            )
        elif isinstance(event, events.AttemptFinished):
            attempt = event.attempt
            mark = "✓" if attempt.finish == "stop" else "✗"
            verdict = "ok" if attempt.finish == "stop" else attempt.finish
            line = (
                f"{mark} {attempt.target} #{attempt.number} {verdict}, "
                f"{attempt.completion_tokens or 0} tok {attempt.seconds:.0f} s"
            )
            if self.attempts and self.attempts[-1].startswith("…"):
                self.attempts[-1] = line
            else:
                self.attempts.append(line)
        if isinstance(event, events.StageStarted):
            if not self.stages:
                self.stages = dict.fromkeys(events.STAGES, ("pending", ""))
            self.stages[event.stage] = ("running", event.detail)
        elif isinstance(event, events.StageFinished):
            self.stages[event.stage] = ("done", f"{event.seconds:.2f} s {event.detail}".strip())
        elif isinstance(event, events.Notice):
            self.notify(
                event.message,
                title="Generation",
                severity="warning" if event.level == "warning" else "information",
                markup=False,
            )
            self._stats.append(event.message)
        elif isinstance(event, events.PrefixCacheStatus):
            self._stats.append(f"prefix cache: {event.status}")
        elif isinstance(event, events.GenerationStats):
            parts = []
            if event.prompt_tokens is not None:
                parts.append(f"prompt {event.prompt_tokens} tokens")
            if event.completion_tokens is not None:
                parts.append(f"wrote {event.completion_tokens} tokens")
            if event.tokens_per_second is not None:
                parts.append(f"{event.tokens_per_second:.1f} tokens/s")
            parts.append(f"{event.seconds:.1f} s")
            self._stats.append(", ".join(parts))
        self._show_stages()

    def _show_stages(self) -> None:
        lines = [
            f"{_ICONS[state]} {stage:<10} {text}" for stage, (state, text) in self.stages.items()
        ]
        self.query_one("#generation-stages", Static).update("\n".join(lines) or _IDLE)
        self.query_one("#generation-attempts", Static).update("\n".join(self.attempts))
        self.query_one("#generation-stats", Static).update("\n".join(self._stats))

    def on_generation_finished(self, message: GenerationFinished) -> None:
        outcome = message.outcome
        self.outcome = outcome
        self._finish_ui()
        # Stages that never started were not needed (the skeleton has no model stages).
        for stage, (state, _text) in self.stages.items():
            if state == "pending":
                self.stages[stage] = ("skipped", "not needed")
        self._show_stages()
        code = self.query_one(CodeView)
        code.show(Path(outcome.skill_path).read_text(encoding="utf-8"))
        report = outcome.report
        record = outcome.record
        behaviour = [
            f for part in (record.run, record.simulation) if part is not None for f in part.findings
        ]
        self.findings = list(dict.fromkeys([*report.findings, *behaviour]))
        self.query_one("#generation-behaviour", Static).update(
            "\n".join(self._behaviour_lines(record))
        )
        findings = self.query_one("#generation-findings", OptionList)
        findings.clear_options()
        findings.add_options(
            Option(Text(f"{f.line}:{f.column} {f.severity} [{f.check}] {f.message}"), id=str(i))
            for i, f in enumerate(self.findings)
        )
        findings.display = bool(self.findings)
        verdict = "checks passed" if report.passed else "checks FAILED"
        for name, part in (("run", record.run), ("sim", record.simulation)):
            if part is not None and part.skipped is None:
                verdict += f", {name} {'passed' if part.passed else 'FAILED'}"
        errors = sum(f.severity == "error" for f in self.findings)
        self.query_one("#generation-status", Static).update(
            f"{outcome.mode}: {verdict} ({errors} errors, {len(self.findings) - errors} warnings)"
            f" — written to {self.sw.workspace.relative(Path(outcome.out_dir))}"
        )
        plot = record.simulation.plot if record.simulation is not None else None
        shown = (
            f"; plot in {self.sw.workspace.relative(Path(outcome.out_dir) / plot)}" if plot else ""
        )
        self.notify(
            f"{verdict}; record in {self.sw.workspace.relative(Path(outcome.record_path))}{shown}",
            title="Generation",
            markup=False,
        )
        self.sw.history_changed()

    @staticmethod
    def _behaviour_lines(record: Any) -> list[str]:
        """The run's and the simulation's verdicts, short enough for the side column."""
        lines: list[str] = []
        run = record.run
        if run is not None:
            if run.skipped is not None:
                lines.append(f"- run: {run.skipped}")
            else:
                mark = "✓" if run.passed else "✗"
                lines.append(f"{mark} run {run.errors} err, {run.warnings} warn")
        simulation = record.simulation
        if simulation is not None:
            if simulation.skipped is not None:
                lines.append(f"- sim: {simulation.skipped}")
            else:
                judged = [v for v in simulation.verdicts if v.passed is not None]
                failed = [v for v in judged if v.passed is False]
                mark = "✓" if simulation.passed else "✗"
                lines.append(
                    f"{mark} sim {simulation.where} {len(judged) - len(failed)}/{len(judged)}"
                )
                lines += [f"  ✗ {simulation.verdict_place(v)} {v.oracle}" for v in failed]
            if simulation.plot:
                lines.append(f"plot: {simulation.plot}")
        return lines

    @on(OptionList.OptionSelected, "#generation-findings")
    def _finding_chosen(self, event: OptionList.OptionSelected) -> None:
        finding = self.findings[int(event.option.id or 0)]
        code = self.query_one(CodeView)
        code.jump_to(finding.line, finding.column)
        code.focus()

    def on_job_failed(self, message: JobFailed) -> None:
        if message.job != self.job:
            return
        self._finish_ui()
        status = self.query_one("#generation-status", Static)
        if message.cancelled:
            status.update("cancelled: nothing was written")
        else:
            status.update(f"✗ {message.message}")

    def commands(self) -> Iterable[SystemCommand]:
        yield SystemCommand(
            "Skeleton only", "Generate without a model next time", self._choose_skeleton
        )

    def _choose_skeleton(self) -> None:
        self.sw.update_session(skeleton=True)
        select = self.query_one("#generation-model", Select)
        with self.prevent(Select.Changed):
            select.value = SKELETON
