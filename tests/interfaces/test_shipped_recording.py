"""The shipped MR-1 recording discovers into the robot's full interface inventory."""

from __future__ import annotations

from pathlib import Path

from skillwright.interfaces.load import load_inventory
from skillwright.interfaces.ros2msg import split_action
from tests.conftest import SHIPPED_CAPABILITIES

RECORDING = SHIPPED_CAPABILITIES / "recordings" / "mr1"


def test_split_action_gives_goal_result_and_feedback() -> None:
    text = "int32 order\n---\nint32[] sequence\n---\nint32[] partial\n"
    assert split_action(text) == ("int32 order", "int32[] sequence", "int32[] partial")
    assert split_action("ACTION: pkg/action/A\nint8 a\n---\nint8 b\n---\nint8 c") == (
        "int8 a",
        "int8 b",
        "int8 c",
    )
    assert split_action("int8 a\n---\nint8 b\n") is None


def test_mr1_recording_has_every_interface_with_definitions() -> None:
    inventory = load_inventory(RECORDING)
    kinds = [i.kind for i in inventory.interfaces]
    assert (kinds.count("topic"), kinds.count("service"), kinds.count("action")) == (29, 38, 10)
    cmd_vel = inventory.interface("/cmd_vel", "topic")
    assert cmd_vel.type_name == "geometry_msgs/msg/Twist"
    assert [f.name for f in cmd_vel.definitions["message"].fields or []] == ["linear", "angular"]
    navigate = inventory.interface("/navigate_to_pose", "action")
    assert navigate.type_name == "nav2_msgs/action/NavigateToPose"
    assert sorted(navigate.definitions) == ["feedback", "goal", "result"]
    feedback = navigate.definitions["feedback"].fields or []
    assert "distance_remaining" in [f.name for f in feedback]
    save_map = inventory.interface("/map_saver/save_map", "service")
    assert sorted(save_map.definitions) == ["request", "response"]
    assert inventory.interface("/rosout").infrastructure is not None


def test_saved_inventory_loads_back_identically(tmp_path: Path) -> None:
    inventory = load_inventory(RECORDING)
    saved = tmp_path / "inventory.json"
    saved.write_text(inventory.model_dump_json(), encoding="utf-8")
    assert load_inventory(saved) == inventory
