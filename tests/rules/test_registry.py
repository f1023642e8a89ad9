"""The registry: every rule documented, and every rule shown to work on its own cases.

One registry-driven test runs each rule's VALID cases (the rule stays silent) and INVALID
cases (it speaks, and its fix makes the edits the case expects and silences it) through the
stage the rule belongs to, as a user meets it: the static checks of ``skillwright check``,
the sandboxed run of ``skillwright run`` (with its second run of waits that gave up), the
MuJoCo validation of ``skillwright validate``. A rule without documentation or without
cases fails here, as does a case left for a rule that is gone.
"""

from __future__ import annotations

import ast
import functools
import json
from pathlib import Path
from typing import Any

import pytest

from skillwright.capability import Capability, load_capability
from skillwright.interfaces.inventory import Inventory
from skillwright.rules import registry
from skillwright.rules.finding import Finding
from skillwright.rules.fixes import apply_fixes
from skillwright.rules.registry import Rule, all_rules
from skillwright.spec import SkillSpec, load_spec
from skillwright.validation.model import CheckReport
from tests.conftest import REPO_ROOT, SHIPPED_CAPABILITIES
from tests.rules import cases as rule_cases

RULES = all_rules()
CASES = {stage: rule_cases.load(stage) for stage in rule_cases.STAGES}


def _params(stage: str) -> list[Any]:
    return [
        pytest.param(code, kind, index, case, id=f"{code}-{kind}-{index}")
        for code, kinds in CASES[stage].items()
        for kind in ("valid", "invalid")
        for index, case in enumerate(kinds.get(kind, []))
    ]


# ------------------------------------------------------------------ the registry itself


@pytest.mark.parametrize("rule", RULES, ids=lambda r: r.code)
def test_every_rule_is_documented(rule: Rule) -> None:
    for part in (rule.summary, rule.why, rule.example):
        assert part.strip(), f"{rule.code} lacks part of its documentation"
    assert rule.grounds, f"{rule.code} names nothing its truth comes from"
    assert (rule.fix is None) == (rule.safety is None)
    text = rule.explain()
    assert text.startswith(f"{rule.code} {rule.name} ")
    assert "Why it matters" in text
    assert ("Fix (" in text) == (rule.fix is not None)


@pytest.mark.parametrize("rule", RULES, ids=lambda r: r.code)
def test_every_rule_has_valid_and_invalid_cases(rule: Rule) -> None:
    cases = CASES[rule.stage].get(rule.code)
    assert cases is not None, f"{rule.code} has no cases in tests/rules/cases/{rule.stage}.yaml"
    assert cases.get("valid"), f"{rule.code} has no VALID case"
    assert cases.get("invalid"), f"{rule.code} has no INVALID case"
    if rule.stage == "static" and rule.fix is not None:
        assert any("fixed" in c for c in cases["invalid"]), (
            f"{rule.code} has a fix and no INVALID case that shows what it does"
        )


def test_no_case_is_left_for_a_rule_that_is_gone() -> None:
    by_stage = {stage: {r.code for r in RULES if r.stage == stage} for stage in rule_cases.STAGES}
    for stage, cases in CASES.items():
        assert set(cases) <= by_stage[stage], f"{stage}.yaml: {set(cases) - by_stage[stage]}"


def test_product_code_makes_findings_only_through_rules() -> None:
    """No module outside ``skillwright.rules`` builds a Finding itself (it would have no
    registered code and could carry data its rule does not declare)."""
    package = REPO_ROOT / "python" / "skillwright"
    offenders = []
    for path in package.rglob("*.py"):
        if path.parent.name == "rules" and path.parent.parent == package:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        offenders += [
            f"{path.relative_to(package)}:{node.lineno}"
            for node in ast.walk(tree)
            if isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name | ast.Attribute)
            and (node.func.id if isinstance(node.func, ast.Name) else node.func.attr) == "Finding"
        ]
    assert offenders == []


def test_a_finding_with_undeclared_data_is_refused() -> None:
    rule = registry.get("SW613")
    rule.finding(line=1, message="execute: it used up the CPU-time limit", data={"state": "x"})
    with pytest.raises(ValueError, match="not declared"):
        rule.finding(line=1, message="m", data={"seconds": 1})


# ------------------------------------------------------------------ static


@functools.cache
def _inputs(stem: str) -> tuple[Capability, SkillSpec]:
    capability = load_capability(SHIPPED_CAPABILITIES / f"{stem}.ttl").capability
    return capability, load_spec(SHIPPED_CAPABILITIES / f"{stem}.spec.yaml")


def _check(source: str, case: dict[str, Any]) -> CheckReport:
    from skillwright.validation.static import check_skill
    from tests.validation.test_static import CATALOG, mr1_catalog

    capability, spec = _inputs(rule_cases.capability_stem(case))
    return check_skill(
        source,
        capability=capability,
        spec=spec,
        catalog={"small": CATALOG, "mr1": mr1_catalog()}[case.get("catalog", "small")],
        retrieved=case.get("retrieved", ["/cmd_vel", "/odom"]),
    )


def _of(findings: list[Finding], code: str) -> list[Finding]:
    return [f for f in findings if f.code == code]


@pytest.mark.parametrize(("code", "kind", "index", "case"), _params("static"))
def test_static_rule_case(code: str, kind: str, index: int, case: dict[str, Any]) -> None:
    source = rule_cases.source_of(case)
    mine = _of(_check(source, case).findings, code)
    if kind == "valid":
        assert mine == [], [f.message for f in mine]
        return
    assert mine, f"{code} is silent on its INVALID case {index}"
    assert all(f.check == registry.get(code).group for f in mine)
    if "fixed" not in case:
        return
    fixed, applied = apply_fixes(source, mine, unsafe=True)
    assert applied, f"{code}'s fix does not apply"
    assert fixed == rule_cases.edited(source, case["fixed"])
    assert _of(_check(fixed, case).findings, code) == [], "the fix leaves the finding"


# ------------------------------------------------------------------ run


class SpeedLimitWorld:
    """A world plug-in that reports every velocity command faster than ``limit`` (m/s)
    through the host's ``report``, as a world of the robot's own would a limit it knows."""

    def __init__(self, limit: float) -> None:
        self.limit = limit
        self._host: Any = None

    def attach(self, host: Any) -> None:
        self._host = host
        for topic in host.topics("geometry_msgs/msg/Twist"):
            host.on_publish(topic, self._on_command)

    def _on_command(self, time: float, message: dict[str, Any]) -> None:
        speed = abs(float(message["linear"]["x"]))
        if speed > self.limit:
            self._host.report("speed", f"{speed:.2f} m/s commanded, over {self.limit} m/s")

    def next_event(self) -> float | None:
        return None

    def advance(self, until: float) -> None:
        return None

    def close(self) -> None:
        self._host = None


@functools.cache
def _mr1_inventory() -> Inventory:
    from skillwright.interfaces.load import discover_path

    return discover_path(SHIPPED_CAPABILITIES / "recordings" / "mr1")


@functools.cache
def _run_codes(key: str) -> tuple[str, ...]:
    """The codes of a run of the case ``key`` (its JSON) as ``skillwright run`` reports
    them; cached, as the VALID cases of many rules are the same run."""
    from skillwright.runtime import session
    from skillwright.runtime.run import run_skill
    from skillwright.runtime.scenario import RunScenario, load_scenario
    from skillwright.runtime.waits import probe_waits

    case = json.loads(key)
    source = rule_cases.source_of(case)
    if case.get("scenario") == "shipped":
        scenario = load_scenario(rule_cases.SKILLS / f"{case['skill']}.scenario.yaml")
    else:
        scenario = RunScenario.model_validate(case.get("scenario", {}))
    world: Any = case.get("world")
    if world == "speed-limit":
        options = case.get("world_options", {})
        world = lambda: SpeedLimitWorld(float(options["limit"]))  # noqa: E731
    stall = session._STALL_SECONDS
    session._STALL_SECONDS = float(case.get("stall_seconds", stall))
    try:

        def once(text: str) -> Any:
            return run_skill(
                Path("skill.py"),
                _mr1_inventory(),
                inputs=case.get("inputs"),
                scenario=scenario,
                world=world,
                source=text,
                capability=_inputs(case["capability"])[0] if "capability" in case else None,
            )

        report = probe_waits(once(source), source, once, scenario.deadlines.state)
    finally:
        session._STALL_SECONDS = stall
    return tuple(f.code for f in report.findings)


@pytest.mark.parametrize(("code", "kind", "index", "case"), _params("run"))
def test_run_rule_case(code: str, kind: str, index: int, case: dict[str, Any]) -> None:
    codes = _run_codes(json.dumps(case, sort_keys=True))
    if kind == "valid":
        assert code not in codes, codes
    else:
        assert code in codes, f"{code} is silent on its INVALID case {index}: {codes}"


# ------------------------------------------------------------------ simulation


@functools.cache
def _simulation_codes(key: str) -> tuple[str, ...]:
    from skillwright.sim.scenario import Scenario, ScenarioSet
    from skillwright.sim.validate import validate_skill

    case = json.loads(key)
    path = rule_cases.base_path(case)
    capability, _ = _inputs(rule_cases.capability_stem(case))
    scenarios = None
    if "scenarios" in case:
        scenarios = ScenarioSet(
            source="tests/rules/cases/simulation.yaml",
            folder=str(REPO_ROOT / "sim"),
            scenarios=[Scenario.model_validate(s) for s in case["scenarios"]],
        )
    report = validate_skill(
        path,
        capability,
        _mr1_inventory(),
        scenarios=scenarios,
        only=None if scenarios else [case["scenario"]],
        plot=False,
        source=rule_cases.source_of(case),
    )
    return tuple(f.code for f in report.findings)


@pytest.mark.parametrize(("code", "kind", "index", "case"), _params("simulation"))
def test_simulation_rule_case(code: str, kind: str, index: int, case: dict[str, Any]) -> None:
    codes = _simulation_codes(json.dumps(case, sort_keys=True))
    if kind == "valid":
        assert code not in codes, codes
    else:
        assert code in codes, f"{code} is silent on its INVALID case {index}: {codes}"
