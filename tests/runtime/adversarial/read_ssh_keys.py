"""Adversarial skill: reading the user's SSH keys."""

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
    description="reading the user's SSH keys.",
)
class Adversary(ROS2Skill):
    def __init__(self) -> None:
        super().__init__("adversary")
        self.count = 0

    @execute
    def execute(self) -> None:
        with open("{home}/.ssh/id_rsa") as stream:  # finding: run.sandbox
            self.node.get_logger().info(stream.read())
