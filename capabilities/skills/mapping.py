"""mapping: sweep a rectangle in front of the MR-1 with Nav2 while SLAM maps it, then save."""

import math
import os
import time

import rclpy
from rclpy.action import ActionClient
from rclpy.duration import Duration
from rclpy.qos import DurabilityPolicy, QoSProfile, qos_profile_sensor_data
from rclpy.time import Time
from tf2_ros import Buffer, TransformException, TransformListener

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from action_msgs.msg import GoalStatus
from geometry_msgs.msg import Twist
from nav2_msgs.action import NavigateToPose
from nav2_msgs.srv import SaveMap
from nav_msgs.msg import OccupancyGrid
from sensor_msgs.msg import LaserScan


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/mapping",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/mapping/mapping",
    description="Explore a rectangular area in front of the MR-1 with SLAM running, steering around obstacles seen by the lidar, and save the resulting occupancy-grid map to a file.",
)
class MappingSkill(ROS2Skill):
    """Drive a back-and-forth sweep of the area with Nav2, then save the SLAM map."""

    LIDAR_RANGE_MAX = 12.0  # resource requirement: lidarRange <= 12.0 m
    LINEAR_VELOCITY_MAX = 0.8  # resource requirement: linearVelocity <= 0.8 m/s
    LANE_SPACING = 2.0  # m, so consecutive lidar sweeps overlap
    MAP_FRAME = "map"
    BASE_FRAME = "base_link"

    def __init__(self) -> None:
        super().__init__("mapping")
        self.in_area_length: float = 0.0
        self.in_area_width: float = 0.0
        self.out_map: str = ""
        self.out_map_length: float = 0.0
        self.out_map_width: float = 0.0
        self.map_msg: OccupancyGrid | None = None
        self.scan_msg: LaserScan | None = None
        self.map_subscription = None
        self.scan_subscription = None
        self.navigate_client = None
        self.save_map_client = None
        self.cmd_vel_publisher = None
        self.tf_buffer = None
        self.tf_listener = None
        self.origin: tuple[float, float, float] | None = None
        self.plan: list[tuple[float, float]] = []
        self.skipped = 0
        self.goal_handle = None

    @skill_parameter(is_required=True, name="inAreaLength", description="Length along the heading. Unit: m.")
    def get_in_area_length(self) -> float:
        return self.in_area_length

    @skill_parameter(is_required=True, name="inAreaWidth", description="Width across the heading. Unit: m.")
    def get_in_area_width(self) -> float:
        return self.in_area_width

    @skill_output(is_required=True, name="outMap", description="Path of the map's YAML file.")
    def get_out_map(self) -> str:
        return self.out_map

    @skill_output(is_required=True, name="outMapLength", description="Map extent along the heading. Unit: m.")
    def get_out_map_length(self) -> float:
        return self.out_map_length

    @skill_output(is_required=True, name="outMapWidth", description="Map extent across the heading. Unit: m.")
    def get_out_map_width(self) -> float:
        return self.out_map_width

    def _on_map(self, msg: OccupancyGrid) -> None:
        self.map_msg = msg

    def _on_scan(self, msg: LaserScan) -> None:
        self.scan_msg = msg

    @staticmethod
    def _wait(future, timeout: float):
        deadline = time.monotonic() + timeout
        while not future.done() and time.monotonic() < deadline:
            time.sleep(0.05)
        return future.result() if future.done() else None

    def _pose(self) -> tuple[float, float, float]:
        transform = self.tf_buffer.lookup_transform(
            self.MAP_FRAME, self.BASE_FRAME, Time(), timeout=Duration(seconds=1.0)
        )
        t = transform.transform.translation
        q = transform.transform.rotation
        return t.x, t.y, math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))

    def _occupied(self, x: float, y: float) -> bool:
        """Whether the map marks the cell at (x, y) as an obstacle."""
        grid = self.map_msg
        if grid is None:
            return False
        info = grid.info
        column = int((x - info.origin.position.x) / info.resolution)
        row = int((y - info.origin.position.y) / info.resolution)
        if not (0 <= column < info.width and 0 <= row < info.height):
            return False
        return grid.data[row * info.width + column] >= 65

    def _drive_to(self, x: float, y: float) -> bool:
        goal = NavigateToPose.Goal()
        goal.pose.header.frame_id = self.MAP_FRAME
        goal.pose.header.stamp = self.node.get_clock().now().to_msg()
        goal.pose.pose.position.x = x
        goal.pose.pose.position.y = y
        goal.pose.pose.orientation.w = 1.0
        self.goal_handle = self._wait(self.navigate_client.send_goal_async(goal), 5.0)
        if self.goal_handle is None or not self.goal_handle.accepted:
            return False
        here = self._pose()
        budget = 20.0 + math.hypot(x - here[0], y - here[1]) / 0.2
        result = self._wait(self.goal_handle.get_result_async(), budget)
        self.goal_handle = None
        return result is not None and result.status == GoalStatus.STATUS_SUCCEEDED

    @starting
    def starting(self) -> None:
        """Check map, map -> base_link, scan and Nav2 within 5 s; remember the origin."""
        if self.in_area_length <= 0.0 or self.in_area_width < 0.0:
            raise ValueError("the area needs a positive length and a non-negative width")
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.map_subscription = self.node.create_subscription(OccupancyGrid, "/map", self._on_map, latched)
        self.scan_subscription = self.node.create_subscription(
            LaserScan, "/scan", self._on_scan, qos_profile_sensor_data
        )
        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)
        self.tf_buffer = Buffer()
        self.tf_listener = TransformListener(self.tf_buffer, self.node)
        self.navigate_client = ActionClient(self.node, NavigateToPose, "/navigate_to_pose")
        self.save_map_client = self.node.create_client(SaveMap, "/map_saver/save_map")
        deadline = time.monotonic() + 5.0
        while (self.map_msg is None or self.scan_msg is None) and time.monotonic() < deadline:
            time.sleep(0.05)
        missing = [name for name, msg in (("/map", self.map_msg), ("/scan", self.scan_msg)) if msg is None]
        if missing:
            raise RuntimeError(f"nothing on {', '.join(missing)} within 5 s: is SLAM running?")
        if not self.tf_buffer.can_transform(self.MAP_FRAME, self.BASE_FRAME, Time(), timeout=Duration(seconds=5.0)):
            raise RuntimeError(f"no {self.MAP_FRAME} -> {self.BASE_FRAME} transform within 5 s")
        if not self.navigate_client.wait_for_server(timeout_sec=5.0):
            raise RuntimeError("Nav2's /navigate_to_pose action server is not available")
        self.origin = self._pose()

    @execute
    def execute(self) -> None:
        """Sweep the lanes with Nav2 (a retry, then skip), save the map, store path and extent."""
        x0, y0, heading = self.origin
        lanes = max(2, int(math.ceil(self.in_area_width / self.LANE_SPACING)) + 1)
        self.plan = []
        for lane in range(lanes):
            across = self.in_area_width * lane / (lanes - 1)
            ends = [0.0, self.in_area_length] if lane % 2 == 0 else [self.in_area_length, 0.0]
            if lane == 0:
                ends = ends[1:]  # the sweep starts where the robot stands
            for distance in ends:
                self.plan.append(
                    (
                        x0 + distance * math.cos(heading) - across * math.sin(heading),
                        y0 + distance * math.sin(heading) + across * math.cos(heading),
                    )
                )
        self.skipped = 0
        for x, y in self.plan:
            if self._occupied(x, y) or not (self._drive_to(x, y) or self._drive_to(x, y)):
                self.skipped += 1
                self.node.get_logger().warning(f"sweep goal ({x:.2f}, {y:.2f}) skipped")
        stamp = time.strftime("%Y%m%d-%H%M%S", time.gmtime(time.time()))
        map_url = os.path.join(os.getcwd(), f"map-{stamp}")
        request = SaveMap.Request()
        request.map_topic = "/map"
        request.map_url = map_url
        request.image_format = "pgm"
        request.map_mode = "trinary"
        request.free_thresh = 0.25
        request.occupied_thresh = 0.65
        if not self.save_map_client.wait_for_service(timeout_sec=5.0):
            raise RuntimeError("the map saver /map_saver/save_map is not available")
        response = self._wait(self.save_map_client.call_async(request), 10.0)
        if response is None or not response.result:
            raise RuntimeError("the map saver did not save the map")
        self.out_map = map_url + ".yaml"
        along, across = self._extent(heading)
        self.out_map_length = along
        self.out_map_width = across

    def _extent(self, heading: float) -> tuple[float, float]:
        """Extent of the known cells (not -1) of the map along and across ``heading``: the
        grid's own width and height only where the heading is along the grid."""
        info = self.map_msg.info
        resolution = info.resolution
        cos_h, sin_h = math.cos(heading), math.sin(heading)
        low_along = low_across = math.inf
        high_along = high_across = -math.inf
        for index, value in enumerate(self.map_msg.data):
            if value < 0:
                continue
            x = info.origin.position.x + (index % info.width + 0.5) * resolution
            y = info.origin.position.y + (index // info.width + 0.5) * resolution
            along = x * cos_h + y * sin_h
            across = -x * sin_h + y * cos_h
            low_along, high_along = min(low_along, along), max(high_along, along)
            low_across, high_across = min(low_across, across), max(high_across, across)
        if low_along > high_along:
            return 0.0, 0.0
        return high_along - low_along + resolution, high_across - low_across + resolution

    @completing
    def completing(self) -> None:
        """Log the map path, its extent and how many goals were skipped."""
        self.node.get_logger().info(
            f"map saved to {self.out_map}: {self.out_map_length:.1f} m x {self.out_map_width:.1f} m, "
            f"{self.skipped} of {len(self.plan)} sweep goals skipped"
        )

    @stopping
    def stopping(self) -> None:
        """Cancel the active navigation goal and publish a zero velocity."""
        if self.goal_handle is not None:
            self._wait(self.goal_handle.cancel_goal_async(), 2.0)
        if self.cmd_vel_publisher is not None:
            self.cmd_vel_publisher.publish(Twist())

    @resetting
    def resetting(self) -> None:
        """Cancel any remaining goal, forget the sweep plan and clear the outputs."""
        if self.goal_handle is not None:
            self._wait(self.goal_handle.cancel_goal_async(), 2.0)
            self.goal_handle = None
        self.plan = []
        self.skipped = 0
        self.out_map = ""
        self.out_map_length = 0.0
        self.out_map_width = 0.0
