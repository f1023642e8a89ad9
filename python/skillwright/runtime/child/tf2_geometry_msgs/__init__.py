"""Stand-in of ``tf2_geometry_msgs``: geometry_msgs types moved by a TransformStamped.

As in the real package, importing it registers its types with tf2, so ``Buffer.transform``
moves a PointStamped, PoseStamped or Vector3Stamped into another frame; the functions take
the message and the transform (``do_transform_pose`` a bare Pose, as from Humble on).
"""

from __future__ import annotations

from _skillwright_child.core import core
from tf2_ros.buffer import _compose, _rotate

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

__all__ = [
    "do_transform_point",
    "do_transform_pose",
    "do_transform_pose_stamped",
    "do_transform_vector3",
]


def _pose_of(transform: Any) -> tuple:
    t, r = transform.transform.translation, transform.transform.rotation
    return ((t.x, t.y, t.z), (r.x, r.y, r.z, r.w))


def _stamped(type_name: str, message: Any, transform: Any) -> Any:
    moved = core().catalog.get(type_name)()
    moved.header.frame_id = transform.header.frame_id
    moved.header.stamp.sec = message.header.stamp.sec
    moved.header.stamp.nanosec = message.header.stamp.nanosec
    return moved


def do_transform_point(point: Any, transform: Any) -> Any:
    """``point`` (a PointStamped) in the transform's target frame."""
    p = point.point
    (x, y, z), _ = _compose(_pose_of(transform), ((p.x, p.y, p.z), (0.0, 0.0, 0.0, 1.0)))
    moved = _stamped("geometry_msgs/msg/PointStamped", point, transform)
    moved.point.x, moved.point.y, moved.point.z = float(x), float(y), float(z)
    return moved


def do_transform_vector3(vector3: Any, transform: Any) -> Any:
    """``vector3`` (a Vector3Stamped) turned into the transform's target frame (a direction:
    rotated, not moved)."""
    v = vector3.vector
    x, y, z = _rotate(_pose_of(transform)[1], (v.x, v.y, v.z))
    moved = _stamped("geometry_msgs/msg/Vector3Stamped", vector3, transform)
    moved.vector.x, moved.vector.y, moved.vector.z = float(x), float(y), float(z)
    return moved


def do_transform_pose(pose: Any, transform: Any) -> Any:
    """``pose`` (a Pose) in the transform's target frame."""
    p, q = pose.position, pose.orientation
    (x, y, z), (qx, qy, qz, qw) = _compose(
        _pose_of(transform), ((p.x, p.y, p.z), (q.x, q.y, q.z, q.w))
    )
    moved = core().catalog.get("geometry_msgs/msg/Pose")()
    moved.position.x, moved.position.y, moved.position.z = float(x), float(y), float(z)
    o = moved.orientation
    o.x, o.y, o.z, o.w = float(qx), float(qy), float(qz), float(qw)
    return moved


def do_transform_pose_stamped(pose: Any, transform: Any) -> Any:
    """``pose`` (a PoseStamped) in the transform's target frame."""
    moved = _stamped("geometry_msgs/msg/PoseStamped", pose, transform)
    moved.pose = do_transform_pose(pose.pose, transform)
    return moved
