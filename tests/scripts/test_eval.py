"""``scripts/eval.py`` without a model: its pairs, their splits, and the table and summary it
reports them in."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

import pytest

from tests.conftest import REPO_ROOT


@pytest.fixture(scope="module")
def evaluation() -> ModuleType:
    spec = importlib.util.spec_from_file_location("evaluation", REPO_ROOT / "scripts" / "eval.py")
    assert spec is not None
    assert spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["evaluation"] = module
    spec.loader.exec_module(module)
    return module


def test_the_test_split_pairs_carry_their_own_scenarios_and_interfaces(
    evaluation: ModuleType,
) -> None:
    pairs = evaluation.pairs(set(), "test")
    assert len(pairs) >= 16
    for pair in pairs:
        assert pair.split == "test"
        assert pair.capability.is_file()
        assert pair.spec.is_file()
        assert pair.scenario is not None
        assert pair.scenario.is_file()
        assert pair.interfaces.exists(), pair.interfaces
    robots = {p.robot: p.interfaces.name for p in pairs}
    assert robots == {
        "mr1": "mr1",
        "tb4": "tb4.json",
        "tiago": "tiago.json",
        "mmo700nav": "mmo700nav.json",
    }


def test_the_dev_split_is_the_shipped_and_the_papers_pairs_with_the_shipped_scenarios(
    evaluation: ModuleType,
) -> None:
    pairs = evaluation.pairs(set(), "dev")
    assert [p.name for p in pairs if p.robot == "mr1"] == sorted(
        p.stem for p in (REPO_ROOT / "capabilities").glob("*.ttl")
    )
    assert all(p.split == "dev" and p.scenario is None for p in pairs)
    both = evaluation.pairs(set(), "all")
    assert [p.key() for p in both] == [p.key() for p in pairs + evaluation.pairs(set(), "test")]
    assert len({p.key() for p in both}) == len(both)


def test_only_picks_by_name_by_robot_and_name_or_by_the_whole_key(evaluation: ModuleType) -> None:
    by_name = {p.key() for p in evaluation.pairs({"collision-avoidance"})}
    assert "dev/mr1/collision-avoidance" in by_name
    assert "test/mmo700nav/collision-avoidance" in by_name
    assert [p.key() for p in evaluation.pairs({"mmo700nav/collision-avoidance"})] == [
        "test/mmo700nav/collision-avoidance"
    ]
    assert [p.key() for p in evaluation.pairs({"test/mr1/strafe"}, "all")] == ["test/mr1/strafe"]
    assert evaluation.pairs({"test/mr1/strafe"}, "dev") == []


def test_a_test_pair_reaches_the_pipeline_with_its_scenario_file(
    evaluation: ModuleType, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import skillwright.pipeline
    from skillwright.errors import InvalidArgumentError

    seen = []

    def capture(request: object, **_: object) -> None:
        seen.append(request)
        raise InvalidArgumentError("stopped by the test")

    monkeypatch.setattr(skillwright.pipeline, "run_generation", capture)
    [pair] = evaluation.pairs({"test/tb4/rotate-degrees"})
    row = evaluation.run(pair, tmp_path, 1, None)
    assert row.failure == "stopped by the test"
    assert (row.split, row.robot, row.name) == ("test", "tb4", "rotate-degrees")
    [request] = seen
    assert request.scenario == pair.scenario
    assert request.interfaces == pair.interfaces
    assert request.out_dir == tmp_path / "n1" / "test" / "tb4" / "rotate-degrees"
    assert request.candidates == 1
    evaluation.run(pair, tmp_path, 1, None, 4)
    assert seen[-1].candidates == 4
    assert seen[-1].out_dir == tmp_path / "n4" / "test" / "tb4" / "rotate-degrees"


def test_the_table_and_the_summary_total_each_split_on_its_own(evaluation: ModuleType) -> None:
    row = evaluation.Row
    rows = [
        row("dev", "mr1", "rotate", passed=True, ran="pass", behaved="6/6", seconds=80.0),
        row("dev", "mr1", "mapping", passed=False, seconds=120.0),
        row("test", "mr1", "strafe", passed=True, ran="pass", behaved="9/10 fail", seconds=90.0),
        row("test", "tb4", "nearest-object", passed=True, ran="pass", behaved="8/8", seconds=60.0),
        row("test", "tiago", "get-position", failure="the model file is missing", seconds=1.0),
    ]
    summary = evaluation.summary(rows)
    assert summary["splits"]["dev n1"] == {
        "candidates": 1,
        "skills": 2,
        "static_pass": 1,
        "ran_clean": 1,
        "behaved": 1,
        "median_seconds": 100.0,
        "total_seconds": 200.0,
        "failures": 0,
        "greedy_not_winner": None,
        "distinct_candidates": None,
    }
    test = summary["splits"]["test n1"]
    assert (test["skills"], test["static_pass"], test["ran_clean"], test["behaved"]) == (3, 2, 2, 1)
    assert test["median_seconds"] == 75.0
    assert test["failures"] == 1
    assert [s["split"] for s in summary["skills"]] == ["dev", "dev", "test", "test", "test"]
    text = evaluation.table(rows)
    lines = text.splitlines()
    assert any(
        line.split()[:8] == ["dev", "pass@1", "2", "1", "1", "1", "100.0", "200.0"]
        for line in lines
    )
    assert any(line.split()[:6] == ["test", "pass@1", "3", "2", "2", "1"] for line in lines)
    assert "the model file is missing" in text
    only_test = evaluation.summary(rows[2:])
    assert list(only_test["splits"]) == ["test n1"]


def test_best_of_n_prints_beside_pass_at_1_with_how_often_greedy_lost(
    evaluation: ModuleType,
) -> None:
    row = evaluation.Row
    rows = [
        row("test", "mr1", "strafe", 1, passed=True, behaved="9/10 fail", seconds=60.0),
        row(
            "test",
            "mr1",
            "strafe",
            4,
            passed=True,
            behaved="10/10",
            seconds=90.0,
            winner=2,
            distinct=3,
        ),
        row(
            "test",
            "tb4",
            "rotate-degrees",
            4,
            passed=True,
            behaved="5/5",
            seconds=70.0,
            winner=0,
            distinct=4,
        ),
    ]
    counts = evaluation.summary(rows)["splits"]
    assert list(counts) == ["test n1", "test n4"]
    assert counts["test n4"]["behaved"] == 2
    assert counts["test n4"]["greedy_not_winner"] == 1
    assert counts["test n4"]["distinct_candidates"] == 7
    text = evaluation.table(rows)
    assert "best-of-4" in text
    assert "1 of 2 (7 distinct candidates)" in text
