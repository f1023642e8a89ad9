"""Stand-in of ``tf_transformations``: turning quaternions into Euler angles and back.

ROS 2 skills take a heading from an orientation with
``tf_transformations.euler_from_quaternion([x, y, z, w])`` (roll, pitch, yaw). Quaternions
are ``[x, y, z, w]`` as in the real package. The Euler angles are the ROS convention
(REP 103): rotations about the fixed axes x, then y, then z (``axes="sxyz"``, the default),
which are the same rotations as about the moving axes z, y', x'' (``"rzyx"``); other axis
orders raise ValueError naming these two.
"""

from __future__ import annotations

import math

__all__ = [
    "euler_from_quaternion",
    "quaternion_conjugate",
    "quaternion_from_euler",
    "quaternion_inverse",
    "quaternion_multiply",
]

_ORDERS = ("sxyz", "rzyx")


def _order(axes: str) -> None:
    if axes not in _ORDERS:
        raise ValueError(
            f"axes {axes!r}: the simulation's tf_transformations knows {' and '.join(_ORDERS)} "
            "(roll, pitch, yaw about the fixed x, y, z axes)"
        )


def euler_from_quaternion(quaternion: object, axes: str = "sxyz") -> tuple[float, float, float]:
    """(roll, pitch, yaw) of the rotation ``quaternion`` (``[x, y, z, w]``)."""
    _order(axes)
    x, y, z, w = (float(v) for v in quaternion)  # type: ignore[attr-defined]
    norm = math.sqrt(x * x + y * y + z * z + w * w) or 1.0
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x))))
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return roll, pitch, yaw


def quaternion_from_euler(ai: float, aj: float, ak: float, axes: str = "sxyz") -> list[float]:
    """``[x, y, z, w]`` of roll ``ai``, pitch ``aj`` and yaw ``ak``."""
    _order(axes)
    cr, sr = math.cos(ai / 2.0), math.sin(ai / 2.0)
    cp, sp = math.cos(aj / 2.0), math.sin(aj / 2.0)
    cy, sy = math.cos(ak / 2.0), math.sin(ak / 2.0)
    return [
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    ]


def quaternion_multiply(quaternion1: object, quaternion0: object) -> list[float]:
    """The rotation ``quaternion0`` followed by ``quaternion1`` (their Hamilton product)."""
    x1, y1, z1, w1 = (float(v) for v in quaternion1)  # type: ignore[attr-defined]
    x0, y0, z0, w0 = (float(v) for v in quaternion0)  # type: ignore[attr-defined]
    return [
        w1 * x0 + x1 * w0 + y1 * z0 - z1 * y0,
        w1 * y0 - x1 * z0 + y1 * w0 + z1 * x0,
        w1 * z0 + x1 * y0 - y1 * x0 + z1 * w0,
        w1 * w0 - x1 * x0 - y1 * y0 - z1 * z0,
    ]


def quaternion_conjugate(quaternion: object) -> list[float]:
    """``[-x, -y, -z, w]``."""
    x, y, z, w = (float(v) for v in quaternion)  # type: ignore[attr-defined]
    return [-x, -y, -z, w]


def quaternion_inverse(quaternion: object) -> list[float]:
    """The rotation that undoes ``quaternion``."""
    x, y, z, w = quaternion_conjugate(quaternion)
    norm = x * x + y * y + z * z + w * w
    return [x / norm, y / norm, z / norm, w / norm]
