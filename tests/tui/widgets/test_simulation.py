"""The simulation view's data: the trace's ground truth, and an oracle's verdict."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from skillwright.pipeline.verdict import Verdict
from skillwright.tui.widgets.simulation import read_trajectories, verdict_of


def test_the_ground_truth_of_each_run_gives_its_path_speed_and_yaw_rate(tmp_path: Path) -> None:
    columns = ["t", "x", "y", "yaw", "vx", "vy", "wz"]
    trace = tmp_path / "simulation.trace.json"
    trace.write_text(
        json.dumps(
            {
                "episodes": [
                    {
                        "name": "normal",
                        "ground_truth": {
                            "columns": columns,
                            "samples": [[0, 0, 0, 0, 0, 0, 0], [1, 0.3, 0.1, 0, 0.3, 0.4, -0.2]],
                        },
                    },
                    {"name": "stop", "ground_truth": {"columns": ["t"], "samples": [[0]]}},
                ]
            }
        ),
        encoding="utf-8",
    )
    runs = read_trajectories(trace)
    assert list(runs) == ["normal"]  # a run without positions is left out
    t, x, y, speed, yaw_rate = runs["normal"][1]
    assert (t, x, y) == (1, 0.3, 0.1)
    assert speed == pytest.approx(math.hypot(0.3, 0.4))
    assert yaw_rate == pytest.approx(0.2)
    assert read_trajectories(tmp_path / "missing.json") == {}


@pytest.mark.parametrize(
    ("passed", "verdict"),
    [(True, Verdict.PASSED), (False, Verdict.FAILED), (None, Verdict.SKIPPED)],
)
def test_an_oracle_that_does_not_apply_is_skipped(passed: bool | None, verdict: Verdict) -> None:
    assert verdict_of(passed) is verdict
