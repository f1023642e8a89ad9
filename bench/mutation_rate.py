"""How many planted mistakes a run of ``skillwright run`` catches, per kind of mistake.

The mutants are those of ``tests/runtime/mutants.py``: each is one of the nine shipped
MR-1 skills (``capabilities/skills``) with one mistake LLMs make (a wrong topic, a field
the message does not have, a stop that does not stop, a capability input replaced by a
number, a wait that never ends, a QoS the robot's publisher cannot serve). Each is run as
the tests run it; a mutant is *caught* when the run reports an error, and *caught by its
check* when the check meant for that kind of mistake is among the errors.

    python bench/mutation_rate.py
"""

from __future__ import annotations

import sys
import time
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def main() -> None:
    from tests.runtime.mutants import KINDS, MUTANTS
    from tests.runtime.test_mutants import EXPECTED, run_mutant

    from skillwright.interfaces.load import load_inventory

    inventory = load_inventory(ROOT / "capabilities" / "recordings" / "mr1")
    rows: dict[str, list[tuple[bool, bool]]] = defaultdict(list)
    started = time.perf_counter()
    for mutant in MUTANTS:
        report = run_mutant(mutant, inventory)
        errors = {f.check for f in report.findings if f.severity == "error"}
        rows[mutant.kind].append((bool(errors), bool(errors & EXPECTED[mutant.kind])))
        verdict = "caught" if errors else "MISSED"
        print(f"  {mutant.id:48s} {verdict:7s} {', '.join(sorted(errors))}")
    print()
    print(
        f"{'kind of mistake':20s} {'mutants':>8s} {'caught':>7s} {'by its check':>13s} {'rate':>6s}"
    )
    total = caught = by_check = 0
    for kind in KINDS:
        results = rows.get(kind, [])
        hits = sum(r[0] for r in results)
        exact = sum(r[1] for r in results)
        total, caught, by_check = total + len(results), caught + hits, by_check + exact
        rate = hits / len(results) if results else 0.0
        print(f"{kind:20s} {len(results):8d} {hits:7d} {exact:13d} {rate:6.0%}")
    print(f"{'all':20s} {total:8d} {caught:7d} {by_check:13d} {caught / total:6.0%}")
    print(f"\n{total} mutants run in {time.perf_counter() - started:.1f} s")


if __name__ == "__main__":
    main()
