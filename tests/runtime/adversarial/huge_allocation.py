"""Adversarial skill: a 50 GB allocation."""

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
    description="a 50 GB allocation.",
)
class Adversary(ROS2Skill):
    def __init__(self) -> None:
        super().__init__("adversary")
        self.count = 0

    @execute
    def execute(self) -> None:
        self.hoard = bytearray(50 * 1024**3)  # finding: run.memory
