"""How many behavioural mistakes the MuJoCo validation catches, per kind of mistake.

First the nine shipped MR-1 skills (``capabilities/skills``) are validated in all their
scenarios (``sim/scenarios``): they should pass. Then each behaviour mutant of
``tests/sim/mutants.py`` — a wrong sign, an ignored input, a stop that does not stop, a
speed over the limit, a drive into the obstacle, a made-up output — is validated in the
scenario that shows its mistake. A mutant is *caught* when the validation fails, and
*caught by its oracle* when an oracle meant for that kind of mistake is among the failed
ones. For comparison, the column *runtime* counts the mutants the sandboxed run's own
findings (``run.*``: motion left running, outputs never set, ...) report, without oracles.

    python bench/behaviour_catch_rate.py [--skip-correct]
"""

from __future__ import annotations

import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def _failed(report: object) -> set[str]:
    return {
        v.oracle
        for s in report.scenarios  # type: ignore[attr-defined]
        for e in s.episodes
        for v in e.verdicts
        if v.passed is False
    }


def main() -> None:
    from tests.sim.mutants import KINDS, MUTANTS

    from skillwright.capability.reader import load_capability
    from skillwright.interfaces.load import load_inventory
    from skillwright.sim.validate import validate_skill

    inventory = load_inventory(ROOT / "capabilities" / "recordings" / "mr1")
    capabilities = {}
    started = time.perf_counter()
    if "--skip-correct" not in sys.argv:
        print("correct skills (capabilities/skills) in their scenarios:")
        for skill in sorted((ROOT / "capabilities" / "skills").glob("*.py")):
            model = ROOT / "capabilities" / f"{skill.stem.replace('_', '-')}.ttl"
            capability = capabilities.setdefault(model, load_capability(model).capability)
            began = time.perf_counter()
            report = validate_skill(skill, capability, inventory)
            failed = sorted(_failed(report))
            verdict = "passed" if report.passed else "FAILED " + ", ".join(failed)
            runs = sum(len(s.episodes) for s in report.scenarios)
            print(
                f"  {skill.stem:32s} {len(report.scenarios)} scenario(s), {runs} run(s) "
                f"{time.perf_counter() - began:6.1f} s  {verdict}"
            )
            for finding in report.findings:
                if finding.severity == "error":
                    print(f"      {finding.line}: [{finding.check}] {finding.message}")
    rows: dict[str, list[tuple[bool, bool, bool]]] = defaultdict(list)
    print("\nbehaviour mutants (tests/sim/mutants.py):")
    with tempfile.TemporaryDirectory() as folder:
        for mutant in MUTANTS:
            capability = capabilities.setdefault(
                mutant.capability, load_capability(mutant.capability).capability
            )
            path = Path(folder) / f"{mutant.skill}.py"
            path.write_text(mutant.source(), encoding="utf-8")
            report = validate_skill(path, capability, inventory, only=[mutant.scenario])
            failed = _failed(report)
            run_errors = {
                f.check
                for f in report.findings
                if f.severity == "error" and f.check.startswith("run.")
            }
            caught = not report.passed
            exact = mutant.caught_by(failed)
            rows[mutant.kind].append((caught, exact, bool(run_errors)))
            shown = ", ".join(sorted(failed)) or "-"
            print(
                f"  {mutant.id:50s} {'caught' if caught else 'MISSED':7s}"
                f"{' (its oracle)' if exact else '':13s} {shown}"
            )
    print()
    print(
        f"{'kind of mistake':26s} {'mutants':>8s} {'caught':>7s} {'by its oracle':>14s} "
        f"{'runtime':>9s} {'rate':>6s}"
    )
    totals = [0, 0, 0, 0]
    for kind in KINDS:
        results = rows.get(kind, [])
        counts = [len(results), *(sum(r[i] for r in results) for i in range(3))]
        totals = [a + b for a, b in zip(totals, counts, strict=True)]
        rate = counts[1] / counts[0] if counts[0] else 0.0
        print(
            f"{kind:26s} {counts[0]:8d} {counts[1]:7d} {counts[2]:14d} {counts[3]:9d} {rate:6.0%}"
        )
    print(
        f"{'all':26s} {totals[0]:8d} {totals[1]:7d} {totals[2]:14d} {totals[3]:9d} "
        f"{totals[1] / max(totals[0], 1):6.0%}"
    )
    print(f"\nin {time.perf_counter() - started:.1f} s")


if __name__ == "__main__":
    main()
