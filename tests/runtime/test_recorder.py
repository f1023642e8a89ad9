"""The trace stays readable and bounded; findings are kept once."""

from __future__ import annotations

from skillwright.rules.run import RUN_QOS, RUN_TOPIC_UNKNOWN
from skillwright.runtime import recorder as recorder_module
from skillwright.runtime.recorder import Recorder, abbreviate


def test_long_arrays_and_non_finite_numbers_are_shortened_for_the_trace() -> None:
    value = {"ranges": [float("inf")] + [1.0] * 40, "name": "x" * 3000}
    short = abbreviate(value)
    assert short["ranges"][0] == "inf"
    assert short["ranges"][-1] == "... 41 items"
    assert len(short["ranges"]) == 17
    assert short["name"].endswith("(3000 characters)")


def test_entries_beyond_the_limit_are_counted_not_kept(monkeypatch: object) -> None:
    recorder = Recorder()
    monkeypatch.setattr(recorder_module, "MAX_ENTRIES", 3)  # type: ignore[attr-defined]
    for index in range(5):
        recorder.record("log", text=str(index))
    assert [e["text"] for e in recorder.entries] == ["0", "1", "2"]
    assert recorder.dropped == 2


def test_the_same_finding_is_kept_once_at_the_latest_line_by_default() -> None:
    recorder = Recorder()
    recorder.line = 12
    recorder.finding(RUN_TOPIC_UNKNOWN, "no such topic")
    recorder.finding(RUN_TOPIC_UNKNOWN, "no such topic", line=12)
    recorder.finding(RUN_QOS, "best effort", severity="warning")
    assert [(f.check, f.line, f.severity) for f in recorder.findings] == [
        ("run.topic", 12, "error"),
        ("run.qos", 12, "warning"),
    ]
