"""The Generation tab: the pipeline runs in a worker, streams, can be cancelled, and writes
the same result folder and record as the headless command."""

from __future__ import annotations

import asyncio
import time
from pathlib import Path
from typing import Any

import pytest
from textual import events
from textual.widgets import DataTable, Input, OptionList, Select, Static, TabbedContent

from skillwright.errors import GenerationCancelledError
from skillwright.pipeline import GenerationRecord
from skillwright.tui.screens.generation import SKELETON, GenerationPane
from skillwright.tui.screens.history import HistoryPane
from skillwright.tui.session import SpecDraft
from skillwright.tui.widgets.code_view import CodeView
from skillwright.tui.widgets.simulation import SimulationView
from tests.tui.conftest import (
    MODEL_RUN,
    STEP,
    Watch,
    app_for,
    notifications,
    preset_session,
    running,
    screen_text,
    wait_until,
    write_models,
)

pytestmark = pytest.mark.anyio

# get-position with only /tf keeps the prompt short enough for the tiny model's context.
INPUTS = {
    "capability": "get-position.ttl",
    "spec_path": "get-position.spec.yaml",
    "interfaces": "recordings/mr1",
    "k": 0,
    "pinned": ("/tf",),
    "dense": False,
    "active_tab": "generation",
    "attempts": 1,
}


def _tab(app: Any) -> str:
    return str(app.query_one("#tabs", TabbedContent).active)


async def _send_keys(app: Any, keys: list[str], done: Any) -> None:
    """Sends ``keys`` as the terminal driver would and waits until ``done()``.

    (``Pilot.press`` waits for the process to go idle after each key, which a busy worker
    thread never lets it do.)
    """
    started = time.monotonic()
    for key in keys:
        app._driver.send_message(events.Key(key, key if len(key) == 1 else None))
    while not done():
        assert time.monotonic() - started < STEP, (
            f"keys {keys} not handled in {STEP} s: tab {_tab(app)}, focus on {app.focused}"
        )
        await asyncio.sleep(0.01)


def _status(app: Any) -> str:
    return str(app.query_one("#generation-status", Static).render())


def _header(app: Any) -> str:
    return str(app.query_one("#generation-header", Static).render())


def _results(workspace: Path) -> list[Path]:
    generated = workspace / "generated"
    return sorted(generated.iterdir()) if generated.exists() else []


async def _ready(pilot: Any, app: Any) -> GenerationPane:
    pane = app.query_one(GenerationPane)
    await wait_until(
        pilot,
        lambda: (
            app.loaded.capability is not None
            and app.loaded.inventory is not None
            and app.spec_pane().spec is not None
            and app.query_one("#generation-model", Select).value is not Select.NULL
        ),
    )
    return pane


async def test_a_skeleton_run_writes_the_result_and_findings_jump_to_their_lines(
    workspace: Path,
) -> None:
    preset_session(workspace, **INPUTS, skeleton=True)
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        pane = await _ready(pilot, app)
        assert app.query_one("#generation-model", Select).value == SKELETON
        await pilot.press("ctrl+g")
        await wait_until(pilot, lambda: pane.outcome is not None)
        [result] = _results(workspace)
        assert result.name.startswith("get_position-")
        record = GenerationRecord.load(result / "record.json")
        assert record.mode == "skeleton"
        assert record.retrieval.pinned == ["/tf"]
        code = app.query_one("#generation-code", CodeView)
        assert code.text == (result / "skill.py").read_text(encoding="utf-8")
        # The stage list's verdicts are the record's: its states still raise, so the checks
        # failed and the run and the simulation were skipped; no model stage ran.
        assert {stage: state for stage, (state, _) in pane.stages.items()} == record.verdicts
        assert record.verdicts == {
            "inputs": "passed",
            "retrieval": "passed",
            "skeleton": "passed",
            "model": "skipped",
            "generation": "skipped",
            "checks": "failed",
            "run": "skipped",
            "simulate": "skipped",
            "outputs": "passed",
        }
        assert _status(app).startswith("failed: ")
        header = _header(app)
        assert header.startswith("✗ FAILED skeleton get_position: checks ✗ failed")
        assert "run - skipped · simulate - skipped" in header
        assert str(result.resolve()) in header
        text = screen_text(app)
        assert "✗ checks" in text
        assert "✓ checks" not in text
        findings = app.query_one("#generation-findings", OptionList)
        assert findings.option_count == len(record.checks.findings) > 0
        findings.focus()
        await pilot.press("down", "enter")
        target = pane.findings[findings.highlighted or 0]
        assert app.focused is code
        assert code.cursor_location[0] == target.line - 1
        # The history lists the new result.
        history = app.query_one(HistoryPane)
        await wait_until(pilot, lambda: [f for f, _ in history.entries] == [result])


def _with_behaviour(record: GenerationRecord) -> GenerationRecord:
    """``record`` as if its skill had been run (one finding) and simulated (one oracle
    failed), with a plot."""
    from skillwright.pipeline.record import (
        RunEpisodeRecord,
        RunRecord,
        SimulationRecord,
        VerdictRecord,
    )
    from skillwright.rules.finding import Finding

    ran = Finding(check="run.exception", severity="error", line=40, message="ValueError here")
    judged = Finding(check="behaviour.output", severity="error", line=30, message="off by 0.3")
    verdicts = [
        VerdictRecord(
            episode="normal", oracle="outcome", kind="outcome", check="", passed=True, message=""
        ),
        VerdictRecord(
            episode="normal",
            oracle="output:outPositionX",
            kind="output",
            check="abs(outPositionX - x) <= 0.03",
            passed=False,
            message="reported 0.0, measured 0.3",
        ),
    ]
    return record.model_copy(
        update={
            "run": RunRecord(
                passed=False,
                world="kinematic",
                errors=1,
                findings=[ran],
                episodes=[
                    RunEpisodeRecord(
                        name="normal", ended="done", virtual_seconds=1.0, wall_seconds=2.0
                    )
                ],
            ),
            "simulation": SimulationRecord(
                passed=False,
                scenario="at_origin",
                verdicts=verdicts,
                findings=[judged],
                plot="simulation.png",
            ),
        }
    )


async def test_run_findings_sim_verdicts_and_the_plot_are_shown_at_80_columns(
    workspace: Path,
) -> None:
    from skillwright.tui.messages import GenerationFinished

    preset_session(workspace, **INPUTS, skeleton=True)
    app = app_for(workspace)
    async with running(app, (80, 24)) as pilot:
        pane = await _ready(pilot, app)
        await pilot.press("ctrl+g")
        await wait_until(pilot, lambda: pane.outcome is not None)
        outcome = pane.outcome
        outcome.record = _with_behaviour(outcome.record)
        pane.post_message(GenerationFinished(outcome))
        await wait_until(pilot, lambda: "run ✗ failed" in _header(app))
        assert "simulate ✗ failed" in _header(app)
        assert "checks ✗ failed" in _header(app)
        checks = {f.check for f in pane.findings}
        assert {"run.exception", "behaviour.output"} <= checks
        findings = app.query_one("#generation-findings", OptionList)
        assert findings.option_count == len(pane.findings)
        # v shows every oracle, the passed one too, with its numbers.
        await pilot.press("v")
        view = app.query_one(SimulationView)
        await wait_until(pilot, lambda: view.display and view.size.height > 0)
        table = app.query_one("#simulation-oracles", DataTable)
        assert table.row_count == 2
        first = [str(cell) for cell in table.get_row_at(0)]
        assert first[:3] == ["✗", "normal", "output:outPositionX"]
        assert first[4] == "abs(outPositionX - x) <= 0.03"
        assert "✓" in [str(cell) for cell in table.get_row_at(1)]
        detail = str(app.query_one("#simulation-oracle", Static).render())
        assert "expected: abs(outPositionX - x) <= 0.03" in detail
        await pilot.press("v")
        assert app.focused is app.query_one("#generation-code", CodeView)


async def test_the_tiny_model_streams_its_tokens_and_reports_each_stage(
    workspace: Path, models_file: Path
) -> None:
    preset_session(workspace, **INPUTS)
    app = app_for(workspace, models_file)
    async with running(app, (160, 48)) as pilot:
        pane = await _ready(pilot, app)
        assert app.query_one("#generation-model", Select).value == "tiny"
        await pilot.press("ctrl+g")
        await wait_until(pilot, lambda: pane.outcome is not None, timeout=MODEL_RUN)
        [result] = _results(workspace)
        record = GenerationRecord.load(result / "record.json")
        assert record.mode == "llm"
        assert record.model is not None
        assert record.model.id == "tiny"
        assert pane.streamed == "".join(a.response for a in record.model.attempts)
        assert pane.streamed
        assert (result / "conversation.txt").is_file()
        # Random weights write no method that passes the checks: nothing is run or simulated,
        # and the stage list says so in the record's words.
        assert {stage: state for stage, (state, _) in pane.stages.items()} == record.verdicts
        assert [pane.stages[n][0] for n in ("checks", "run", "simulate")] == [
            "failed",
            "skipped",
            "skipped",
        ]
        # One line per answer, in the order asked, with how it ended.
        attempts = str(app.query_one("#generation-attempts", Static).render()).splitlines()
        assert [line.split()[1] for line in attempts][:3] == ["starting", "execute", "completing"]
        assert all(line.startswith("✗") and "#1" in line for line in attempts)
        stats = str(app.query_one("#generation-stats", Static).render())
        assert f"prefix cache: {record.model.prefix_cache}" in stats
        assert "tokens/s" in stats
        assert f"wrote {record.model.completion_tokens} tokens" in stats
        text = screen_text(app)
        generation = pane.stages["generation"][0]
        assert generation == ("failed" if record.model.states_missing else "passed")
        assert ("✗ generation" if record.model.states_missing else "✓ generation") in text


async def test_best_of_n_is_chosen_beside_the_model_and_every_candidate_is_recorded(
    workspace: Path, models_file: Path
) -> None:
    preset_session(workspace, candidates=2, **INPUTS)
    app = app_for(workspace, models_file)
    async with running(app, (160, 48)) as pilot:
        pane = await _ready(pilot, app)
        assert app.query_one("#generation-candidates", Select).value == 2
        await pilot.press("ctrl+g")
        await wait_until(pilot, lambda: pane.outcome is not None, timeout=MODEL_RUN)
        [result] = _results(workspace)
        record = GenerationRecord.load(result / "record.json")
        assert record.model is not None
        assert record.model.candidates_asked == 2
        assert [v.index for v in record.model.candidates] == [0, 1]
        assert sum(v.won for v in record.model.candidates) == 1
        starting = [a for a in record.model.attempts if a.target == "starting"]
        assert sorted(a.candidate for a in starting if a.candidate is not None) == [0, 1]
        # Only the greedy candidate's text is streamed to the screen.
        greedy = "".join(a.response for a in record.model.attempts if a.candidate in (0, None))
        assert pane.streamed == greedy


async def test_the_ui_keeps_working_while_the_model_runs_and_esc_cancels_it(
    workspace: Path, tmp_path: Path, tiny_gguf: Path
) -> None:
    # The byte-level tiny model (not the wordy one) reads the prompt for seconds: the keys
    # below are pressed while the worker is busy in llama.cpp. The answer is long enough that
    # the run is still going when the test presses Esc: the tiny model writes a few hundred
    # tokens a second, and on a busy machine the keys can take many seconds.
    models = write_models(tmp_path / "long.toml", tiny_gguf, max_tokens=8000)
    preset_session(workspace, **INPUTS)
    app = app_for(workspace, models)
    async with running(app, (120, 40)) as pilot:
        pane = await _ready(pilot, app)
        await pilot.press("ctrl+g")
        await wait_until(pilot, lambda: pane.running and "model" in pane.stages)
        # While the worker loads the model and evaluates the prompt, keys are answered.
        options = app.query_one("#capability-list")
        await _send_keys(app, ["f2"], lambda: app.focused is options)
        table = app.query_one("#interfaces-table")
        await _send_keys(app, ["f4"], lambda: app.focused is table)
        field = app.query_one("#interfaces-filter", Input)
        await _send_keys(app, ["slash"], lambda: app.focused is field)
        await _send_keys(app, list("abc"), lambda: field.value == "abc")
        await _send_keys(app, ["f6"], lambda: _tab(app) == "generation")
        assert pane.running, "the keys were handled while the generation worker ran"
        # Once the model writes, the progress counts its tokens against the answer's budget.
        await wait_until(pilot, lambda: pane.streamed, timeout=MODEL_RUN)
        progress = app.query_one("#generation-progress", Static)
        await wait_until(pilot, lambda: "/8000 tokens" in str(progress.render()))
        lines = str(progress.render()).splitlines()
        assert lines[0].startswith("elapsed ")
        assert " · generation " in lines[0]
        assert lines[1].startswith("writing ")
        assert lines[1].endswith("(first answer)")
        # Esc stops it; nothing is written, and nothing it streamed is left on screen.
        await pilot.press("escape")
        await wait_until(pilot, lambda: not pane.running)
        assert "cancelled: nothing was written" in _status(app)
        assert app.query_one("#generation-code", CodeView).text == ""
        assert "…" not in str(app.query_one("#generation-attempts", Static).render())
        assert pane.stages["generation"] == ("not run", "cancelled")
        assert str(progress.render()) == ""
        assert any("cancelled" in n for n in notifications(app))
        assert _results(workspace) == []
        assert not app.query_one("#generation-start").disabled


async def test_a_model_in_use_elsewhere_is_waited_for_on_the_status_line_and_esc_ends_it(
    workspace: Path, models_file: Path, wordy_gguf: Path
) -> None:
    import threading

    from skillwright.llm.model_lock import acquire_model_lock, note_activity

    taken, done = threading.Event(), threading.Event()

    def hold() -> None:  # another generation (a CLI run) holds the model
        note_activity(skill="patrol", stage="generation")
        lock = acquire_model_lock("tiny", wordy_gguf)
        taken.set()
        done.wait(120)
        lock.release()

    holder = threading.Thread(target=hold)
    holder.start()
    assert taken.wait(30)
    preset_session(workspace, **INPUTS)
    app = app_for(workspace, models_file)
    try:
        async with running(app, (160, 48)) as pilot:
            pane = await _ready(pilot, app)
            await pilot.press("ctrl+g")
            await wait_until(pilot, lambda: "waiting for model tiny" in _status(app))
            status = _status(app)
            assert "skill patrol, stage generation; next in line" in status
            assert status.endswith("Esc cancels; nothing is written then")
            await pilot.press("escape")
            await wait_until(pilot, lambda: not pane.running)
            assert "cancelled: nothing was written" in _status(app)
            assert _results(workspace) == []
    finally:
        done.set()
        holder.join(30)


async def test_a_missing_model_is_named_and_nothing_is_written(
    workspace: Path, models_file: Path
) -> None:
    preset_session(workspace, **INPUTS, model="ghost")
    app = app_for(workspace, models_file)
    async with running(app, (120, 40)) as pilot:
        pane = await _ready(pilot, app)
        select = app.query_one("#generation-model", Select)
        assert select.value == "ghost"
        assert "ghost (file missing)" in screen_text(app)
        await pilot.press("ctrl+g")
        await wait_until(pilot, lambda: "✗" in _status(app))
        assert not pane.running
        assert "ghost" in _status(app)
        assert any("ghost.gguf" in n for n in notifications(app))
        assert _results(workspace) == []


async def test_generation_names_the_input_that_is_missing(workspace: Path) -> None:
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("ctrl+g")
        await wait_until(pilot, lambda: any("capability first" in n for n in notifications(app)))
        assert not app.query_one(GenerationPane).running


async def test_an_invalid_specification_stops_generation_and_shows_the_form(
    workspace: Path,
) -> None:
    inputs = {**INPUTS, "spec_path": None, "spec_draft": SpecDraft(name="no_states")}
    preset_session(workspace, **inputs)
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await wait_until(
            pilot,
            lambda: (
                app.loaded.capability is not None
                and app.loaded.inventory is not None
                and app.spec_pane().ready
            ),
        )
        await pilot.press("ctrl+g")
        await wait_until(pilot, lambda: any("'execute' state" in n for n in notifications(app)))
        assert app.query_one("#tabs", TabbedContent).active == "specification"
        assert _results(workspace) == []


async def test_quitting_during_a_generation_stops_it_and_writes_nothing(
    workspace: Path, tmp_path: Path, wordy_gguf: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.pipeline import run as pipeline_run

    # The engine call's own outcome, whatever the app has done by then: a pipeline that ran
    # to its end after the quit would return an Outcome instead of raising.
    generation = Watch(monkeypatch, pipeline_run, "run_generation")
    models = write_models(tmp_path / "long.toml", wordy_gguf, max_tokens=8000)
    preset_session(workspace, **INPUTS)
    app = app_for(workspace, models)
    async with running(app) as pilot:
        pane = await _ready(pilot, app)
        await pilot.press("ctrl+g")
        await wait_until(pilot, lambda: pane.streamed, timeout=MODEL_RUN)
        await pilot.press("ctrl+q")
    assert isinstance(await generation.first(), GenerationCancelledError)
    assert _results(workspace) == []


async def test_a_new_run_asks_before_it_replaces_the_result_on_screen(workspace: Path) -> None:
    from skillwright.tui.screens.confirm import ConfirmScreen

    preset_session(workspace, **INPUTS, skeleton=True)
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        pane = await _ready(pilot, app)
        await pilot.press("ctrl+g")
        await wait_until(pilot, lambda: pane.outcome is not None)
        [first] = _results(workspace)
        # Enter on the focused Generate button asks first; No keeps the result.
        app.set_focus(app.query_one("#generation-start"))
        await pilot.press("enter")
        await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
        assert "History" in str(app.screen.query_one("#confirm-question", Static).render())
        await pilot.press("enter")  # the focus is on No: an Enter too many confirms nothing
        await wait_until(pilot, lambda: not isinstance(app.screen, ConfirmScreen))
        assert not pane.running
        assert pane.shown is not None
        assert pane.shown[0] == first
        await pilot.press("ctrl+g")
        await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
        await pilot.press("y")
        await wait_until(pilot, lambda: len(_results(workspace)) == 2 and pane.outcome)
        assert pane.shown is not None
        assert pane.shown[0] != first


async def test_the_last_result_is_shown_again_after_a_restart(workspace: Path) -> None:
    preset_session(workspace, **INPUTS, skeleton=True)
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        pane = await _ready(pilot, app)
        await pilot.press("ctrl+g")
        await wait_until(pilot, lambda: pane.outcome is not None)
        [result] = _results(workspace)
        await wait_until(pilot, lambda: app.session.last_result is not None)
        app.save_session_now()
    again = app_for(workspace)
    async with running(again, (120, 40)) as pilot:
        pane = again.query_one(GenerationPane)
        await wait_until(pilot, lambda: pane.shown is not None)
        assert pane.shown is not None
        assert pane.shown[0] == result
        assert str(result.resolve()) in _header(again)
        assert "restored from the last session" in _status(again)
        code = again.query_one("#generation-code", CodeView)
        assert code.text == (result / "skill.py").read_text(encoding="utf-8")
        assert pane.stages["checks"][0] == "failed"
