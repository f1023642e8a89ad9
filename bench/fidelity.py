"""How far skillwright's judge agrees with the paper's on skills it did not write.

The material is ``../shared/data/cap2skill/skill-implementations/``: the six skills the
paper's authors wrote by hand (no published verdict: they are working code, so a faithful
judge passes them, F on every criterion), five of the paper's gpt-4o skills with the
paper's verdicts, and one of them as the authors corrected it (expected F). Each skill is
judged as a user would judge it, against the paper robot's interface report:

The reference mapping and navigate-to-point are judged against
``tests/fixtures/slam_nav2_report.json`` (that report plus the SLAM Toolbox and Nav2
interfaces they use); every other skill against the report itself.

- the static checks (``check``) with the skill's capability model and specification;
- the sandboxed run (``run``) with the kinematic world and the capability's derived
  scenario's inputs, by the capability's names (the binding gives them to the skill);
- the MuJoCo validation (``validate``) in the capability's derived scenarios.

Our findings are mapped onto the paper's criteria (syntax, the four annotation criteria,
executability, interfaces, behaviour) as F (nothing found), P (something, not all) and N;
the table prints both verdicts per skill and criterion and the agreement counts.

    python bench/fidelity.py
"""

from __future__ import annotations

import sys
import time
from collections.abc import Sequence
from pathlib import Path

import yaml

from skillwright.capability import load_capability
from skillwright.capability.model import Capability
from skillwright.interfaces.load import discover_path
from skillwright.rules.finding import Finding
from skillwright.runtime.run import run_skill
from skillwright.runtime.sandbox import ChildPool
from skillwright.sim.scenario import scenarios_for
from skillwright.sim.validate import runtime_scenario, validate_skill
from skillwright.spec import load_spec
from skillwright.validation.catalog import catalog_from_inventory
from skillwright.validation.static import check_skill

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "cap2skill"
"""``../shared`` beside the repository, where CI keeps it."""
CRITERIA = (
    "syntax",
    "annotation_skill",
    "annotation_parameters",
    "annotation_outputs",
    "annotation_states",
    "executability",
    "interfaces",
    "behaviour",
)
_SKILL = {"SW102", "SW103", "SW104", "SW105", "SW106"}
_STATES = {"SW109", "SW111", "SW112"}
_ANNOTATION = {"SW107", "SW108", "SW116"}
SLAM_NAV2 = Path(__file__).resolve().parents[1] / "tests" / "fixtures" / "slam_nav2_report.json"
"""The paper robot's report with the standard SLAM Toolbox services and the Nav2
``/navigate_to_pose`` action, which the reference mapping and navigate-to-point use."""
_NEEDS_SLAM_NAV2 = {"mapping", "navigate_to_point"}


def inventory_path(stem: str) -> Path:
    """The interface report a skill is judged against."""
    if stem in _NEEDS_SLAM_NAV2:
        return SLAM_NAV2
    return DATA / "interface-reports" / "ros2_system_report.json"


def _errors(findings: Sequence[Finding], codes: set[str] | None = None) -> list[Finding]:
    return [f for f in findings if f.severity == "error" and (codes is None or f.code in codes)]


def _annotations(findings: Sequence[Finding], capability: Capability, decorator: str) -> str:
    """F, P or N for the inputs' (or outputs') annotations; - when the model has none."""
    wanted = capability.inputs if decorator == "skill_parameter" else capability.outputs
    if not wanted:
        return "-"
    missing = {
        f.data.get("parameter")
        for f in findings
        if f.code in _ANNOTATION and f.data.get("decorator") == decorator and f.code == "SW107"
    }
    others = [
        f
        for f in findings
        if f.code in _ANNOTATION - {"SW107"} and f.data.get("decorator") == decorator
    ]
    if not missing and not others:
        return "F"
    return "N" if len(missing) == len(wanted) else "P"


def judge(path: Path, stem: str, pool: ChildPool) -> tuple[dict[str, str], list[str]]:
    """Our verdict per criterion, and the codes behind each N or P."""
    capability = load_capability(DATA / "capability-models" / f"{stem.replace('_', '-')}.ttl")
    model = capability.capability
    spec = load_spec(DATA / "skill-specs" / f"{stem}.json")
    inventory = discover_path(inventory_path(stem))
    source = path.read_text(encoding="utf-8")
    static = check_skill(
        source, capability=model, spec=spec, catalog=catalog_from_inventory(inventory)
    ).findings
    verdict: dict[str, str] = {}
    verdict["syntax"] = "N" if _errors(static, {"SW101"}) else "F"
    verdict["annotation_skill"] = "N" if _errors(static, _SKILL) else "F"
    verdict["annotation_parameters"] = _annotations(static, model, "skill_parameter")
    verdict["annotation_outputs"] = _annotations(static, model, "skill_output")
    verdict["annotation_states"] = "N" if _errors(static, _STATES) else "F"
    grounding = [f for f in static if f.code.startswith("SW2")]
    verdict["interfaces"] = (
        "N" if _errors(grounding) and len(_errors(grounding)) > 1 else "P" if grounding else "F"
    )
    from skillwright.sim.bindings import bind_interfaces

    scenarios = scenarios_for(model, localised=bind_interfaces(inventory).has_localisation)
    first = scenarios.scenarios[0]
    run = run_skill(
        path,
        inventory,
        scenario=runtime_scenario(first),
        world="kinematic",
        capability=model,
        children=pool,
    )
    verdict["executability"] = "N" if _errors(run.findings) else "F"
    simulated = validate_skill(
        path, model, inventory, scenarios=scenarios, plot=False, children=pool
    )
    failed = simulated.failed_oracles()
    outcome = any(o.endswith("/outcome") for o in failed)
    # Behaviour is what the oracles judge; a state that raised in a run is executability's.
    verdict["behaviour"] = "F" if not failed else "N" if outcome else "P"
    why = sorted(
        {f.code for f in [*static, *run.findings] if f.severity == "error"}
        | {o.rsplit("/", 1)[-1] for o in failed}
    )
    return verdict, why


def main() -> int:
    if not DATA.is_dir():
        print(f"the Cap2Skill data is not at {DATA}; it lies beside the repository in CI")
        return 1
    paper = yaml.safe_load((DATA / "skill-implementations" / "verdicts.yaml").read_text())
    # (label, file, expected verdicts, whether they are assumed rather than published)
    skills: list[tuple[str, Path, dict[str, str], bool]] = []
    for path in sorted((DATA / "skill-implementations" / "reference").glob("*.py")):
        skills.append((f"reference/{path.stem}", path, dict.fromkeys(CRITERIA, "F"), True))
    for name, entry in paper["gpt-4o"].items():
        path = DATA / "skill-implementations" / "gpt-4o" / f"{name}.py"
        assumed = entry.get("expected") == "F"
        expected = (
            dict.fromkeys(CRITERIA, "F")
            if assumed
            else {c: str(entry.get(c, "-")) for c in CRITERIA}
        )
        skills.append((f"gpt-4o/{name}", path, expected, assumed))
    agree = dict.fromkeys(CRITERIA, 0)
    counted = dict.fromkeys(CRITERIA, 0)
    pool = ChildPool()
    started = time.perf_counter()
    short = [c.replace("annotation_", "ann_")[:11] for c in CRITERIA]
    head = f"{'skill':<42}" + "".join(f"{c:>12}" for c in short)
    print(head + "   (paper/ours)")
    try:
        for label, path, expected, assumed in skills:
            stem = path.stem.removesuffix("_corrected")
            ours, why = judge(path, stem, pool)
            cells = []
            for criterion in CRITERIA:
                theirs = expected[criterion]
                if assumed and ours[criterion] == "-":
                    # An assumed F has no meaning where the capability has no such
                    # annotation (no inputs): the paper writes "-" there too.
                    theirs = "-"
                mine = "-" if theirs == "-" else ours[criterion]
                if theirs != "-":
                    counted[criterion] += 1
                    agree[criterion] += theirs == mine
                mark = "" if theirs == mine else "*"
                cells.append(f"{theirs}/{mine}{mark}".rjust(12))
            print(f"{label:<42}" + "".join(cells) + (f"   {' '.join(why)}" if why else ""))
    finally:
        pool.close()
    print(f"{'agreement':<42}" + "".join(f"{agree[c]}/{counted[c]}".rjust(12) for c in CRITERIA))
    total = sum(agree.values()), sum(counted.values())
    print(f"in all {total[0]} of {total[1]} verdicts agree; {time.perf_counter() - started:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
