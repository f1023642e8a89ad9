"""Reading skill specifications: the reference JSON, hand-written YAML, and bad input."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from skillwright.errors import InputFileNotFoundError, SpecError
from skillwright.spec import PACKML_STATES, SkillSpec, load_spec, parse_spec
from tests.conftest import SHIPPED_CAPABILITIES

PAPER_SPECS = {
    "collision_avoidance": ["starting", "execute", "completing", "stopping", "resetting"],
    "get_distance_to_nearest_object": ["starting", "execute", "completing", "resetting"],
    "get_position": ["starting", "execute", "completing", "resetting"],
    "mapping": ["starting", "execute", "completing", "stopping", "resetting"],
    "move_forward": ["starting", "execute", "completing", "stopping", "resetting"],
    "move_to_point": ["starting", "execute", "completing", "stopping", "aborting", "resetting"],
    "navigate_to_point": [
        "starting",
        "execute",
        "completing",
        "stopping",
        "aborting",
        "resetting",
    ],
    "rotate": ["starting", "execute", "completing", "stopping", "resetting"],
    "set_velocity": ["starting", "execute", "completing", "stopping", "resetting"],
}

GOOD: dict[str, Any] = {
    "name": "move_forward",
    "description": "Drive forward.",
    "skill_interface": "REST",
    "states": {"execute": "Drive.", "starting": "Prepare."},
}


@pytest.mark.parametrize("name", sorted(PAPER_SPECS))
def test_each_paper_spec_loads_in_its_own_format(shared_data: Path, name: str) -> None:
    spec = load_spec(shared_data / "cap2skill" / "skill-specs" / f"{name}.json")
    assert spec.name == name
    assert spec.skill_interface == "REST"
    assert list(spec.states) == PAPER_SPECS[name]


def test_move_forward_spec_keeps_the_behaviour_text(shared_data: Path) -> None:
    spec = load_spec(shared_data / "cap2skill" / "skill-specs" / "move_forward.json")
    assert spec.description == "Move the mobile robot forward a desired distance in a desired time."
    assert spec.states["stopping"] == "Set the velocity of the robot to zero."


@pytest.mark.parametrize(
    "path", sorted(SHIPPED_CAPABILITIES.glob("*.spec.yaml")), ids=lambda p: p.name
)
def test_each_shipped_spec_loads(path: Path) -> None:
    spec = load_spec(path)
    assert "execute" in spec.states
    assert spec.description


def test_states_come_out_in_packml_order_whatever_the_input_order() -> None:
    spec = parse_spec({**GOOD, "states": {"resetting": "r", "execute": "e", "starting": "s"}})
    assert list(spec.states) == ["starting", "execute", "resetting"]


def test_yaml_and_json_forms_give_the_same_spec(tmp_path: Path) -> None:
    yaml_file = tmp_path / "spec.yaml"
    yaml_file.write_text(
        "name: move_forward\ndescription: Drive forward.\nskill_interface: rest\n"
        "states:\n  starting: Prepare.\n  execute: |\n    Drive.\n",
        encoding="utf-8",
    )
    json_file = tmp_path / "spec.json"
    json_file.write_text(json.dumps(parse_spec(GOOD).to_reference()), encoding="utf-8")
    assert load_spec(yaml_file) == load_spec(json_file) == parse_spec(GOOD)


def test_reference_round_trip_loses_nothing(shared_data: Path) -> None:
    for path in sorted((shared_data / "cap2skill" / "skill-specs").glob("*.json")):
        spec = load_spec(path)
        assert parse_spec(spec.to_reference()) == spec


@pytest.mark.parametrize(
    ("alias", "canonical"), [("OPC UA", "OPC_UA"), ("opcua", "OPC_UA"), ("mqtt", "MQTT")]
)
def test_interface_spellings_are_normalised(alias: str, canonical: str) -> None:
    assert parse_spec({**GOOD, "skill_interface": alias}).skill_interface == canonical


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"name": "move forward"}, "name 'move forward' is not a valid identifier"),
        ({"name": "class"}, "name 'class' is not a valid identifier"),
        ({"skill_interface": "SOAP"}, "skill_interface 'SOAP' is not supported; allowed: REST"),
        ({"colour": "red"}, "unknown field(s) colour; allowed: name, description"),
        ({"states": {"starting": "s"}}, "the 'execute' state is required"),
        ({"states": {"execute": "e", "running": "r"}}, "'running' is not a PackML acting state"),
        ({"states": {"execute": "  "}}, "state 'execute' needs a behaviour text"),
        (
            {"states": [{"name": "execute", "action": "a"}, {"name": "Execute", "action": "b"}]},
            "states[1] (Execute): state 'execute' is given twice",
        ),
        ({"states": [{"name": "execute", "text": "a"}]}, "states[0] must be an object"),
        ({"states": "execute"}, "'states' must be a list"),
    ],
)
def test_bad_specs_say_which_field_or_state_is_wrong(change: dict[str, Any], message: str) -> None:
    with pytest.raises(SpecError) as info:
        parse_spec({**GOOD, **change}, "spec.json")
    assert str(info.value).startswith("spec.json: ")
    assert message in str(info.value)


def test_unknown_state_error_lists_every_allowed_state() -> None:
    with pytest.raises(SpecError) as info:
        parse_spec({**GOOD, "states": {"execute": "e", "pause": "p"}})
    for state in PACKML_STATES:
        assert state in str(info.value)


def test_missing_required_fields_are_named() -> None:
    with pytest.raises(SpecError, match="missing field"):
        parse_spec({"name": "x"})


def test_json_syntax_error_names_line_and_column(tmp_path: Path) -> None:
    path = tmp_path / "bad.json"
    path.write_text('{\n  "skill": {\n    "name": "x",,\n', encoding="utf-8")
    with pytest.raises(SpecError, match=r"bad\.json:3:17: JSON syntax error"):
        load_spec(path)


def test_yaml_syntax_error_names_line_and_column(tmp_path: Path) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text("name: x\nstates:\n  execute: [unclosed\n", encoding="utf-8")
    with pytest.raises(SpecError, match=r"bad\.yaml:\d+:\d+: YAML syntax error"):
        load_spec(path)


def test_missing_spec_file_is_reported(tmp_path: Path) -> None:
    with pytest.raises(InputFileNotFoundError, match=r"specification .*none\.json: no such file"):
        load_spec(tmp_path / "none.json")


def test_spec_documents_are_frozen() -> None:
    spec: SkillSpec = parse_spec(GOOD)
    with pytest.raises(ValueError, match="frozen"):
        spec.name = "other"  # type: ignore[misc]
