"""The infrastructure rule table flags ROS 2 plumbing and leaves task interfaces alone."""

from __future__ import annotations

import pytest

from skillwright.interfaces.infrastructure import RULES, classify
from skillwright.interfaces.inventory import InterfaceKind


@pytest.mark.parametrize(
    ("kind", "name", "type_name", "rule"),
    [
        ("topic", "/rosout", "rcl_interfaces/msg/Log", "rosout"),
        ("topic", "/parameter_events", "rcl_interfaces/msg/ParameterEvent", "parameter_events"),
        (
            "topic",
            "/robot/parameter_events",
            "rcl_interfaces/msg/ParameterEvent",
            "parameter_events",
        ),
        (
            "topic",
            "/events/write_split",
            "rosbag2_interfaces/msg/WriteSplitEvent",
            "recorder_events",
        ),
        (
            "service",
            "/talker/get_parameters",
            "rcl_interfaces/srv/GetParameters",
            "parameter_services",
        ),
        (
            "service",
            "/talker/set_parameters_atomically",
            "rcl_interfaces/srv/SetParametersAtomically",
            "parameter_services",
        ),
        (
            "service",
            "/talker/get_type_description",
            "type_description_interfaces/srv/GetTypeDescription",
            "type_description_service",
        ),
        (
            "topic",
            "/camera/transition_event",
            "lifecycle_msgs/msg/TransitionEvent",
            "lifecycle_transition_event",
        ),
        ("service", "/camera/change_state", "lifecycle_msgs/srv/ChangeState", "lifecycle_services"),
        (
            "service",
            "/camera/set_logger_levels",
            "rcl_interfaces/srv/SetLoggerLevels",
            "logger_level_services",
        ),
        ("topic", "/clock", "rosgraph_msgs/msg/Clock", "clock"),
        (
            "topic",
            "/performance_metrics",
            "gazebo_msgs/msg/PerformanceMetrics",
            "performance_metrics",
        ),
        ("topic", "/robot_description", "std_msgs/msg/String", "robot_model"),
        ("topic", "/robot_description_semantic", "std_msgs/msg/String", "robot_model"),
        ("topic", "/bond", "bond/msg/Status", "bond"),
        (
            "service",
            "/lifecycle_manager_navigation/manage_nodes",
            "nav2_msgs/srv/ManageLifecycleNodes",
            "lifecycle_manager_services",
        ),
        (
            "service",
            "/lifecycle_manager_navigation/is_active",
            "std_srvs/srv/Trigger",
            "lifecycle_manager_state",
        ),
        (
            "service",
            "/controller_manager/configure_controller",
            "controller_manager_msgs/srv/ConfigureController",
            "controller_bring_up",
        ),
        (
            "service",
            "/controller_manager/list_hardware_interfaces",
            "controller_manager_msgs/srv/ListHardwareInterfaces",
            "controller_introspection",
        ),
        (
            "service",
            "/apply_joint_effort",
            "gazebo_msgs/srv/ApplyJointEffort",
            "simulator_services",
        ),
        (
            "service",
            "/world/empty/control",
            "ros_gz_interfaces/srv/ControlWorld",
            "simulator_services",
        ),
        ("service", "/pause_physics", "std_srvs/srv/Empty", "simulator_physics_services"),
        ("topic", "/gazebo/model_states", "gazebo_msgs/msg/ModelStates", "simulator_ground_truth"),
        ("topic", "/markers", "visualization_msgs/msg/MarkerArray", "visualisation"),
        ("topic", "/display_planned_path", "moveit_msgs/msg/DisplayTrajectory", "visualisation"),
        (
            "service",
            "/container/_container/load_node",
            "composition_interfaces/srv/LoadNode",
            "component_container_services",
        ),
        ("service", "/rosbag2_recorder/pause", "rosbag2_interfaces/srv/Pause", "recorder_services"),
    ],
)
def test_infrastructure_is_flagged(
    kind: InterfaceKind, name: str, type_name: str, rule: str
) -> None:
    flag = classify(kind, name, type_name)
    assert flag is not None
    assert flag.rule == rule
    assert flag.reason


@pytest.mark.parametrize(
    ("kind", "name", "type_name"),
    [
        ("topic", "/cmd_vel", "geometry_msgs/msg/Twist"),
        ("topic", "/rosout_agg", "rcl_interfaces/msg/Log"),
        ("service", "/arm/set_speed", "demo/srv/SetSpeed"),
        ("action", "/navigate_to_pose", "nav2_msgs/action/NavigateToPose"),
        # Names alone do not make a topic a parameter service.
        ("topic", "/get_parameters", "std_msgs/msg/String"),
        # A skill selects and checks its controllers: that is control, not bring-up.
        (
            "service",
            "/controller_manager/switch_controller",
            "controller_manager_msgs/srv/SwitchController",
        ),
        (
            "service",
            "/controller_manager/list_controllers",
            "controller_manager_msgs/srv/ListControllers",
        ),
        # Empty services of the robot's own, and simulated sensors, are not simulator plumbing.
        ("service", "/reset_odometry", "std_srvs/srv/Empty"),
        ("topic", "/bumper", "gazebo_msgs/msg/ContactsState"),
        # Strings that are not the robot model stay control.
        ("topic", "/speech", "std_msgs/msg/String"),
    ],
)
def test_task_interfaces_are_not_flagged(kind: InterfaceKind, name: str, type_name: str) -> None:
    assert classify(kind, name, type_name) is None


def test_rule_identifiers_are_unique() -> None:
    assert len({rule.rule for rule in RULES}) == len(RULES)
