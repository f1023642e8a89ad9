"""What the static checks cost per shipped MR-1 skill, and what one shared set of facts saves.

:func:`skillwright.validation.static.check_skill` parses a skill once, works out its facts
(:class:`skillwright.validation.facts.SkillFacts`) when a check first asks for one and hands
the same facts to every check of :data:`~skillwright.validation.static.STATIC_CHECKS`. For
each hand-written skill in ``capabilities/skills`` this prints, as the median of several
rounds:

* ``check``: the time of ``check_skill`` against the MR-1's whole catalog;
* ``facts``: the time of parsing the file and working out every fact of it (each cached
  property of ``SkillFacts``, and the walk of the class and of each method);
* ``per check``: what the checks would cost if each of them worked the facts out for itself
  again, as each module did before the facts were shared: ``check`` plus one ``facts`` for
  every check but the first (a bound from above: not every check needs every fact);
* the ratio of that to ``check``.

    python bench/bench_checks.py [ROUNDS]
"""

from __future__ import annotations

import os
import statistics
import sys
import time
from collections.abc import Callable
from functools import cached_property, partial
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
SKILLS = ROOT / "capabilities" / "skills"
RECORDING = ROOT / "capabilities" / "recordings" / "mr1"


def _median(rounds: int, work: Callable[[], object]) -> float:
    work()  # the first call fills the module caches (signatures, stand-ins), not the facts
    times = []
    for _ in range(rounds):
        start = time.perf_counter()
        work()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def _every_fact(source: str, **given: Any) -> object:
    """The facts of ``source``, each worked out."""
    from skillwright.validation.facts import SkillFacts

    facts = SkillFacts.build(source, **given)
    for name, value in vars(SkillFacts).items():
        if isinstance(value, cached_property):
            getattr(facts, name)
    for method in facts.functions:
        facts.walk(method)
    return facts


def main() -> None:
    from skillwright.capability.reader import load_capability
    from skillwright.interfaces.load import load_inventory
    from skillwright.spec.loader import load_spec
    from skillwright.validation.catalog import catalog_from_inventory
    from skillwright.validation.facts import SkillFacts
    from skillwright.validation.static import STATIC_CHECKS, check_skill

    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    catalog = catalog_from_inventory(load_inventory(RECORDING))
    facts_of_every_kind = [
        name for name, value in vars(SkillFacts).items() if isinstance(value, cached_property)
    ]
    checks = len(STATIC_CHECKS)
    print(f"load average at start: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"{checks} checks, {len(facts_of_every_kind)} cached facts, median of {rounds} rounds")
    print(f"{'skill':32} {'check':>9} {'facts':>9} {'per check':>10} {'ratio':>6}")
    totals = [0.0, 0.0, 0.0]
    for path in sorted(SKILLS.glob("*.py")):
        name = path.stem.replace("_", "-")
        source = path.read_text(encoding="utf-8")
        capability = load_capability(ROOT / "capabilities" / f"{name}.ttl").capability
        spec = load_spec(ROOT / "capabilities" / f"{name}.spec.yaml")

        given = {"capability": capability, "spec": spec, "catalog": catalog}
        checked = _median(rounds, partial(check_skill, source, **given))
        built = _median(rounds, partial(_every_fact, source, **given))
        apart = checked + (checks - 1) * built
        totals = [totals[0] + checked, totals[1] + built, totals[2] + apart]
        print(
            f"{path.stem:32} {checked * 1e3:7.1f}ms {built * 1e3:7.1f}ms {apart * 1e3:8.1f}ms "
            f"{apart / checked:5.1f}x"
        )
    print(
        f"{'total':32} {totals[0] * 1e3:7.1f}ms {totals[1] * 1e3:7.1f}ms "
        f"{totals[2] * 1e3:8.1f}ms {totals[2] / totals[0]:5.1f}x"
    )


if __name__ == "__main__":
    main()
