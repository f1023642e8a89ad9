"""The Generation tab: run :func:`skillwright.pipeline.run_generation` and watch it work.

Each stage's start and end (with its verdict, :mod:`skillwright.pipeline.verdict`), every
answer the model starts (a first answer, or a repair and the rules of the findings it fixes)
and how it ended, the prefix cache, throughput and every streamed token arrive as pipeline
events, posted from the worker thread; a timer shows the elapsed time, the tokens written
against the answer's budget and their rate while it runs (:mod:`skillwright.tui.progress`).
Esc sets the pipeline's cancel event; the pipeline then stops and writes nothing. While
another generation (a CLI run, ``make eval``) holds the model, the status line says so: the
model, this run's place in line and what the holder is doing.

A finished result shows a header with its verdict and the verdict of each judging stage,
its folder as an absolute path (``o`` opens it, ``y`` copies it), the code with the findings,
and (``v``) the simulation: every oracle's verdict with its numbers and the base's path and
speed drawn in the terminal. The result folder and record are the pipeline's, exactly as in
headless mode. A new run asks first when it would replace a result on screen (the result
stays on disk and in History).
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import threading
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

from rich.text import Text
from textual import on, work
from textual.app import ComposeResult, SystemCommand
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, Vertical, VerticalScroll
from textual.widgets import Button, ContentSwitcher, OptionList, Select, Static
from textual.widgets.option_list import Option
from textual.worker import Worker

from skillwright.errors import SkillwrightError
from skillwright.pipeline.verdict import StageVerdict, Verdict, attempt_verdict, overall
from skillwright.tui.messages import (
    GenerationEvent,
    GenerationFinished,
    JobFailed,
    ModelsListed,
    ResultRestored,
)
from skillwright.tui.progress import Progress
from skillwright.tui.screens.base import Pane
from skillwright.tui.screens.confirm import ConfirmScreen
from skillwright.tui.widgets.code_view import CodeView
from skillwright.tui.widgets.simulation import SimulationView

if TYPE_CHECKING:
    from skillwright.rules.finding import Finding

__all__ = ["JUDGING", "SKELETON", "GenerationPane", "stage_text"]

SKELETON = "skeleton"
CANDIDATE_CHOICES = (1, 2, 4, 8)
"""Candidate skills of the first round the selector offers (best-of-N; 1: greedy only)."""
"""Value of the model selector that asks for the deterministic skeleton only."""

JUDGING = ("checks", "run", "simulate")
"""The stages that judge the skill; the result header names their verdicts."""

_IDLE = "Ctrl+G generates a skill from the current inputs."
_RUNNING_STATUS = "Esc cancels; nothing is written then"
_PENDING, _RUNNING = "pending", "running"
_TICK = 0.5
"""Seconds between updates of the live progress."""


def stage_text(stage: str, state: str, text: str) -> Text:
    """One line of the stage list: the mark (``·`` to come, ``…`` running, else the
    verdict's), the stage and what it did, coloured as its verdict."""
    if state == _PENDING:
        return Text(f"· {stage:<10} {text}".rstrip(), style="dim")
    if state == _RUNNING:
        return Text(f"… {stage:<10} {text}".rstrip(), style="bold")
    verdict = Verdict(state)
    line = Text()
    line.append(f"{verdict.mark} ", style=verdict.style)
    line.append(f"{stage:<10} ")
    line.append(text)
    return line


def _attempt_line(attempt: Any) -> Text:
    """One line per answer of the model, with its verdict's mark and word."""
    judged = attempt_verdict(attempt)
    line = Text()
    line.append(f"{judged.verdict.mark} ", style=judged.verdict.style)
    line.append(f"{attempt.target} #{attempt.number} ")
    word = judged.verdict.word + (f" ({judged.reason})" if judged.reason else "")
    line.append(word, style=judged.verdict.style)
    if attempt.finish != "fixed":
        line.append(f", {attempt.completion_tokens or 0} tok {attempt.seconds:.0f} s")
    return line


def verdict_words(verdicts: dict[str, StageVerdict]) -> Text:
    """``checks ✗ failed · run - skipped · simulate ✓ passed``, each in its colour."""
    text = Text()
    for number, stage in enumerate(JUDGING):
        judged = verdicts[stage]
        if number:
            text.append(" · ", style="dim")
        text.append(f"{stage} ")
        text.append(f"{judged.verdict.mark} {judged.verdict.word}", style=judged.verdict.style)
    return text


def open_folder(folder: Path) -> str | None:
    """Opens ``folder`` in the desktop's file manager; the problem when it cannot."""
    opener = "open" if sys.platform == "darwin" else "xdg-open"
    program = shutil.which(opener)
    if program is None:
        return f"no {opener} on this machine to open folders with"
    try:
        subprocess.Popen(
            [program, str(folder)],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,
        )
    except OSError as error:
        return f"{opener} could not be started ({error.strerror or error})"
    return None


class GenerationPane(Pane):
    """Model choice, stage progress, the result's verdicts, code, findings and simulation."""

    job = "generation"
    primary = "#generation-code"
    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("v", "toggle_view", "Code/Simulation"),
        Binding("o", "open_folder", "Open folder"),
        Binding("y", "copy_folder", "Copy path"),
    ]

    def __init__(self) -> None:
        super().__init__(id="generation-pane")
        self._worker: Worker[None] | None = None
        self._cancel: threading.Event | None = None
        self.stages: dict[str, tuple[str, str]] = {}
        """Stage -> (state, text shown after it); the state is ``pending``, ``running`` or
        the word of its :class:`~skillwright.pipeline.verdict.Verdict`."""
        self.findings: list[Finding] = []
        self.outcome: Any = None
        """The pipeline ``Outcome`` of the result shown (a restored one has only a record)."""
        self.shown: tuple[Path, Any] | None = None
        """The result on screen: its folder and record."""
        self._stats: list[str] = []
        self.attempts: list[Any] = []
        """The model's answers of the current run (``Attempt`` documents), in order."""
        self._asking: Any = None
        """The answer being written (its ``AttemptStarted`` event), if one is."""
        self._waiting = False
        """The run waits for a model another generation holds (the status line says so)."""
        self.streamed = ""
        """Everything the model wrote in the current run."""
        self.progress = Progress()

    def compose(self) -> ComposeResult:
        with Horizontal(id="generation-bar", classes="bar"):
            yield Select[str]([], prompt="model", id="generation-model", compact=True)
            yield Select[int](
                [("1 candidate", 1)]
                + [(f"best of {n} candidates", n) for n in CANDIDATE_CHOICES if n > 1],
                value=self.sw.session.candidates
                if self.sw.session.candidates in CANDIDATE_CHOICES
                else 1,
                allow_blank=False,
                id="generation-candidates",
                compact=True,
            )
            yield Button("Generate ^G", id="generation-start", variant="primary", compact=True)
            yield Button("Cancel Esc", id="generation-cancel", compact=True)
        yield Static(_IDLE, id="generation-header", markup=False)
        with Horizontal(id="generation-body"):
            with VerticalScroll(id="generation-side"):
                yield OptionList(id="generation-stages")
                yield Static("", id="generation-stage-detail", markup=False)
                yield Static("", id="generation-progress", markup=False)
                yield Static("", id="generation-attempts", markup=False)
                yield Static("", id="generation-stats", markup=False)
            with ContentSwitcher(initial="generation-main", id="generation-view"):
                with Vertical(id="generation-main"):
                    yield CodeView(id="generation-code")
                    yield OptionList(id="generation-findings")
                yield SimulationView(id="generation-simulation")
        yield Static("", id="generation-status", markup=False)

    def on_mount(self) -> None:
        self.query_one("#generation-cancel").disabled = True
        self.query_one("#generation-findings").display = False
        self._show_stages()
        self.set_interval(_TICK, self._tick)
        self._list_models()
        self._restore()

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

    @on(Select.Changed, "#generation-candidates")
    def _candidates_chosen(self, event: Select.Changed) -> None:
        if isinstance(event.value, int):
            self.sw.update_session(candidates=event.value)

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
        """Checks the inputs are there, asks before replacing a result on screen, then runs
        the pipeline in a worker."""
        if self.running:
            self.notify("a generation is running; Esc cancels it", title="Generation", markup=False)
            return
        if self.shown is None:
            self._start()
            return
        folder = self.sw.workspace.relative(self.shown[0])
        self.app.push_screen(
            ConfirmScreen(
                f"Start a new generation? It replaces the result on screen ({folder}); that "
                "folder stays on disk and in History (F7).",
                "Generate",
            ),
            self._confirmed,
        )

    def _confirmed(self, answer: bool | None) -> None:
        if answer:
            self._start()

    def _start(self) -> None:
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
            "ontologies": self.sw.workspace.ontologies(),
            "model": None if session.skeleton else session.model,
            "skeleton": session.skeleton,
            "k": session.k,
            "include_infrastructure": session.show_infrastructure,
            "pinned": tuple(n for n in session.pinned if n in known),
            "dropped": tuple(n for n in session.dropped if n in known),
            "models_file": self.sw.models_file,
            "dense": session.dense,
            "attempts": session.attempts,
            "candidates": 1 if session.skeleton else session.candidates,
        }
        self._reset()
        self._cancel = threading.Event()
        self.progress.begin()
        self.query_one("#generation-start").disabled = True
        self.query_one("#generation-cancel").disabled = False
        self.query_one("#generation-header", Static).update(
            f"generating {spec.name} into {out_dir.resolve()} …"
        )
        self.query_one("#generation-status", Static).update(_RUNNING_STATUS)
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
        self._asking = None
        self.findings = []
        self.outcome = None
        self.shown = None
        self.streamed = ""
        self.query_one(CodeView).show("")
        self.query_one(ContentSwitcher).current = "generation-main"
        findings = self.query_one("#generation-findings", OptionList)
        findings.clear_options()
        findings.display = False
        self._show_stages()

    def _finish_ui(self) -> None:
        self.progress.end()
        self.query_one("#generation-progress", Static).update("")
        self.query_one("#generation-start").disabled = False
        self.query_one("#generation-cancel").disabled = True

    # --- events -----------------------------------------------------------------------------------
    def on_generation_event(self, message: GenerationEvent) -> None:
        from skillwright.pipeline import events

        event = message.event
        if isinstance(event, events.ModelWaiting):
            # Every half second while it waits: only the status line changes.
            self._waiting = True
            self.query_one("#generation-status", Static).update(
                f"{event.message} — {_RUNNING_STATUS}"
            )
            return
        if self._waiting:
            self._waiting = False
            self.query_one("#generation-status", Static).update(_RUNNING_STATUS)
        if isinstance(event, events.TokenChunk):
            self.streamed += event.text
            self.progress.tokens(event.pieces)
            self.query_one(CodeView).append(event.text)
            return
        if isinstance(event, events.AttemptStarted):
            self._asking = event
            self.progress.answer_started(
                event.target, event.number, event.max_tokens, event.problem_codes
            )
            what = "repairing" if event.number > 1 else "writing"
            why = f" for {', '.join(event.problem_codes)}" if event.problem_codes else ""
            gap = "\n" if self.streamed else ""
            self.query_one(CodeView).append(
                f"{gap}# {what} {event.target} (answer {event.number}){why}\n"
            )
        elif isinstance(event, events.AttemptFinished):
            self._asking = None
            self.progress.answer_ended()
            self.attempts.append(event.attempt)
        elif isinstance(event, events.StageStarted):
            if not self.stages:
                self.stages = dict.fromkeys(events.STAGES, (_PENDING, ""))
            self.stages[event.stage] = (_RUNNING, event.detail)
            self.progress.stage_started(event.stage)
        elif isinstance(event, events.StageFinished):
            text = f"{event.seconds:.2f} s {event.detail}".strip()
            self.stages[event.stage] = (event.verdict, text)
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

    def _tick(self) -> None:
        """Redraws the live progress (and the running stage's clock) while a run goes on."""
        if self.progress.started is None:
            return
        self.query_one("#generation-progress", Static).update("\n".join(self.progress.lines()))

    def _show_stages(self) -> None:
        stages = self.query_one("#generation-stages", OptionList)
        highlighted = stages.highlighted
        stages.clear_options()
        if self.stages:
            lines = [stage_text(stage, *state) for stage, state in self.stages.items()]
            stages.add_options(
                Option(line, id=stage) for line, stage in zip(lines, self.stages, strict=True)
            )
            if highlighted is not None and highlighted < len(lines):
                stages.highlighted = highlighted
        stages.display = bool(self.stages)
        self._show_stage_detail()
        attempts = Text("\n").join(_attempt_line(a) for a in self.attempts)
        if self._asking is not None:
            what = "repairing" if self._asking.number > 1 else "writing"
            codes = self._asking.problem_codes
            why = f" for {', '.join(codes)}" if codes else ""
            if attempts:
                attempts.append("\n")
            attempts.append(f"… {self._asking.target} #{self._asking.number} {what}{why}")
        self.query_one("#generation-attempts", Static).update(attempts)
        self.query_one("#generation-stats", Static).update("\n".join(self._stats))
        self._tick()

    @on(OptionList.OptionHighlighted, "#generation-stages")
    def _show_stage_detail(self) -> None:
        """The whole text of the highlighted stage (or the running one), under the list."""
        box = self.query_one("#generation-stage-detail", Static)
        stages = self.query_one("#generation-stages", OptionList)
        names = list(self.stages)
        chosen: str | None = None
        if stages.has_focus and stages.highlighted is not None and stages.highlighted < len(names):
            chosen = names[stages.highlighted]
        else:
            chosen = next((n for n, (state, _) in self.stages.items() if state == _RUNNING), None)
        if chosen is None:
            box.update("")
            return
        state, text = self.stages[chosen]
        word = {_PENDING: "to come", _RUNNING: "running"}.get(state, state)
        box.update(f"{chosen} ({word}): {text}" if text else f"{chosen} ({word})")

    # --- the result -------------------------------------------------------------------------------
    def on_generation_finished(self, message: GenerationFinished) -> None:
        outcome = message.outcome
        self._finish_ui()
        self.show_result(Path(outcome.out_dir), outcome.record)
        self.outcome = outcome
        self.sw.update_session(last_result=self.sw.workspace.relative(Path(outcome.out_dir)))
        judged = overall(self._verdicts(outcome.record))
        plot = outcome.record.simulation.plot if outcome.record.simulation is not None else None
        self.notify(
            f"{judged.word}; record in {Path(outcome.record_path).resolve()}"
            + ("; v shows the simulation" if plot else ""),
            title="Generation",
            severity="information" if judged is Verdict.PASSED else "warning",
            markup=False,
        )
        self.sw.history_changed()

    @staticmethod
    def _verdicts(record: Any) -> dict[str, StageVerdict]:
        from skillwright.pipeline.verdict import stage_verdicts

        return stage_verdicts(record)

    def show_result(self, folder: Path, record: Any, *, restored: bool = False) -> None:
        """Shows the result in ``folder`` (its ``record``): verdicts, code, findings and the
        simulation. ``restored``: it is the last result of an earlier session."""
        from skillwright.pipeline import events

        self.shown = (folder, record)
        verdicts = self._verdicts(record)
        stages = dict(self.stages) or dict.fromkeys(events.STAGES, (_PENDING, ""))
        for stage, judged in verdicts.items():
            state, text = stages.get(stage, (_PENDING, ""))
            if state in (_PENDING, _RUNNING):
                # Never started in this run (or restored): the record says why.
                seconds = record.timings.get(stage)
                text = "" if seconds is None else f"{seconds:.2f} s"
                text = f"{text} {judged.reason}".strip()
            stages[stage] = (judged.verdict.word, self._with_own_time(stage, text, record))
        self.stages = stages
        # The record's answers are judged (their errors filled in), the events' were not yet.
        self.attempts = list(record.model.attempts) if record.model is not None else []
        self._asking = None
        self._show_stages()
        skill = folder / "skill.py"
        try:
            code = skill.read_text(encoding="utf-8")
        except OSError as error:
            code = f"# {skill}: cannot be read ({error.strerror or error})\n"
        self.query_one(CodeView).show(code)
        behaviour = [
            f for part in (record.run, record.simulation) if part is not None for f in part.findings
        ]
        self.findings = list(dict.fromkeys([*record.checks.findings, *behaviour]))
        findings = self.query_one("#generation-findings", OptionList)
        findings.clear_options()
        findings.add_options(
            Option(
                Text(f"{f.line}:{f.column} {f.severity} [{f.code or f.check}] {f.message}"),
                id=str(i),
            )
            for i, f in enumerate(self.findings)
        )
        findings.display = bool(self.findings)
        self.query_one(SimulationView).show(record.simulation, folder)
        self._show_header(folder, record, verdicts, restored=restored)

    @staticmethod
    def _with_own_time(stage: str, text: str, record: Any) -> str:
        """The run's and the simulation's own wall time: the stage only reuses the result
        when the repair loop already ran the same code, and then takes no time itself."""
        part = {"run": record.run, "simulate": record.simulation}.get(stage)
        seconds = getattr(part, "seconds", None)
        if seconds is None or f"took {seconds:.1f} s" in text:
            return text
        return f"{text}; took {seconds:.1f} s".lstrip("; ")

    def _show_header(
        self, folder: Path, record: Any, verdicts: dict[str, StageVerdict], *, restored: bool
    ) -> None:
        judged = overall(verdicts)
        header = Text(f"{judged.mark} {judged.word.upper()} ", style=f"bold {judged.style}")
        header.append(f"{record.mode} {record.skill_name}: ")
        header.append_text(verdict_words(verdicts))
        header.append(f"\n{folder.resolve()}", style="bold")
        header.append("  o opens · y copies", style="dim")
        if record.simulation is not None and record.simulation.skipped is None:
            header.append(" · v simulation", style="dim")
        self.query_one("#generation-header", Static).update(header)
        errors = sum(f.severity == "error" for f in self.findings)
        when = f"restored from the last session ({record.created})" if restored else "written"
        self.query_one("#generation-status", Static).update(
            f"{judged.word}: {errors} error(s), {len(self.findings) - errors} warning(s); {when}"
        )

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
        # What was running did not finish: it has no verdict, and the streamed answers were
        # discarded with the rest.
        for stage, (state, _text) in self.stages.items():
            if state == _RUNNING:
                why = "cancelled" if message.cancelled else "stopped by an error"
                self.stages[stage] = (Verdict.NOT_RUN.word, why)
        self._asking = None
        self._show_stages()
        status = self.query_one("#generation-status", Static)
        header = self.query_one("#generation-header", Static)
        if message.cancelled:
            status.update("cancelled: nothing was written")
            header.update("cancelled: nothing was written; the streamed answers were discarded")
        else:
            status.update(f"✗ {message.message}")
            header.update(Text(f"✗ {message.message}", style="red"))
        self.query_one(CodeView).show("")

    # --- restoring the last result ---------------------------------------------------------------
    def _restore(self) -> None:
        stored = self.sw.session.last_result
        if stored:
            folder = self.sw.workspace.absolute(stored)
            if (folder / "record.json").is_file():
                self._read_result(folder)

    @work(thread=True, group="generation-restore", exit_on_error=False)
    def _read_result(self, folder: Path) -> None:
        from skillwright.pipeline.record import GenerationRecord

        try:
            record = GenerationRecord.load(folder / "record.json")
        except SkillwrightError as error:
            self.fail(f"the last result could not be shown: {error}")
            return
        self.post_message(ResultRestored(folder, record))

    def on_result_restored(self, message: ResultRestored) -> None:
        if self.running or self.shown is not None:
            return  # a new run started (or finished) meanwhile: it is what the user wants
        self.show_result(message.folder, message.record, restored=True)

    # --- keys of a result -------------------------------------------------------------------------
    def _folder(self) -> Path | None:
        if self.shown is None:
            self.notify("no result on screen yet: generate one (Ctrl+G)", title="Generation")
            return None
        return self.shown[0].resolve()

    def action_toggle_view(self) -> None:
        """Switches between the code with its findings and the simulation."""
        switcher = self.query_one(ContentSwitcher)
        if switcher.current == "generation-main":
            switcher.current = "generation-simulation"
            self.focus_now(self.query_one("#simulation-oracles"))
        else:
            switcher.current = "generation-main"
            self.focus_now(self.query_one(CodeView))

    def action_open_folder(self) -> None:
        """Opens the result's folder in the file manager (says why when it cannot)."""
        folder = self._folder()
        if folder is None:
            return
        problem = open_folder(folder)
        if problem is None:
            self.notify(f"opened {folder}", title="Generation", markup=False)
        else:
            self.app.copy_to_clipboard(str(folder))
            self.notify(
                f"{problem}; its path is copied instead: {folder}",
                title="Generation",
                severity="warning",
                markup=False,
            )

    def action_copy_folder(self) -> None:
        """Copies the result folder's absolute path (through the terminal's clipboard)."""
        folder = self._folder()
        if folder is not None:
            self.app.copy_to_clipboard(str(folder))
            self.notify(f"copied {folder}", title="Generation", markup=False)

    def commands(self) -> Iterable[SystemCommand]:
        yield SystemCommand(
            "Skeleton only", "Generate without a model next time", self._choose_skeleton
        )
        yield SystemCommand(
            "Show simulation", "The oracles and the plots of the result (v)", self._simulation
        )
        yield SystemCommand(
            "Open result folder", "In the file manager (o)", self.action_open_folder
        )
        yield SystemCommand("Copy result folder", "Its absolute path (y)", self.action_copy_folder)

    def _simulation(self) -> None:
        self.sw.action_show_tab("generation")
        if self.query_one(ContentSwitcher).current == "generation-main":
            self.action_toggle_view()

    def _choose_skeleton(self) -> None:
        self.sw.update_session(skeleton=True)
        select = self.query_one("#generation-model", Select)
        with self.prevent(Select.Changed):
            select.value = SKELETON
