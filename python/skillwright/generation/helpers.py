"""The helper methods a skeleton offers its skill, as real code: mypy checks them here, and
the skeleton copies their text from this file (:func:`helper_lines`).

They are written once and tested so that a small model spends its tokens on behaviour:
waiting with a deadline while callbacks run (rclpy delivers messages and completes futures
only while the executor gets to run), waiting for a future (service responses, action goals
and results), the life of an action goal, a MoveIt or Nav2 goal, a tf2 lookup, the nearest
reading of a LaserScan, the heading of a quaternion and the base's stop.

What the copy changes, and nothing else:

- the annotations that name what only mypy needs here (the protocols below of the rclpy,
  tf2 and message objects a helper reads, and ``typing`` names) are left out, since the
  skill imports none of them;
- the helpers of an action are templates: ``stem`` in a name (``_send_stem_goal``,
  ``self.stem_client``) is the action's stem (:func:`~skillwright.generation.skeleton.action_stem`),
  ``Action`` its class and ``/action`` its name; the check of a MoveIt error code (the
  ``if`` on ``MoveItErrorCodes``) is kept only for MoveIt actions, whose results carry one;
- ``_stop_base`` repeats its ``if`` for every velocity publisher, ``velocity_publisher``
  standing for the handle and ``Velocity`` for its message class;
- in ``_settle_base`` ``odometry_msg`` is the attribute holding the latest odometry message
  and ``/odometry`` its topic.

The class body is not formatted by ruff (``fmt: off``): its layout is the skeleton's, which
the prompts show the model as it is.
"""

from __future__ import annotations

import ast
import inspect
import io
import math
import re
import time
import tokenize
from collections.abc import Mapping, Sequence
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol, TypeVar

if TYPE_CHECKING:
    from collections.abc import Callable

__all__ = ["SkeletonHelpers", "helper_lines", "helper_names", "helper_signature"]

_T = TypeVar("_T")
_T_co = TypeVar("_T_co", covariant=True)


class _Future(Protocol[_T_co]):
    """rclpy's Future, as far as the helpers use it."""

    def done(self) -> bool: ...
    def result(self) -> _T_co: ...


class _WrappedResult(Protocol):
    """What a goal handle's result future gives: the goal's status and the action's result."""

    status: int
    result: Action.Result


class _GoalHandle(Protocol):
    """rclpy's ClientGoalHandle."""

    accepted: bool

    def get_result_async(self) -> _Future[_WrappedResult]: ...
    def cancel_goal_async(self) -> _Future[object]: ...


class _FeedbackMessage(Protocol):
    """What an action client hands its feedback callback: the goal's id and the feedback."""

    feedback: object


class _ActionClient(Protocol):
    """rclpy's ActionClient."""

    def send_goal_async(
        self, goal: object, feedback_callback: Callable[[_FeedbackMessage], None]
    ) -> _Future[_GoalHandle]: ...


class _TransformStamped(Protocol):
    """geometry_msgs/msg/TransformStamped, read by the skill."""

    transform: Any


class _Buffer(Protocol):
    """tf2_ros's Buffer."""

    def lookup_transform(
        self, target_frame: str, source_frame: str, time: object
    ) -> _TransformStamped: ...


class _LaserScan(Protocol):
    """sensor_msgs/msg/LaserScan."""

    ranges: Sequence[float]
    range_min: float
    range_max: float
    angle_min: float
    angle_increment: float


class _Quaternion(Protocol):
    """geometry_msgs/msg/Quaternion."""

    x: float
    y: float
    z: float
    w: float


class _Publisher(Protocol):
    """rclpy's Publisher."""

    def publish(self, msg: object) -> None: ...


class _Message:
    """A generated ROS 2 message class, whose fields mypy does not know."""

    def __init__(self, **fields: object) -> None:
        self.__dict__.update(fields)

    def __getattr__(self, name: str) -> Any:
        raise AttributeError(name)


if TYPE_CHECKING:
    # What the skill imports (rclpy, tf2_ros and message packages, which the host need not
    # have), as far as the helpers use it.

    class TransformException(Exception): ...  # noqa: N818 (tf2_ros's name)

    class MoveGroup:
        class Goal(_Message): ...

        class Result(_Message): ...

    class NavigateToPose:
        class Goal(_Message): ...

    class Action:
        class Result(_Message): ...

    Constraints: Any = None
    GoalStatus: Any = None
    MoveItErrorCodes: Any = None
    Pose: Any = None
    PositionConstraint: Any = None
    SolidPrimitive: Any = None
    Time: Any = None
    Velocity: Any = None


class SkeletonHelpers:
    """The helpers, as methods of a skill; the attributes are what the skeleton's
    ``__init__`` and states set."""

    tf_buffer: _Buffer
    stem_client: _ActionClient
    stem_goal_handle: _GoalHandle | None
    stem_result_future: _Future[_WrappedResult] | None
    stem_feedback: object
    velocity_publisher: _Publisher | None
    odometry_msg: Any

    # fmt: off
    # rclpy runs a skill's callbacks on its executor while the skill waits; a wait without a
    # deadline hangs a state forever when the message never comes.
    def _wait_until(self, condition: Callable[[], object], timeout: float, what: str) -> None:
        """Waits until ``condition()`` is true while callbacks keep running; raises
        RuntimeError naming ``what`` after ``timeout`` seconds."""
        deadline = time.monotonic() + timeout
        while not condition():
            if time.monotonic() > deadline:
                raise RuntimeError(f"no {what} within {timeout:g} s")
            time.sleep(0.02)

    # rclpy's call_async and send_goal_async give a future at once; its result() is None
    # until the executor completes it.
    def _result_of(self, future: _Future[_T], timeout: float, what: str) -> _T:
        """Waits for ``future`` (a service call, a goal, a result) and returns its
        result; raises RuntimeError naming ``what`` after ``timeout`` seconds."""
        self._wait_until(future.done, timeout, what)
        return future.result()

    # An action goal's life: send_goal_async gives a future of a ClientGoalHandle, which
    # says whether the server accepted the goal and gives the result and the cancel.
    def _send_stem_goal(self, goal: _Message, timeout: float) -> None:
        """Sends ``goal`` to /action and waits until the server accepts it;
        raises RuntimeError if it rejects the goal or does not answer within
        ``timeout`` s."""
        self.stem_feedback = None
        future = self.stem_client.send_goal_async(
            goal, feedback_callback=self._on_stem_feedback
        )
        goal_handle = self._result_of(future, timeout, "answer to the /action goal")
        if not goal_handle.accepted:
            raise RuntimeError("/action rejected the goal")
        self.stem_goal_handle = goal_handle
        self.stem_result_future = goal_handle.get_result_async()

    def _on_stem_feedback(self, message: _FeedbackMessage) -> None:
        """Keeps the latest feedback of the /action goal."""
        self.stem_feedback = message.feedback

    # A goal that ends ABORTED or CANCELED still gives a result; only STATUS_SUCCEEDED means
    # the action did its work. A MoveIt result carries its own MoveItErrorCodes as well.
    def _stem_result(self, timeout: float) -> "Action.Result":
        """Waits for the result of the goal sent with self._send_stem_goal and
        returns it; raises RuntimeError if none was sent, none came within
        ``timeout`` s or the goal did not succeed."""
        if self.stem_result_future is None:
            raise RuntimeError("no goal was sent to /action")
        response = self._result_of(self.stem_result_future, timeout, "result of the /action goal")
        self.stem_goal_handle = None
        if response.status != GoalStatus.STATUS_SUCCEEDED:
            raise RuntimeError(f"the /action goal ended with status {response.status}")
        if response.result.error_code.val != MoveItErrorCodes.SUCCESS:
            raise RuntimeError(
                f"/action failed with error code {response.result.error_code.val}"
            )
        return response.result

    def _cancel_stem_goal(self, timeout: float) -> None:
        """Cancels the goal in progress on /action, if any, and waits until the
        server confirms; raises RuntimeError without a confirmation within
        ``timeout`` s."""
        if self.stem_goal_handle is not None:
            future = self.stem_goal_handle.cancel_goal_async()
            self._result_of(future, timeout, "cancellation of the /action goal")
            self.stem_goal_handle = None

    # MoveIt's MoveGroup goal is a MotionPlanRequest: a position constraint (a sphere of the
    # tolerance around the point) for the link, planned and, with plan_only False, executed.
    def _position_goal(
        self, group: str, link: str, frame: str,
        x: float, y: float, z: float, tolerance: float,
    ) -> MoveGroup.Goal:
        """A move-group goal that plans and executes a motion of ``link`` (planning group
        ``group``) to the point (x, y, z) in ``frame``, within ``tolerance`` metres, in any
        orientation."""
        region = SolidPrimitive()
        region.type = SolidPrimitive.SPHERE
        region.dimensions = [float(tolerance)]
        target = Pose()
        target.position.x = float(x)
        target.position.y = float(y)
        target.position.z = float(z)
        target.orientation.w = 1.0
        constraint = PositionConstraint()
        constraint.header.frame_id = frame
        constraint.link_name = link
        constraint.constraint_region.primitives = [region]
        constraint.constraint_region.primitive_poses = [target]
        constraint.weight = 1.0
        goal = MoveGroup.Goal()
        goal.request.group_name = group
        goal.request.goal_constraints = [Constraints(position_constraints=[constraint])]
        goal.request.num_planning_attempts = 1
        goal.planning_options.plan_only = False
        return goal

    # Nav2's NavigateToPose goal holds a PoseStamped whose pose holds the heading as a
    # quaternion: three layers to get right. The coordinates go through float, as a
    # message's float field refuses an int.
    def _pose_goal(self, frame: str, x: float, y: float, yaw: float) -> NavigateToPose.Goal:
        """A navigate-to-pose goal: the base at the point (x, y) in ``frame``, heading
        ``yaw`` radians (0 along the frame's x axis, counter-clockwise positive). The stamp
        stays zero, which Nav2 reads as the latest transform."""
        goal = NavigateToPose.Goal()
        goal.pose.header.frame_id = frame
        goal.pose.pose.position.x = float(x)
        goal.pose.pose.position.y = float(y)
        goal.pose.pose.orientation.z = math.sin(yaw / 2.0)
        goal.pose.pose.orientation.w = math.cos(yaw / 2.0)
        return goal

    # tf2's lookup_transform raises until the buffer has the frames (a listener fills it
    # from /tf as messages come), so the lookup is retried until a deadline; Time() asks for
    # the latest transform.
    def _transform(self, target_frame: str, source_frame: str, timeout: float) -> _TransformStamped:
        """The latest transform from ``source_frame`` into ``target_frame`` (a
        TransformStamped) from the tf2 buffer; raises RuntimeError after ``timeout``
        seconds without one."""
        deadline = time.monotonic() + timeout
        while True:
            try:
                return self.tf_buffer.lookup_transform(
                    target_frame, source_frame, Time()
                )
            except TransformException as error:
                if time.monotonic() > deadline:
                    raise RuntimeError(
                        f"no transform from {source_frame} to {target_frame} "
                        f"within {timeout:g} s ({error})"
                    ) from None
            time.sleep(0.05)

    # A LaserScan's ranges are indexed by angle (angle_min + i * angle_increment): the bearing
    # needs the index, which min() of the ranges loses; a reading outside [range_min,
    # range_max] (NaN, inf) is no obstacle.
    def _closest_reading(self, *scans: _LaserScan) -> tuple[float, float]:
        """The closest valid reading of the ``scans`` (LaserScans: one, or each scanner
        of a robot whose scanners see different sides): its range in metres and its
        bearing in radians (0 along the x axis of the scanner it came from, positive to
        the left). NaN, infinite and out-of-range readings are skipped; (math.inf, 0.0)
        when none is valid."""
        closest, bearing = math.inf, 0.0
        for scan in scans:
            for index, distance in enumerate(scan.ranges):
                if scan.range_min <= distance <= scan.range_max and distance < closest:
                    closest = distance
                    bearing = scan.angle_min + index * scan.angle_increment
        return closest, bearing

    # An orientation is a quaternion, whose z is not an angle (for a pure yaw it is
    # sin(yaw / 2)). It takes the quaternion, so one helper serves Odometry, poses and tf
    # transforms alike.
    def _yaw(self, q: _Quaternion) -> float:
        """The heading (yaw) of the quaternion ``q`` in radians, in [-pi, pi]: 0 along the
        frame's x axis, positive counter-clockwise (to the left). ``q`` is an orientation
        such as an Odometry's pose.pose.orientation or a transform's transform.rotation.
        The change of the heading since a start is the angle turned; wrap a difference d
        into [-pi, pi] with math.atan2(math.sin(d), math.cos(d))."""
        return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))

    # A base keeps driving on its last velocity command until told otherwise.
    def _stop_base(self) -> None:
        """Commands zero velocity, so the base stands still."""
        if self.velocity_publisher is not None:
            self.velocity_publisher.publish(Velocity())

    # A base brakes for a while after a zero command; nav_msgs/Odometry's twist (in the
    # base's own frame, REP 105) is what says it has stopped: under 1 cm/s and 0.02 rad/s
    # (about 1 degree a second), what wheel odometry of a base standing still reads.
    def _settle_base(self, timeout: float) -> None:
        """Commands zero velocity and waits until odometry shows the base at rest (under
        0.01 m/s and 0.02 rad/s); raises RuntimeError after ``timeout`` seconds."""
        self._stop_base()

        def at_rest() -> bool:
            if self.odometry_msg is None:
                return False
            twist = self.odometry_msg.twist.twist
            moving = math.hypot(twist.linear.x, twist.linear.y)
            return moving < 0.01 and abs(twist.angular.z) < 0.02

        self._wait_until(at_rest, timeout, "rest of the base on /odometry")
    # fmt: on


_TEMPLATE = re.compile(r"(?<![^_])stem(?![^_])")
"""``stem`` as a part of a name (``_send_stem_goal``, ``stem_client``): where the action's
stem goes."""


@cache
def _methods() -> dict[str, ast.FunctionDef]:
    tree = ast.parse(_SOURCE)
    cls = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "SkeletonHelpers")
    return {n.name: n for n in cls.body if isinstance(n, ast.FunctionDef)}


@cache
def _typing_only() -> frozenset[str]:
    """The names an annotation may use that the skill does not have: this module's protocols
    and ``typing``'s names."""
    tree = ast.parse(_SOURCE)
    names = {n.name for n in tree.body if isinstance(n, ast.ClassDef) and n.name.startswith("_")}
    names |= {"_T", "Callable", "Sequence", "Any"}
    return frozenset(names)


_SOURCE = Path(__file__).read_text(encoding="utf-8")
_LINES = _SOURCE.splitlines()


def helper_names() -> tuple[str, ...]:
    """The helpers' names as this module spells them (templates with ``stem``)."""
    return tuple(_methods())


def _template(name: str) -> str:
    """The method of :class:`SkeletonHelpers` that the skeleton's helper ``name`` is made from
    (``_send_navigate_to_pose_goal`` from ``_send_stem_goal``)."""
    if name in _methods():
        return name
    for template in _methods():
        if "stem" not in template.split("_"):
            continue
        pattern = "".join(
            r"\w+" if part == "stem" else re.escape(part)
            for part in re.split(r"(?<![^_])(stem)(?![^_])", template)
        )
        if re.fullmatch(pattern, name):
            return template
    raise LookupError(f"the skeleton has no helper {name}")


def helper_signature(name: str) -> inspect.Signature:
    """The parameters the skeleton's helper ``name`` takes, without ``self`` (positions and
    names as the skill's copy has them)."""
    signature = inspect.signature(getattr(SkeletonHelpers, _template(name)))
    parameters = [
        p.replace(annotation=inspect.Parameter.empty)
        for p in list(signature.parameters.values())[1:]
    ]
    return inspect.Signature(parameters)


def _names_in(node: ast.expr) -> set[str]:
    return {n.id for n in ast.walk(node) if isinstance(n, ast.Name)}


def _end_line(node: ast.expr) -> int:
    return node.lineno if node.end_lineno is None else node.end_lineno


def _end_column(node: ast.expr) -> int:
    return node.col_offset if node.end_col_offset is None else node.end_col_offset


def _untyped(method: ast.FunctionDef, text: str, first_line: int) -> str:
    """``text`` (the method's source from ``first_line``) without the annotations that name
    what the skill does not have."""
    starts = [0]
    for line in text.splitlines(keepends=True):
        starts.append(starts[-1] + len(line))
    cuts: list[tuple[int, int]] = []
    arguments = method.args
    for argument in [*arguments.args, *arguments.kwonlyargs, arguments.vararg, arguments.kwarg]:
        annotation = None if argument is None else argument.annotation
        if argument is None or annotation is None or not _names_in(annotation) & _typing_only():
            continue
        begin = starts[argument.lineno - first_line] + argument.col_offset + len(argument.arg)
        end = starts[_end_line(annotation) - first_line] + _end_column(annotation)
        cuts.append((begin, end))
    returns = method.returns
    if returns is not None and _names_in(returns) & _typing_only():
        end = starts[_end_line(returns) - first_line] + _end_column(returns)
        begin = text.rindex(" -> ", 0, end)
        cuts.append((begin, end))
    for begin, end in sorted(cuts, reverse=True):
        text = text[:begin] + text[end:]
    return text


_NAMED = frozenset({"Action", "velocity_publisher", "Velocity", "odometry_msg"})
"""The template's placeholders that are whole names."""


def _substituted(text: str, names: Mapping[str, str]) -> str:
    """``text`` with the template's names (``stem``, ``Action``, ``/action``,
    ``velocity_publisher``, ``Velocity``, ``odometry_msg``, ``/odometry``) replaced by
    ``names``' values, in names and strings."""
    pieces = []
    last = 0
    starts = [0]
    for line in text.splitlines(keepends=True):
        starts.append(starts[-1] + len(line))
    for token in tokenize.generate_tokens(io.StringIO(text).readline):
        if token.type not in (tokenize.NAME, tokenize.STRING):
            continue
        word = token.string
        if "stem" in names:
            word = _TEMPLATE.sub(names["stem"], word)
        if token.type == tokenize.NAME:
            word = names.get(word, word) if word in _NAMED else word
        else:
            if "/action" in names:
                word = re.sub(r"/action\b", names["/action"], word)
            if "/odometry" in names:
                word = re.sub(r"/odometry\b", names["/odometry"], word)
            if "Action" in names:
                word = re.sub(r"\bAction\b", names["Action"], word)
        if word != token.string:
            begin = starts[token.start[0] - 1] + token.start[1]
            end = starts[token.end[0] - 1] + token.end[1]
            pieces.append(text[last:begin] + word)
            last = end
    pieces.append(text[last:])
    return "".join(pieces)


def helper_lines(
    template: str,
    names: Mapping[str, str] | None = None,
    *,
    repeated: Sequence[Mapping[str, str]] | None = None,
    moveit: bool = False,
) -> list[str]:
    """The source of the helper ``template`` (a name :func:`helper_names` gives) as the
    skeleton writes it, in class indentation: annotations the skill lacks left out, the
    template's ``names`` replaced, the MoveIt error-code check kept only when ``moveit``, and
    the statements after the docstring repeated once for every entry of ``repeated``."""
    method = _methods()[template]
    first = method.lineno
    body = method.body
    docstring_end = body[0].end_lineno if isinstance(body[0], ast.Expr) else first
    head = "\n".join(_LINES[first - 1 : docstring_end]) + "\n"
    head = _untyped(method, head, first)
    lines = [_substituted(head, names or {}).rstrip("\n")]
    statements = []
    for statement in body[1:]:
        mentions = {n.id for n in ast.walk(statement) if isinstance(n, ast.Name)}
        if "MoveItErrorCodes" in mentions and not moveit:
            continue
        statements.append("\n".join(_LINES[statement.lineno - 1 : statement.end_lineno]))
    block = "\n".join(statements)
    for each in repeated or [names or {}]:
        if block:
            lines.append(_substituted(block, {**(names or {}), **each}))
    return "\n".join(lines).splitlines()
