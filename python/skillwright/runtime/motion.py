"""Nav2's and MoveIt's motion action servers, as the simulated worlds serve them.

One implementation of the servers' protocol behaviour for every world: which goals are
accepted and which are refused and why, feedback while the robot moves, cancelling, the
result and its error code, and what each goal did (for the trace and the ground truth). How
the base or the arm actually moves is the world's part, behind :class:`MotionWorld`: the
kinematic world (:mod:`skillwright.runtime.worlds.kinematic`) integrates the command, the
MuJoCo world (:mod:`skillwright.sim.world`) actuates its wheels. Nothing here imports MuJoCo.

* :class:`BaseMotionServer` serves ``nav2_msgs/action/NavigateToPose``,
  ``NavigateThroughPoses`` and the behaviour server's ``Spin``, ``BackUp`` and
  ``DriveOnHeading`` (:data:`ACTION_TYPES`), one goal at a time, as Nav2's single controller
  does: a new goal on any of them pre-empts the running one, which is aborted. Goals are
  accepted and then aborted, never rejected, when they cannot be done: Nav2's action servers
  (``nav2_util::SimpleActionServer``) accept every goal while active, and the navigators and
  behaviours abort what they cannot do, e.g. a goal pose that TF cannot transform into the
  global frame or a path the planner cannot find. Navigation follows the world's plan (a
  holonomic pursuit of the next waypoint, facing the direction of travel, slowing to stop at
  the goal, then turning to the goal's heading) and aborts a run that makes no progress, as
  Nav2's progress checker does (0.5 m within 10 s). ``time_allowance`` is honoured as the
  behaviours honour it. Results carry ``total_elapsed_time`` and Jazzy's ``error_code``
  where the robot's message definition has them (:func:`fill`).
* :class:`ArmServer` serves ``moveit_msgs/action/MoveGroup`` for a tool centre point moved
  on a straight line: a request for a planning group, link or frame the world does not know,
  without a position constraint, or beyond the arm's reach is aborted with the
  ``moveit_msgs/msg/MoveItErrorCodes`` value MoveIt gives it; ``plan_only`` succeeds at once;
  ``max_velocity_scaling_factor`` scales the arm's speed, 0 meaning MoveIt's
  ``default_velocity_scaling_factor``; a new goal pre-empts the running one (PREEMPTED).

Both run at the controllers' period in virtual time: the world calls :meth:`tick` when
``next_tick`` is due.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Final, Protocol

if TYPE_CHECKING:
    from skillwright.runtime.api import ActionGoal

__all__ = [
    "ACTION_TYPES",
    "ArmConfig",
    "ArmServer",
    "BaseMotionServer",
    "Command",
    "MotionWorld",
    "NavConfig",
    "duration",
    "fill",
    "from_duration",
    "wrap_pi",
    "yaw_of",
]

ACTION_TYPES: Final[dict[str, str]] = {
    "nav2_msgs/action/NavigateToPose": "navigate_to_pose",
    "nav2_msgs/action/NavigateThroughPoses": "navigate_through_poses",
    "nav2_msgs/action/Spin": "spin",
    "nav2_msgs/action/BackUp": "backup",
    "nav2_msgs/action/DriveOnHeading": "drive_on_heading",
    "moveit_msgs/action/MoveGroup": "move_group",
}
"""The action types the servers serve, and the kind each is served as."""

Message = dict[str, Any]

# moveit_msgs/msg/MoveItErrorCodes
MOVEIT_SUCCESS = 1
MOVEIT_PLANNING_FAILED = -1
MOVEIT_PREEMPTED = -7
MOVEIT_INVALID_GROUP_NAME = -15
MOVEIT_INVALID_GOAL_CONSTRAINTS = -16
MOVEIT_INVALID_LINK_NAME = -19
MOVEIT_FRAME_TRANSFORM_FAILURE = -21
MOVEIT_NO_IK_SOLUTION = -31

CONTROL_PERIOD = 0.05
"""The controllers run at 20 Hz, as Nav2's controller server does by default."""
FEEDBACK_PERIOD = 0.1


@dataclass(frozen=True)
class Command:
    """A body-frame velocity: forward, to the left, counter-clockwise yaw rate."""

    vx: float = 0.0
    vy: float = 0.0
    wz: float = 0.0

    def is_zero(self, linear: float = 1e-6, angular: float = 1e-6) -> bool:
        """Whether every component is (practically) zero."""
        return abs(self.vx) <= linear and abs(self.vy) <= linear and abs(self.wz) <= angular


def wrap_pi(angle: float) -> float:
    """``angle`` in [-pi, pi)."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


def fill(template: Mapping[str, Any], values: Mapping[str, Any]) -> Message:
    """``template`` (a message at its defaults) with the fields of ``values`` it has.

    Message definitions differ between ROS distributions (Jazzy's Nav2 results carry an
    error code, Humble's do not); fields a type lacks are left out rather than guessed.
    """
    out = dict(template)
    for key, value in values.items():
        if key in out:
            if isinstance(value, Mapping) and isinstance(out[key], Mapping):
                out[key] = fill(out[key], value)
            else:
                out[key] = value
    return out


def duration(seconds: float) -> Message:
    """A ``builtin_interfaces/Duration``."""
    whole = math.floor(seconds)
    return {"sec": int(whole), "nanosec": round((seconds - whole) * 1e9) % 1_000_000_000}


def from_duration(value: Any) -> float:
    """Seconds of a ``builtin_interfaces/Duration`` dict (0 when malformed)."""
    if not isinstance(value, Mapping):
        return 0.0
    return float(value.get("sec", 0) or 0) + float(value.get("nanosec", 0) or 0) * 1e-9


def yaw_of(orientation: Any) -> float:
    """Yaw of a quaternion dict (0 for a malformed or all-zero quaternion)."""
    if not isinstance(orientation, Mapping):
        return 0.0
    x, y, z, w = (float(orientation.get(k, 0.0) or 0.0) for k in ("x", "y", "z", "w"))
    if x == y == z == w == 0.0:
        return 0.0
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def _point(value: Any) -> tuple[float, float, float]:
    if not isinstance(value, Mapping):
        return (0.0, 0.0, 0.0)
    return tuple(float(value.get(k, 0.0) or 0.0) for k in ("x", "y", "z"))  # type: ignore[return-value]


class MotionWorld(Protocol):
    """What the servers need from the world: the part that differs between worlds."""

    @property
    def now(self) -> float:
        """Virtual time (seconds)."""

    def base_pose(self) -> tuple[float, float, float]:
        """The base's pose (x, y, yaw) in the global frame, where Nav2 plans."""

    def drive(self, command: Command) -> None:
        """Command the base, as Nav2's controller publishes its velocity command."""

    def plan(
        self, start: tuple[float, float], goal: tuple[float, float]
    ) -> list[tuple[float, float]] | None:
        """A collision-free path from ``start`` to ``goal`` (both ends included), or
        ``None`` when the planner finds none."""

    def to_map(
        self, frame: str, x: float, y: float, yaw: float
    ) -> tuple[float, float, float] | None:
        """A goal pose given in ``frame``, in the global frame; ``None`` when TF has no
        transform from ``frame`` to it."""

    def message(self, type_name: str) -> Message:
        """A message of ``type_name`` at its defaults (the robot's definition)."""

    def pose_stamped(self, x: float, y: float, yaw: float) -> Message:
        """A ``geometry_msgs/PoseStamped`` of a pose in the global frame, stamped now."""

    def record_goal(self, entry: dict[str, Any]) -> None:
        """Log what a goal did: accepted, executing, how and why it ended."""


@dataclass(frozen=True)
class NavConfig:
    """Limits of the navigation controller (the robot's Nav2 configuration)."""

    speed_max: float
    yaw_rate_max: float
    accel: float
    yaw_accel: float
    xy_tolerance: float
    yaw_tolerance: float


@dataclass
class _BaseTask:
    goal: ActionGoal
    kind: str
    result_type: str
    feedback_type: str
    started: float
    waypoints: list[tuple[float, float]] = field(default_factory=list)
    final_yaw: float | None = None
    target: float = 0.0
    speed: float = 0.0
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    travelled: float = 0.0
    last_yaw: float = 0.0
    time_allowance: float = 0.0
    progress_anchor: tuple[float, float, float] = (0.0, 0.0, 0.0)
    next_feedback: float = 0.0
    poses_remaining: int = 0
    legs: list[tuple[float, float, float]] = field(default_factory=list)


class BaseMotionServer:
    """One Nav2-like server for every base motion action of the robot; one goal at a time
    (a new goal pre-empts the running one, which is aborted)."""

    def __init__(self, world: MotionWorld, config: NavConfig) -> None:
        self.world = world
        self.config = config
        self.task: _BaseTask | None = None
        self.next_tick: float | None = None
        self._entry: dict[str, Any] = {}

    def handler(self, kind: str, type_name: str) -> _ActionAdapter:
        """The action handler of an action of ``type_name``, served as ``kind``."""
        return _ActionAdapter(lambda goal: self.on_goal(goal, kind, type_name), self.on_cancel)

    # --- goals -----------------------------------------------------------------------
    def on_goal(self, goal: ActionGoal, kind: str, type_name: str) -> None:
        """Check the goal, accept or refuse it, and start executing it."""
        world = self.world
        now = world.now
        request = goal.request
        x, y, yaw = world.base_pose()
        task = _BaseTask(
            goal=goal,
            kind=kind,
            result_type=f"{type_name}_Result",
            feedback_type=f"{type_name}_Feedback",
            started=now,
            origin=(x, y, yaw),
            last_yaw=yaw,
            progress_anchor=(now, x, y),
            next_feedback=now + FEEDBACK_PERIOD,
        )
        task.time_allowance = from_duration(request.get("time_allowance"))
        refusal = self._prepare(task, request)
        goal.accept()
        entry = {"action": goal.action, "serves": kind, "accepted": now, "goal": request}
        if refusal is not None:
            goal.abort(self._result(task, error=True))
            world.record_goal({**entry, "outcome": "aborted", "finished": now, "reason": refusal})
            return
        if self.task is not None:
            self._finish("aborted", "pre-empted by a new goal")
        task.goal = goal
        self.task = task
        if task.legs:
            entry["target_xy"] = [task.legs[-1][0], task.legs[-1][1]]
        self._entry = entry
        self.next_tick = now + CONTROL_PERIOD
        world.record_goal({**entry, "outcome": "executing"})

    def on_cancel(self, goal: ActionGoal) -> bool:
        """Cancel requests are always granted: the base is told to stop at once."""
        if self.task is None or self.task.goal is not goal:
            return False
        self._finish("canceled", "cancelled by the skill")
        return True

    def _prepare(self, task: _BaseTask, request: Message) -> str | None:
        world = self.world
        x, y, _yaw = task.origin
        if task.kind in ("navigate_to_pose", "navigate_through_poses"):
            if task.kind == "navigate_to_pose":
                poses = [request.get("pose")]
            else:
                raw = request.get("poses")
                if raw is None and isinstance(request.get("goals"), Mapping):
                    raw = request["goals"].get("goals")
                poses = list(raw or [])
            if not poses:
                return "no goal pose in the request"
            legs = []
            for pose in poses:
                if not isinstance(pose, Mapping):
                    return "a goal pose is not a PoseStamped"
                frame = str((pose.get("header") or {}).get("frame_id", ""))
                inner = pose.get("pose") or {}
                gx, gy, _ = _point(inner.get("position"))
                gyaw = yaw_of(inner.get("orientation"))
                mapped = world.to_map(frame, gx, gy, gyaw)
                if mapped is None:
                    return f"goal frame {frame!r} is unknown (TF cannot transform it to the map)"
                legs.append(mapped)
            task.legs = legs
            task.poses_remaining = len(legs)
            return self._plan_leg(task, (x, y))
        if task.kind == "spin":
            task.target = float(request.get("target_yaw", 0.0) or 0.0)
            return None
        distance = _point(request.get("target"))[0]
        speed = abs(float(request.get("speed", 0.0) or 0.0))
        if speed <= 0.0:
            return "speed must be positive"
        task.target = abs(distance)
        # BackUp drives backwards whatever the sign; DriveOnHeading follows the sign.
        sign = -1.0 if task.kind == "backup" or distance < 0 else 1.0
        task.speed = sign * min(speed, self.config.speed_max)
        return None

    def _plan_leg(self, task: _BaseTask, start: tuple[float, float]) -> str | None:
        gx, gy, gyaw = task.legs[0]
        path = self.world.plan(start, (gx, gy))
        if path is None:
            return f"no path to ({gx:.2f}, {gy:.2f}): the goal is in or behind an obstacle"
        task.waypoints = path[1:]
        task.final_yaw = gyaw
        return None

    # --- execution -------------------------------------------------------------------
    def tick(self) -> None:
        """One control period: command the base, send feedback, finish when done."""
        task = self.task
        if task is None:
            self.next_tick = None
            return
        world = self.world
        now = world.now
        self.next_tick = now + CONTROL_PERIOD
        x, y, yaw = world.base_pose()
        task.travelled += abs(wrap_pi(yaw - task.last_yaw))
        task.last_yaw = yaw
        if task.time_allowance > 0 and now - task.started > task.time_allowance:
            self._finish("aborted", "time allowance exceeded")
            return
        if task.kind in ("navigate_to_pose", "navigate_through_poses"):
            self._follow(task, now, x, y, yaw)
        elif task.kind == "spin":
            self._spin(task, yaw)
        else:
            self._straight(task, x, y)
        if self.task is not None and now >= task.next_feedback - 1e-9:
            task.next_feedback = now + FEEDBACK_PERIOD
            task.goal.feedback(self._feedback(task, now, x, y, yaw))

    def _follow(self, task: _BaseTask, now: float, x: float, y: float, yaw: float) -> None:
        config = self.config
        anchor_t, ax, ay = task.progress_anchor
        if math.hypot(x - ax, y - ay) >= 0.5:
            task.progress_anchor = (now, x, y)
        elif now - anchor_t > 10.0:
            self._finish("aborted", "no progress: moved less than 0.5 m in 10 s")
            return
        gx, gy, _ = task.legs[0]
        remaining = math.hypot(gx - x, gy - y)
        if remaining <= config.xy_tolerance * 0.5 or (
            remaining <= config.xy_tolerance and not task.waypoints[:-1]
        ):
            yaw_error = wrap_pi((task.final_yaw or 0.0) - yaw)
            if abs(yaw_error) <= config.yaw_tolerance * 0.5:
                if len(task.legs) > 1:
                    task.legs.pop(0)
                    task.poses_remaining = len(task.legs)
                    reason = self._plan_leg(task, (x, y))
                    if reason is not None:
                        self._finish("aborted", reason)
                    return
                self._finish("succeeded", "goal reached")
                return
            rate = math.copysign(
                min(config.yaw_rate_max, math.sqrt(2 * config.yaw_accel * abs(yaw_error)) * 0.7),
                yaw_error,
            )
            self.world.drive(Command(wz=rate))
            return
        # Waypoints are corners around obstacles: reach each one before heading for the next.
        while (
            len(task.waypoints) > 1
            and math.hypot(task.waypoints[0][0] - x, task.waypoints[0][1] - y) < 0.15
        ):
            task.waypoints.pop(0)
        tx, ty = task.waypoints[0]
        dx, dy = tx - x, ty - y
        length = math.hypot(dx, dy) or 1e-9
        speed = min(config.speed_max, math.sqrt(2 * config.accel * remaining) * 0.7, remaining * 2)
        heading = math.atan2(dy, dx)
        yaw_error = (
            wrap_pi(heading - yaw) if remaining > 0.3 else wrap_pi((task.final_yaw or yaw) - yaw)
        )
        # Face the direction of travel; slow down while the heading is far off.
        speed *= max(0.0, math.cos(min(abs(yaw_error), math.pi / 2)))
        wx, wy = dx / length * speed, dy / length * speed
        c, s = math.cos(yaw), math.sin(yaw)
        rate = max(-config.yaw_rate_max, min(config.yaw_rate_max, 1.5 * yaw_error))
        self.world.drive(Command(vx=c * wx + s * wy, vy=-s * wx + c * wy, wz=rate))

    def _spin(self, task: _BaseTask, yaw: float) -> None:
        config = self.config
        remaining = abs(task.target) - task.travelled
        if remaining <= 0.01:
            self._finish("succeeded", "turned by the requested angle")
            return
        rate = min(config.yaw_rate_max, math.sqrt(2 * config.yaw_accel * remaining) * 0.7)
        self.world.drive(Command(wz=math.copysign(rate, task.target or 1.0)))

    def _straight(self, task: _BaseTask, x: float, y: float) -> None:
        config = self.config
        ox, oy, _ = task.origin
        remaining = task.target - math.hypot(x - ox, y - oy)
        if remaining <= 0.005:
            self._finish("succeeded", "travelled the requested distance")
            return
        speed = min(abs(task.speed), math.sqrt(2 * config.accel * remaining) * 0.7)
        self.world.drive(Command(vx=math.copysign(speed, task.speed)))

    # --- messages and endings --------------------------------------------------------
    def _feedback(self, task: _BaseTask, now: float, x: float, y: float, yaw: float) -> Message:
        template = self.world.message(task.feedback_type)
        ox, oy, _ = task.origin
        if task.kind in ("navigate_to_pose", "navigate_through_poses"):
            gx, gy, _ = task.legs[0]
            remaining = math.hypot(gx - x, gy - y)
            return fill(
                template,
                {
                    "current_pose": self.world.pose_stamped(x, y, yaw),
                    "navigation_time": duration(now - task.started),
                    "estimated_time_remaining": duration(
                        remaining / max(self.config.speed_max, 1e-3)
                    ),
                    "number_of_recoveries": 0,
                    "distance_remaining": remaining,
                    "number_of_poses_remaining": task.poses_remaining,
                },
            )
        if task.kind == "spin":
            return fill(template, {"angular_distance_traveled": task.travelled})
        return fill(template, {"distance_traveled": math.hypot(x - ox, y - oy)})

    def _result(self, task: _BaseTask, *, error: bool) -> Message:
        template = self.world.message(task.result_type)
        # Nav2 (Jazzy) result codes: 0 none; the behaviours' and navigators' "unknown"
        # failure codes are in their 700s / 9000s; any non-zero value means failure.
        values: dict[str, Any] = {
            "total_elapsed_time": duration(self.world.now - task.started),
            "error_code": 9000 if error else 0,
        }
        return fill(template, values)

    def _finish(self, outcome: str, reason: str) -> None:
        task = self.task
        if task is None:
            return
        self.task = None
        self.next_tick = None
        self.world.drive(Command())
        goal = task.goal
        if goal.active:
            if outcome == "succeeded":
                goal.succeed(self._result(task, error=False))
            elif outcome == "canceled":
                goal.canceled(self._result(task, error=False))
            else:
                goal.abort(self._result(task, error=True))
        self.world.record_goal(
            {**self._entry, "outcome": outcome, "finished": self.world.now, "reason": reason}
        )


@dataclass(frozen=True)
class _Target:
    """Where a move-group goal sends the tool: the point in the arm's base frame, and the
    frame and link the request named."""

    point: tuple[float, float, float]
    frame: str
    link: str


@dataclass(frozen=True)
class ArmConfig:
    """The arm as MoveIt knows it (its SRDF and joint limits)."""

    group: str | None
    """The planning group; ``None`` when the world does not know the robot's groups (then
    every ``group_name`` is taken)."""
    tip_link: str | None
    """The group's tip link; ``None``: every ``link_name`` is taken as the tip."""
    base_frame: str
    """The frame of a position constraint with an empty ``header.frame_id``."""
    reach: float | None
    """How far from the arm's base a target may lie (``None``: anywhere)."""
    speed_max: float
    """Tool speed (m/s) at a velocity scaling of 1."""
    home: tuple[float, float, float]
    """Where the tool starts, in the arm's base frame."""
    default_velocity_scaling: float = 0.1
    """MoveIt's ``default_velocity_scaling_factor``, used when a request leaves
    ``max_velocity_scaling_factor`` at 0 (0.1 in MoveIt's own defaults)."""
    groups: Mapping[str, str | None] | None = None
    """Every planning group the robot's semantic description (SRDF) declares, with the tip
    link of its chain (``None``: not a chain); when given, move_group serves a request for
    any of them (it plans for every group of its SRDF) and :attr:`group` is not asked for."""


class ArmServer:
    """A move-group server for the arm's tool centre point."""

    def __init__(
        self,
        world: MotionWorld,
        config: ArmConfig,
        frame_offset: Callable[[str], tuple[float, float, float] | None],
    ) -> None:
        self.world = world
        self.config = config
        self.frame_offset = frame_offset
        """Frame name -> what to add to a point in that frame to express it in the arm's
        base frame (``None``: TF does not know the frame)."""
        self.tcp = config.home
        """Where the tool is, in the arm's base frame."""
        self.frame = config.base_frame
        self.link = config.tip_link
        """Frame and link of the last goal accepted (the link is ``None`` before one when
        the world does not know the tip)."""
        self.goal: ActionGoal | None = None
        self.target = config.home
        self.speed = 0.0
        self.started = 0.0
        self.type_name = ""
        self.next_tick: float | None = None
        self._entry: dict[str, Any] = {}

    def handler(self, type_name: str) -> _ActionAdapter:
        """The action handler of the move-group action of type ``type_name``."""
        self.type_name = type_name
        return _ActionAdapter(self.on_goal, self.on_cancel)

    def _result(self, code: int) -> Message:
        template = self.world.message(f"{self.type_name}_Result")
        return fill(template, {"error_code": {"val": code}, "planning_time": 0.01})

    def on_goal(self, goal: ActionGoal) -> None:
        """Check the motion request, refuse it with MoveIt's code or start moving."""
        now = self.world.now
        goal.accept()
        entry = {
            "action": goal.action,
            "serves": "move_group",
            "accepted": now,
            "goal": goal.request,
        }
        code, reason, target = self._target(goal.request)
        if code != MOVEIT_SUCCESS or target is None:
            goal.abort(self._result(code))
            self.world.record_goal(
                {**entry, "outcome": "aborted", "finished": now, "reason": reason}
            )
            return
        if self.goal is not None and self.goal.active:
            self.goal.abort(self._result(MOVEIT_PREEMPTED))
        options = goal.request.get("planning_options") or {}
        if isinstance(options, Mapping) and options.get("plan_only"):
            goal.succeed(self._result(MOVEIT_SUCCESS))
            self.world.record_goal(
                {**entry, "outcome": "succeeded", "finished": now, "reason": "planned only"}
            )
            return
        request = goal.request.get("request") or {}
        scaling = float(request.get("max_velocity_scaling_factor", 0.0) or 0.0)
        # MoveIt reads 0 (unset) as its default scaling of 0.1.
        scaling = self.config.default_velocity_scaling if scaling <= 0.0 else min(scaling, 1.0)
        self.goal = goal
        self.target = target.point
        self.frame, self.link = target.frame, target.link
        self.speed = self.config.speed_max * scaling
        self.started = now
        self._entry = entry
        self.next_tick = now + 0.02
        goal.feedback(fill(self.world.message(f"{self.type_name}_Feedback"), {"state": "MONITOR"}))
        self.world.record_goal({**entry, "outcome": "executing", "target": list(target.point)})

    def _target(self, message: Message) -> tuple[int, str, _Target | None]:
        request = message.get("request") or {}
        if not isinstance(request, Mapping):
            return MOVEIT_INVALID_GOAL_CONSTRAINTS, "the request is not a MotionPlanRequest", None
        group = str(request.get("group_name", ""))
        tip = self.config.tip_link
        known = self.config.groups
        if known:
            if group not in known:
                return (
                    MOVEIT_INVALID_GROUP_NAME,
                    f"unknown planning group {group!r}; the robot's groups are "
                    + ", ".join(repr(g) for g in sorted(known)),
                    None,
                )
            tip = known[group] or tip
        elif self.config.group is not None and group != self.config.group:
            return (
                MOVEIT_INVALID_GROUP_NAME,
                f"unknown planning group {group!r}; the robot's group is {self.config.group!r}",
                None,
            )
        constraints = request.get("goal_constraints") or []
        positions: list[Any] = []
        for item in constraints if isinstance(constraints, list) else []:
            if isinstance(item, Mapping):
                positions.extend(item.get("position_constraints") or [])
        if not positions:
            return (
                MOVEIT_INVALID_GOAL_CONSTRAINTS,
                "no position constraint (joint and orientation goals are not simulated)",
                None,
            )
        constraint = positions[0]
        link = str(constraint.get("link_name", ""))
        if tip is not None and link != tip:
            return (
                MOVEIT_INVALID_LINK_NAME,
                f"link {link!r} is not the tip of group {group!r}, which is {tip!r}",
                None,
            )
        frame = str((constraint.get("header") or {}).get("frame_id", "")) or self.config.base_frame
        offset = self.frame_offset(frame)
        if offset is None:
            return MOVEIT_FRAME_TRANSFORM_FAILURE, f"unknown frame {frame!r}", None
        region = constraint.get("constraint_region") or {}
        poses = region.get("primitive_poses") or [] if isinstance(region, Mapping) else []
        if not poses:
            return MOVEIT_INVALID_GOAL_CONSTRAINTS, "the position constraint has no region", None
        px, py, pz = _point(poses[0].get("position") if isinstance(poses[0], Mapping) else None)
        ox, oy, oz = _point(constraint.get("target_point_offset"))
        target = (px + ox + offset[0], py + oy + offset[1], pz + oz + offset[2])
        reach = self.config.reach
        if reach is not None and math.sqrt(sum(v * v for v in target)) > reach:
            return MOVEIT_NO_IK_SOLUTION, "the target is beyond the arm's reach", None
        return MOVEIT_SUCCESS, "", _Target(target, frame, link)

    def on_cancel(self, goal: ActionGoal) -> bool:
        """Stop the arm where it is."""
        if goal is not self.goal:
            return False
        self._end("canceled", "cancelled by the skill", MOVEIT_PREEMPTED)
        return True

    def tick(self) -> None:
        """Move the tool centre point one control period towards its target."""
        if self.goal is None:
            self.next_tick = None
            return
        now = self.world.now
        self.next_tick = now + 0.02
        delta = [t - c for t, c in zip(self.target, self.tcp, strict=True)]
        distance = math.sqrt(sum(d * d for d in delta))
        step = self.speed * 0.02
        if distance <= step:
            self.tcp = self.target
            self._end("succeeded", "target reached", MOVEIT_SUCCESS)
            return
        x, y, z = (c + d / distance * step for c, d in zip(self.tcp, delta, strict=True))
        self.tcp = (x, y, z)

    def _end(self, outcome: str, reason: str, code: int) -> None:
        goal = self.goal
        if goal is None:
            return
        self.goal = None
        self.next_tick = None
        if goal.active:
            if outcome == "succeeded":
                goal.succeed(self._result(code))
            elif outcome == "canceled":
                goal.canceled(self._result(code))
            else:
                goal.abort(self._result(code))
        self.world.record_goal(
            {**self._entry, "outcome": outcome, "finished": self.world.now, "reason": reason}
        )


@dataclass
class _ActionAdapter:
    """An :class:`~skillwright.runtime.api.ActionHandler` made of two callables."""

    goal_callback: Callable[[ActionGoal], None]
    cancel_callback: Callable[[ActionGoal], bool]

    def on_goal(self, goal: ActionGoal) -> None:
        """Hand the goal to the server."""
        self.goal_callback(goal)

    def on_cancel(self, goal: ActionGoal) -> bool:
        """Hand the cancel request to the server."""
        return self.cancel_callback(goal)
