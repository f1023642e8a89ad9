"""get_distance_to_nearest_object: the closest valid lidar return, its range and bearing."""

import math
import time

import rclpy
from rclpy.qos import qos_profile_sensor_data

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from sensor_msgs.msg import LaserScan


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/get_distance_to_nearest_object",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/getDistanceToNearestObject/getDistanceToNearestObject",
    description="Report how far away the closest object seen by the MR-1's 2-D lidar is and in which direction it lies relative to the base's forward axis.",
)
class GetDistanceToNearestObjectSkill(ROS2Skill):
    """Pick the closest valid return of the next scan."""

    def __init__(self) -> None:
        super().__init__("get_distance_to_nearest_object")
        self.out_angle: float = 0.0
        self.out_distance: float = 0.0
        self.scan_subscription = None
        self.scan_msg: LaserScan | None = None
        self.scans = 0

    @skill_output(is_required=True, name="outAngle", description="Bearing in [-pi, pi]. Unit: rad.")
    def get_out_angle(self) -> float:
        return self.out_angle

    @skill_output(is_required=True, name="outDistance", description="Range. Unit: m.")
    def get_out_distance(self) -> float:
        return self.out_distance

    def _on_scan(self, msg: LaserScan) -> None:
        self.scan_msg = msg
        self.scans += 1

    @starting
    def starting(self) -> None:
        """Subscribe to the lidar scan (best effort, as the lidar publishes it)."""
        self.scan_subscription = self.node.create_subscription(
            LaserScan, "/scan", self._on_scan, qos_profile_sensor_data
        )

    @execute
    def execute(self) -> None:
        """Wait at most 2 s for the next scan; keep the smallest valid range and its bearing."""
        seen = self.scans
        deadline = time.monotonic() + 2.0
        while self.scans == seen and time.monotonic() < deadline:
            time.sleep(0.02)
        if self.scans == seen:
            raise RuntimeError("no lidar scan on /scan within 2 s")
        scan = self.scan_msg
        best = None
        for index, distance in enumerate(scan.ranges):
            if math.isfinite(distance) and scan.range_min <= distance <= scan.range_max:
                if best is None or distance < best[1]:
                    best = (index, distance)
        if best is None:
            self.node.get_logger().info("no valid return in the scan: nothing within range")
            self.out_distance = scan.range_max
            self.out_angle = 0.0
            return
        index, distance = best
        bearing = scan.angle_min + index * scan.angle_increment
        self.out_distance = distance
        self.out_angle = math.atan2(math.sin(bearing), math.cos(bearing))

    @completing
    def completing(self) -> None:
        """Log the distance and the bearing, also in degrees."""
        self.node.get_logger().info(
            f"nearest object {self.out_distance:.3f} m away at {self.out_angle:.3f} rad "
            f"({math.degrees(self.out_angle):.1f} deg)"
        )

    @resetting
    def resetting(self) -> None:
        """Drop the scan subscription and clear the outputs."""
        if self.scan_subscription is not None:
            self.node.destroy_subscription(self.scan_subscription)
            self.scan_subscription = None
        self.scan_msg = None
        self.out_angle = 0.0
        self.out_distance = 0.0
