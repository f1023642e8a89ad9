"""collision_avoidance: move for a while at a velocity, halting early for close obstacles."""

import math
import time

import rclpy
from rclpy.qos import qos_profile_sensor_data

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from geometry_msgs.msg import Twist
from sensor_msgs.msg import LaserScan


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/collision_avoidance",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/collisionAvoidance/collisionAvoidance",
    description="Move the MR-1 base with a requested linear and angular velocity for a requested time while watching the 2-D lidar, and halt early when an obstacle comes closer than a requested minimum distance.",
)
class CollisionAvoidanceSkill(ROS2Skill):
    """Drive at a clipped velocity for a duration unless the lidar sees something too close."""

    ANGULAR_VELOCITY_MAX = 1.2  # resource requirement: angularVelocity <= 1.2 rad/s
    LIDAR_RANGE_MAX = 12.0  # resource requirement: lidarRange <= 12.0 m
    LINEAR_VELOCITY_MAX = 0.8  # resource requirement: linearVelocity <= 0.8 m/s

    def __init__(self) -> None:
        super().__init__("collision_avoidance")
        self.in_angular_velocity: float = 0.0
        self.in_duration: float = 0.0
        self.in_linear_velocity_x: float = 0.0
        self.in_linear_velocity_y: float = 0.0
        self.in_min_obstacle_distance: float = 0.0
        self.out_angular_velocity: float = 0.0
        self.out_duration: float = 0.0
        self.out_linear_velocity_x: float = 0.0
        self.out_linear_velocity_y: float = 0.0
        self.out_obstacle_angle: float = 0.0
        self.out_obstacle_distance: float = 0.0
        self.scan_subscription = None
        self.scan_msg: LaserScan | None = None
        self.cmd_vel_publisher = None
        self.moving = False
        self.reason = ""

    @skill_parameter(is_required=True, name="inAngularVelocity", description="Yaw rate. Unit: rad/s.")
    def get_in_angular_velocity(self) -> float:
        return self.in_angular_velocity

    @skill_parameter(is_required=True, name="inDuration", description="How long to move. Unit: s.")
    def get_in_duration(self) -> float:
        return self.in_duration

    @skill_parameter(is_required=True, name="inLinearVelocityX", description="Forward speed. Unit: m/s.")
    def get_in_linear_velocity_x(self) -> float:
        return self.in_linear_velocity_x

    @skill_parameter(is_required=True, name="inLinearVelocityY", description="Sideways speed. Unit: m/s.")
    def get_in_linear_velocity_y(self) -> float:
        return self.in_linear_velocity_y

    @skill_parameter(is_required=True, name="inMinObstacleDistance", description="Closest allowed obstacle. Unit: m.")
    def get_in_min_obstacle_distance(self) -> float:
        return self.in_min_obstacle_distance

    @skill_output(is_required=True, name="outAngularVelocity", description="Final yaw rate. Unit: rad/s.")
    def get_out_angular_velocity(self) -> float:
        return self.out_angular_velocity

    @skill_output(is_required=True, name="outDuration", description="Time moved. Unit: s.")
    def get_out_duration(self) -> float:
        return self.out_duration

    @skill_output(is_required=True, name="outLinearVelocityX", description="Final forward speed. Unit: m/s.")
    def get_out_linear_velocity_x(self) -> float:
        return self.out_linear_velocity_x

    @skill_output(is_required=True, name="outLinearVelocityY", description="Final sideways speed. Unit: m/s.")
    def get_out_linear_velocity_y(self) -> float:
        return self.out_linear_velocity_y

    @skill_output(is_required=True, name="outObstacleAngle", description="Bearing of the closest reading. Unit: rad.")
    def get_out_obstacle_angle(self) -> float:
        return self.out_obstacle_angle

    @skill_output(is_required=True, name="outObstacleDistance", description="Range of the closest reading. Unit: m.")
    def get_out_obstacle_distance(self) -> float:
        return self.out_obstacle_distance

    def _on_scan(self, msg: LaserScan) -> None:
        self.scan_msg = msg

    def _closest(self) -> tuple[float, float]:
        """Range and bearing of the closest valid reading of the latest scan."""
        scan = self.scan_msg
        best = (math.inf, 0.0)
        for index, distance in enumerate(scan.ranges):
            if math.isfinite(distance) and scan.range_min <= distance <= min(scan.range_max, self.LIDAR_RANGE_MAX):
                if distance < best[0]:
                    bearing = scan.angle_min + index * scan.angle_increment
                    best = (distance, math.atan2(math.sin(bearing), math.cos(bearing)))
        return best

    def _publish_zero(self) -> None:
        self.moving = False
        if self.cmd_vel_publisher is not None:
            self.cmd_vel_publisher.publish(Twist())

    @starting
    def starting(self) -> None:
        """Check the inputs, subscribe to the scan and wait at most 2 s for the first one."""
        if self.in_min_obstacle_distance <= 0.0:
            raise ValueError(f"the minimum obstacle distance must be positive, got {self.in_min_obstacle_distance} m")
        if self.in_duration < 0.0:
            raise ValueError(f"the duration must not be negative, got {self.in_duration} s")
        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)
        self.scan_subscription = self.node.create_subscription(
            LaserScan, "/scan", self._on_scan, qos_profile_sensor_data
        )
        deadline = time.monotonic() + 2.0
        while self.scan_msg is None and time.monotonic() < deadline:
            time.sleep(0.02)
        if self.scan_msg is None:
            raise RuntimeError("no lidar scan on /scan within 2 s")

    @execute
    def execute(self) -> None:
        """Move at 20 Hz for the duration unless an obstacle is closer than the minimum."""
        vx, vy = self.in_linear_velocity_x, self.in_linear_velocity_y
        speed = math.hypot(vx, vy)
        if speed > self.LINEAR_VELOCITY_MAX:
            scale = self.LINEAR_VELOCITY_MAX / speed
            vx, vy = vx * scale, vy * scale
            self.node.get_logger().warning(f"velocity clipped to {self.LINEAR_VELOCITY_MAX} m/s")
        wz = max(-self.ANGULAR_VELOCITY_MAX, min(self.ANGULAR_VELOCITY_MAX, self.in_angular_velocity))
        if wz != self.in_angular_velocity:
            self.node.get_logger().warning(f"yaw rate clipped to {self.ANGULAR_VELOCITY_MAX} rad/s")
        command = Twist()
        command.linear.x = vx
        command.linear.y = vy
        command.angular.z = wz
        started = time.monotonic()
        self.moving = True
        self.reason = "time"
        while self.moving:
            distance, _ = self._closest()
            if distance < self.in_min_obstacle_distance:
                self.reason = "obstacle"
                break
            if time.monotonic() - started >= self.in_duration:
                break
            self.cmd_vel_publisher.publish(command)
            time.sleep(0.05)
        self._publish_zero()
        self.out_duration = time.monotonic() - started
        self.out_obstacle_distance, self.out_obstacle_angle = self._closest()
        self.out_linear_velocity_x = 0.0
        self.out_linear_velocity_y = 0.0
        self.out_angular_velocity = 0.0

    @completing
    def completing(self) -> None:
        """Log why the motion ended, how long it lasted and where the closest obstacle was."""
        self.node.get_logger().info(
            f"motion ended by {self.reason} after {self.out_duration:.2f} s; closest reading "
            f"{self.out_obstacle_distance:.2f} m at {self.out_obstacle_angle:.2f} rad"
        )

    @stopping
    def stopping(self) -> None:
        """Publish a zero velocity at once and end the command loop."""
        self._publish_zero()

    @aborting
    def aborting(self) -> None:
        """Publish a zero velocity so the base is never left moving after a fault."""
        self._publish_zero()

    @resetting
    def resetting(self) -> None:
        """Publish zero, drop the scan subscription and clear the outputs."""
        self._publish_zero()
        if self.scan_subscription is not None:
            self.node.destroy_subscription(self.scan_subscription)
            self.scan_subscription = None
        self.scan_msg = None
        self.out_angular_velocity = 0.0
        self.out_duration = 0.0
        self.out_linear_velocity_x = 0.0
        self.out_linear_velocity_y = 0.0
        self.out_obstacle_angle = 0.0
        self.out_obstacle_distance = 0.0
