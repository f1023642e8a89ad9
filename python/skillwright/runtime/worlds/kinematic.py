"""A kinematic world: a mobile base that follows its velocity command, Nav2-style
navigation, and an arm whose tool goes where MoveIt is asked to move it.

No physics, no collisions, no sensors beyond odometry, the map pose, transforms and scans:
the base's velocity approaches the commanded one within acceleration limits and stops when
commands stop coming (like a base driver's command timeout); its pose integrates that
velocity. It is
enough to run motion skills to completion without MuJoCo, and it is the reference
implementation of the world plug-in API (:mod:`skillwright.runtime`).

What it takes over, where the robot has them:

* ``odom_topic`` (``nav_msgs/msg/Odometry``; by default every one the robot has) and
  ``tf_topic`` (``map -> odom -> base``; by default the robot's ``tf``) at ``rate_hz``. The
  ``map`` frame is there only if the robot is ``localised``: by default, if a localisation
  or SLAM shows in its graph (a pose topic of the type below, or an OccupancyGrid named
  ``map``), as the simulation decides it. A robot without one has ``odom -> base`` only and
  takes navigation goals in ``odom``: when every robot had a map here, a skill that asked the
  paper's robot (no localisation) for its pose in ``map`` passed its run and then found no
  such frame in the simulation. The
  velocity command on ``cmd_topic`` drives the base (by default the robot's Twist topic named
  like a command, as the simulation binds it: ``/panther/cmd_vel`` on a Husarion Panther,
  where a fixed ``/cmd_vel`` left the base standing and every motion skill failed its run).
* ``navigate_action`` (``nav2_msgs/action/NavigateToPose``; by default the robot's action of
  that type, and likewise the next one): drives straight to the goal
  at ``nav_speed``, turning on the way, with feedback twice a second.
* ``move_group_action`` (``moveit_msgs/action/MoveGroup``): moves the link of the goal's
  first position constraint to the constraint's point (in its header frame) at
  ``arm_speed``, then publishes that frame -> link on ``tf_topic``; targets beyond
  ``arm_reach`` fail with MoveIt's NO_IK_SOLUTION.
* ``pose_topics`` (``geometry_msgs/msg/PoseWithCovarianceStamped``; by default every one
  the scenario's script does not publish): the base's pose in the map frame, as a
  localisation (AMCL, SLAM Toolbox) gives it, with each odometry message. A recorded one is
  taken over too: replayed, it stood still while the base turned, and a skill that rightly
  read its heading from the map pose never saw it change.
* ``scan_topics`` (``sensor_msgs/msg/LaserScan``; by default every one that neither the
  recording nor the scenario publishes): a 360-degree scan from the base's pose of the
  walls of a ``room`` (width along x, depth along y) centred on the start, at
  ``scan_rate_hz``. Beams beyond ``scan_range``'s far end read ``inf``, nearer than its near
  end ``-inf`` (REP 117). Without
  it a robot known only from a report had scans with no ranges at all, and a skill that
  rightly refuses an empty scan failed its run.

Every option can be set from a scenario's ``world_options``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from skillwright.interfaces.roles import TWIST_TYPES, command_topic
from skillwright.runtime.api import ActionGoal

if TYPE_CHECKING:
    from skillwright.runtime.graph import GraphHost

__all__ = ["KinematicWorld"]

_STEP = 0.01
_ODOMETRY = "nav_msgs/msg/Odometry"
_TF = "tf2_msgs/msg/TFMessage"
_NAVIGATE = "nav2_msgs/action/NavigateToPose"
_MOVE_GROUP = "moveit_msgs/action/MoveGroup"
_POSE = "geometry_msgs/msg/PoseWithCovarianceStamped"
_GRID = "nav_msgs/msg/OccupancyGrid"
_SCAN = "sensor_msgs/msg/LaserScan"
_MOVEIT_SUCCESS = 1  # moveit_msgs/msg/MoveItErrorCodes.SUCCESS
_MOVEIT_NO_IK_SOLUTION = -31  # moveit_msgs/msg/MoveItErrorCodes.NO_IK_SOLUTION


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


def _yaw(quaternion: dict[str, float]) -> float:
    x, y, z, w = (float(quaternion.get(k, 0.0)) for k in ("x", "y", "z", "w"))
    if x == y == z == w == 0.0:
        return 0.0
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def _quaternion(yaw: float) -> dict[str, float]:
    return {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2.0), "w": math.cos(yaw / 2.0)}


def _approach(current: float, target: float, step: float) -> float:
    if abs(target - current) <= step:
        return target
    return current + math.copysign(step, target - current)


@dataclass
class _Navigation:
    goal: ActionGoal
    x: float
    y: float
    yaw: float | None
    started: float
    last_feedback: float


@dataclass
class _ArmMotion:
    goal: ActionGoal
    frame: str
    link: str
    target: tuple[float, float, float]


class KinematicWorld:
    """See the module docstring; every keyword is an option."""

    def __init__(
        self,
        *,
        cmd_topic: str | None = None,
        odom_topic: str | None = None,
        tf_topic: str | None = None,
        map_frame: str = "map",
        localised: bool | None = None,
        odom_frame: str = "odom",
        base_frame: str = "base_link",
        start: tuple[float, float, float] | list[float] = (0.0, 0.0, 0.0),
        rate_hz: float = 50.0,
        linear_acceleration: float = 1.5,
        angular_acceleration: float = 3.0,
        command_timeout: float = 0.5,
        navigate_action: str | None = None,
        nav_speed: float = 0.5,
        nav_yaw_rate: float = 1.0,
        nav_tolerance: float = 0.05,
        move_group_action: str | None = None,
        arm_base_frame: str = "arm_base_link",
        arm_home: tuple[float, float, float] | list[float] = (0.4, 0.0, 0.3),
        arm_speed: float = 0.2,
        arm_reach: float | None = 0.85,
        pose_topics: list[str] | None = None,
        scan_topics: list[str] | None = None,
        room: tuple[float, float] | list[float] = (8.0, 6.0),
        scan_rate_hz: float = 10.0,
        scan_beams: int = 360,
        scan_range: tuple[float, float] | list[float] = (0.05, 12.0),
    ) -> None:
        if rate_hz <= 0 or scan_rate_hz <= 0:
            raise ValueError("world options rate_hz and scan_rate_hz must be positive")
        if scan_beams < 1 or len(room) != 2 or min(room) <= 0:
            raise ValueError("world options: scan_beams must be >= 1 and room two sizes > 0")
        self.cmd_topic = cmd_topic
        self.odom_topic = odom_topic
        self.tf_topic = tf_topic
        self.map_frame = map_frame
        self.localised = localised
        self.odom_frame = odom_frame
        self.base_frame = base_frame
        self.start = tuple(float(v) for v in start)
        self.period = 1.0 / rate_hz
        self.linear_acceleration = linear_acceleration
        self.angular_acceleration = angular_acceleration
        self.command_timeout = command_timeout
        self.navigate_action = navigate_action
        self.nav_speed = nav_speed
        self.nav_yaw_rate = nav_yaw_rate
        self.nav_tolerance = nav_tolerance
        self.move_group_action = move_group_action
        self.arm_base_frame = arm_base_frame
        self.arm_home = tuple(float(v) for v in arm_home)
        self.arm_speed = arm_speed
        self.arm_reach = arm_reach
        self.pose_topics = pose_topics
        self.scan_topics = scan_topics
        self.room = (float(room[0]), float(room[1]))
        self.scan_period = 1.0 / scan_rate_hz
        self.scan_beams = scan_beams
        self.scan_range = (float(scan_range[0]), float(scan_range[1]))
        self._host: GraphHost | None = None

    # --- the plug-in API ------------------------------------------------------------

    def attach(self, host: GraphHost) -> None:
        """Starts afresh: the base at ``start``, still; the arm at ``arm_home``."""
        self._host = host
        self._time = host.now
        self._x, self._y, self._theta = self.start
        self._vx = self._vy = self._wz = 0.0
        self._command = (0.0, 0.0, 0.0)
        self._command_time: float | None = None
        self._next_publish = host.now
        self._navigation: _Navigation | None = None
        self._arm: dict[tuple[str, str], tuple[float, float, float]] = {}
        self._arm_motion: _ArmMotion | None = None
        self._cmd = self.cmd_topic or command_topic(
            name for type_name in TWIST_TYPES for name in host.topics(type_name)
        )
        odometry = None if self.odom_topic is None else [self.odom_topic]
        self._odoms = _taken(host, _ODOMETRY, odometry, lambda _topic: True)
        tfs = [t for t in host.topics(_TF) if t.rsplit("/", 1)[-1] == "tf"]
        tf = self.tf_topic or min(tfs, key=len, default=None)
        self._tf = tf if tf is not None and host.type_of(tf) == _TF else None
        if self._tf is not None:
            host.own_topic(self._tf)
        self._poses = _taken(host, _POSE, self.pose_topics, lambda t: not host.scripted(t))
        self._localised = self.localised
        if self._localised is None:
            maps = [g for g in host.topics(_GRID) if g.rsplit("/", 1)[-1] == "map"]
            self._localised = bool(host.topics(_POSE) or maps)
        self._global_frame = self.map_frame if self._localised else self.odom_frame
        self._scans = _taken(host, _SCAN, self.scan_topics, lambda t: not host.provided(t))
        self._next_scan = host.now
        if self._cmd is not None and host.type_of(self._cmd) in TWIST_TYPES:
            host.on_publish(self._cmd, self._on_command)
        navigate = self.navigate_action or _action_of(host, _NAVIGATE)
        if navigate is not None and host.type_of(navigate) == _NAVIGATE:
            host.serve_action(navigate, _Handler(self._navigate, self._cancel_navigation))
        move_group = self.move_group_action or _action_of(host, _MOVE_GROUP)
        if move_group is not None and host.type_of(move_group) == _MOVE_GROUP:
            host.serve_action(move_group, _Handler(self._move_arm, self._cancel_arm))

    def next_event(self) -> float | None:
        events = [self._next_scan] if self._scans else []
        if self._odoms or self._tf or self._poses:
            events.append(self._next_publish)
        return min(events, default=None)

    def advance(self, until: float) -> None:
        while self._time < until - 1e-12:
            step = min(_STEP, until - self._time)
            self._step(step)
            self._time += step
        self._time = max(self._time, until)
        publishes = self._odoms or self._tf or self._poses
        if until >= self._next_publish - 1e-9 and publishes:
            self._publish()
            while self._next_publish <= until + 1e-9:
                self._next_publish += self.period
        if self._scans and until >= self._next_scan - 1e-9:
            self._publish_scans()
            while self._next_scan <= until + 1e-9:
                self._next_scan += self.scan_period

    def close(self) -> None:
        self._host = None

    # --- motion ---------------------------------------------------------------------

    def _on_command(self, time: float, message: dict[str, Any]) -> None:
        twist = message.get("twist", message)
        linear, angular = twist["linear"], twist["angular"]
        self._command = (float(linear["x"]), float(linear["y"]), float(angular["z"]))
        self._command_time = time

    def _target_velocity(self) -> tuple[float, float, float]:
        if self._navigation is not None:
            return self._navigation_velocity(self._navigation)
        if self._command_time is None or self._time - self._command_time > self.command_timeout:
            return (0.0, 0.0, 0.0)
        return self._command

    def _step(self, dt: float) -> None:
        vx, vy, wz = self._target_velocity()
        linear = self.linear_acceleration * dt
        self._vx = _approach(self._vx, vx, linear)
        self._vy = _approach(self._vy, vy, linear)
        self._wz = _approach(self._wz, wz, self.angular_acceleration * dt)
        cos, sin = math.cos(self._theta), math.sin(self._theta)
        self._x += (self._vx * cos - self._vy * sin) * dt
        self._y += (self._vx * sin + self._vy * cos) * dt
        self._theta = _wrap(self._theta + self._wz * dt)
        if self._navigation is not None:
            self._navigation_progress(self._navigation)
        if self._arm_motion is not None:
            self._arm_progress(self._arm_motion, dt)

    # --- navigation -----------------------------------------------------------------

    def _navigate(self, goal: ActionGoal) -> None:
        host = self._require_host()
        pose = goal.request.get("pose", {})
        frame = pose.get("header", {}).get("frame_id", "")
        if frame not in {self._global_frame, "/" + self._global_frame}:
            goal.reject()
            host.record(
                "navigation", {"rejected": f"goal frame {frame!r} is not {self._global_frame!r}"}
            )
            return
        position = pose["pose"]["position"]
        orientation = pose["pose"]["orientation"]
        has_yaw = any(float(orientation.get(k, 0.0)) for k in ("x", "y", "z", "w"))
        if self._navigation is not None and self._navigation.goal.active:
            self._navigation.goal.abort(host.message("nav2_msgs/action/NavigateToPose_Result"))
        goal.accept()
        self._navigation = _Navigation(
            goal=goal,
            x=float(position["x"]),
            y=float(position["y"]),
            yaw=_yaw(orientation) if has_yaw else None,
            started=host.now,
            last_feedback=host.now,
        )

    def _navigation_velocity(self, navigation: _Navigation) -> tuple[float, float, float]:
        dx, dy = navigation.x - self._x, navigation.y - self._y
        distance = math.hypot(dx, dy)
        if distance > self.nav_tolerance:
            heading = math.atan2(dy, dx)
            error = _wrap(heading - self._theta)
            speed = min(self.nav_speed, distance) * max(0.0, math.cos(error))
            return (speed, 0.0, max(-self.nav_yaw_rate, min(self.nav_yaw_rate, 2.0 * error)))
        if navigation.yaw is not None:
            error = _wrap(navigation.yaw - self._theta)
            return (0.0, 0.0, max(-self.nav_yaw_rate, min(self.nav_yaw_rate, 2.0 * error)))
        return (0.0, 0.0, 0.0)

    def _navigation_progress(self, navigation: _Navigation) -> None:
        host = self._require_host()
        distance = math.hypot(navigation.x - self._x, navigation.y - self._y)
        heading_done = navigation.yaw is None or abs(_wrap(navigation.yaw - self._theta)) < 0.05
        if (
            distance <= self.nav_tolerance
            and heading_done
            and abs(self._vx) < 0.02
            and abs(self._wz) < 0.05
        ):
            self._navigation = None
            navigation.goal.succeed(host.message("nav2_msgs/action/NavigateToPose_Result"))
            return
        if self._time - navigation.last_feedback >= 0.5:
            navigation.last_feedback = self._time
            feedback = host.message("nav2_msgs/action/NavigateToPose_Feedback")
            feedback["current_pose"]["header"] = {
                "stamp": host.stamp(self._time),
                "frame_id": self._global_frame,
            }
            feedback["current_pose"]["pose"] = self._pose()
            feedback["distance_remaining"] = distance
            elapsed = self._time - navigation.started
            feedback["navigation_time"] = {"sec": int(elapsed), "nanosec": int((elapsed % 1) * 1e9)}
            remaining = distance / self.nav_speed if self.nav_speed > 0 else 0.0
            feedback["estimated_time_remaining"] = {
                "sec": int(remaining),
                "nanosec": int((remaining % 1) * 1e9),
            }
            navigation.goal.feedback(feedback)

    def _cancel_navigation(self, goal: ActionGoal) -> bool:
        if self._navigation is not None and self._navigation.goal is goal:
            self._navigation = None
        self._require_host().call_later(0.0, lambda: goal.canceled() if goal.active else None)
        return True

    # --- arm ------------------------------------------------------------------------

    def _move_arm(self, goal: ActionGoal) -> None:
        host = self._require_host()
        result = host.message("moveit_msgs/action/MoveGroup_Result")
        constraints = goal.request.get("request", {}).get("goal_constraints", [])
        positions = constraints[0].get("position_constraints", []) if constraints else []
        region = positions[0].get("constraint_region", {}) if positions else {}
        poses = region.get("primitive_poses", [])
        if not poses:
            goal.accept()
            result["error_code"]["val"] = -2  # MoveItErrorCodes.INVALID_MOTION_PLAN
            goal.abort(result)
            host.record(
                "arm", {"aborted": "the goal has no position constraint with a primitive pose"}
            )
            return
        point = poses[0]["position"]
        target = (float(point["x"]), float(point["y"]), float(point["z"]))
        frame = positions[0]["header"]["frame_id"] or self.arm_base_frame
        link = positions[0]["link_name"]
        goal.accept()
        if self.arm_reach is not None and math.dist(target, (0.0, 0.0, 0.0)) > self.arm_reach:
            result["error_code"]["val"] = _MOVEIT_NO_IK_SOLUTION
            goal.abort(result)
            return
        self._arm.setdefault((frame, link), self.arm_home)  # type: ignore[arg-type]
        self._arm_motion = _ArmMotion(goal=goal, frame=frame, link=link, target=target)
        feedback = host.message("moveit_msgs/action/MoveGroup_Feedback")
        feedback["state"] = "MONITOR"
        goal.feedback(feedback)

    def _arm_progress(self, motion: _ArmMotion, dt: float) -> None:
        key = (motion.frame, motion.link)
        current = self._arm[key]
        distance = math.dist(current, motion.target)
        travel = self.arm_speed * dt
        if distance <= travel:
            self._arm[key] = motion.target
            self._arm_motion = None
            result = self._require_host().message("moveit_msgs/action/MoveGroup_Result")
            result["error_code"]["val"] = _MOVEIT_SUCCESS
            motion.goal.succeed(result)
            return
        self._arm[key] = tuple(
            c + (t - c) * travel / distance for c, t in zip(current, motion.target, strict=True)
        )  # type: ignore[assignment]

    def _cancel_arm(self, goal: ActionGoal) -> bool:
        if self._arm_motion is not None and self._arm_motion.goal is goal:
            self._arm_motion = None
        self._require_host().call_later(0.0, lambda: goal.canceled() if goal.active else None)
        return True

    # --- publishing -----------------------------------------------------------------

    def _require_host(self) -> GraphHost:
        if self._host is None:
            raise RuntimeError("the kinematic world is not attached")
        return self._host

    def _pose(self) -> dict[str, Any]:
        return {
            "position": {"x": self._x, "y": self._y, "z": 0.0},
            "orientation": _quaternion(self._theta),
        }

    def _publish(self) -> None:
        host = self._require_host()
        stamp = host.stamp()
        for topic in self._odoms:
            odom = host.message(_ODOMETRY)
            odom["header"] = {"stamp": stamp, "frame_id": self.odom_frame}
            odom["child_frame_id"] = self.base_frame
            odom["pose"]["pose"] = self._pose()
            odom["twist"]["twist"] = {
                "linear": {"x": self._vx, "y": self._vy, "z": 0.0},
                "angular": {"x": 0.0, "y": 0.0, "z": self._wz},
            }
            host.publish(topic, odom)
        for topic in self._poses:
            if not host.wants(topic):
                continue
            pose = host.message(_POSE)
            pose["header"] = {"stamp": stamp, "frame_id": self.map_frame}
            pose["pose"]["pose"] = self._pose()
            host.publish(topic, pose)
        if self._tf is not None:
            identity = {"translation": {"x": 0.0, "y": 0.0, "z": 0.0}, "rotation": _quaternion(0.0)}
            transforms = []
            if self._localised:
                transforms.append(
                    {
                        "header": {"stamp": stamp, "frame_id": self.map_frame},
                        "child_frame_id": self.odom_frame,
                        "transform": identity,
                    }
                )
            transforms += [
                {
                    "header": {"stamp": stamp, "frame_id": self.odom_frame},
                    "child_frame_id": self.base_frame,
                    "transform": {
                        "translation": {"x": self._x, "y": self._y, "z": 0.0},
                        "rotation": _quaternion(self._theta),
                    },
                },
            ]
            for (frame, link), (x, y, z) in sorted(self._arm.items()):
                transforms.append(
                    {
                        "header": {"stamp": stamp, "frame_id": frame},
                        "child_frame_id": link,
                        "transform": {
                            "translation": {"x": x, "y": y, "z": z},
                            "rotation": _quaternion(0.0),
                        },
                    }
                )
            host.publish(self._tf, {"transforms": transforms})

    # --- laser scans ---------------------------------------------------------------

    def _publish_scans(self) -> None:
        host = self._require_host()
        wanted = [topic for topic in self._scans if host.wants(topic)]
        if not wanted:
            return
        near, far = self.scan_range
        increment = 2.0 * math.pi / self.scan_beams
        ranges = [
            _inside_or_inf(self._wall_distance(self._theta - math.pi + i * increment), near, far)
            for i in range(self.scan_beams)
        ]
        for topic in wanted:
            scan = host.message(_SCAN)
            scan["header"] = {"stamp": host.stamp(), "frame_id": self.base_frame}
            scan["angle_min"] = -math.pi
            scan["angle_max"] = math.pi - increment
            scan["angle_increment"] = increment
            scan["scan_time"] = self.scan_period
            scan["time_increment"] = self.scan_period / self.scan_beams
            scan["range_min"], scan["range_max"] = near, far
            scan["ranges"] = ranges
            host.publish(topic, scan)

    def _wall_distance(self, heading: float) -> float:
        """Distance from the base along ``heading`` (world frame) to the nearest wall of the
        room ahead, ``inf`` when none is (the base has left the room)."""
        half_x, half_y = self.room[0] / 2.0, self.room[1] / 2.0
        cx, cy = self.start[0], self.start[1]
        dx, dy = math.cos(heading), math.sin(heading)
        nearest = math.inf
        for wall_x in (cx - half_x, cx + half_x):
            if abs(dx) > 1e-12:
                t = (wall_x - self._x) / dx
                if t > 0 and abs(self._y + t * dy - cy) <= half_y:
                    nearest = min(nearest, t)
        for wall_y in (cy - half_y, cy + half_y):
            if abs(dy) > 1e-12:
                t = (wall_y - self._y) / dy
                if t > 0 and abs(self._x + t * dx - cx) <= half_x:
                    nearest = min(nearest, t)
        return nearest


def _inside_or_inf(distance: float, near: float, far: float) -> float:
    """A beam's reading (REP 117): the distance, ``inf`` beyond the scanner's range and
    ``-inf`` nearer than it can measure."""
    if distance < near:
        return -math.inf
    return distance if distance <= far else math.inf


class _Handler:
    """Adapts two functions to the ActionHandler protocol."""

    def __init__(self, on_goal: Any, on_cancel: Any) -> None:
        self.on_goal = on_goal
        self.on_cancel = on_cancel


def _action_of(host: GraphHost, type_name: str) -> str | None:
    """The robot's action of ``type_name`` (the shortest name when there are several)."""
    found = [
        i.name for i in host.inventory.interfaces if i.kind == "action" and i.type_name == type_name
    ]
    return min(found, key=lambda n: (len(n), n), default=None)


def _taken(
    host: GraphHost, type_name: str, chosen: list[str] | None, keep: Callable[[str], bool]
) -> list[str]:
    """The robot's topics of ``type_name`` the world publishes from now on: the ``chosen``
    ones (a world option) the robot has, else every one ``keep`` accepts."""
    present = host.topics(type_name)
    if chosen is not None:
        topics = [t for t in chosen if t in present]
    else:
        topics = [t for t in present if keep(t)]
    for topic in topics:
        host.own_topic(topic)
    return topics
