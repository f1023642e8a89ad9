"""The evaluation's test split (``eval/test``), checked without any generation model: every
pair's capability, specification and scenarios read and agree, the robots' inventories are
what their script writes, and retrieval runs on each pair.

Nothing here judges how well the pipeline does on these pairs: the split exists to measure
that, so no test may hold a number the pipeline could be tuned to (eval/test/README.md)."""

from __future__ import annotations

import importlib.util
import sys
from functools import cache
from pathlib import Path
from types import ModuleType

import pytest

from skillwright.capability.model import Capability, Expression
from skillwright.capability.reader import load_capability
from skillwright.interfaces.inventory import Inventory
from skillwright.interfaces.load import load_inventory
from skillwright.retrieval.retrieve import rank_interfaces
from skillwright.sim.openmath import as_value, evaluate, is_output_variable
from skillwright.sim.scenario import load_scenario_file, scenarios_for
from skillwright.spec.loader import load_spec
from skillwright.spec.model import PACKML_STATES
from tests.conftest import REPO_ROOT, SHIPPED_CAPABILITIES

SPLIT = REPO_ROOT / "eval" / "test"
ROBOTS = SPLIT / "robots"
PAIRS = sorted(SPLIT.glob("*/*.ttl"))
RECORDING = SHIPPED_CAPABILITIES / "recordings" / "mr1"


def _id(path: Path) -> str:
    return f"{path.parent.name}/{path.stem}"


def _sibling(ttl: Path, suffix: str) -> Path:
    return ttl.with_name(ttl.stem + suffix)


@cache
def _inventory(robot: str) -> Inventory:
    return load_inventory(RECORDING if robot == "mr1" else ROBOTS / f"{robot}.json")


@cache
def _capability(ttl: Path) -> Capability:
    return load_capability(ttl).capability


def test_the_split_has_at_least_sixteen_pairs_on_four_robots() -> None:
    assert len(PAIRS) >= 16
    assert {p.parent.name for p in PAIRS} == {"mr1", "tb4", "tiago", "mmo700nav"}
    assert sum(p.parent.name == "mr1" for p in PAIRS) >= 8


@pytest.mark.parametrize("ttl", PAIRS, ids=_id)
def test_the_capability_reads_with_inputs_and_outputs_in_units(ttl: Path) -> None:
    load = load_capability(ttl)
    # The CaSk import is never fetched (offline), and a capability that only reports has no
    # inputs; anything else the reader says is a mistake in the model.
    others = [w for w in load.warnings if "owl:imports" not in w and "has no inputs" not in w]
    assert others == []
    capability = load.capability
    assert capability.comment
    assert capability.comment.startswith("I am a")
    assert capability.outputs
    assert capability.resource is not None
    for parameter in (*capability.inputs, *capability.outputs):
        assert parameter.comment, parameter.name
        for element in parameter.components:
            assert element.unit, f"{element.name} has no unit"
    assert capability.constraints


@pytest.mark.parametrize("ttl", PAIRS, ids=_id)
def test_the_specification_reads_a_few_sentences_per_state(ttl: Path) -> None:
    spec = load_spec(_sibling(ttl, ".spec.yaml"))
    assert "execute" in spec.states
    assert set(spec.states) <= set(PACKML_STATES)
    for state, text in spec.states.items():
        assert len(text.split(". ")) <= 6, f"{state} reads like a recipe"
        assert "self." not in text, f"{state} gives code"
        assert "()" not in text, f"{state} gives code"


def _preconditions(capability: Capability) -> list[tuple[str, Expression]]:
    outputs = {e.iri for p in capability.outputs for e in p.components if e.iri}
    return [
        (c.name, c.expression)
        for c in capability.constraints
        if not is_output_variable(c.expression, outputs)
    ]


def _values(capability: Capability, inputs: dict[str, object]) -> dict[str, float | str | bool]:
    values: dict[str, float | str | bool] = {}
    for parameter in capability.inputs:
        for element in parameter.components:
            value = as_value(inputs.get(element.name))
            if value is not None and element.iri:
                values[element.iri] = value
    if capability.resource is not None:
        for prop in capability.resource.properties:
            for instance in prop.instances:
                value = as_value(instance.value)
                if instance.iri and value is not None:
                    values[instance.iri] = value
    return values


@pytest.mark.parametrize("ttl", PAIRS, ids=_id)
def test_the_scenarios_load_against_their_capability_within_its_limits(ttl: Path) -> None:
    path = _sibling(ttl, ".scenario.yaml")
    capability = _capability(ttl)
    parsed = load_scenario_file(path)
    assert 1 <= len(parsed.scenarios) <= 4
    chosen = scenarios_for(capability, path)
    assert chosen.source == str(path)
    units = {e.iri: e.unit for p in capability.inputs for e in p.components if e.iri}
    for scenario in parsed.scenarios:
        assert scenario.description, scenario.name
        given = {e.name for p in capability.inputs for e in p.components}
        assert set(scenario.inputs) == given, f"{scenario.name} leaves inputs to be derived"
        if scenario.expect != "completed":
            continue
        # A scenario the skill should complete asks for nothing the capability forbids.
        values = _values(capability, scenario.inputs)
        for name, expression in _preconditions(capability):
            result = evaluate(expression, values, units, {})
            assert result.value is True, f"{scenario.name} violates {name}: {result.checks}"


@pytest.mark.parametrize("ttl", PAIRS, ids=_id)
def test_the_scenarios_bind_every_output_the_simulator_can_measure(ttl: Path) -> None:
    capability = _capability(ttl)
    chosen = scenarios_for(capability, _sibling(ttl, ".scenario.yaml"))
    completed = [s for s in chosen.scenarios if s.expect == "completed"]
    assert completed
    for scenario in completed:
        unbound = [n for n in chosen.notes if n.startswith(f"scenario {scenario.name}:")]
        # Counts (rounds) are the only outputs no simulator quantity fits.
        assert all("outRounds" in n for n in unbound), unbound


@pytest.mark.parametrize("ttl", PAIRS, ids=_id)
def test_retrieval_ranks_the_robots_interfaces_for_the_pair(ttl: Path) -> None:
    inventory = _inventory(ttl.parent.name)
    hits = rank_interfaces(inventory, _capability(ttl), load_spec(_sibling(ttl, ".spec.yaml")))
    names = {i.name for i in inventory.interfaces}
    assert len(hits) == 4
    assert {h.name for h in hits} <= names


def _inventory_script() -> ModuleType:
    spec = importlib.util.spec_from_file_location(
        "make_inventories", ROBOTS / "make_inventories.py"
    )
    assert spec is not None
    assert spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("make_inventories", module)
    spec.loader.exec_module(module)
    return module


def test_the_saved_inventories_are_what_their_script_writes() -> None:
    script = _inventory_script()
    for robot in script.ROBOTS:
        saved = (ROBOTS / f"{robot}.json").read_text(encoding="utf-8")
        assert saved == script.inventory_text(robot), (
            f"{robot}.json: run {ROBOTS.name}/make_inventories.py"
        )
        inventory = load_inventory(ROBOTS / f"{robot}.json")
        assert inventory.sources[0].location == f"tests/retrieval/robots/{robot}.yaml"
        assert len(inventory.interfaces) > 200


def test_every_pairs_robot_has_its_interfaces() -> None:
    robots = {p.parent.name for p in PAIRS} - {"mr1"}
    assert {p.stem for p in ROBOTS.glob("*.json")} == robots
