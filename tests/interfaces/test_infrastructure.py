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
    ],
)
def test_task_interfaces_are_not_flagged(kind: InterfaceKind, name: str, type_name: str) -> None:
    assert classify(kind, name, type_name) is None


def test_rule_identifiers_are_unique() -> None:
    assert len({rule.rule for rule in RULES}) == len(RULES)
