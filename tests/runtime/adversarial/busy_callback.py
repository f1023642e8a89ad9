"""Adversarial skill: a subscription callback that never returns."""

import os
import socket
import sys
import threading
import time

import rclpy

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="urn:skillwright:test:adversary",
    module_iri="urn:skillwright:test:robot",
    capability_iri="urn:skillwright:test:capability",
    description="a subscription callback that never returns.",
)
class Adversary(ROS2Skill):
    def __init__(self) -> None:
        super().__init__("adversary")
        self.count = 0

    def _on_odom(self, msg) -> None:
        while True:
            self.count += 1  # finding: run.busy

    @execute
    def execute(self) -> None:
        from nav_msgs.msg import Odometry

        self.node.create_subscription(Odometry, "/odom", self._on_odom, 10)
        time.sleep(1.0)
