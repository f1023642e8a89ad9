"""Finding the interfaces the world serves by type and role, and the recorded geometry."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from skillwright.interfaces.inventory import Inventory
from skillwright.sim.bindings import (
    ScanGeometry,
    bind_interfaces,
    default_geometries,
    nominal_rate,
    recorded_facts,
    split_views,
)


@pytest.mark.parametrize(
    ("measured", "nominal"),
    [
        (49.93, 50.0),
        (9.718, 10.0),
        (4.69, 5.0),
        (0.52, 0.5),
        (0.839, 0.839),
        (None, 7.0),
        (0.0, 7.0),
    ],
)
def test_a_measured_rate_snaps_to_the_nominal_rate_within_ten_percent(
    measured: float | None, nominal: float
) -> None:
    assert nominal_rate(measured, 7.0) == pytest.approx(nominal)


def test_the_mr1_recording_binds_every_role(mr1_inventory: Inventory) -> None:
    bindings = bind_interfaces(mr1_inventory)
    assert bindings.command_topic == "/cmd_vel"
    assert bindings.odometry_topics == ["/odom"]
    assert bindings.scan_topics == ["/scan"]
    assert bindings.imu_topics == ["/imu/data"]
    assert bindings.pose_topics == ["/pose"]
    assert (bindings.tf_topic, bindings.tf_static_topic) == ("/tf", "/tf_static")
    assert (bindings.map_topic, bindings.map_metadata_topic) == ("/map", "/map_metadata")
    assert bindings.actions == {
        "/backup": "backup",
        "/move_action": "move_group",
        "/navigate_through_poses": "navigate_through_poses",
        "/navigate_to_pose": "navigate_to_pose",
        "/spin": "spin",
    }
    assert set(bindings.services.values()) == {"nav2_save_map", "slam_save_map", "compute_fk"}
    assert bindings.rates["/odom"] == 50.0
    assert bindings.rates["/scan"] == 10.0
    assert bindings.has_localisation
    assert "/cmd_vel" not in bindings.owned_topics()


def test_the_scan_geometry_and_frames_come_from_the_first_recorded_messages(
    mr1_inventory: Inventory, recording: Path
) -> None:
    bindings = bind_interfaces(mr1_inventory)
    facts = recorded_facts(mr1_inventory, bindings, recording)
    scan = facts.scans["/scan"]
    assert scan.recorded
    assert scan.count == 360
    assert scan.angle_min == pytest.approx(-math.pi)
    assert scan.angle_max == pytest.approx(math.pi - 2 * math.pi / 360, abs=1e-6)
    assert (scan.range_min, scan.range_max, scan.frame_id) == (
        pytest.approx(0.05),
        12.0,
        "laser_link",
    )
    assert (facts.odom_frame, facts.base_frame, facts.map_frame) == ("odom", "base_link", "map")
    assert facts.map_resolution == pytest.approx(0.05)
    assert facts.notes == []


def test_a_report_without_messages_gives_default_geometry_and_says_so(shared_data: Path) -> None:
    from skillwright.interfaces.load import load_inventory

    inventory = load_inventory(
        shared_data / "cap2skill" / "interface-reports" / "ros2_system_report.json"
    )
    bindings = bind_interfaces(inventory)
    assert bindings.command_topic == "/cmd_vel"
    assert bindings.odometry_topics == ["/odom"]
    assert bindings.scan_topics == ["/scan", "/scan2"]
    assert not bindings.has_localisation
    assert bindings.actions == {}
    facts = recorded_facts(inventory, bindings)
    assert "defaults" in facts.notes[0]
    # the paper's robot's two corner scanners: a half turn each, the front one and the rear
    front, rear = facts.scans["/scan"], facts.scans["/scan2"]
    assert front.count == rear.count == 180
    assert math.degrees(front.angle_min) == pytest.approx(-90)
    assert math.degrees(rear.angle_min) == pytest.approx(90)
    assert rear.angle_min == pytest.approx(front.angle_max + front.angle_increment)
    assert facts.notes[1:] == [
        "/scan: one scanner of a split view; it sees from -90 to 89 degrees only",
        "/scan2: one scanner of a split view; it sees from 90 to 269 degrees only",
    ]


def test_a_scanner_of_its_own_sees_all_around_and_split_views_share_the_turn() -> None:
    assert default_geometries(["/scan"]) == {"/scan": ScanGeometry()}
    assert split_views(["/scan_raw", "/scan", "/b_scan", "/f_scan"]) == [
        ["/b_scan", "/f_scan"],
        ["/scan"],
        ["/scan_raw"],
    ]
    thirds = default_geometries(["/lidar_1/scan", "/lidar_2/scan", "/lidar_3/scan"])
    assert [g.count for g in thirds.values()] == [120, 120, 120]
    assert [round(math.degrees(g.angle_min)) for g in thirds.values()] == [-60, 60, 180]


def test_an_inventory_without_a_base_says_what_is_missing() -> None:
    from skillwright.interfaces.inventory import Resource

    bindings = bind_interfaces(Inventory(resource=Resource(name="arm only")))
    assert bindings.command_topic is None
    assert any("no velocity command topic" in note for note in bindings.notes)
    assert any("no Odometry topic" in note for note in bindings.notes)


SRDF = """<?xml version="1.0"?>
<robot name="mmo700">
  <group name="arm"><chain base_link="arm_base_link" tip_link="tool0"/></group>
  <group name="gripper"><link name="finger_left"/><link name="finger_right"/></group>
  <group name="arm_with_gripper"><group name="arm"/><group name="gripper"/></group>
  <group_state name="home" group="arm"/>
</robot>"""


def test_planning_groups_and_their_tips_come_from_the_srdf() -> None:
    from skillwright.sim.bindings import srdf_groups

    assert srdf_groups(SRDF) == {"arm": "tool0", "gripper": None, "arm_with_gripper": "tool0"}
    assert srdf_groups("not xml") == {}


def test_the_srdf_topic_is_the_string_topic_move_group_publishes(
    mr1_inventory: Inventory,
) -> None:
    from skillwright.interfaces.inventory import Interface
    from skillwright.sim.bindings import semantic_topic

    assert semantic_topic(mr1_inventory) is None  # the MR-1's recording has no SRDF
    srdf = Interface(
        name="/robot_description_semantic", kind="topic", type_name="std_msgs/msg/String"
    )
    with_srdf = mr1_inventory.model_copy(update={"interfaces": [*mr1_inventory.interfaces, srdf]})
    assert semantic_topic(with_srdf) == "/robot_description_semantic"
