"""Uniform interface descriptions, and the deterministic ``rules`` engine that writes them.

Every interface gets the same five parts, whichever engine wrote them: what it is for,
which module of the resource it belongs to, the tasks it serves, who uses it, and its key
fields. The parts are joined into one paragraph for embedding, so retrieval compares like
with like. The rules engine needs no model: it reads the ROS 2 type (the strongest
signal), then the name, then the package, and falls back to a plain account of the
kind, type and fields. It never claims more than those give.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

from skillwright.interfaces.inventory import Description

__all__ = ["MODULES", "Description", "describe_by_rules"]

MODULES = (
    "base motion",
    "localisation",
    "perception",
    "mapping",
    "navigation",
    "manipulation",
    "controller management",
    "simulation",
    "diagnostics",
    "system",
    "other",
)
"""Modules of a resource an interface can belong to."""


@dataclass(frozen=True)
class _Rule:
    kinds: str  # letters t, s, a for topic, service, action
    type_pattern: str  # fullmatch on the type name
    purpose: str  # may use {name} and {what}
    module: str
    tasks: tuple[str, ...]
    used_by: tuple[str, ...]
    name_pattern: str | None = None  # search on the interface name


_RULES: tuple[_Rule, ...] = (
    _Rule(
        "t",
        r"geometry_msgs/msg/Twist(Stamped)?",
        "Commands the base's linear and angular velocity (forward, sideways, turning).",
        "base motion",
        ("drive forward", "rotate in place", "set velocity", "stop the base", "avoid collisions"),
        ("navigation controller", "teleoperation", "skills"),
        r"cmd|command",
    ),
    _Rule(
        "t",
        r"geometry_msgs/msg/Twist(Stamped)?",
        "Carries a velocity (linear and angular) of {what}.",
        "base motion",
        ("monitor velocity",),
        ("motion controllers",),
    ),
    _Rule(
        "t",
        r"nav_msgs/msg/Odometry",
        "Reports the base's estimated pose and velocity from odometry, "
        "relative to where it started.",
        "localisation",
        (
            "measure travelled distance",
            "measure velocity",
            "track position and heading",
            "close the loop of motion commands",
        ),
        ("base driver", "localisation", "navigation"),
    ),
    _Rule(
        "t",
        r"sensor_msgs/msg/LaserScan",
        "2-D range measurements around the robot from a laser scanner.",
        "perception",
        (
            "detect obstacles",
            "find the nearest object and its bearing",
            "mapping",
            "localisation",
            "collision avoidance",
        ),
        ("lidar driver", "SLAM", "costmaps"),
    ),
    _Rule(
        "t",
        r"sensor_msgs/msg/PointCloud2",
        "3-D points measured around the robot (depth camera or 3-D lidar).",
        "perception",
        ("detect obstacles", "perceive objects", "mapping"),
        ("sensor driver", "costmaps"),
    ),
    _Rule(
        "t",
        r"sensor_msgs/msg/(Image|CompressedImage)",
        "Camera images.",
        "perception",
        ("detect objects", "inspect the scene"),
        ("camera driver", "perception nodes"),
    ),
    _Rule(
        "t",
        r"sensor_msgs/msg/CameraInfo",
        "Calibration of a camera (intrinsics, distortion).",
        "perception",
        ("project between image and 3-D",),
        ("camera driver",),
    ),
    _Rule(
        "t",
        r"sensor_msgs/msg/Imu",
        "Orientation, angular velocity and linear acceleration from an inertial unit.",
        "localisation",
        ("estimate orientation and turning rate", "sensor fusion"),
        ("IMU driver", "state estimation"),
    ),
    _Rule(
        "t",
        r"sensor_msgs/msg/BatteryState",
        "State of charge and health of the battery.",
        "diagnostics",
        ("monitor battery", "decide when to recharge"),
        ("power driver",),
    ),
    _Rule(
        "t",
        r"sensor_msgs/msg/JointState",
        "Positions, velocities and efforts of the robot's joints.",
        "manipulation",
        ("read arm configuration", "monitor joint motion", "compute forward kinematics"),
        ("joint state broadcaster", "robot state publisher", "motion planning"),
    ),
    _Rule(
        "t",
        r"nav_msgs/msg/OccupancyGrid",
        "A costmap: the grid of obstacle costs the navigation stack plans around.",
        "navigation",
        ("plan collision-free paths", "check free space"),
        ("Nav2 costmaps",),
        r"costmap",
    ),
    _Rule(
        "t",
        r"nav_msgs/msg/OccupancyGrid",
        "The occupancy grid map of the environment (free, occupied, unknown cells).",
        "mapping",
        ("build and save a map", "localise in the map", "plan paths"),
        ("SLAM", "map server", "navigation"),
    ),
    _Rule(
        "t",
        r"nav_msgs/msg/Path",
        "A path as a sequence of poses, e.g. the plan the navigation stack follows.",
        "navigation",
        ("show or follow the planned path",),
        ("planner", "controller"),
    ),
    _Rule(
        "t",
        r"geometry_msgs/msg/PoseWithCovarianceStamped",
        "Sets the robot's initial pose estimate for localisation.",
        "localisation",
        ("initialise localisation",),
        ("operators", "RViz"),
        r"initial",
    ),
    _Rule(
        "t",
        r"geometry_msgs/msg/PoseWithCovarianceStamped",
        "The robot's estimated pose in the map frame, with its uncertainty.",
        "localisation",
        ("get the current position and heading in the map", "check localisation quality"),
        ("SLAM", "AMCL", "navigation"),
    ),
    _Rule(
        "t",
        r"geometry_msgs/msg/PoseStamped",
        "A goal pose for the navigation stack to drive to.",
        "navigation",
        ("send the robot to a pose",),
        ("RViz", "operators"),
        r"goal",
    ),
    _Rule(
        "t",
        r"geometry_msgs/msg/PoseStamped",
        "A pose in a named frame: {what}.",
        "localisation",
        ("read a pose",),
        ("nodes",),
    ),
    _Rule(
        "t",
        r"tf2_msgs/msg/TFMessage",
        "Transforms between the robot's coordinate frames (map, odom, base_link, sensors, "
        "arm links).",
        "localisation",
        ("look up the robot's pose in the map", "convert positions between frames"),
        ("robot state publisher", "localisation", "every node using tf2"),
    ),
    _Rule(
        "t",
        r"trajectory_msgs/msg/JointTrajectory",
        "Commands a joint trajectory to the arm's trajectory controller.",
        "manipulation",
        ("move the arm along joint waypoints",),
        ("motion planning", "skills"),
    ),
    _Rule(
        "t",
        r"control_msgs/msg/JointTrajectoryControllerState",
        "State of the joint trajectory controller: desired, actual and error.",
        "manipulation",
        ("monitor arm tracking",),
        ("trajectory controller",),
    ),
    _Rule(
        "t",
        r"control_msgs/msg/DynamicJointState",
        "All interface values of the robot's joints as ros2_control reports them.",
        "controller management",
        ("monitor joints",),
        ("joint state broadcaster",),
    ),
    _Rule(
        "t",
        r"std_msgs/msg/String",
        "The robot's URDF model (links, joints, limits).",
        "system",
        ("read the robot model",),
        ("robot state publisher", "motion planning"),
        r"robot_description",
    ),
    _Rule(
        "t",
        r"diagnostic_msgs/msg/DiagnosticArray",
        "Health reports of the robot's hardware and software components.",
        "diagnostics",
        ("monitor component health",),
        ("drivers", "diagnostic aggregator"),
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/NavigateToPose",
        "Drives the robot to a goal pose, planning and following a collision-free path.",
        "navigation",
        ("navigate to a point", "move to a goal position", "go to a pose"),
        ("skills", "behaviour trees", "operators"),
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/NavigateThroughPoses",
        "Drives the robot through a sequence of poses, avoiding obstacles.",
        "navigation",
        ("follow waypoints", "patrol"),
        ("skills", "behaviour trees"),
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/ComputePathToPose",
        "Plans a collision-free path from the current pose to a goal pose.",
        "navigation",
        ("plan a path",),
        ("behaviour trees",),
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/FollowPath",
        "Makes the controller follow a given path.",
        "navigation",
        ("follow a path",),
        ("behaviour trees",),
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/Spin",
        "Rotates the base in place by a given angle (Nav2 behaviour).",
        "navigation",
        ("rotate by an angle",),
        ("behaviour trees", "recoveries"),
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/BackUp",
        "Drives the base straight backwards by a distance (Nav2 behaviour).",
        "navigation",
        ("back up",),
        ("behaviour trees", "recoveries"),
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/DriveOnHeading",
        "Drives the base straight along its heading for a distance (Nav2 behaviour).",
        "navigation",
        ("drive forward a distance",),
        ("behaviour trees",),
    ),
    _Rule(
        "a",
        r"moveit_msgs/action/MoveGroup",
        "Plans and executes a motion of the arm to a goal (pose or joint values) with MoveIt.",
        "manipulation",
        ("move the arm to a point", "reach a pose"),
        ("skills", "operators"),
    ),
    _Rule(
        "a",
        r"moveit_msgs/action/ExecuteTrajectory",
        "Executes a planned arm trajectory.",
        "manipulation",
        ("execute a planned motion",),
        ("MoveIt clients",),
    ),
    _Rule(
        "a",
        r"control_msgs/action/FollowJointTrajectory",
        "Makes the arm controller follow a joint trajectory and reports progress.",
        "manipulation",
        ("move the arm along joint waypoints",),
        ("MoveIt", "skills"),
    ),
    _Rule(
        "a",
        r"control_msgs/action/GripperCommand",
        "Opens or closes the gripper to a position with a maximum effort.",
        "manipulation",
        ("grasp", "release"),
        ("skills",),
    ),
    _Rule(
        "s",
        r"moveit_msgs/srv/GetPositionIK",
        "Computes joint values that put the arm's end effector at a pose (inverse kinematics).",
        "manipulation",
        ("reach a point", "check reachability"),
        ("MoveIt clients",),
    ),
    _Rule(
        "s",
        r"moveit_msgs/srv/GetPositionFK",
        "Computes link poses from joint values (forward kinematics).",
        "manipulation",
        ("get the end effector position",),
        ("MoveIt clients",),
    ),
    _Rule(
        "s",
        r"moveit_msgs/srv/GetMotionPlan",
        "Plans an arm motion without executing it.",
        "manipulation",
        ("plan arm motion",),
        ("MoveIt clients",),
    ),
    _Rule(
        "s",
        r"(nav2_msgs/srv/SaveMap|slam_toolbox/srv/SaveMap)",
        "Saves the current map to files.",
        "mapping",
        ("save the map",),
        ("operators", "skills"),
    ),
    _Rule(
        "s",
        r"slam_toolbox/srv/SerializePoseGraph",
        "Saves SLAM's pose graph so mapping can continue later.",
        "mapping",
        ("store mapping session",),
        ("operators",),
    ),
    _Rule(
        "s",
        r"nav2_msgs/srv/LoadMap",
        "Loads a saved map into the map server.",
        "mapping",
        ("load a map",),
        ("operators",),
    ),
    _Rule(
        "s",
        r"nav2_msgs/srv/ClearEntireCostmap",
        "Clears the obstacles a costmap has accumulated.",
        "navigation",
        ("recover from stale obstacles",),
        ("recoveries",),
    ),
    _Rule(
        "s",
        r"controller_manager_msgs/srv/\w+",
        "Manages ros2_control controllers and hardware ({what}).",
        "controller management",
        ("switch or inspect controllers",),
        ("operators", "launch tooling"),
    ),
    _Rule(
        "s",
        r"gazebo_msgs/srv/\w+",
        "Simulator service ({what}).",
        "simulation",
        ("manipulate the simulation",),
        ("simulation tooling",),
    ),
    _Rule(
        "t",
        r"gazebo_msgs/msg/\w+",
        "Simulator topic ({what}).",
        "simulation",
        ("observe the simulation",),
        ("simulation tooling",),
    ),
    _Rule(
        "s",
        r"std_srvs/srv/(Empty|Trigger|SetBool)",
        "Triggers an operation: {what}.",
        "other",
        (),
        ("operators",),
    ),
    _Rule(
        "t",
        r"rcl_interfaces/msg/Log",
        "Log messages of all nodes.",
        "system",
        ("debugging",),
        ("every node",),
    ),
    _Rule(
        "t",
        r"rcl_interfaces/msg/ParameterEvent",
        "Notifications of parameter changes.",
        "system",
        ("introspection",),
        ("every node",),
    ),
    _Rule(
        "t",
        r"rosgraph_msgs/msg/Clock",
        "Simulated or played-back time.",
        "system",
        ("time keeping",),
        ("simulator", "bag player"),
    ),
    _Rule(
        "s",
        r"rcl_interfaces/srv/\w+",
        "Reads or changes a node's parameters ({what}).",
        "system",
        ("configuration", "introspection"),
        ("tooling",),
    ),
    _Rule(
        "st",
        r"lifecycle_msgs/(srv|msg)/\w+",
        "Lifecycle management of a node ({what}).",
        "system",
        ("bring nodes up and down",),
        ("lifecycle manager",),
    ),
    _Rule(
        "s",
        r"type_description_interfaces/srv/GetTypeDescription",
        "Returns the description of a message type a node uses.",
        "system",
        ("introspection",),
        ("tooling",),
    ),
)

_PACKAGE_MODULES = {
    "nav2_msgs": "navigation",
    "nav_msgs": "navigation",
    "moveit_msgs": "manipulation",
    "control_msgs": "manipulation",
    "trajectory_msgs": "manipulation",
    "sensor_msgs": "perception",
    "geometry_msgs": "base motion",
    "tf2_msgs": "localisation",
    "slam_toolbox": "mapping",
    "gazebo_msgs": "simulation",
    "controller_manager_msgs": "controller management",
    "diagnostic_msgs": "diagnostics",
    "rcl_interfaces": "system",
    "lifecycle_msgs": "system",
}


def _what(name: str) -> str:
    words = re.split(r"[/_]+", name.strip("/"))
    return " ".join(w for w in words if w) or name


def _matches(rule: _Rule, kind: str, name: str, type_name: str) -> bool:
    if kind[0] not in rule.kinds:
        return False
    if not re.fullmatch(rule.type_pattern, type_name):
        return False
    return rule.name_pattern is None or re.search(rule.name_pattern, name) is not None


def describe_by_rules(
    kind: str, name: str, type_name: str, field_paths: Sequence[str] = ()
) -> Description:
    """A description from the interface's kind, name, type and field paths alone."""
    key_fields = list(field_paths[:8])
    for rule in _RULES:
        if _matches(rule, kind, name, type_name):
            return Description(
                purpose=rule.purpose.format(name=name, what=_what(name)),
                module=rule.module,
                tasks=list(rule.tasks),
                used_by=list(rule.used_by),
                key_fields=key_fields,
                engine="rules",
            )
    package = type_name.split("/", 1)[0]
    short_type = type_name.rsplit("/", 1)[-1]
    verb = {"topic": "Topic", "service": "Service", "action": "Action"}.get(kind, kind)
    purpose = f"{verb} {name} ({short_type}): {_what(name)}."
    return Description(
        purpose=purpose,
        module=_PACKAGE_MODULES.get(package, "other"),
        tasks=[],
        used_by=[],
        key_fields=key_fields,
        engine="rules",
    )
