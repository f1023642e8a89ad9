"""move_forward: a hand-written, complete skill used as the checker's known-good case."""

import math
import time

import rclpy

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/move_forward",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/moveForward/moveForward",
    description="Drive forward over a distance at a speed, then stop.",
)
class MoveForwardSkill(ROS2Skill):
    LINEAR_VELOCITY_MAX = 0.8  # resource requirement: linearVelocity <= 0.8 m/s

    def __init__(self) -> None:
        super().__init__("move_forward")
        self.in_distance: float = 0.0
        self.in_linear_velocity: float = 0.0
        self.out_distance: float = 0.0
        self.out_linear_velocity: float = 0.0
        self.cmd_vel_publisher = None
        self.odom_subscription = None
        self.odom_msg: Odometry | None = None
        self.start_x = 0.0
        self.start_y = 0.0

    @skill_parameter(is_required=True, name="inDistance", description="Distance [m].")
    def get_in_distance(self) -> float:
        return self.in_distance

    @skill_parameter(is_required=True, name="inLinearVelocity", description="Speed [m/s].")
    def get_in_linear_velocity(self) -> float:
        return self.in_linear_velocity

    @skill_output(is_required=True, name="outDistance", description="Travelled [m].")
    def get_out_distance(self) -> float:
        return self.out_distance

    @skill_output(is_required=True, name="outLinearVelocity", description="Final speed [m/s].")
    def get_out_linear_velocity(self) -> float:
        return self.out_linear_velocity

    def _on_odom(self, msg: Odometry) -> None:
        self.odom_msg = msg

    def _travelled(self) -> float:
        position = self.odom_msg.pose.pose.position
        return math.hypot(position.x - self.start_x, position.y - self.start_y)

    @starting
    def starting(self) -> None:
        """Subscribe to odometry and wait for the first message."""
        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)
        self.odom_subscription = self.node.create_subscription(Odometry, "/odom", self._on_odom, 10)
        deadline = time.time() + 2.0
        while self.odom_msg is None and time.time() < deadline:
            time.sleep(0.05)

    @execute
    def execute(self) -> None:
        """Drive until the distance is covered, then stop."""
        self.start_x = self.odom_msg.pose.pose.position.x
        self.start_y = self.odom_msg.pose.pose.position.y
        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)
        command = Twist()
        command.linear.x = speed
        while self._travelled() < self.in_distance:
            self.cmd_vel_publisher.publish(command)
            time.sleep(0.05)
        self.cmd_vel_publisher.publish(Twist())
        self.out_distance = self._travelled()
        self.out_linear_velocity = self.odom_msg.twist.twist.linear.x

    @completing
    def completing(self) -> None:
        """Log requested and travelled distance."""
        self.node.get_logger().info(f"{self.in_distance} m asked, {self.out_distance} m done")

    @stopping
    def stopping(self) -> None:
        """Halt the base."""
        self.cmd_vel_publisher.publish(Twist())

    @resetting
    def resetting(self) -> None:
        """Release the handles."""
        if self.cmd_vel_publisher is not None:
            self.cmd_vel_publisher.publish(Twist())
            self.node.destroy_publisher(self.cmd_vel_publisher)
            self.cmd_vel_publisher = None
        if self.odom_subscription is not None:
            self.node.destroy_subscription(self.odom_subscription)
            self.odom_subscription = None
