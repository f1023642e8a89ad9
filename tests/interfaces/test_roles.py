"""Which topic is a base's velocity command; what role an interface plays and which words ask for it."""

from __future__ import annotations

import pytest

from skillwright.interfaces.roles import command_topic, interface_role, normalised_words


@pytest.mark.parametrize(
    ("names", "chosen"),
    [
        (["/cmd_vel_nav", "/cmd_vel"], "/cmd_vel"),
        (["/panther/cmd_vel", "/panther/cmd_vel_nav"], "/panther/cmd_vel"),
        (["/stretch/cmd_vel", "/robot/cmd_vel"], "/robot/cmd_vel"),  # equals: the shorter
        (["/controller/cmd_vel_raw", "/cmd_vel_nav"], "/controller/cmd_vel_raw"),
        (["/base/twist_cmd"], "/base/twist_cmd"),
        (["/cmd_vel_nav"], "/cmd_vel_nav"),  # only Nav2's: still the one there is
        (["/turtle1/velocity", "/key_twist"], None),
        ([], None),
    ],
)
def test_the_command_is_the_twist_named_like_one_cmd_vel_first(
    names: list[str], chosen: str | None
) -> None:
    assert command_topic(names) == chosen


@pytest.mark.parametrize(
    ("interface", "role"),
    [
        (("/cmd_vel", "topic", "geometry_msgs/msg/Twist", "publish"), "velocity command"),
        (("/odom", "topic", "nav_msgs/msg/Odometry", "subscribe"), "odometry"),
        (("/scan", "topic", "sensor_msgs/msg/LaserScan", "subscribe"), "range sensor"),
        (("/tf", "topic", "tf2_msgs/msg/TFMessage", "subscribe"), "transform tree"),
        (
            ("/navigate_to_pose", "action", "nav2_msgs/action/NavigateToPose", "call"),
            "navigation goal",
        ),
        (("/move_action", "action", "moveit_msgs/action/MoveGroup", "call"), "planned arm motion"),
        (("/backup", "action", "nav2_msgs/action/BackUp", "call"), "action BackUp"),
        (("/imu/data", "topic", "sensor_msgs/Imu", "subscribe"), "inertial measurement"),
        # A Twist the skill reads is no command of its own.
        (("/odom_twist", "topic", "geometry_msgs/msg/Twist", "subscribe"), "topic Twist"),
    ],
)
def test_an_interface_has_the_role_its_type_gives(
    interface: tuple[str, str, str, str], role: str
) -> None:
    assert interface_role(*interface).name == role


@pytest.mark.parametrize(
    ("text", "called"),
    [
        ("Drive backwards by the requested distance, then stop.", None),
        ("Back up by the requested distance with Nav2's behaviour.", "back up"),
        ("Send a goal to /backup.", "backup"),
    ],
)
def test_a_nav2_behaviour_is_called_for_by_what_it_does_not_by_a_direction(
    text: str, called: str | None
) -> None:
    role = interface_role("/backup", "action", "nav2_msgs/action/BackUp", "call")
    assert role.called_for(normalised_words(text)) == called


def test_the_velocity_command_is_called_for_by_motion_not_by_a_rotation_quaternion() -> None:
    role = interface_role("/cmd_vel", "topic", "geometry_msgs/msg/Twist", "publish")
    assert role.called_for(normalised_words("Publish a zero velocity command.")) == "velocit"
    assert role.called_for(normalised_words("Rotate the base on the spot.")) == "rotate"
    assert (
        role.called_for(normalised_words("Compute the yaw from the rotation quaternion.")) is None
    )


def test_a_namespace_and_a_vague_last_part_do_not_call_for_an_interface() -> None:
    imu = interface_role("/imu/data", "topic", "sensor_msgs/msg/Imu", "subscribe")
    assert imu.called_for(normalised_words("Store the data as outputs.")) is None
    assert imu.called_for(normalised_words("Read the IMU.")) == "imu"
    dock = interface_role("/panther/dock_robot", "action", "nav2_msgs/action/DockRobot", "call")
    assert dock.called_for(normalised_words("Drive the Panther forward.")) is None
    assert dock.called_for(normalised_words("Dock the robot at its charger.")) == "dock the robot"
    saver = interface_role("/map_saver/save_map", "service", "nav2_msgs/srv/SaveMap", "call")
    assert saver.called_for(normalised_words("Save it with the map saver service.")) == (
        "map saver"
    )


def test_arm_motions_share_a_family_and_its_generic_words() -> None:
    moveit = interface_role("/move_action", "action", "moveit_msgs/action/MoveGroup", "call")
    trajectory = interface_role(
        "/arm/follow_joint_trajectory",
        "action",
        "control_msgs/action/FollowJointTrajectory",
        "call",
    )
    assert moveit.family == trajectory.family == "arm motion"
    words = normalised_words("Move the manipulator to the point.")
    assert moveit.called_for(words) is None
    assert trajectory.called_for(words) is None
    assert trajectory.called_for_generically(words) == "manipulator"
    assert moveit.called_for(normalised_words("Plan the motion with MoveIt.")) == "move it"


def test_normalised_words_split_names_and_case() -> None:
    assert normalised_words("inLinearVelocity") == "in linear velocity"
    assert normalised_words("/map_saver/save_map") == "map saver save map"
    assert normalised_words("Nav2's goal") == "nav2 s goal"
