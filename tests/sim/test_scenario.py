"""Scenario files: the shipped ones, derived ones, and clear errors for bad ones."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.capability.model import Capability
from skillwright.errors import FileFormatError, InputFileNotFoundError
from skillwright.sim.scenario import (
    QUANTITIES,
    default_scenario,
    infer_quantity,
    load_scenario_file,
    scenarios_for,
)

MOVE_FORWARD = "http://skillwright.dev/robots/mr1/capabilities/moveForward/moveForward"


def test_every_shipped_capability_has_scenarios_binding_every_output(
    mr1_capabilities: dict[str, Capability],
) -> None:
    for name, capability in mr1_capabilities.items():
        chosen = scenarios_for(capability)
        assert chosen.source.endswith(f"{name}.yaml"), name
        outputs = {e.name for p in capability.outputs for e in p.components}
        for scenario in chosen.scenarios:
            if scenario.expect == "completed":
                assert outputs <= set(scenario.ground_truth), (name, scenario.name)
            assert set(scenario.inputs) == {e.name for p in capability.inputs for e in p.components}


@pytest.mark.parametrize(
    ("capability", "output", "quantity"),
    [
        ("move-forward", "outDistance", "travelled_distance"),
        ("move-forward", "outLinearVelocity", "linear_velocity_x"),
        ("rotate", "outHeading", "heading"),
        ("get-distance-to-nearest-object", "outDistance", "nearest_obstacle_distance"),
        ("get-distance-to-nearest-object", "outAngle", "nearest_obstacle_bearing"),
        ("collision-avoidance", "outObstacleAngle", "nearest_obstacle_bearing"),
        ("collision-avoidance", "outDuration", "command_duration"),
        ("collision-avoidance", "outLinearVelocityY", "linear_velocity_y"),
        ("navigate-to-point", "outPositionX", "position_x"),
        ("move-to-point", "outPositionZ", "tcp_position_z"),
        ("mapping", "outMap", "map_file"),
        ("mapping", "outMapWidth", "map_width"),
        ("set-velocity", "outAngularVelocity", "angular_velocity"),
    ],
)
def test_what_an_output_measures_is_inferred_from_its_name_unit_and_comment(
    mr1_capabilities: dict[str, Capability], capability: str, output: str, quantity: str
) -> None:
    model = mr1_capabilities[capability]
    parameter, element = next(
        (p, e) for p in model.outputs for e in p.components if e.name == output
    )
    assert infer_quantity(element, parameter) == quantity
    assert quantity in QUANTITIES


def test_a_capability_without_a_file_gets_a_derived_scenario_within_its_limits(
    mr1_capabilities: dict[str, Capability],
) -> None:
    capability = mr1_capabilities["set-velocity"].model_copy(
        update={"iri": "urn:other", "name": "other"}
    )
    chosen = scenarios_for(capability)
    assert chosen.source == "derived from other"
    assert "no scenario file" in chosen.notes[0]
    scenario = chosen.scenarios[0]
    assert scenario.inputs["inLinearVelocity"] == pytest.approx(0.3)
    assert scenario.inputs["inAngularVelocity"] == pytest.approx(0.5)
    assert scenario.ground_truth["outLinearVelocity"] == "linear_velocity_x"
    assert default_scenario(capability).world == "open_floor"


@pytest.mark.parametrize(
    ("stem", "world"),
    [
        ("get-distance-to-nearest-object", "walled_room"),
        ("collision-avoidance", "walled_room"),
        ("mapping", "walled_room"),
        ("move-forward", "open_floor"),
        ("rotate", "open_floor"),
    ],
)
def test_a_derived_scenario_has_walls_for_a_capability_that_senses_or_maps_them(
    mr1_capabilities: dict[str, Capability], stem: str, world: str
) -> None:
    # On the open floor a scan returns nothing: a skill that says "no object detected" there
    # is right, and the scenario expecting it to complete would blame it.
    capability = mr1_capabilities[stem].model_copy(update={"iri": "urn:other"})
    assert default_scenario(capability).world == world


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "mine.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def test_a_users_file_fills_missing_inputs_and_bindings_and_says_so(
    tmp_path: Path, mr1_capabilities: dict[str, Capability]
) -> None:
    path = _write(
        tmp_path,
        f"capability: {MOVE_FORWARD}\nscenarios:\n  - name: short\n    inputs: {{inDistance: 0.5}}\n",
    )
    chosen = scenarios_for(mr1_capabilities["move-forward"], path)
    scenario = chosen.scenarios[0]
    assert scenario.inputs == {"inDistance": 0.5, "inLinearVelocity": pytest.approx(0.3)}
    assert scenario.ground_truth["outDistance"] == "travelled_distance"
    assert any("inLinearVelocity not given" in note for note in chosen.notes)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("capability: x\nscenarios: [\n", r"mine.yaml:3:1: YAML syntax error"),
        ("- a\n- b\n", "a mapping with `capability` and `scenarios`"),
        (
            f"capability: {MOVE_FORWARD}\nscenarios: []\n",
            r"mine.yaml:2: scenarios: List should have at least 1 item",
        ),
        (
            f"capability: {MOVE_FORWARD}\nscenarios:\n  - name: a\n    duration: -1\n",
            r"mine.yaml:4: scenarios.0.duration: Input should be greater than 0",
        ),
        (
            f"capability: {MOVE_FORWARD}\nscenarios:\n  - name: a\n    wrold: corridor\n",
            r"mine.yaml:4: scenarios.0.wrold: Extra inputs are not permitted",
        ),
        (
            f"capability: {MOVE_FORWARD}\nscenarios:\n  - name: a\n  - name: a\n",
            r"mine.yaml:4: scenarios.1.name: scenario name 'a' is used twice",
        ),
    ],
)
def test_a_malformed_file_is_an_error_naming_file_line_and_field(
    tmp_path: Path, text: str, message: str
) -> None:
    with pytest.raises(FileFormatError, match=message):
        load_scenario_file(_write(tmp_path, text))


@pytest.mark.parametrize(
    ("body", "message"),
    [
        (
            "    inputs: {inDistanse: 1.0}\n",
            r"mine.yaml:5: scenarios.0.inputs.inDistanse: moveForward has no input 'inDistanse'; its inputs are inDistance, inLinearVelocity",
        ),
        (
            "    ground_truth: {outDistance: odometer}\n",
            r"mine.yaml:5: .*'odometer' is not something the simulator measures",
        ),
        ("    ground_truth: {outSpeed: heading}\n", r"has no output or input 'outSpeed'"),
        (
            "    world: moon\n",
            r"mine.yaml:5: scenarios.0.world: world 'moon': not one of the shipped worlds",
        ),
        (
            "    runtime: {actoins: {}}\n",
            r"mine.yaml:5: scenarios.0.runtime.actoins: unknown runtime setting",
        ),
        (
            "    runtime: {deadlines: {state: -2}}\n",
            r"scenarios.0.runtime.deadlines.state: Input should be greater than 0",
        ),
        ("    tolerances: {m: -1}\n", r"a tolerance is a non-negative number"),
    ],
)
def test_names_the_capability_does_not_have_are_errors_with_the_line(
    tmp_path: Path, mr1_capabilities: dict[str, Capability], body: str, message: str
) -> None:
    path = _write(
        tmp_path, f"capability: {MOVE_FORWARD}\nscenarios:\n  - name: a\n    duration: 5\n{body}"
    )
    with pytest.raises(FileFormatError, match=message):
        scenarios_for(mr1_capabilities["move-forward"], path)


def test_a_file_for_another_capability_is_refused(
    tmp_path: Path, mr1_capabilities: dict[str, Capability]
) -> None:
    path = _write(tmp_path, f"capability: {MOVE_FORWARD}\nscenarios:\n  - name: a\n")
    with pytest.raises(
        FileFormatError, match=r"the scenarios are for .*moveForward, not for .*rotate"
    ):
        scenarios_for(mr1_capabilities["rotate"], path)


def test_a_missing_file_is_a_not_found_error(tmp_path: Path) -> None:
    with pytest.raises(InputFileNotFoundError, match="no such file"):
        load_scenario_file(tmp_path / "absent.yaml")


def test_a_world_file_is_found_relative_to_the_scenario_file(
    tmp_path: Path, mr1_capabilities: dict[str, Capability]
) -> None:
    from skillwright.sim.assets import sim_dir

    (tmp_path / "mine.xml").write_text(
        (sim_dir() / "worlds" / "open_floor.xml")
        .read_text()
        .replace("../mr1.xml", str(sim_dir() / "mr1.xml"))
    )
    path = _write(
        tmp_path, f"capability: {MOVE_FORWARD}\nscenarios:\n  - name: a\n    world: mine.xml\n"
    )
    chosen = scenarios_for(mr1_capabilities["move-forward"], path)
    assert chosen.folder == str(tmp_path)


def test_the_papers_models_bind_every_output_with_the_capabilitys_comment_as_context(
    shared_data: Path,
) -> None:
    from skillwright.capability.reader import load_capability

    expected = {
        "get-distance-to-nearest-object": {
            "outDistance": "nearest_obstacle_distance",
            "outDegree": "nearest_obstacle_bearing",
        },
        "rotate": {"outDegree": "heading", "outVelocity": "linear_velocity_x"},
        "move-to-point": {
            "outPositionX": "tcp_position_x",
            "outPositionY": "tcp_position_y",
            "outPositionZ": "tcp_position_z",
        },
    }
    for name, bindings in expected.items():
        capability = load_capability(
            shared_data / "cap2skill" / "capability-models" / f"{name}.ttl"
        ).capability
        chosen = scenarios_for(capability)
        assert chosen.scenarios[0].ground_truth == bindings, name
