"""A kinematic world: a mobile base that follows its velocity command, Nav2's motion
actions, and an arm whose tool goes where MoveIt is asked to move it.

No physics, no collisions, no sensors beyond odometry, the map pose, transforms and scans:
the base's velocity approaches the commanded one within acceleration limits and stops when
commands stop coming (like a base driver's command timeout); its pose integrates that
velocity. It is enough to run motion skills to completion without MuJoCo, and it is the
reference implementation of the world plug-in API (:mod:`skillwright.runtime`).

What it takes over, where the robot has them:

* ``odom_topic`` (``nav_msgs/msg/Odometry``; by default every one the robot has) and
  ``tf_topic`` (``map -> odom -> base``; by default the robot's ``tf``) at ``rate_hz``. The
  ``map`` frame is there only if the robot is ``localised``: by default, if a localisation
  or SLAM shows in its graph (a pose topic of the type below, or an OccupancyGrid named
  ``map``), as the simulation decides it. REP 105 puts ``map`` above ``odom`` only where a
  localisation publishes ``map -> odom``; a robot without one has ``odom -> base`` only, and
  a skill that looks its pose up in ``map`` there must fail here as it fails on the robot.
  The velocity command on ``cmd_topic`` drives the base (by default the robot's Twist topic
  named like a command, as the simulation binds it: drivers publish it under their own
  namespace, e.g. ``/panther/cmd_vel``).
* the motion actions, served by :mod:`skillwright.runtime.motion` (the servers the MuJoCo
  world uses too): ``navigate_action`` (``nav2_msgs/action/NavigateToPose``; by default the
  robot's action of that type), the robot's ``NavigateThroughPoses``, ``Spin``, ``BackUp``
  and ``DriveOnHeading``, driving the base at up to ``nav_speed`` and ``nav_yaw_rate`` on a
  straight path (the world has no obstacles) to within ``nav_tolerance`` and
  ``nav_yaw_tolerance``. Goal poses are taken in the global frame (``map``, or ``odom``
  without a localisation) and in ``odom`` (``map -> odom`` is the identity here); a goal in
  any other frame is aborted, as Nav2 aborts a goal TF cannot transform.
  ``move_group_action`` (``moveit_msgs/action/MoveGroup``) moves the link of the goal's
  first position constraint to the constraint's point (in its header frame) at
  ``arm_speed`` times the request's ``max_velocity_scaling_factor`` (``arm_velocity_scaling``
  when the request leaves it at 0), then publishes that frame -> link on ``tf_topic``;
  targets beyond ``arm_reach`` fail with MoveIt's NO_IK_SOLUTION. The world knows neither
  the robot's planning groups nor its links (its SRDF), so it takes any.
* ``pose_topics`` (``geometry_msgs/msg/PoseWithCovarianceStamped``; by default every one
  the scenario's script does not publish): the base's pose in the map frame, as a
  localisation (AMCL, SLAM Toolbox) gives it, with each odometry message. A recorded one is
  taken over too: a localisation's pose follows the base, and a replayed one would stand
  still while the base moves.
* ``scan_topics`` (``sensor_msgs/msg/LaserScan``; by default every one that neither the
  recording nor the scenario publishes): a 360-degree scan from the base's pose of the
  walls of a ``room`` (width along x, depth along y) centred on the start, at
  ``scan_rate_hz``. Beams beyond ``scan_range``'s far end read ``inf``, nearer than its near
  end ``-inf`` (REP 117). A robot known only from a report has no recorded scans, and a
  LaserScan without ranges is one a skill rightly refuses.

Every option can be set from a scenario's ``world_options``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from skillwright.interfaces.roles import TWIST_TYPES, command_topic
from skillwright.runtime.motion import (
    ACTION_TYPES,
    ArmConfig,
    ArmServer,
    BaseMotionServer,
    Command,
    NavConfig,
    wrap_pi,
)

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


def _quaternion(yaw: float) -> dict[str, float]:
    return {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2.0), "w": math.cos(yaw / 2.0)}


def _approach(current: float, target: float, step: float) -> float:
    if abs(target - current) <= step:
        return target
    return current + math.copysign(step, target - current)


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
        nav_yaw_tolerance: float = 0.1,
        move_group_action: str | None = None,
        arm_base_frame: str = "arm_base_link",
        arm_home: tuple[float, float, float] | list[float] = (0.4, 0.0, 0.3),
        arm_speed: float = 0.2,
        arm_velocity_scaling: float = 1.0,
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
        if not 0.0 < arm_velocity_scaling <= 1.0:
            raise ValueError("world option arm_velocity_scaling must be in (0, 1]")
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
        self.move_group_action = move_group_action
        self.nav_config = NavConfig(
            speed_max=nav_speed,
            yaw_rate_max=nav_yaw_rate,
            accel=linear_acceleration,
            yaw_accel=angular_acceleration,
            xy_tolerance=nav_tolerance,
            yaw_tolerance=nav_yaw_tolerance,
        )
        home = tuple(float(v) for v in arm_home)
        self.arm_config = ArmConfig(
            group=None,
            tip_link=None,
            base_frame=arm_base_frame,
            reach=arm_reach,
            speed_max=arm_speed,
            home=(home[0], home[1], home[2]),
            default_velocity_scaling=arm_velocity_scaling,
        )
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
        self._command = Command()
        self._command_time: float | None = None
        self._next_publish = host.now
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
        self.base_server = BaseMotionServer(self, self.nav_config)
        self.arm: ArmServer | None = None
        chosen = {_NAVIGATE: self.navigate_action, _MOVE_GROUP: self.move_group_action}
        for type_name, kind in ACTION_TYPES.items():
            name = chosen.get(type_name) or _action_of(host, type_name)
            if name is None or host.type_of(name) != type_name:
                continue
            if kind == "move_group":
                self.arm = ArmServer(self, self.arm_config, lambda _frame: (0.0, 0.0, 0.0))
                host.serve_action(name, self.arm.handler(type_name))
            else:
                host.serve_action(name, self.base_server.handler(kind, type_name))

    def next_event(self) -> float | None:
        events = [self._next_scan] if self._scans else []
        if self._odoms or self._tf or self._poses:
            events.append(self._next_publish)
        events += [tick for tick in self._ticks() if tick is not None]
        return min(events, default=None)

    def advance(self, until: float) -> None:
        while True:
            due = min((t for t in self._ticks() if t is not None), default=None)
            if due is None or due > until + 1e-9:
                break
            self._integrate(due)
            for server in (self.base_server, self.arm):
                tick = None if server is None else server.next_tick
                if server is not None and tick is not None and tick <= due + 1e-9:
                    server.tick()
        self._integrate(until)
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

    # --- what the motion servers need (MotionWorld) ---------------------------------

    @property
    def now(self) -> float:
        """Virtual time: the host's."""
        return self._require_host().now

    def base_pose(self) -> tuple[float, float, float]:
        """The base's pose; the global frame and ``odom`` coincide here."""
        return self._x, self._y, self._theta

    def drive(self, command: Command) -> None:
        """A command of the world's own controllers, taken like one on ``cmd_topic``."""
        self._command = command
        self._command_time = self.now

    def plan(
        self, start: tuple[float, float], goal: tuple[float, float]
    ) -> list[tuple[float, float]] | None:
        """The straight line: nothing stands in the way in this world."""
        return [start, goal]

    def to_map(
        self, frame: str, x: float, y: float, yaw: float
    ) -> tuple[float, float, float] | None:
        """A pose in the global frame or in ``odom`` (the same place here), else ``None``."""
        known = {self._global_frame, self.odom_frame}
        return (x, y, yaw) if frame.lstrip("/") in known else None

    def message(self, type_name: str) -> dict[str, Any]:
        """A message of that type at its defaults (from the host)."""
        return self._require_host().message(type_name)

    def pose_stamped(self, x: float, y: float, yaw: float) -> dict[str, Any]:
        """A ``geometry_msgs/PoseStamped`` in the global frame, stamped now."""
        return {
            "header": {"stamp": self._require_host().stamp(), "frame_id": self._global_frame},
            "pose": {"position": {"x": x, "y": y, "z": 0.0}, "orientation": _quaternion(yaw)},
        }

    def record_goal(self, entry: dict[str, Any]) -> None:
        """Log a motion goal's progress in the run's trace."""
        self._require_host().record("goal", {k: v for k, v in entry.items() if k != "goal"})

    # --- motion ---------------------------------------------------------------------

    def _ticks(self) -> list[float | None]:
        return [s.next_tick for s in (self.base_server, self.arm) if s is not None]

    def _on_command(self, time: float, message: dict[str, Any]) -> None:
        twist = message.get("twist", message)
        linear, angular = twist["linear"], twist["angular"]
        self._command = Command(float(linear["x"]), float(linear["y"]), float(angular["z"]))
        self._command_time = time

    def _integrate(self, until: float) -> None:
        while self._time < until - 1e-12:
            step = min(_STEP, until - self._time)
            self._step(step)
            self._time += step
        self._time = max(self._time, until)

    def _step(self, dt: float) -> None:
        command = self._command
        if self._command_time is None or self._time - self._command_time > self.command_timeout:
            command = Command()
        linear = self.linear_acceleration * dt
        self._vx = _approach(self._vx, command.vx, linear)
        self._vy = _approach(self._vy, command.vy, linear)
        self._wz = _approach(self._wz, command.wz, self.angular_acceleration * dt)
        cos, sin = math.cos(self._theta), math.sin(self._theta)
        self._x += (self._vx * cos - self._vy * sin) * dt
        self._y += (self._vx * sin + self._vy * cos) * dt
        self._theta = wrap_pi(self._theta + self._wz * dt)

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
            host.publish(self._tf, {"transforms": self._transforms(stamp)})

    def _transforms(self, stamp: dict[str, int]) -> list[dict[str, Any]]:
        def transform(parent: str, child: str, x: float, y: float, z: float, yaw: float) -> Any:
            return {
                "header": {"stamp": stamp, "frame_id": parent},
                "child_frame_id": child,
                "transform": {
                    "translation": {"x": x, "y": y, "z": z},
                    "rotation": _quaternion(yaw),
                },
            }

        transforms = []
        if self._localised:
            transforms.append(transform(self.map_frame, self.odom_frame, 0.0, 0.0, 0.0, 0.0))
        transforms.append(
            transform(self.odom_frame, self.base_frame, self._x, self._y, 0.0, self._theta)
        )
        # The tool, once a goal named it, in the frame that goal used (every frame's
        # offset from the arm's base is zero in this world).
        if self.arm is not None and self.arm.link is not None:
            x, y, z = self.arm.tcp
            transforms.append(transform(self.arm.frame, self.arm.link, x, y, z, 0.0))
        return transforms

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
