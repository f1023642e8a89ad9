"""A skill that exercises the stand-ins and logs what it sees (test_standins.py reads it)."""

import copy
import datetime
import math
import threading
import time

import rclpy
from rclpy.duration import Duration
from rclpy.qos import qos_profile_sensor_data
from rclpy.time import Time
from rclpy.wait_for_message import wait_for_message
from tf2_ros import Buffer, LookupException, TransformListener

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from action_msgs.msg import GoalStatus
from controller_manager_msgs.srv import ListControllers
from geometry_msgs.msg import Twist, Vector3
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="urn:skillwright:test:probe",
    module_iri="urn:skillwright:test:robot",
    capability_iri="urn:skillwright:test:capability",
    description="Probe the simulated rclpy.",
)
class Probe(ROS2Skill):
    def __init__(self) -> None:
        super().__init__("probe")

    @execute
    def execute(self) -> None:
        log = self.node.get_logger().info
        start = time.monotonic()
        time.sleep(0.5)
        log(f"sleep {time.monotonic() - start:.3f}")

        ticks = []
        timer = self.node.create_timer(0.1, lambda: ticks.append(time.monotonic()))
        time.sleep(0.55)
        timer.cancel()
        log(f"timer {len(ticks)}")

        rate = self.node.create_rate(10)
        start = time.monotonic()
        for _ in range(5):
            rate.sleep()
        log(f"rate {time.monotonic() - start:.2f}")

        scans = []
        self.node.create_subscription(LaserScan, "/scan", scans.append, qos_profile_sensor_data)
        rclpy.spin_once(self.node, timeout_sec=1.0)
        log(f"spin_once {len(scans)} {len(scans[0].ranges)}")

        ok, odom = wait_for_message(Odometry, self.node, "/odom", time_to_wait=1.0)
        log(f"wait_for_message {ok} {odom.header.frame_id}")

        event = threading.Event()
        start = time.monotonic()
        log(f"event {event.wait(0.3)} {time.monotonic() - start:.2f}")
        threading.Timer(0.2, event.set).start()
        log(f"event set {event.wait(1.0)}")

        stamp = self.node.get_clock().now().to_msg()
        log(f"clock {stamp.sec == int(time.time())} {datetime.datetime.now().year}")
        log(f"duration {(Duration(seconds=1.5) + Duration(nanoseconds=500_000_000)).nanoseconds}")

        client = self.node.create_client(ListControllers, "/controller_manager/list_controllers")
        log(f"service ready {client.wait_for_service(timeout_sec=1.0)}")
        future = client.call_async(ListControllers.Request())
        log(f"future done at once {future.done()} {future.result()}")
        rclpy.spin_until_future_complete(self.node, future, timeout_sec=2.0)
        log(f"response {type(future.result()).__name__}")

        twist = Twist(linear=Vector3(x=1.0))
        log(f"twist {twist.linear.x} {twist.angular.z}")
        try:
            twist.linear.x = 1
        except AssertionError as error:
            log(f"assert {error}")
        try:
            Twist(speed=1.0)
        except AssertionError as error:
            log(f"constructor {error}")
        try:
            log(f"never {Odometry().position}")
        except AttributeError as error:
            log(f"field {error}")
        log(f"copy {copy.deepcopy(twist) == twist}")
        log(f"fields {Twist.get_fields_and_field_types()}")
        log(f"constant {GoalStatus.STATUS_SUCCEEDED}")
        log(
            f"covariance {len(Odometry().pose.covariance)} {math.isclose(sum(Odometry().pose.covariance), 0.0)}"
        )
        try:
            self.node.get_logger().info("a %s b", "c")
        except TypeError as error:
            log(f"logger {type(error).__name__}")
        publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)
        try:
            publisher.publish(Vector3())
        except TypeError as error:
            log(f"publish {error}")
        publishers = self.node.get_publishers_info_by_topic("/odom")
        log(
            f"odom publishers {[(p.node_name, p.topic_type, p.qos_profile.reliability.name) for p in publishers]}"
        )
        mine = self.node.get_publishers_info_by_topic("cmd_vel")
        log(
            f"cmd_vel publishers {[(p.node_name, p.endpoint_type.name, p.qos_profile.depth) for p in mine]}"
        )
        readers = self.node.get_subscriptions_info_by_topic("/scan")
        log(f"scan subscriptions {sorted(p.node_name for p in readers)}")
        self.node.declare_parameters("limits", [("speed", 0.5), ("turn", 1.0)])
        log(f"parameters {sorted(self.node.get_parameters_by_prefix('limits'))}")
        self.node.undeclare_parameter("limits.turn")
        log(
            f"parameters {sorted(self.node.get_parameters_by_prefix('limits'))} {self.node.get_node_names_and_namespaces()}"
        )
        buffer = Buffer()
        listener = TransformListener(buffer, self.node)
        time.sleep(0.5)
        try:
            buffer.lookup_transform("earth", "base_link", Time())
        except LookupException as error:
            log(f"tf {str(error).split('(frames on /tf so far: ')[1].split(', ')[:2]}")
        del listener
