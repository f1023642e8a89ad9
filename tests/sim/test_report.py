"""The validation report's verdict summaries."""

from __future__ import annotations

import pytest

from skillwright.rules.finding import Finding
from skillwright.sim.oracles import Verdict
from skillwright.sim.report import EpisodeVerdicts, ScenarioReport, ValidationReport


def _verdict(oracle: str, passed: bool | None) -> Verdict:
    return Verdict(oracle=oracle, kind="contact", check="c", passed=passed, message="m")


def test_a_report_passes_only_when_no_oracle_fails_and_no_error_is_found() -> None:
    episode = EpisodeVerdicts(
        episode="normal",
        ended="completed",
        verdicts=[_verdict("a", True), _verdict("b", None)],
        virtual_seconds=10.0,
        wall_seconds=0.5,
        world_seconds=0.3,
        publish_seconds=0.05,
    )
    scenario = ScenarioReport(name="s", world="open_floor", episodes=[episode])
    report = ValidationReport(
        skill="k.py", capability="c", scenario_source="f", scenarios=[scenario]
    )
    assert report.passed
    assert episode.speed == 20.0
    assert episode.world_speed == pytest.approx(40.0)
    report.findings.append(Finding(check="run.motion", severity="error", line=3, message="m"))
    assert not report.passed
    failing = episode.model_copy(
        update={"verdicts": [_verdict("contact", False)], "episode": "stop"}
    )
    scenario.episodes.append(failing)
    assert report.failed_oracles() == ["s/stop/contact"]
    assert not ScenarioReport(name="empty", world="w").passed
