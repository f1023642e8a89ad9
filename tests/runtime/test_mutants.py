"""Every mutant of the shipped skills is caught by a run (see ``mutants.py``)."""

from __future__ import annotations

import pytest

from skillwright.interfaces.inventory import Inventory
from skillwright.runtime.report import RunReport
from skillwright.runtime.run import run_skill
from skillwright.runtime.scenario import Deadlines, load_scenario
from tests.runtime.mutants import MUTANTS, Mutant

EXPECTED = {
    "wrong topic": {"run.topic", "run.service", "run.action", "run.exception"},
    "wrong field": {"run.field"},
    "missing stop": {"run.motion"},
    "hard-coded input": {"run.input"},
    "never returns": {"run.timeout"},
    "wrong QoS": {"run.qos"},
}


def run_mutant(mutant: Mutant, inventory: Inventory) -> RunReport:
    """Runs a mutant with its skill's scenario, short deadlines, and a Stop run only
    where the mistake is about stopping."""
    scenario = load_scenario(mutant.path.with_suffix(".scenario.yaml")).model_copy(
        update={
            # Mapping sweeps for about 15 s of virtual time; everything else is done in 5.
            "deadlines": Deadlines(
                state=40.0 if mutant.skill == "mapping" else 10.0, busy=2.0, run=60.0
            ),
            "stop_run": "always" if mutant.kind == "missing stop" else "never",
            "settle": 0.3,
        }
    )
    return run_skill(mutant.path, inventory, source=mutant.source(), scenario=scenario)


@pytest.mark.parametrize("mutant", MUTANTS, ids=lambda m: m.id)
def test_mutant_is_caught_by_the_check_for_its_kind(
    mutant: Mutant, mr1_inventory: Inventory
) -> None:
    report = run_mutant(mutant, mr1_inventory)

    errors = {f.check for f in report.findings if f.severity == "error"}
    assert errors & EXPECTED[mutant.kind], report.findings
