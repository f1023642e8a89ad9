"""Stand-in of ``tf2_ros.buffer``: the latest transform of every frame, composed on lookup.

Lookups answer with the latest transforms whatever time is asked for (the simulation
has no history to interpolate in); a lookup with a timeout waits in virtual time until
the frames are connected.
"""

from __future__ import annotations

import math

from _skillwright_child.core import core
from rclpy.duration import Duration
from rclpy.time import Time

from tf2_ros.errors import ConnectivityException, LookupException

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

_Pose = tuple[tuple[float, float, float], tuple[float, float, float, float]]


def _multiply(a: tuple, b: tuple) -> tuple[float, float, float, float]:
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def _rotate(q: tuple, v: tuple) -> tuple[float, float, float]:
    x, y, z, _ = _multiply(_multiply(q, (v[0], v[1], v[2], 0.0)), (-q[0], -q[1], -q[2], q[3]))
    return (x, y, z)


def _compose(a: _Pose, b: _Pose) -> _Pose:
    """a then b: the pose b (given in a's frame) expressed in a's parent."""
    translation = _rotate(a[1], b[0])
    return (
        (a[0][0] + translation[0], a[0][1] + translation[1], a[0][2] + translation[2]),
        _multiply(a[1], b[1]),
    )


def _inverse(a: _Pose) -> _Pose:
    conjugate = (-a[1][0], -a[1][1], -a[1][2], a[1][3])
    moved = _rotate(conjugate, a[0])
    return ((-moved[0], -moved[1], -moved[2]), conjugate)


def _normalised(q: tuple) -> tuple[float, float, float, float]:
    norm = math.sqrt(sum(c * c for c in q)) or 1.0
    return (q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm)


class Buffer:
    """Holds transforms by child frame; ``lookup_transform`` chains them through the tree."""

    def __init__(self, cache_time: Duration | None = None, node: Any = None) -> None:
        self._parents: dict[str, tuple[str, _Pose, dict]] = {}
        self._waiting: list[tuple[str, str, Any]] = []

    def clear(self) -> None:
        self._parents.clear()

    def set_transform(self, transform: Any, authority: str) -> bool:
        child = transform.child_frame_id.lstrip("/")
        parent = transform.header.frame_id.lstrip("/")
        if not child or not parent or child == parent:
            return False
        t = transform.transform.translation
        r = transform.transform.rotation
        pose = ((t.x, t.y, t.z), _normalised((r.x, r.y, r.z, r.w)))
        stamp = {"sec": transform.header.stamp.sec, "nanosec": transform.header.stamp.nanosec}
        self._parents[child] = (parent, pose, stamp)
        for waiting in list(self._waiting):
            target, source, future = waiting
            if self.can_transform(target, source):
                self._waiting.remove(waiting)
                future.set_result(True)
        return True

    def set_transform_static(self, transform: Any, authority: str) -> bool:
        return self.set_transform(transform, authority)

    def _chain(self, frame: str) -> list[str]:
        chain = [frame]
        while chain[-1] in self._parents and len(chain) < 1000:
            chain.append(self._parents[chain[-1]][0])
        return chain

    def _to_root(self, frame: str, stop: str) -> tuple[_Pose, dict | None]:
        pose: _Pose = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
        newest: dict | None = None
        while frame != stop:
            parent, step, stamp = self._parents[frame]
            pose = _compose(step, pose)
            if newest is None or (stamp["sec"], stamp["nanosec"]) > (
                newest["sec"],
                newest["nanosec"],
            ):
                newest = stamp
            frame = parent
        return pose, newest

    def _resolve(self, target: str, source: str) -> tuple[_Pose, dict | None]:
        target = target.lstrip("/")
        source = source.lstrip("/")
        known = set(self._parents) | {p for p, _, _ in self._parents.values()}
        for frame in (target, source):
            if frame not in known:
                # tf2's own words, then (the sandbox's addition) the frames the robot does
                # have, so that a repair can pick one: the paper's robot has no map frame.
                have = ", ".join(sorted(known)) or "none yet"
                error = LookupException(
                    f'"{frame}" passed to lookupTransform argument '
                    f"{'target_frame' if frame == target else 'source_frame'} does not exist. "
                    f"(frames on /tf so far: {have})"
                )
                # What the run's report reads (the message is for the skill and its reader).
                error.skillwright_data = {"frame": frame, "frames": sorted(known)}
                raise error
        target_chain = self._chain(target)
        source_chain = self._chain(source)
        common = next((f for f in source_chain if f in target_chain), None)
        if common is None:
            raise ConnectivityException(
                f"Could not find a connection between '{target}' and '{source}' because they "
                "are not part of the same tree. Tf has two or more unconnected trees."
            )
        source_pose, source_stamp = self._to_root(source, common)
        target_pose, target_stamp = self._to_root(target, common)
        stamps = [s for s in (source_stamp, target_stamp) if s is not None]
        newest = max(stamps, key=lambda s: (s["sec"], s["nanosec"])) if stamps else None
        return _compose(_inverse(target_pose), source_pose), newest

    def can_transform(
        self,
        target_frame: str,
        source_frame: str,
        time: Time | None = None,
        timeout: Duration | None = None,
        return_debug_tuple: bool = False,
    ) -> Any:
        def ready() -> bool:
            try:
                self._resolve(target_frame, source_frame)
            except (LookupException, ConnectivityException):
                return False
            return True

        ok = self._wait(ready, timeout)
        if return_debug_tuple:
            return ok, "" if ok else f"cannot transform {source_frame} into {target_frame}"
        return ok

    def _wait(self, ready: Any, timeout: Duration | None) -> bool:
        if ready():
            return True
        if timeout is None or timeout.nanoseconds <= 0:
            return False
        c = core()
        return c.block(c.now + timeout.nanoseconds / 1e9, ready, "tf lookup")

    def lookup_transform(
        self,
        target_frame: str,
        source_frame: str,
        time: Time | None = None,
        timeout: Duration | None = None,
    ) -> Any:
        if timeout is not None and not isinstance(timeout, Duration):
            raise TypeError("timeout must be an rclpy.duration.Duration")
        self.can_transform(target_frame, source_frame, time, timeout)
        pose, stamp = self._resolve(target_frame, source_frame)
        c = core()
        transform = c.catalog.get("geometry_msgs/msg/TransformStamped")()
        transform.header.frame_id = target_frame
        if stamp is None:
            sec, nanosec = divmod(c.ros_time_ns(), 10**9)
            stamp = {"sec": sec, "nanosec": nanosec}
        transform.header.stamp.sec = stamp["sec"]
        transform.header.stamp.nanosec = stamp["nanosec"]
        transform.child_frame_id = source_frame
        translation = transform.transform.translation
        translation.x, translation.y, translation.z = (float(v) for v in pose[0])
        rotation = transform.transform.rotation
        rotation.x, rotation.y, rotation.z, rotation.w = (float(v) for v in pose[1])
        return transform

    def lookup_transform_full(
        self,
        target_frame: str,
        target_time: Time,
        source_frame: str,
        source_time: Time,
        fixed_frame: str,
        timeout: Duration | None = None,
    ) -> Any:
        """The source frame at ``source_time`` in the target frame at ``target_time``: with
        only the latest transforms to go by, the same as :meth:`lookup_transform`."""
        return self.lookup_transform(target_frame, source_frame, target_time, timeout)

    def can_transform_full(
        self,
        target_frame: str,
        target_time: Time,
        source_frame: str,
        source_time: Time,
        fixed_frame: str,
        timeout: Duration | None = None,
        return_debug_tuple: bool = False,
    ) -> Any:
        return self.can_transform(
            target_frame, source_frame, target_time, timeout, return_debug_tuple
        )

    def lookup_transform_async(
        self, target_frame: str, source_frame: str, time: Time | None = None
    ) -> Any:
        from rclpy.task import Future

        future = Future()
        future.set_result(self.lookup_transform(target_frame, source_frame, time))
        return future

    def all_frames_as_string(self) -> str:
        return "".join(
            f"Frame {child} exists with parent {parent}.\n"
            for child, (parent, _, _) in sorted(self._parents.items())
        )

    def all_frames_as_yaml(self) -> str:
        return "".join(
            f"{child}:\n  parent: '{parent}'\n"
            for child, (parent, _, _) in sorted(self._parents.items())
        )

    def wait_for_transform_async(self, target_frame: str, source_frame: str, time: Any) -> Any:
        """A future that is done (``True``) once ``source_frame`` can be put in
        ``target_frame``."""
        from rclpy.task import Future

        future = Future()
        if self.can_transform(target_frame, source_frame):
            future.set_result(True)
        else:
            self._waiting.append((target_frame, source_frame, future))
        return future

    def get_latest_common_time(self, target_frame: str, source_frame: str) -> Time:
        """The time of the latest transform between the two frames (now for frames that
        only static or world-made transforms join)."""
        _, stamp = self._resolve(target_frame, source_frame)
        if stamp is None:
            return Time(nanoseconds=core().ros_time_ns())
        return Time(seconds=stamp["sec"], nanoseconds=stamp["nanosec"])

    def transform(
        self,
        object_stamped: Any,
        target_frame: str,
        timeout: Duration | None = None,
        new_type: Any = None,
    ) -> Any:
        """``object_stamped`` (a PointStamped, PoseStamped or Vector3Stamped) in
        ``target_frame``, by tf2_geometry_msgs' conversions, as tf2_ros' BufferInterface."""
        transform = self.lookup_transform(
            target_frame, object_stamped.header.frame_id, Time(), timeout
        )
        return _moved(object_stamped, transform, new_type)

    def transform_full(
        self,
        object_stamped: Any,
        target_frame: str,
        target_time: Time,
        fixed_frame: str,
        timeout: Duration | None = None,
        new_type: Any = None,
    ) -> Any:
        """As :meth:`transform`: with only the latest transforms, times make no difference."""
        return self.transform(object_stamped, target_frame, timeout, new_type)


def _moved(message: Any, transform: Any, new_type: Any) -> Any:
    import tf2_geometry_msgs

    kind = type(message).__name__
    moves = {
        "PointStamped": tf2_geometry_msgs.do_transform_point,
        "PoseStamped": tf2_geometry_msgs.do_transform_pose_stamped,
        "Vector3Stamped": tf2_geometry_msgs.do_transform_vector3,
    }
    if kind not in moves:
        from tf2_ros.errors import TypeException

        raise TypeException(
            f"no tf2 conversion of a {kind}: tf2_geometry_msgs moves PointStamped, "
            "PoseStamped and Vector3Stamped"
        )
    moved = moves[kind](message, transform)
    if new_type is not None and not isinstance(moved, new_type):
        from tf2_ros.errors import TypeException

        raise TypeException(f"cannot convert a {kind} to {new_type.__name__}")
    return moved
