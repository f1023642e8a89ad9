"""One verdict model: every combination of stage results gets the same mark, colour and word
in the TUI's stage list, its result header and History, and the ``generate`` summary."""

from __future__ import annotations

import itertools
from dataclasses import replace
from typing import Any

import pytest

from skillwright.generation.model import AppliedFix, Attempt
from skillwright.pipeline import GenerationRequest, Outcome, run_generation
from skillwright.pipeline.commands import _summary
from skillwright.pipeline.record import (
    ChecksRecord,
    GenerationRecord,
    ModelRecord,
    RunRecord,
    SimulationRecord,
    VerdictRecord,
)
from skillwright.pipeline.verdict import (
    Verdict,
    attempt_verdict,
    behaviour_verdict,
    overall,
    stage_verdicts,
)
from skillwright.rules.finding import Finding
from skillwright.tui.screens.generation import stage_text, verdict_words
from skillwright.tui.screens.history import summary_lines, verdict_cell
from tests.conftest import SHIPPED_CAPABILITIES

ERROR = Finding(check="run.exception", severity="error", line=3, message="ValueError")


@pytest.fixture(scope="module")
def skeleton(tmp_path_factory: pytest.TempPathFactory) -> Outcome:
    """A real result folder (the skeleton of set-velocity) to vary the record of."""
    out = tmp_path_factory.mktemp("verdict") / "set_velocity-20250101-080000"
    return run_generation(
        GenerationRequest(
            capability=SHIPPED_CAPABILITIES / "set-velocity.ttl",
            spec=SHIPPED_CAPABILITIES / "set-velocity.spec.yaml",
            interfaces=SHIPPED_CAPABILITIES / "recordings" / "mr1",
            out_dir=out,
            skeleton=True,
            dense=False,
            run=False,
            simulate=False,
        )
    )


def _attempt(target: str, finish: Any, errors: int | None, chosen: bool = True) -> Attempt:
    fixes = [AppliedFix(code="SW601", safety="unsafe", line=3)] if finish == "fixed" else []
    return Attempt(
        target=target,
        kind="state",
        number=1,
        temperature=0.0,
        seed=0,
        finish=finish,
        response="",
        seconds=1.0,
        errors=errors,
        fixes=fixes,
        chosen=chosen,
    )


def _model(writing: str) -> ModelRecord | None:
    if writing == "none":
        return None
    attempts = [_attempt("execute", "stop", 0)]
    if writing == "fixed":
        attempts = [_attempt("execute", "stop", 1, chosen=False), _attempt("execute", "fixed", 0)]
    return ModelRecord(
        id="scripted",
        backend="scripted",
        context_length=4096,
        sampling={},
        prompt_version=1,
        prefix_cache="off",
        attempts=attempts,
        states_missing=["stopping"] if writing == "missing" else [],
    )


CHECKS = {
    "passed": ChecksRecord(passed=True, errors=0, warnings=1, findings=[]),
    "failed": ChecksRecord(passed=False, errors=1, warnings=0, findings=[ERROR]),
}


def _run(kind: str) -> RunRecord | None:
    return {
        "off": None,
        "skipped": RunRecord(passed=False, skipped="stopped after its budget of 120 s"),
        "passed": RunRecord(passed=True, world="kinematic"),
        "failed": RunRecord(passed=False, world="kinematic", errors=1, findings=[ERROR]),
    }[kind]


def _simulation(kind: str) -> SimulationRecord | None:
    verdict = VerdictRecord(
        episode="normal",
        oracle="output:outLinearVelocity",
        kind="output",
        check="abs(outLinearVelocity - vx) <= 0.05",
        passed=kind != "failed",
        message="",
    )
    return {
        "off": None,
        "skipped": SimulationRecord(passed=False, skipped="could not simulate: no MuJoCo"),
        "passed": SimulationRecord(passed=True, scenario="arc", verdicts=[verdict]),
        "failed": SimulationRecord(
            passed=False, scenario="arc", verdicts=[verdict], findings=[ERROR]
        ),
    }[kind]


def _expected(kind: str, checks: str) -> Verdict:
    """What the run or the simulation must be called."""
    if kind == "off":
        return Verdict.SKIPPED
    if kind == "skipped":
        # no verdict: skipped after static errors, else it should have judged and did not
        return Verdict.SKIPPED if checks == "failed" else Verdict.NOT_RUN
    return Verdict(kind)


COMBINATIONS = list(
    itertools.product(
        ["none", "written", "fixed", "missing"],
        ["passed", "failed"],
        ["off", "skipped", "passed", "failed"],
        ["off", "skipped", "passed", "failed"],
    )
)


@pytest.mark.parametrize(("writing", "checks", "run", "simulation"), COMBINATIONS)
def test_every_view_gives_each_stage_the_same_mark_colour_and_word(
    skeleton: Outcome,
    capsys: pytest.CaptureFixture[str],
    writing: str,
    checks: str,
    run: str,
    simulation: str,
) -> None:
    record: GenerationRecord = skeleton.record.model_copy(
        update={
            "model": _model(writing),
            "checks": CHECKS[checks],
            "run": _run(run),
            "simulation": _simulation(simulation),
        }
    )
    verdicts = stage_verdicts(record)
    expected = {
        "model": Verdict.SKIPPED if writing == "none" else Verdict.PASSED,
        "generation": {
            "none": Verdict.SKIPPED,
            "written": Verdict.PASSED,
            "fixed": Verdict.FIXED,
            "missing": Verdict.FAILED,
        }[writing],
        "checks": Verdict(checks),
        "run": _expected(run, checks),
        "simulate": _expected(simulation, checks),
    }
    assert {stage: verdicts[stage].verdict for stage in expected} == expected
    found = set(expected.values())
    judged = overall(verdicts)
    if Verdict.FAILED in found:
        assert judged is Verdict.FAILED
    elif Verdict.NOT_RUN in found:
        assert judged is Verdict.NOT_RUN
    else:
        assert judged is Verdict.PASSED

    header = verdict_words(verdicts)
    summary = summary_lines(skeleton.out_dir, record)[-1]
    for stage, given in verdicts.items():
        # The stage list: its mark first, in the verdict's colour.
        line = stage_text(stage, given.verdict.word, "detail")
        assert line.plain.startswith(f"{given.verdict.mark} {stage}")
        assert [s.style for s in line.spans if s.start == 0] == [given.verdict.style]
        # History: the cell is mark and word in the colour.
        cell = verdict_cell(given.verdict)
        assert (cell.plain, cell.style) == (
            f"{given.verdict.mark} {given.verdict.word}",
            given.verdict.style,
        )
    for stage in ("checks", "run", "simulate"):
        given = verdicts[stage].verdict
        words = f"{stage} {given.mark} {given.word}"
        assert words in header.plain
        start = header.plain.index(words) + len(stage) + 1
        assert any(s.start == start and s.style == given.style for s in header.spans)
        assert words in summary
    assert summary.startswith(f"{judged.mark} {judged.word}: ")

    # The command line prints the same words (its colours are the same Rich styles).
    _summary(replace(skeleton, record=record))
    printed = capsys.readouterr().out
    assert f"checks {expected['checks'].word}:" in printed
    assert f"verdict: {judged.word}" in printed
    for name, kind, stage in (("run", run, "run"), ("simulation", simulation, "simulate")):
        if kind != "off":
            assert f"{name} {expected[stage].word}" in printed
        else:
            assert f"{name} " not in printed.replace("simulation.png", "")


def test_the_five_verdicts_are_told_apart_by_mark_colour_and_word() -> None:
    for what in ("mark", "style", "word"):
        assert len({getattr(v, what) for v in Verdict}) == len(Verdict)
    assert Verdict.FAILED.markup() == "[red]failed[/]"
    assert Verdict.PASSED.style == "green"


@pytest.mark.parametrize(
    ("finish", "errors", "expected"),
    [
        ("stop", 0, Verdict.PASSED),
        ("stop", 2, Verdict.FAILED),
        ("stop", None, Verdict.NOT_RUN),
        ("length", None, Verdict.FAILED),
        ("repetition", None, Verdict.FAILED),
        ("unparsable", None, Verdict.FAILED),
        ("cancelled", None, Verdict.NOT_RUN),
        ("fixed", 0, Verdict.FIXED),
    ],
)
def test_an_answer_of_the_model_is_judged_by_how_it_ended_and_its_errors(
    finish: str, errors: int | None, expected: Verdict
) -> None:
    judged = attempt_verdict(_attempt("execute", finish, errors))
    assert judged.verdict is expected
    if expected is Verdict.FIXED:
        assert judged.reason == "SW601"  # the rule whose fix was put in


def test_a_run_that_ended_over_its_budget_is_not_a_pass() -> None:
    over = RunRecord(passed=False, skipped="stopped after its budget of 120 s")
    judged = behaviour_verdict(over, checks_passed=True)
    assert judged.verdict is Verdict.NOT_RUN
    assert judged.reason == "stopped after its budget of 120 s"


def test_a_saved_record_keeps_each_stages_verdict(skeleton: Outcome) -> None:
    record = GenerationRecord.load(skeleton.record_path)
    assert record.verdicts == {s: v.verdict.word for s, v in stage_verdicts(record).items()}
    assert record.verdicts["checks"] == "failed"  # the skeleton's states still raise
    assert record.verdicts["run"] == "skipped"
