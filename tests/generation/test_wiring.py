"""Only interfaces the specification or the capability calls for get handles."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import pytest
import yaml

from skillwright.capability import Capability, load_capability
from skillwright.generation.card import CardInterface, task_card
from skillwright.generation.model import InterfaceRef
from skillwright.generation.skeleton import build_skeleton, topic_role
from skillwright.generation.wiring import wire
from skillwright.interfaces.inventory import Inventory
from skillwright.interfaces.load import load_inventory
from skillwright.spec import SkillSpec, load_spec, parse_spec
from tests.conftest import SHIPPED_CAPABILITIES


@cache
def _mr1() -> Inventory:
    return load_inventory(SHIPPED_CAPABILITIES / "recordings" / "mr1")


def _refs(inventory: Inventory, names: list[str]) -> list[InterfaceRef]:
    out = []
    for name in names:
        interface = inventory.interface(name)
        role = topic_role(name, interface.type_name) if interface.kind == "topic" else "call"
        out.append(
            InterfaceRef(name=name, kind=interface.kind, type_name=interface.type_name, role=role)
        )
    return out


def _shipped(stem: str) -> tuple[Capability, SkillSpec]:
    capability = load_capability(SHIPPED_CAPABILITIES / f"{stem}.ttl").capability
    return capability, load_spec(SHIPPED_CAPABILITIES / f"{stem}.spec.yaml")


def _names(refs: list[InterfaceRef]) -> list[str]:
    return [r.name for r in refs]


REVERSE = """
name: reverse
description: Drive the base backwards over a requested distance.
skill_interface: REST
states:
  starting: Wait for odometry, at most 2 s.
  execute: >
    Drive backwards at the requested speed until odometry shows the requested distance
    travelled, then publish a zero velocity command.
  stopping: Stop the base.
"""


def test_a_nav2_behaviour_ranking_put_first_gets_no_handle_when_nothing_asks_for_it() -> None:
    capability, _ = _shipped("move-forward")
    spec = parse_spec(yaml.safe_load(REVERSE), "reverse.yaml")
    refs = _refs(_mr1(), ["/backup", "/cmd_vel", "/odom"])
    wiring = wire(capability, spec, refs)
    assert _names(wiring.wired) == ["/cmd_vel", "/odom"]
    assert [u.interface.name for u in wiring.unwired] == ["/backup"]
    assert "action BackUp" in wiring.unwired[0].reason
    skeleton = build_skeleton(capability, spec, wiring.wired, unwired=wiring.unwired)
    assert "backup" not in skeleton.code.lower()
    assert any("/backup" in note for note in skeleton.notes)

    asked = parse_spec(
        yaml.safe_load(REVERSE.replace("Drive backwards at", "Back up with Nav2's behaviour at")),
        "reverse.yaml",
    )
    assert "/backup" in _names(wire(capability, asked, refs).wired)
    pinned = wire(capability, spec, refs, pinned=["/backup"])
    assert pinned.reasons["/backup"] == "pinned by the user"


def test_the_card_lists_an_unwired_interface_without_a_handle_or_its_fields() -> None:
    capability, _ = _shipped("move-forward")
    spec = parse_spec(yaml.safe_load(REVERSE), "reverse.yaml")
    refs = _refs(_mr1(), ["/cmd_vel", "/odom", "/backup"])
    wiring = wire(capability, spec, refs)
    skeleton = build_skeleton(capability, spec, wiring.wired, unwired=wiring.unwired)
    items = [CardInterface(_mr1().interface(r.name), r) for r in refs]
    card = task_card(capability, skeleton, items)
    assert (
        "Not wired (nothing in the specification calls for them; no handle): "
        "/backup (BackUp action)" in card.splitlines()
    )
    assert "self.backup_client" not in card
    assert "BackUp.Goal()" not in card
    assert "self.cmd_vel_publisher publishes Twist on /cmd_vel" in card


def test_the_velocity_command_stays_where_a_state_stops_the_base() -> None:
    capability, spec = _shipped("get-distance-to-nearest-object")
    refs = _refs(_mr1(), ["/scan", "/cmd_vel"])
    assert _names(wire(capability, spec, refs).wired) == ["/scan"]
    stops = spec.model_copy(
        update={"states": {**spec.states, "stopping": "Publish a zero velocity command."}}
    )
    wiring = wire(capability, stops, refs)
    assert _names(wiring.wired) == ["/scan", "/cmd_vel"]
    assert wiring.reasons["/cmd_vel"].startswith("the stopping state stops the base")


def test_the_shipped_pairs_lose_only_the_handles_nothing_asks_for() -> None:
    capability, spec = _shipped("rotate")
    wiring = wire(capability, spec, _refs(_mr1(), ["/cmd_vel", "/pose", "/spin", "/odom"]))
    assert _names(wiring.wired) == ["/cmd_vel", "/pose", "/odom"]
    assert [u.interface.name for u in wiring.unwired] == ["/spin"]

    capability, spec = _shipped("get-position")
    wiring = wire(capability, spec, _refs(_mr1(), ["/pose", "/tf", "/odom", "/cmd_vel"]))
    # "the yaw from the rotation quaternion" asks for no motion.
    assert [u.interface.name for u in wiring.unwired] == ["/cmd_vel"]

    capability, spec = _shipped("mapping")
    names = ["/map", "/scan", "/navigate_to_pose", "/map_saver/save_map", "/cmd_vel"]
    assert _names(wire(capability, spec, _refs(_mr1(), names)).wired) == names


def test_a_specification_that_names_moveit_leaves_the_joint_trajectory_unwired() -> None:
    capability, spec = _shipped("move-to-point")
    names = ["/move_action", "/tf", "/arm_controller/follow_joint_trajectory"]
    wiring = wire(capability, spec, _refs(_mr1(), names))
    assert _names(wiring.wired) == ["/move_action", "/tf"]
    assert "joint trajectory" in wiring.unwired[0].reason


def _paper(shared_data: Path, stem: str) -> tuple[Capability, SkillSpec, Inventory]:
    cap2skill = shared_data / "cap2skill"
    capability = load_capability(cap2skill / "capability-models" / f"{stem}.ttl").capability
    spec = load_spec(cap2skill / "skill-specs" / f"{stem.replace('-', '_')}.json")
    inventory = load_inventory(cap2skill / "interface-reports" / "ros2_system_report.json")
    return capability, spec, inventory


def test_the_papers_move_the_manipulator_wires_every_means_of_moving_the_arm(
    shared_data: Path,
) -> None:
    capability, spec, inventory = _paper(shared_data, "move-to-point")
    names = [
        "/joint_trajectory_controller/follow_joint_trajectory",
        "/tf",
        "/joint_trajectory_controller/joint_trajectory",
    ]
    wiring = wire(capability, spec, _refs(inventory, names))
    assert _names(wiring.wired) == names
    assert wiring.reasons[names[0]] == "arm motion: the capability says 'manipulator'"


@pytest.mark.parametrize(
    ("stem", "given", "unwired"),
    [
        ("rotate", ["/cmd_vel", "/odom", "/scan"], ["/scan"]),
        ("move-forward", ["/cmd_vel", "/scan", "/odom", "/scan2"], ["/scan", "/scan2"]),
        ("get-position", ["/odom", "/tf", "/joint_states"], ["/joint_states"]),
        ("collision-avoidance", ["/scan", "/cmd_vel", "/scan2"], []),
    ],
)
def test_the_papers_pairs_lose_the_sensors_their_texts_never_mention(
    shared_data: Path, stem: str, given: list[str], unwired: list[str]
) -> None:
    capability, spec, inventory = _paper(shared_data, stem)
    wiring = wire(capability, spec, _refs(inventory, given))
    assert [u.interface.name for u in wiring.unwired] == unwired


def test_odometry_is_wired_for_the_rest_the_skeleton_waits_for() -> None:
    # Collision avoidance asserts its final velocities zero and never mentions odometry.
    capability, _ = _shipped("collision-avoidance")
    spec = parse_spec(
        {
            "name": "go",
            "skill_interface": "REST",
            "states": {"execute": "Drive ahead, then publish a zero velocity command."},
        },
        "go.yaml",
    )
    wiring = wire(capability, spec, _refs(_mr1(), ["/cmd_vel", "/odom"]))
    assert wiring.reasons["/odom"].startswith("the skeleton brings the base to rest for")
    # Without a velocity command the skeleton cannot bring the base to rest.
    alone = wire(capability, spec, _refs(_mr1(), ["/scan", "/odom"]))
    assert "/odom" not in alone.reasons


def test_when_nothing_is_called_for_the_best_ranked_keeps_its_handle() -> None:
    capability, _ = _shipped("get-distance-to-nearest-object")
    spec = parse_spec(
        {"name": "idle", "skill_interface": "REST", "states": {"execute": "Do what is asked."}},
        "idle.yaml",
    )
    bare = capability.model_copy(update={"comment": None, "label": "x", "outputs": []})
    wiring = wire(bare, spec, _refs(_mr1(), ["/joint_states", "/imu/data"]))
    assert _names(wiring.wired) == ["/joint_states"]
    assert [u.interface.name for u in wiring.unwired] == ["/imu/data"]
