"""Which interfaces are ROS 2 or tooling plumbing rather than part of the robot's task.

The rules are a plain table so that enrichment (and the user reading an inventory) can
see exactly why an interface was flagged. A rule matches on the interface kind and on
the name (last path segments) and/or the type; the first matching rule wins.

The line between plumbing and control follows one question: would a skill that runs on
the real robot command, sense or plan through this interface? Parameters, logging,
introspection, lifecycle and bring-up, time, metadata, visualisation and the simulator's
own services fail it; everything else is control (see
:mod:`~skillwright.interfaces.relevance`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from skillwright.interfaces.inventory import InfrastructureFlag, InterfaceKind

__all__ = ["RULES", "InfrastructureRule", "classify"]


@dataclass(frozen=True)
class InfrastructureRule:
    """One row of the rule table."""

    rule: str
    """Stable identifier, recorded in the inventory."""
    kinds: frozenset[InterfaceKind]
    """Interface kinds the rule applies to."""
    reason: str
    """Why interfaces matching it are infrastructure."""
    name: re.Pattern[str] | None = None
    """Pattern the full interface name must match (``search``), if any."""
    type_name: re.Pattern[str] | None = None
    """Pattern the interface type must match (``fullmatch``), if any."""

    def matches(self, kind: InterfaceKind, name: str, type_name: str) -> bool:
        """Whether an interface of ``kind`` called ``name`` of ``type_name`` is covered."""
        if kind not in self.kinds:
            return False
        if self.name is not None and not self.name.search(name):
            return False
        return self.type_name is None or bool(self.type_name.fullmatch(type_name))


_TOPIC = frozenset[InterfaceKind]({"topic"})
_SERVICE = frozenset[InterfaceKind]({"service"})

RULES: tuple[InfrastructureRule, ...] = (
    InfrastructureRule(
        rule="rosout",
        kinds=_TOPIC,
        name=re.compile(r"^/rosout$"),
        reason="log output every ROS 2 node publishes; for debugging, not for control",
    ),
    InfrastructureRule(
        rule="parameter_events",
        kinds=_TOPIC,
        name=re.compile(r"(^|/)parameter_events$"),
        reason="notifications of parameter changes, published by every node",
    ),
    InfrastructureRule(
        rule="recorder_events",
        kinds=_TOPIC,
        name=re.compile(r"^/events/(write_split|read_split)$"),
        reason="rosbag2's own notifications about bag files being split or read",
    ),
    InfrastructureRule(
        rule="parameter_services",
        kinds=_SERVICE,
        name=re.compile(
            r"/(describe_parameters|get_parameters|get_parameter_types|list_parameters"
            r"|set_parameters|set_parameters_atomically)$"
        ),
        reason="parameter services every node offers; introspection and configuration",
    ),
    InfrastructureRule(
        rule="type_description_service",
        kinds=_SERVICE,
        name=re.compile(r"/get_type_description$"),
        reason="returns message type descriptions; introspection",
    ),
    InfrastructureRule(
        rule="lifecycle_transition_event",
        kinds=_TOPIC,
        type_name=re.compile(r"lifecycle_msgs/msg/TransitionEvent"),
        reason="lifecycle state-change notifications of a managed node",
    ),
    InfrastructureRule(
        rule="lifecycle_services",
        kinds=_SERVICE,
        type_name=re.compile(
            r"lifecycle_msgs/srv/(ChangeState|GetState|GetAvailableStates"
            r"|GetAvailableTransitions)"
        ),
        reason="lifecycle management of a managed node (configure, activate, ...)",
    ),
    InfrastructureRule(
        rule="logger_level_services",
        kinds=_SERVICE,
        name=re.compile(r"/(get_logger_levels|set_logger_levels)$"),
        reason="changes the verbosity of a node's logging",
    ),
    InfrastructureRule(
        rule="clock",
        kinds=_TOPIC,
        type_name=re.compile(r"rosgraph_msgs/msg/Clock"),
        reason="simulated or played-back time; nodes read it through their ROS clock, "
        "a skill never subscribes to it itself",
    ),
    InfrastructureRule(
        rule="performance_metrics",
        kinds=_TOPIC,
        type_name=re.compile(
            r"gazebo_msgs/msg/PerformanceMetrics|statistics_msgs/msg/MetricsMessage"
        ),
        reason="performance figures of the simulator or of topic statistics; for profiling",
    ),
    InfrastructureRule(
        rule="robot_model",
        kinds=_TOPIC,
        name=re.compile(r"(^|/)robot_description(_semantic)?$"),
        type_name=re.compile(r"std_msgs/msg/String"),
        reason="the robot's URDF/SRDF model as text: metadata for model-based tools "
        "(robot_state_publisher, MoveIt), not a command or a measurement",
    ),
    InfrastructureRule(
        rule="bond",
        kinds=_TOPIC,
        type_name=re.compile(r"bond/msg/Status"),
        reason="heartbeats between a lifecycle manager and the nodes it supervises",
    ),
    InfrastructureRule(
        rule="lifecycle_manager_services",
        kinds=_SERVICE,
        type_name=re.compile(r"nav2_msgs/srv/ManageLifecycleNodes"),
        reason="starts, pauses and resets the Nav2 servers as a group; bring-up",
    ),
    InfrastructureRule(
        rule="lifecycle_manager_state",
        kinds=_SERVICE,
        name=re.compile(r"/lifecycle_manager[^/]*/is_active$"),
        reason="tells whether a lifecycle manager has brought its nodes up; bring-up",
    ),
    InfrastructureRule(
        rule="controller_bring_up",
        kinds=_SERVICE,
        type_name=re.compile(
            r"controller_manager_msgs/srv/(LoadController|UnloadController|ConfigureController"
            r"|LoadConfigureController|ReloadControllerLibraries|SetHardwareComponentState)"
        ),
        reason="bring-up of the ros2_control stack (loading, configuring and unloading "
        "controllers, hardware component lifecycle), done by launch files and the spawner; "
        "a skill selects active controllers with switch_controller",
    ),
    InfrastructureRule(
        rule="controller_introspection",
        kinds=_SERVICE,
        type_name=re.compile(
            r"controller_manager_msgs/srv/(ListControllerTypes|ListHardwareComponents"
            r"|ListHardwareInterfaces)"
        ),
        reason="lists the controller plugins or hardware the controller manager knows; "
        "introspection",
    ),
    InfrastructureRule(
        rule="simulator_services",
        kinds=_SERVICE,
        type_name=re.compile(r"(gazebo_msgs|ros_gz_interfaces)/srv/\w+"),
        reason="acts on the simulator (models, forces, world state), bypassing the robot's "
        "controllers; it does not exist on the real robot",
    ),
    InfrastructureRule(
        rule="simulator_physics_services",
        kinds=_SERVICE,
        name=re.compile(r"/(pause_physics|unpause_physics|reset_simulation|reset_world)$"),
        type_name=re.compile(r"std_srvs/srv/Empty"),
        reason="pauses or resets the simulator's physics or world; it does not exist on "
        "the real robot",
    ),
    InfrastructureRule(
        rule="simulator_ground_truth",
        kinds=_TOPIC,
        type_name=re.compile(r"gazebo_msgs/msg/(ModelStates|LinkStates)"),
        reason="the simulator's true poses of every model; not available on the real robot",
    ),
    InfrastructureRule(
        rule="visualisation",
        kinds=_TOPIC,
        type_name=re.compile(
            r"visualization_msgs/msg/\w+|moveit_msgs/msg/(DisplayTrajectory|DisplayRobotState)"
        ),
        reason="markers and displays for RViz; for people watching, not for control",
    ),
    InfrastructureRule(
        rule="component_container_services",
        kinds=_SERVICE,
        type_name=re.compile(r"composition_interfaces/srv/\w+"),
        reason="loads and unloads nodes in a component container; deployment",
    ),
    InfrastructureRule(
        rule="recorder_services",
        kinds=_SERVICE,
        type_name=re.compile(r"rosbag2_interfaces/srv/\w+"),
        reason="controls a rosbag2 recorder or player",
    ),
)


def classify(kind: InterfaceKind, name: str, type_name: str) -> InfrastructureFlag | None:
    """The flag of the first rule that covers the interface, or ``None``."""
    for rule in RULES:
        if rule.matches(kind, name, type_name):
            return InfrastructureFlag(rule=rule.rule, reason=rule.reason)
    return None
