"""get_distance_to_nearest_object for the paper's robot: the nearest return of its two corner
scanners, which each see one side. ``SCANNERS`` is what a test narrows to one."""

import math
import time

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from sensor_msgs.msg import LaserScan

SCANNERS = ("/scan", "/scan2")


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/tests/skills/nearest_of_two_scanners",
    module_iri="http://www.hsu-hh.de/aut/ontologies/mobile-robots/neobotix/mmo700/neobotixMMO700",
    capability_iri="http://www.hsu-hh.de/aut/ontologies/mobile-robots/neobotix/mmo700/capabilities/getDistanceToNearestObject/getDistanceToNearestObject",
    description="The distance and bearing of the nearest object either corner scanner sees.",
)
class NearestOfTwoScannersSkill(ROS2Skill):
    """Keep the latest scan of each scanner; report the nearest valid return of all."""

    def __init__(self) -> None:
        super().__init__("nearest_of_two_scanners")
        self.out_degree: float = 0.0
        self.out_distance: float = 0.0
        self.subscriptions: list = []
        self.latest: dict[str, LaserScan] = {}

    @skill_output(is_required=True, name="outDegree", description="Bearing. Unit: degree.")
    def get_out_degree(self) -> float:
        return self.out_degree

    @skill_output(is_required=True, name="outDistance", description="Range. Unit: m.")
    def get_out_distance(self) -> float:
        return self.out_distance

    def _keeper(self, topic: str):
        def keep(msg: LaserScan) -> None:
            self.latest[topic] = msg

        return keep

    @starting
    def starting(self) -> None:
        """Subscribe to every scanner."""
        for topic in SCANNERS:
            self.subscriptions.append(
                self.node.create_subscription(LaserScan, topic, self._keeper(topic), 10)
            )

    @execute
    def execute(self) -> None:
        """Wait at most 2 s for a scan of each scanner; keep the nearest valid return."""
        deadline = time.monotonic() + 2.0
        while len(self.latest) < len(SCANNERS) and time.monotonic() < deadline:
            time.sleep(0.02)
        if len(self.latest) < len(SCANNERS):
            raise RuntimeError(f"no scan on {', '.join(sorted(set(SCANNERS) - set(self.latest)))}")
        best = (math.inf, 0.0)
        for scan in self.latest.values():
            for index, distance in enumerate(scan.ranges):
                if scan.range_min <= distance <= scan.range_max and distance < best[0]:
                    best = (distance, scan.angle_min + index * scan.angle_increment)
        distance, bearing = best
        self.out_distance = distance
        self.out_degree = math.degrees(math.atan2(math.sin(bearing), math.cos(bearing)))

    @completing
    def completing(self) -> None:
        """Log the result."""
        self.node.get_logger().info(f"nearest {self.out_distance:.3f} m at {self.out_degree:.1f}")

    @resetting
    def resetting(self) -> None:
        """Drop the subscriptions."""
        for subscription in self.subscriptions:
            self.node.destroy_subscription(subscription)
        self.subscriptions = []
        self.latest = {}
