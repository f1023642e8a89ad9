"""How many behavioural mistakes the MuJoCo validation catches, per kind of mistake.

First the nine shipped MR-1 skills (``capabilities/skills``) are validated in all their
scenarios (``sim/scenarios``): they should pass. Then each behaviour mutant of
``tests/sim/mutants.py`` — a wrong sign, an ignored input, a stop that does not stop, a
speed over the limit, a drive into the obstacle, a made-up output — is validated in the
scenario that shows its mistake. A mutant is *caught* when the validation fails, and
*caught by its oracle* when an oracle meant for that kind of mistake is among the failed
ones. For comparison, the column *runtime* counts the mutants the sandboxed run's own
findings (``run.*``: motion left running, outputs never set, ...) report, without oracles.

With ``--derived`` each skill and each mutant is also judged in the scenarios derived from
its capability model alone (``sim/derive.py``: no scenario file), and the table gets the
derived-only counts beside the files' and their ratio. A mutant is judged in the one file
scenario that shows its mistake, but in every derived scenario (nothing tells which one
would).

    python bench/behaviour_catch_rate.py [--skip-correct] [--derived]
"""

from __future__ import annotations

import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

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


def _correct(inventory: Any, capabilities: dict[Path, Any], derived: bool) -> int:
    """Validates the shipped skills; the number that passed."""
    from skillwright.capability.reader import load_capability
    from skillwright.sim.scenario import derived_set
    from skillwright.sim.validate import validate_skill

    where = "derived scenarios (no file)" if derived else "their scenario files"
    print(f"correct skills (capabilities/skills) in {where}:")
    passed = 0
    for skill in sorted((ROOT / "capabilities" / "skills").glob("*.py")):
        model = ROOT / "capabilities" / f"{skill.stem.replace('_', '-')}.ttl"
        capability = capabilities.setdefault(model, load_capability(model).capability)
        began = time.perf_counter()
        chosen = derived_set(capability) if derived else None
        report = validate_skill(skill, capability, inventory, scenarios=chosen)
        passed += bool(report.passed)
        verdict = "passed" if report.passed else "FAILED"
        runs = sum(len(s.episodes) for s in report.scenarios)
        print(
            f"  {skill.stem:32s} {len(report.scenarios)} scenario(s), {runs} run(s) "
            f"{time.perf_counter() - began:6.1f} s  {verdict}"
        )
        for scenario in report.scenarios:
            for episode in scenario.episodes:
                for v in episode.verdicts:
                    if v.passed is False:
                        print(f"      {scenario.name} ({episode.episode}): {v.oracle}: {v.message}")
        for finding in report.findings:
            if finding.severity == "error" and not finding.check.startswith("sim"):
                print(f"      {finding.line}: [{finding.check}] {finding.message}")
    return passed


def _judge_derived(
    mutant: Any, path: Path, capability: Any, inventory: Any
) -> tuple[bool, bool, bool]:
    """Validates a mutant in the scenarios derived from its capability alone; (caught, by its
    oracle, caught by the nominal derived scenario alone: the one a capability without a
    file got before the variants)."""
    from skillwright.sim.scenario import derived_set
    from skillwright.sim.validate import validate_skill

    chosen = derived_set(capability)
    report = validate_skill(path, capability, inventory, scenarios=chosen)
    failed = _failed(report)
    caught = not report.passed
    exact = bool(mutant.caught_by(failed))
    first = chosen.scenarios[0].name
    alone = validate_skill(path, capability, inventory, scenarios=chosen, only=[first])
    nominal = not alone.passed
    where = sorted(
        {
            s.name
            for s in report.scenarios
            for e in s.episodes
            for v in e.verdicts
            if v.passed is False
        }
    )
    print(
        f"  {'':50s} {'caught' if caught else 'MISSED':7s}{' (its oracle)' if exact else '':13s} "
        f"derived: {', '.join(where) or '-'}: {', '.join(sorted(failed)) or '-'}"
    )
    return caught, exact, nominal


def _compare(
    kinds: tuple[str, ...],
    rows: dict[str, list[tuple[bool, bool, bool]]],
    derived_rows: dict[str, list[tuple[bool, bool, bool]]],
    correct: dict[str, int],
) -> None:
    """The table of mutants caught with the files against derived scenarios only (all of
    them, and the nominal one alone)."""
    print()
    print(
        f"{'kind of mistake':26s} {'mutants':>8s} {'files':>7s} {'derived':>8s} "
        f"{'by its oracle':>14s} {'nominal':>8s} {'ratio':>6s}"
    )
    sums = [0, 0, 0, 0, 0]
    for kind in kinds:
        results = rows.get(kind, [])
        found = derived_rows.get(kind, [])
        counts = [
            len(results),
            sum(r[0] for r in results),
            sum(r[0] for r in found),
            sum(r[1] for r in found),
            sum(r[2] for r in found),
        ]
        sums = [a + b for a, b in zip(sums, counts, strict=True)]
        ratio = f"{counts[2] / counts[1]:.2f}" if counts[1] else "-"
        print(
            f"{kind:26s} {counts[0]:8d} {counts[1]:7d} {counts[2]:8d} {counts[3]:14d} "
            f"{counts[4]:8d} {ratio:>6s}"
        )
    ratio = f"{sums[2] / sums[1]:.2f}" if sums[1] else "-"
    print(
        f"{'all':26s} {sums[0]:8d} {sums[1]:7d} {sums[2]:8d} {sums[3]:14d} {sums[4]:8d} {ratio:>6s}"
    )
    print(
        f"\ncaught with the scenario files: {sums[1]}/{sums[0]}; with derived scenarios only: "
        f"{sums[2]}/{sums[0]} (ratio derived/files {ratio}); with the nominal derived scenario "
        f"alone: {sums[4]}/{sums[0]}"
    )
    if correct:
        print(
            f"shipped skills passing: {correct.get('files', 0)}/9 with the files, "
            f"{correct.get('derived', '-')}/9 with derived scenarios only"
        )


def main() -> None:
    from tests.sim.mutants import KINDS, MUTANTS

    from skillwright.capability.reader import load_capability
    from skillwright.interfaces.load import load_inventory
    from skillwright.sim.validate import validate_skill

    derived = "--derived" in sys.argv
    inventory = load_inventory(ROOT / "capabilities" / "recordings" / "mr1")
    capabilities: dict[Path, Any] = {}
    started = time.perf_counter()
    correct: dict[str, int] = {}
    if "--skip-correct" not in sys.argv:
        correct["files"] = _correct(inventory, capabilities, derived=False)
        if derived:
            print()
            correct["derived"] = _correct(inventory, capabilities, derived=True)
    rows: dict[str, list[tuple[bool, bool, bool]]] = defaultdict(list)
    derived_rows: dict[str, list[tuple[bool, bool, bool]]] = defaultdict(list)
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
            if derived:
                derived_rows[mutant.kind].append(
                    _judge_derived(mutant, path, capability, inventory)
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
    if derived:
        _compare(KINDS, rows, derived_rows, correct)
    print(f"\nin {time.perf_counter() - started:.1f} s")


if __name__ == "__main__":
    main()
