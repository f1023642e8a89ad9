"""What standard interface types do, as retrieval needs to know it: direct or auxiliary.

Word overlap alone lets a composite action beat the plain interface a skill actually uses:
a move-forward capability shares "drive", "distance" and "speed" with Nav2's ``BackUp``
behaviour and ``SpeedLimit`` topic, and "position" with MoveIt's forward kinematics service,
while the velocity command (a ``Twist``) and the measured pose and velocity (an
``Odometry``) carry exactly what the capability commands and measures. So every candidate
gets a *directness* from its type, by what the type's definition and package say it is:

- **direct**: the type carries a quantity a skill commands or measures itself, or is the
  one entry point of a whole task: ``Twist`` (velocity), ``Odometry`` (pose and velocity),
  ``LaserScan``/``Range``/``PointCloud2`` (ranges), ``Imu``, ``JointState``, ``TFMessage``
  (frames), a pose estimate, ``OccupancyGrid`` (a map), ``NavigateToPose`` (move the base
  to a pose), MoveIt's ``MoveGroup`` (move the arm to a goal), ``FollowJointTrajectory``,
  a gripper command;
- **auxiliary**: the type is a building block or a side channel of such a task, used by
  the stacks themselves rather than by a skill: Nav2's behaviours (back up, spin, drive on
  heading, assisted teleop, wait) and its planner, smoother and controller steps, speed
  limits, costmaps and their updates, paths, behaviour-tree logs; MoveIt's kinematics,
  planning and planning-scene services and messages; controller state, controller manager
  and lifecycle plumbing; visualisation markers, footprints, clicked points, camera
  calibration, diagnostics, bare strings and triggers;
- **neutral**: everything else (vendor types this table does not know), and the map service
  (``GetMap``): it hands out a copy of the map that the map topic publishes, so where both
  exist the topic is the direct one, and where only the service exists it still competes.

Retrieval multiplies each candidate's evidence by the factor of its directness
(:class:`~skillwright.retrieval.retrieve.Ranking`), so a direct interface wins a tie of
words and an auxiliary one still wins when the capability or the spec clearly asks for it.
Rules are by type, never by one robot's interface names. The names they read are conventions
of the stacks every such robot runs: everything under a Nav2 costmap's namespace
(``/global_costmap/costmap``, an ``OccupancyGrid`` of costs and not a map, and the layers'
``voxel_marked_cloud``) is the costmap's own; Nav2's ``cmd_vel_nav`` and ``cmd_vel_teleop``
are its controller's and assisted teleop's velocities on their way to the velocity smoother,
not the base's command; a base controller's ``cmd_vel_out`` (ros2_controllers' drive
controllers with ``publish_limited_velocity``) is the command it applied after its limits, a
copy it publishes, where its input ``cmd_vel`` or ``cmd_vel_unstamped`` sits beside it; and
``goal_pose`` is the pose RViz's goal tool hands the navigator
(the ``NavigateToPose`` action does the same with feedback, a result and a cancel); and a
name with a ``visualization`` or ``debug`` part (SLAM Toolbox's
``/slam_toolbox/scan_visualization``) is a copy republished for display, not the sensor; so
is the DWB controller's ``cost_cloud``, its trajectory scores as points, and Cartographer's
``scan_matched_points2``, the points of one scan as its matcher placed them on the submap
(the lidar's own cloud is the sensor).

A sensor stream whose name says it merges others of its kind (``/scan_concatenated``,
``/scan_merged``) sees what each of them sees: :func:`merges` finds it, and retrieval gives it
at least the evidence of the streams of its type beside it.
"""

from __future__ import annotations

import re
from typing import Literal

from skillwright.interfaces.inventory import Interface

__all__ = [
    "Body",
    "Directness",
    "body_of",
    "body_of_text",
    "directness",
    "merges",
    "split_view",
    "unreached",
]

Body = Literal["arm", "base"]

Directness = Literal["direct", "neutral", "auxiliary"]

_DIRECT = re.compile(
    "|".join(
        (
            r"geometry_msgs/msg/Twist(Stamped)?",
            r"geometry_msgs/msg/PoseWithCovarianceStamped",
            r"nav_msgs/msg/(Odometry|OccupancyGrid)",
            r"sensor_msgs/msg/(LaserScan|Range|PointCloud2?|Imu|JointState)",
            r"tf2_msgs/msg/TFMessage",
            r"nav2_msgs/action/NavigateToPose",
            r"moveit_msgs/action/MoveGroup",
            r"control_msgs/action/(FollowJointTrajectory|(Parallel)?GripperCommand)",
            r"trajectory_msgs/msg/JointTrajectory",
        )
    )
)

_AUXILIARY = re.compile(
    "|".join(
        (
            # Nav2: behaviours composed of base motion, the navigator's inner steps,
            # limits, costmaps, plans and its own plumbing
            r"nav2_msgs/action/(BackUp|Spin|DriveOnHeading|AssistedTeleop|Wait"
            r"|ComputePath\w*|SmoothPath|FollowPath|FollowWaypoints|FollowGPSWaypoints)",
            r"nav2_msgs/msg/\w+",
            r"nav2_msgs/srv/\w*(Costmap|Path|Lifecycle)\w*",
            r"map_msgs/msg/\w+",
            r"nav_msgs/msg/(Path|MapMetaData|GridCells)",
            r"dwb_msgs/\w+/\w+",
            # MoveIt: kinematics, planning and the planning scene serve move_group
            r"moveit_msgs/(srv|msg)/\w+",
            r"moveit_msgs/action/(ExecuteTrajectory|LocalPlanner|GlobalPlanner)",
            # ros2_control: controller state and management
            r"control_msgs/msg/\w*(ControllerState|DynamicJointState)\w*",
            r"control_msgs/srv/QueryTrajectoryState",
            r"controller_manager_msgs/\w+/\w+",
            r"lifecycle_msgs/\w+/\w+",
            r"bond/msg/\w+",
            # display and bookkeeping
            r"visualization_msgs/msg/\w+",
            r"geometry_msgs/msg/(Polygon|PolygonStamped|PointStamped)",
            r"sensor_msgs/msg/CameraInfo",
            r"diagnostic_msgs/\w+/\w+",
            r"std_msgs/msg/String",
            r"std_srvs/srv/(Empty|Trigger)",
        )
    )
)


_COSTMAP = re.compile(r"(^|/)[^/]*costmap[^/]*(/|$)")
_DWB_COSTS = re.compile(r"(^|/)cost_cloud$")
_SCAN_MATCHED = re.compile(r"(^|/)scan_matched_points2$")
_NAV2_VELOCITY = re.compile(r"(^|/)cmd_vel_(nav|teleop)$")
_CONTROLLER_ECHO = re.compile(r"(^|/)[^/]*controller/cmd_vel_out$")
_TWIST = "geometry_msgs/msg/Twist"  # and TwistStamped
_NAV2_GOAL = re.compile(r"(^|/)goal_pose$")
_POSE = "geometry_msgs/msg/PoseStamped"
_DISPLAY = re.compile(r"(^|/|_)(visuali[sz]ation|debug)(/|_|$)")


def directness(interface: Interface) -> Directness:
    """How directly the interface's type carries what a skill commands or measures."""
    if any(p.search(interface.name) for p in (_COSTMAP, _DWB_COSTS, _SCAN_MATCHED, _DISPLAY)):
        return "auxiliary"
    if _NAV2_VELOCITY.search(interface.name) and interface.type_name.startswith(_TWIST):
        return "auxiliary"
    if _CONTROLLER_ECHO.search(interface.name) and interface.type_name.startswith(_TWIST):
        return "auxiliary"
    if _NAV2_GOAL.search(interface.name) and interface.type_name == _POSE:
        return "auxiliary"
    if _DIRECT.fullmatch(interface.type_name):
        return "direct"
    if _AUXILIARY.fullmatch(interface.type_name):
        return "auxiliary"
    return "neutral"


_SENSOR_STREAM = re.compile(r"sensor_msgs/msg/(LaserScan|PointCloud2?|Range)")
_MERGING = re.compile(r"(^|/|_)(merged?|concat(enated)?|combined|fused|fusion)(/|_|$)")


def merges(interface: Interface) -> bool:
    """Whether a sensor stream's name says it merges several of its kind (a scan merger's
    ``/scan_merged``, the KMR iiwa's ``/scan_concatenated`` of two 270-degree scanners): the
    one that sees all around, where each part sees a side."""
    return bool(
        _SENSOR_STREAM.fullmatch(interface.type_name) and _MERGING.search(interface.name.lower())
    )


_SIDE_WORDS = frozenset(
    ("front", "rear", "back", "left", "right", "f", "b", "l", "r", "fl", "fr", "rl", "rr")
)


def _view(name: str) -> tuple[tuple[str, ...], bool]:
    """The name with its numbers and the words that say where on the robot a sensor sits
    taken out (``/scan2`` and ``/scan``, ``/robot/front_laser/scan`` and
    ``/robot/rear_laser/scan`` share one), and whether it had such a word."""
    parts, sided = [], False
    for part in name.lower().split("/"):
        words = [w.rstrip("0123456789") for w in re.split(r"[^0-9a-z]+", part) if w]
        sided = sided or any(w in _SIDE_WORDS for w in words)
        parts.append("_".join(w for w in words if w and w not in _SIDE_WORDS))
    return tuple(parts), sided


def split_view(a: Interface, b: Interface) -> bool:
    """Whether two sensor streams are parts of one split view: two scanners on opposite
    corners (the MMO-700's ``/scan`` and ``/scan2``, a mecanum base's ``front_laser`` and
    ``rear_laser``), each seeing a side the other does not. Their names differ only by a
    number, or both name a side: a plain ``/scan`` beside ``/f_scan`` and ``/b_scan`` (a
    MuR620) is the whole view, not a part. A processing word (``/scan_raw`` and
    ``/scan_filtered``, a ``_deskewed`` cloud) makes another version of the same view, and
    a stream that merges them (:func:`merges`) is none of the parts."""
    if not (
        a.name != b.name
        and a.kind == b.kind == "topic"
        and a.type_name == b.type_name
        and _SENSOR_STREAM.fullmatch(a.type_name) is not None
        and not merges(a)
        and not merges(b)
    ):
        return False
    (key_a, sided_a), (key_b, sided_b) = _view(a.name), _view(b.name)
    return key_a == key_b and sided_a == sided_b


_CONVENTIONAL_NAMES = {
    "nav_msgs/msg/OccupancyGrid": "map",
    "sensor_msgs/msg/LaserScan": "scan",
    "nav_msgs/msg/Odometry": "odom",
    "geometry_msgs/msg/Twist": "cmd_vel",
    "geometry_msgs/msg/TwistStamped": "cmd_vel",
}
"""The name the ROS conventions (REP 105, Nav2, the SLAM packages, the base controllers) give
the stream of each of these types that the standard stack reads or writes."""


def conventional(interface: Interface) -> bool:
    """Whether a topic carries the conventional name of its type (``map`` for an occupancy
    grid, ``scan``, ``odom``, ``cmd_vel``): the stream the standard stack produces or
    consumes, where its siblings' extra words (the HSR's ``/dynamic_obstacle_map`` and
    ``/static_distance_ros_map`` beside SLAM's ``/map``) name variants of it."""
    wanted = _CONVENTIONAL_NAMES.get(interface.type_name)
    return (
        interface.kind == "topic"
        and wanted is not None
        and interface.name.rsplit("/", 1)[-1] == wanted
    )


def unreached(interface: Interface, role: str | None) -> bool:
    """Whether the graph shows nobody at the other end of what a skill would do with the
    interface: a command topic (``role`` ``command``) nobody subscribes to, a measured topic
    nobody publishes and nothing was recorded on, an action no server serves. Only a live
    graph counts endpoints; without counts nothing is unreached.

    On a Stretch, Nav2's behaviour server publishes a ``/cmd_vel`` that nothing reads (the
    driver listens on ``/stretch/cmd_vel``); by its name it looks like the base's command.
    """
    counts = interface.endpoints
    if counts is None:
        return False
    if interface.kind == "action":
        return counts.servers == 0
    if interface.kind != "topic":
        return False
    if role == "command":
        return counts.subscribers == 0
    recorded = interface.traffic is not None and interface.traffic.message_count > 0
    return counts.publishers == 0 and not recorded


# Types that move or sense one part of a mobile manipulator only: the base (velocity,
# odometry, navigation, maps, costmaps) or the arm (MoveIt, joint trajectories, grippers).
_BASE_TYPES = re.compile(
    r"geometry_msgs/msg/(Twist(Stamped)?|PoseWithCovarianceStamped)"
    r"|nav_msgs/\w+/\w+|nav2_msgs/\w+/\w+|map_msgs/\w+/\w+"
)
_ARM_TYPES = re.compile(
    r"moveit_msgs/\w+/\w+|trajectory_msgs/msg/\w+|control_msgs/action/\w+"
    r"|control_msgs/msg/JointTrajectoryControllerState|control_msgs/srv/QueryTrajectoryState"
)
_ARM_WORDS = re.compile(r"\b(manipulator|arm|gripper|end[- ]effector|joints?)\b", re.IGNORECASE)
_BASE_WORDS = re.compile(r"\b(mobile|base|navigat\w*|drive|wheels?)\b", re.IGNORECASE)


def body_of(interface: Interface) -> Body | None:
    """The part of the robot the interface's type moves or senses, if only one."""
    if _BASE_TYPES.fullmatch(interface.type_name):
        return "base"
    if _ARM_TYPES.fullmatch(interface.type_name):
        return "arm"
    return None


def body_of_text(text: str) -> Body | None:
    """The part of the robot a capability's text is about: the arm when it names one (a
    manipulator of a mobile robot is still the arm), else the base when it names one."""
    if _ARM_WORDS.search(text):
        return "arm"
    if _BASE_WORDS.search(text):
        return "base"
    return None
