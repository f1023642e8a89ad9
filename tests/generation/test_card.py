"""The task card: a skill's context in few tokens."""

from __future__ import annotations

from functools import cache

from skillwright.capability.reader import load_capability
from skillwright.generation.card import CardInterface, field_paths, task_card
from skillwright.generation.model import InterfaceRef
from skillwright.generation.skeleton import build_skeleton, topic_role
from skillwright.interfaces.inventory import Inventory
from skillwright.interfaces.load import load_inventory
from skillwright.spec.loader import load_spec
from tests.conftest import SHIPPED_CAPABILITIES


@cache
def _inventory() -> Inventory:
    return load_inventory(SHIPPED_CAPABILITIES / "recordings" / "mr1")


def _card(capability: str, names: list[str]) -> str:
    load = load_capability(SHIPPED_CAPABILITIES / f"{capability}.ttl")
    spec = load_spec(SHIPPED_CAPABILITIES / f"{capability}.spec.yaml")
    items = []
    for name in names:
        interface = _inventory().interface(name)
        role = (
            topic_role(interface.name, interface.type_name) if interface.kind == "topic" else "call"
        )
        ref = InterfaceRef(name=name, kind=interface.kind, type_name=interface.type_name, role=role)
        items.append(CardInterface(interface, ref))
    skeleton = build_skeleton(load.capability, spec, [i.ref for i in items])
    return task_card(load.capability, skeleton, items)


def test_the_card_names_inputs_outputs_limits_handles_and_helpers() -> None:
    card = _card("move-forward", ["/cmd_vel", "/odom"])
    lines = card.splitlines()
    assert lines[0] == "Skill MoveForwardSkill: capability moveForward of mr1."
    assert (
        "Inputs (set before starting): self.in_distance (float, m), "
        "self.in_linear_velocity (float, m/s)" in lines
    )
    assert (
        "Outputs: self.out_distance (float, m), self.out_linear_velocity (float, m/s; set by "
        "the skeleton in completing once the base is at rest)" in lines
    )
    assert "Limits: self.LINEAR_VELOCITY_MAX = 0.8 (m/s)" in lines
    assert (
        "- self.cmd_vel_publisher publishes Twist on /cmd_vel. "
        "Twist: linear.{x,y,z}, angular.{x,y,z}" in lines
    )
    odom = next(line for line in lines if line.startswith("- self.odom_msg"))
    assert "latest Odometry from /odom (None until one arrives)" in odom
    assert "pose.pose.position.{x,y,z}" in odom
    assert "twist.twist.linear.{x,y,z}" in odom
    assert lines[-1].startswith("Helpers: self._wait_until(condition, timeout, what)")
    assert "self._stop_base() commands zero velocity" in lines[-1]


def test_actions_show_goal_result_and_feedback() -> None:
    card = _card("navigate-to-point", ["/navigate_to_pose"])
    line = next(line for line in card.splitlines() if "/navigate_to_pose" in line)
    assert line.startswith("- self.navigate_to_pose_client: ActionClient for NavigateToPose")
    assert "NavigateToPose.Goal(): pose.header.stamp (time)" in line
    assert "Result:" in line
    assert "Feedback:" in line
    assert "self._result_of(future, timeout, what)" in card


def test_a_huge_definition_is_shown_shallower_not_whole() -> None:
    card = _card("move-forward", ["/move_action"])
    line = next(line for line in card.splitlines() if "/move_action" in line)
    assert (
        "MoveGroup.Goal(): request (MotionPlanRequest), planning_options (PlanningOptions)" in line
    )
    assert len(line) < 1000


def test_field_paths_group_siblings_of_one_type() -> None:
    twist = _inventory().interface("/cmd_vel").definitions["message"].fields
    assert field_paths(twist) == "linear.{x,y,z}, angular.{x,y,z}"
    assert field_paths(twist, depth=0) == "{linear,angular} (Vector3)"
    assert field_paths([]) == "(no fields)"
