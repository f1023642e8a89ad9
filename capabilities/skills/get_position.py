"""get_position: report the MR-1's pose in the SLAM map frame from tf."""

import math

import rclpy
from rclpy.duration import Duration
from rclpy.time import Time
from tf2_ros import Buffer, TransformException, TransformListener

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/get_position",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/getPosition/getPosition",
    description="Report where the MR-1 base currently is in the SLAM map: x and y of base_link in the map frame and its heading.",
)
class GetPositionSkill(ROS2Skill):
    """Report x, y and heading of base_link in the map frame."""

    MAP_FRAME = "map"  # frames named by the MR-1's capability model
    BASE_FRAME = "base_link"

    def __init__(self) -> None:
        super().__init__("get_position")
        self.out_heading: float = 0.0
        self.out_position_x: float = 0.0
        self.out_position_y: float = 0.0
        self.stamp_sec = 0
        self.tf_buffer = None
        self.tf_listener = None

    @skill_output(
        is_required=True,
        name="outHeading",
        description="Heading of base_link in the map frame, in [0, 2*pi). Unit: rad.",
    )
    def get_out_heading(self) -> float:
        return self.out_heading

    @skill_output(
        is_required=True,
        name="outPositionX",
        description="x of base_link in the map frame. Unit: m.",
    )
    def get_out_position_x(self) -> float:
        return self.out_position_x

    @skill_output(
        is_required=True,
        name="outPositionY",
        description="y of base_link in the map frame. Unit: m.",
    )
    def get_out_position_y(self) -> float:
        return self.out_position_y

    @starting
    def starting(self) -> None:
        """Create a tf2 buffer and listener on the node so transforms can be looked up."""
        self.tf_buffer = Buffer()
        self.tf_listener = TransformListener(self.tf_buffer, self.node)

    @execute
    def execute(self) -> None:
        """Look up map -> base_link (at most 2 s), store x, y and the yaw wrapped into [0, 2*pi)."""
        try:
            transform = self.tf_buffer.lookup_transform(
                self.MAP_FRAME, self.BASE_FRAME, Time(), timeout=Duration(seconds=2.0)
            )
        except TransformException as error:
            self.node.get_logger().error(
                f"no {self.MAP_FRAME} -> {self.BASE_FRAME} transform: {error}"
            )
            raise RuntimeError("localisation does not provide the robot's pose") from error
        translation = transform.transform.translation
        q = transform.transform.rotation
        yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
        self.out_position_x = translation.x
        self.out_position_y = translation.y
        self.out_heading = yaw % (2.0 * math.pi)
        self.stamp_sec = transform.header.stamp.sec

    @completing
    def completing(self) -> None:
        """Log the reported position and heading together with the time stamp of the transform."""
        self.node.get_logger().info(
            f"position ({self.out_position_x:.3f}, {self.out_position_y:.3f}) m, "
            f"heading {self.out_heading:.3f} rad, transform time {self.stamp_sec} s"
        )

    @resetting
    def resetting(self) -> None:
        """Clear the stored outputs."""
        self.out_heading = 0.0
        self.out_position_x = 0.0
        self.out_position_y = 0.0
