"""move_forward for the behaviour tests: brakes in proportion to the distance left."""

import math
import time

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
    description="Drive straight ahead over a distance and stop.",
)
class MoveForward(ROS2Skill):
    SPEED_LIMIT = 0.8  # m/s, the MR-1's linear velocity requirement
    GAIN = 1.2  # 1/s: commanded speed per metre left, so braking starts in time

    def __init__(self) -> None:
        super().__init__("move_forward")
        self.in_distance: float = 0.0
        self.in_linear_velocity: float = 0.0
        self.out_distance: float = 0.0
        self.out_linear_velocity: float = 0.0
        self.publisher = None
        self.odom = None
        self.origin = (0.0, 0.0)
        self.active = False

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

    def _keep(self, msg: Odometry) -> None:
        self.odom = msg

    def _travelled(self) -> float:
        p = self.odom.pose.pose.position
        return math.hypot(p.x - self.origin[0], p.y - self.origin[1])

    def _halt(self) -> None:
        self.active = False
        self.publisher.publish(Twist())

    @starting
    def starting(self) -> None:
        if self.in_distance < 0.0:
            raise ValueError("a negative distance is not forward travel")
        self.publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)
        self.node.create_subscription(Odometry, "/odom", self._keep, 10)
        deadline = time.monotonic() + 2.0
        while self.odom is None and time.monotonic() < deadline:
            time.sleep(0.05)
        if self.odom is None:
            raise RuntimeError("no odometry")

    @execute
    def execute(self) -> None:
        p = self.odom.pose.pose.position
        self.origin = (p.x, p.y)
        top = min(abs(self.in_linear_velocity), self.SPEED_LIMIT)
        command = Twist()
        self.active = True
        while self.active and self._travelled() < self.in_distance:
            left = self.in_distance - self._travelled()
            command.linear.x = max(0.04, min(top, self.GAIN * left))
            self.publisher.publish(command)
            time.sleep(0.05)
        self._halt()
        deadline = time.monotonic() + 3.0
        while abs(self.odom.twist.twist.linear.x) > 0.01 and time.monotonic() < deadline:
            time.sleep(0.02)
        self.out_distance = self._travelled()
        self.out_linear_velocity = self.odom.twist.twist.linear.x

    @completing
    def completing(self) -> None:
        self.node.get_logger().info(f"travelled {self.out_distance:.3f} m")

    @stopping
    def stopping(self) -> None:
        self._halt()

    @resetting
    def resetting(self) -> None:
        self._halt()
