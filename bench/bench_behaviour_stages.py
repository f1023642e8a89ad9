"""What the run and simulate stages add to a generation, per shipped MR-1 skill.

For each hand-written skill in ``capabilities/skills`` (the file a generation ends with when
the model gets it right), the three judgements the pipeline makes of a candidate, each timed
in wall and CPU time (this process plus its children):

* the static checks (the alternative: what a generation without the stages pays),
* the run stage (:meth:`skillwright.pipeline.behaviour.Behaviour.run`: sandbox, kinematic
  world, the capability's default scenario),
* the simulate stage (:meth:`~skillwright.pipeline.behaviour.Behaviour.simulate`: MuJoCo,
  the same scenario, oracles, plot),

and the ratio of run + simulate to the static checks. In the repair loop each distinct
file that passes the static checks pays run (+ simulate when the run is clean) once.

    python bench/bench_behaviour_stages.py [SKILL_STEM ...]
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SKILLS = ROOT / "capabilities" / "skills"
RECORDING = ROOT / "capabilities" / "recordings" / "mr1"


def _clock() -> tuple[float, float]:
    times = os.times()
    return (
        time.perf_counter(),
        times.user + times.system + times.children_user + times.children_system,
    )


def main() -> None:
    from skillwright.capability.reader import load_capability
    from skillwright.interfaces.load import load_inventory
    from skillwright.pipeline.behaviour import Behaviour
    from skillwright.spec.loader import load_spec
    from skillwright.validation.catalog import catalog_from_inventory
    from skillwright.validation.static import check_skill

    inventory = load_inventory(RECORDING)
    catalog = catalog_from_inventory(inventory)
    stems = sys.argv[1:] or sorted(p.stem for p in SKILLS.glob("*.py"))
    print(f"load average at start: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"{'skill':32} {'static':>8} {'run':>8} {'sim':>8} {'run+sim/static':>15}  verdicts")
    totals = [0.0, 0.0, 0.0]
    for stem in stems:
        name = stem.replace("_", "-")
        code = (SKILLS / f"{stem}.py").read_text(encoding="utf-8")
        load = load_capability(ROOT / "capabilities" / f"{name}.ttl")
        spec = load_spec(ROOT / "capabilities" / f"{name}.spec.yaml")
        wall, cpu = _clock()
        report = check_skill(code, capability=load.capability, spec=spec, catalog=catalog)
        static = _clock()[0] - wall
        with tempfile.TemporaryDirectory() as work:
            behaviour = Behaviour(load.capability, inventory, SKILLS / f"{stem}.py", Path(work))
            wall, cpu = _clock()
            run = behaviour.run(code)
            run_wall, run_cpu = _clock()[0] - wall, _clock()[1] - cpu
            wall, cpu = _clock()
            sim = behaviour.simulate(code)
            sim_wall, sim_cpu = _clock()[0] - wall, _clock()[1] - cpu
            record = behaviour.sim_record(sim, None)
        judged = [v for v in record.verdicts if v.passed is not None]
        passed = sum(bool(v.passed) for v in judged)
        run_ok = "run ok" if run.report is not None and run.report.passed else "run FAIL"
        print(
            f"{stem:32} {static:7.2f}s {run_wall:7.2f}s {sim_wall:7.2f}s "
            f"{(run_wall + sim_wall) / max(static, 1e-6):14.0f}x  {run_ok}, sim "
            f"{record.scenario} {passed}/{len(judged)} (static {len(report.findings)} findings; "
            f"cpu run {run_cpu:.2f}s sim {sim_cpu:.2f}s)"
        )
        totals[0] += static
        totals[1] += run_wall
        totals[2] += sim_wall
    count = len(stems)
    print(
        f"{'mean':32} {totals[0] / count:7.2f}s {totals[1] / count:7.2f}s "
        f"{totals[2] / count:7.2f}s {(totals[1] + totals[2]) / max(totals[0], 1e-6):14.0f}x"
    )
    print(f"load average at end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
