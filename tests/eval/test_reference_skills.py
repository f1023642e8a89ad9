"""The test split's hand-written reference skills (``tests/fixtures/test_split_skills``): one
per pair, each passing ``skillwright validate`` (static checks and every scenario in MuJoCo)
and the pipeline's run stage, which proves the pair's scenarios can be passed; and none of
them is where the generator could see it."""

from __future__ import annotations

import json
import re
from functools import cache
from pathlib import Path

import pytest
from click.testing import CliRunner

from skillwright.capability.reader import load_capability
from skillwright.cli import main
from skillwright.interfaces.load import load_inventory
from skillwright.pipeline.behaviour import Behaviour
from skillwright.sim.scenario import load_scenario_file
from tests.conftest import REPO_ROOT, SHIPPED_CAPABILITIES

SPLIT = REPO_ROOT / "eval" / "test"
SKILLS = REPO_ROOT / "tests" / "fixtures" / "test_split_skills"
EXAMPLES = REPO_ROOT / "python" / "skillwright" / "generation" / "examples"
PAIRS = sorted(SPLIT.glob("*/*.ttl"))
RECORDING = SHIPPED_CAPABILITIES / "recordings" / "mr1"

RUN_STAGE_LIMITS = {
    "mr1/face-nearest-obstacle": (
        "the run stage's kinematic world replays the recording's scans, which do not turn with "
        "the base: a skill that turns until the closest return is ahead never sees it come "
        "round (SW605), though it passes every MuJoCo scenario"
    ),
}
"""Pairs whose correct skill the run stage cannot pass, and why: a limit of the judge, kept
visible here (strict xfail) rather than worked around in the pair or the skill."""


def _id(path: Path) -> str:
    return f"{path.parent.name}/{path.stem}"


@cache
def _skills() -> dict[str, Path]:
    """The reference skills by the capability IRI their ``@skill`` names."""
    found: dict[str, Path] = {}
    for path in sorted(SKILLS.glob("*.py")):
        match = re.search(r'capability_iri="([^"]+)"', path.read_text(encoding="utf-8"))
        assert match, f"{path.name} names no capability_iri"
        assert match.group(1) not in found, f"two reference skills for {match.group(1)}"
        found[match.group(1)] = path
    return found


def _skill_for(ttl: Path) -> Path:
    return _skills()[load_capability(ttl).capability.iri]


def _interfaces(ttl: Path) -> Path:
    robot = ttl.parent.name
    return RECORDING if robot == "mr1" else SPLIT / "robots" / f"{robot}.json"


def test_every_pair_has_exactly_one_reference_skill() -> None:
    iris = {load_capability(ttl).capability.iri for ttl in PAIRS}
    assert set(_skills()) == iris


def test_the_generator_never_sees_the_reference_skills_or_the_test_pairs() -> None:
    examples = [p for p in EXAMPLES.rglob("*") if p.is_file()]
    assert examples
    names = {p.name for p in _skills().values()}
    assert names.isdisjoint(p.name for p in examples)
    text = "\n".join(p.read_text(encoding="utf-8") for p in examples)
    for path in _skills().values():
        source = path.read_text(encoding="utf-8")
        for pattern in (r'skill_iri="([^"]+)"', r'capability_iri="([^"]+)"', r"^class (\w+)"):
            for found in re.findall(pattern, source, flags=re.MULTILINE):
                assert found not in text, f"{found} of {path.name} is in the generation examples"
    shipped = {
        p.read_text(encoding="utf-8") for p in (SHIPPED_CAPABILITIES / "skills").glob("*.py")
    }
    assert shipped.isdisjoint(p.read_text(encoding="utf-8") for p in _skills().values())


@pytest.mark.slow
@pytest.mark.parametrize("ttl", PAIRS, ids=_id)
def test_the_reference_skill_passes_validate_in_every_scenario(ttl: Path, tmp_path: Path) -> None:
    scenarios = ttl.with_name(ttl.stem + ".scenario.yaml")
    command = [
        "validate",
        str(_skill_for(ttl)),
        "--capability",
        str(ttl),
        "--spec",
        str(ttl.with_name(ttl.stem + ".spec.yaml")),
        "--scenario",
        str(scenarios),
        "--interfaces",
        str(_interfaces(ttl)),
        "-o",
        str(tmp_path / "validation"),
        "--no-plot",
        "--json",
    ]
    result = CliRunner().invoke(main, command)
    assert result.exit_code == 0, result.output
    report = json.loads(result.stdout)
    assert report["passed"] is True
    assert report["findings"] == []
    episodes = [e for s in report["scenarios"] for e in s["episodes"]]
    assert len(report["scenarios"]) == len(load_scenario_file(scenarios).scenarios)
    assert all(v["passed"] is not False for e in episodes for v in e["verdicts"])


@pytest.mark.slow
@pytest.mark.parametrize(
    "ttl",
    [
        pytest.param(ttl, marks=pytest.mark.xfail(reason=RUN_STAGE_LIMITS[_id(ttl)], strict=True))
        if _id(ttl) in RUN_STAGE_LIMITS
        else ttl
        for ttl in PAIRS
    ],
    ids=_id,
)
def test_the_reference_skill_runs_clean_in_the_run_stage(ttl: Path, tmp_path: Path) -> None:
    capability = load_capability(ttl).capability
    skill = _skill_for(ttl)
    behaviour = Behaviour(
        capability,
        load_inventory(_interfaces(ttl)),
        skill,
        tmp_path,
        simulate=False,
        scenario_file=ttl.with_name(ttl.stem + ".scenario.yaml"),
    )
    result = behaviour.run(skill.read_text(encoding="utf-8"))
    assert result.report is not None, result.skipped
    assert [f.message for f in result.findings if f.severity == "error"] == []
