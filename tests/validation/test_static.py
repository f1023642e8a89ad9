"""Static checks: a good skill passes; each failure mode is found, located and explained."""

from __future__ import annotations

import functools
from pathlib import Path

import pytest

from skillwright.capability import Capability, load_capability
from skillwright.generation.model import InterfaceRef
from skillwright.generation.repair import _unset_output
from skillwright.generation.skeleton import build_skeleton
from skillwright.interfaces.load import load_inventory
from skillwright.spec import SkillSpec, load_spec
from skillwright.validation.catalog import catalog_from_inventory
from skillwright.validation.model import Catalog, CatalogEntry, CheckReport, FieldTree
from skillwright.validation.static import check_skill
from tests.conftest import SHIPPED_CAPABILITIES

GOOD = (Path(__file__).parent / "skills" / "move_forward_good.py").read_text(encoding="utf-8")

VECTOR: FieldTree = {"x": None, "y": None, "z": None}
TWIST: FieldTree = {"linear": VECTOR, "angular": VECTOR}
HEADER: FieldTree = {"stamp": {"sec": None, "nanosec": None}, "frame_id": None}
ODOMETRY: FieldTree = {
    "header": HEADER,
    "child_frame_id": None,
    "pose": {
        "pose": {"position": VECTOR, "orientation": {**VECTOR, "w": None}},
        "covariance": None,
    },
    "twist": {"twist": TWIST, "covariance": None},
}
CATALOG = Catalog(
    entries={
        "/cmd_vel": CatalogEntry(
            name="/cmd_vel", kind="topic", type_name="geometry_msgs/msg/Twist"
        ),
        "/odom": CatalogEntry(name="/odom", kind="topic", type_name="nav_msgs/msg/Odometry"),
        "/scan": CatalogEntry(name="/scan", kind="topic", type_name="sensor_msgs/msg/LaserScan"),
        "/navigate_to_pose": CatalogEntry(
            name="/navigate_to_pose", kind="action", type_name="nav2_msgs/action/NavigateToPose"
        ),
    },
    fields={"geometry_msgs/msg/Twist": TWIST, "nav_msgs/msg/Odometry": ODOMETRY},
)


def run(source: str, inputs: tuple[Capability, SkillSpec], **kwargs: object) -> CheckReport:
    capability, spec = inputs
    return check_skill(
        source,
        capability=capability,
        spec=spec,
        catalog=CATALOG,
        retrieved=kwargs.pop("retrieved", ["/cmd_vel", "/odom"]),  # type: ignore[arg-type]
        **kwargs,  # type: ignore[arg-type]
    )


@functools.cache
def mr1_catalog() -> Catalog:
    """The catalog of the shipped MR-1 recording (every message definition it holds)."""
    return catalog_from_inventory(load_inventory(SHIPPED_CAPABILITIES / "recordings" / "mr1"))


def check_on_mr1(source: str, inputs: tuple[Capability, SkillSpec]) -> CheckReport:
    """The checks of ``source`` against the MR-1's whole catalog, nothing retrieved."""
    capability, spec = inputs
    return check_skill(source, capability=capability, spec=spec, catalog=mr1_catalog())


def messages(report: CheckReport, check: str | None = None) -> list[str]:
    return [f.message for f in report.findings if check is None or f.check == check]


def test_the_hand_written_skill_passes_without_findings(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    report = run(GOOD, move_forward)
    assert report.findings == []
    assert report.passed
    assert report.used_interfaces == ["/cmd_vel", "/odom"]


def test_syntax_error_is_located(move_forward: tuple[Capability, SkillSpec]) -> None:
    report = run(GOOD.replace("def _travelled(self)", "def _travelled(self"), move_forward)
    (finding,) = report.findings
    assert finding.check == "syntax"
    assert finding.line > 0
    assert not report.passed


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        (
            'capability_iri="http://skillwright.dev/robots/mr1/capabilities/moveForward/moveForward"',
            'capability_iri="http://example.org/other"',
            "@skill capability_iri is 'http://example.org/other', expected",
        ),
        (
            "SkillInterface.REST",
            "SkillInterface.MQTT",
            "skill_interface should be SkillInterface.REST",
        ),
        ("(ROS2Skill)", "(object)", "must derive from ROS2Skill"),
        (
            'name="inDistance", description="Distance [m]."',
            'name="charge", description="What is left of the battery [%]."',
            "no @skill_parameter for the capability's input inDistance",
        ),
        (
            'name="outLinearVelocity", description="Final speed [m/s]."',
            'name="charge", description="Battery left [%]."',
            "no @skill_output for the capability's output",
        ),
        (
            'name="inDistance", description="Distance [m]."',
            'name="charge", description="What is left of the battery [%]."',
            "@skill_parameter 'charge' matches no input of the capability",
        ),
        ("    @stopping\n", "", "no method decorated @stopping"),
        (
            "    @completing\n",
            "    @completing\n    @holding\n",
            "@holding is not in the specification",
        ),
    ],
)
def test_annotation_problems_are_found(
    move_forward: tuple[Capability, SkillSpec], old: str, new: str, expected: str
) -> None:
    assert old in GOOD
    report = run(GOOD.replace(old, new, 1), move_forward)
    assert any(expected in m for m in messages(report, "annotations")), messages(report)


def test_missing_skill_decorator(move_forward: tuple[Capability, SkillSpec]) -> None:
    report = run(GOOD.replace("@skill(", "@other(", 1), move_forward)
    assert "no class decorated with @skill(...)" in messages(report)


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        ('"/cmd_vel"', '"/base/cmd_vel"', "topic /base/cmd_vel does not exist on this robot"),
        (
            "from geometry_msgs.msg import Twist",
            "from geometry_msgs.msg import TwistStamped as Twist",
            "/cmd_vel carries geometry_msgs/msg/Twist, but the code uses geometry_msgs/msg/TwistStamped",
        ),
        (
            'self.node.create_publisher(Twist, "/cmd_vel", 10)',
            'self.node.create_client(Twist, "/cmd_vel")',
            "/cmd_vel is a topic on this robot, but the code uses it as a service",
        ),
        (
            "command.linear.x = speed",
            "command.linear.forward = speed",
            "has no field 'forward' in linear",
        ),
        (
            "position = self.odom_msg.pose.pose.position",
            "position = self.odom_msg.pose.position",
            "nav_msgs/msg/Odometry has no field 'position' in pose",
        ),
        (
            "self.out_linear_velocity = self.odom_msg.twist.twist.linear.x",
            "self.out_linear_velocity = self.odom_msg.velocity",
            "has no field 'velocity'",
        ),
        (
            "self.cmd_vel_publisher.publish(Twist())\n        self.out_distance",
            "self.cmd_vel_publisher.publish(Twist(linear_x=0.0))\n        self.out_distance",
            "geometry_msgs/msg/Twist has no field 'linear_x'",
        ),
    ],
)
def test_grounding_problems_are_found(
    move_forward: tuple[Capability, SkillSpec], old: str, new: str, expected: str
) -> None:
    assert old in GOOD
    report = run(GOOD.replace(old, new, 1), move_forward)
    found = messages(report, "grounding")
    assert any(expected in m for m in found), found
    assert not report.passed


def test_callback_parameter_fields_are_checked(move_forward: tuple[Capability, SkillSpec]) -> None:
    source = GOOD.replace(
        "        self.odom_msg = msg\n", "        self.odom_msg = msg\n        print(msg.pos)\n", 1
    )
    report = run(source, move_forward)
    assert any("has no field 'pos'" in m for m in messages(report, "grounding"))


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        (
            '        self.node.get_logger().info(f"{self.in_distance} m asked, {self.out_distance} m done")\n',
            "        pass\n",
            "@completing has no behaviour",
        ),
        (
            '        self.node.get_logger().info(f"{self.in_distance} m asked, {self.out_distance} m done")\n',
            "        ...\n",
            "@completing has no behaviour",
        ),
        (
            "        self.cmd_vel_publisher.publish(Twist())\n\n    @resetting",
            "        raise NotImplementedError\n\n    @resetting",
            "raises NotImplementedError",
        ),
        (
            "speed = min(",
            "speed = min(  # TODO check sign\n            ",
            "left-over marker in a comment: # TODO",
        ),
    ],
)
def test_placeholders_are_found(
    move_forward: tuple[Capability, SkillSpec], old: str, new: str, expected: str
) -> None:
    assert old in GOOD
    report = run(GOOD.replace(old, new, 1), move_forward)
    assert any(expected in m for m in messages(report, "placeholders")), messages(report)


@pytest.mark.parametrize(
    ("old", "new"),
    [
        (
            "while self._travelled() < self.in_distance:",
            "while self._travelled() < 2.5:\n            distance = 2.5",
        ),
        (
            "speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)",
            "self.linear_velocity = 0.5\n        speed = self.linear_velocity",
        ),
        (
            "while self._travelled() < self.in_distance:",
            "while self._travelled() < self.in_distance:\n            if self.distance_left > 0.3:\n                pass",
        ),
    ],
)
def test_constants_standing_in_for_inputs_are_found(
    move_forward: tuple[Capability, SkillSpec], old: str, new: str
) -> None:
    assert old in GOOD
    report = run(GOOD.replace(old, new, 1), move_forward)
    assert any("stands in for the capability input" in m for m in messages(report, "constants")), (
        messages(report)
    )


def test_resource_limits_and_input_storage_are_not_mistaken_for_inputs(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    assert messages(run(GOOD, move_forward), "constants") == []


def test_collision_avoidance_minimum_distance_hard_coded_is_caught() -> None:
    capability = load_capability(SHIPPED_CAPABILITIES / "collision-avoidance.ttl").capability
    spec = load_spec(SHIPPED_CAPABILITIES / "collision-avoidance.spec.yaml")
    source = (
        "class C:\n"
        "    def execute(self):\n"
        "        min_obstacle_distance = 0.5\n"
        "        if self.nearest < min_obstacle_distance:\n"
        "            self.stop()\n"
    )
    report = check_skill(source, capability=capability, spec=spec)
    constants = [f for f in report.findings if f.check == "constants"]
    assert len(constants) == 1
    assert "inMinObstacleDistance" in constants[0].message
    assert constants[0].line == 3


def test_retrieved_but_unused_and_used_but_not_retrieved(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    report = run(GOOD, move_forward, retrieved=["/cmd_vel", "/scan"])
    found = messages(report, "interfaces")
    assert "/scan was retrieved but the code never uses it" in found
    assert any(m.startswith("/odom is used but was not retrieved") for m in found)
    assert report.passed  # warnings only


def test_handles_made_by_keyword_are_checked_as_rclpy_takes_them() -> None:
    # rclpy's ActionClient(node, action_type, action_name) and create_publisher(msg_type,
    # topic, qos_profile): the same handles by keyword are the same interfaces
    path = SHIPPED_CAPABILITIES / "skills" / "navigate_to_point.py"
    source = path.read_text(encoding="utf-8")
    inputs = (
        load_capability(SHIPPED_CAPABILITIES / "navigate-to-point.ttl").capability,
        load_spec(SHIPPED_CAPABILITIES / "navigate-to-point.spec.yaml"),
    )
    keywords = source.replace(
        'ActionClient(self.node, NavigateToPose, "/navigate_to_pose")',
        'ActionClient(self.node, action_type=NavigateToPose, action_name="navigate_to_pose")',
    ).replace(
        'create_publisher(Twist, "/cmd_vel", 10)',
        'create_publisher(msg_type=Twist, topic="/cmd_vel", qos_profile=10)',
    )
    assert keywords.count("action_type=") == keywords.count("msg_type=") == 1
    found, expected = check_on_mr1(keywords, inputs), check_on_mr1(source, inputs)
    assert [f.code for f in found.findings] == [f.code for f in expected.findings]
    assert found.used_interfaces == expected.used_interfaces


def test_skeleton_is_well_formed_but_fails_for_its_placeholders(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    capability, spec = move_forward
    interfaces = [
        InterfaceRef(
            name="/cmd_vel", kind="topic", type_name="geometry_msgs/msg/Twist", role="publish"
        ),
        InterfaceRef(
            name="/odom", kind="topic", type_name="nav_msgs/msg/Odometry", role="subscribe"
        ),
    ]
    skeleton = build_skeleton(capability, spec, interfaces)
    report = run(skeleton.code, move_forward)
    assert {f.check for f in report.findings} == {"placeholders"}
    assert len(report.findings) == len(spec.states)


def test_numbers_the_specification_gives_and_zero_are_not_stand_ins_for_inputs(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # The spec says: slow down to 0.1 m/s for the last 0.1 m.
    source = GOOD.replace(
        "        while self._travelled() < self.in_distance:",
        "        travelled_distance = 0.0\n"
        "        while self._travelled() < self.in_distance:\n"
        "            if self.in_distance - self._travelled() < 0.1:\n"
        "                command.linear.x = 0.1",
    )
    assert not messages(run(source, move_forward), "constants")
    hard_coded = source.replace("travelled_distance = 0.0", "travelled_distance = 2.5")
    assert messages(run(hard_coded, move_forward), "constants")


def test_a_message_field_given_a_number_is_an_error(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "        command = Twist()\n        command.linear.x = speed",
        "        command = Twist(linear=speed + 0.0)",
    )
    assert "command = Twist(linear=" in source
    report = run(source.replace("linear=speed + 0.0", "linear=0.5"), move_forward)
    (found,) = [f for f in report.findings if "is a message" in f.message]
    assert "geometry_msgs/msg/Twist's field 'linear' is a message (fields x, y, z)" in (
        found.message
    )
    assert found.replacement == "command = Twist(linear=Vector3(x=0.5))"
    report = run(
        source.replace("linear=speed + 0.0", "linear=self.in_linear_velocity"), move_forward
    )
    (found,) = [f for f in report.findings if "is a message" in f.message]
    assert found.replacement == "command = Twist(linear=Vector3(x=self.in_linear_velocity))"


@pytest.mark.parametrize(
    ("helper", "call"),
    [
        (  # the MR-1 move-forward of the evaluation at d678df9: a lambda kept on the skill
            "        self._clipped = lambda v: min(abs(v), self.LINEAR_VELOCITY_MAX)\n",
            "self._clipped(self.in_linear_velocity)",
        ),
        ("", "self._clamp(self.in_linear_velocity)"),  # a method annotated -> float
        ("", "self._halved(self.in_linear_velocity)"),  # a method that returns arithmetic
    ],
)
def test_a_message_field_given_what_a_numeric_helper_returns_is_an_error(
    move_forward: tuple[Capability, SkillSpec], helper: str, call: str
) -> None:
    methods = (
        "    def _clamp(self, v) -> float:\n        return v\n\n"
        "    def _halved(self, v):\n        return v / 2.0\n\n"
        "    @execute\n"
    )
    source = GOOD.replace("    @execute\n", methods, 1).replace(
        "        command = Twist()\n        command.linear.x = speed",
        helper + f"        pace = {call}\n        command = Twist(linear=pace)",
    )
    assert "command = Twist(linear=pace)" in source
    (found,) = [f for f in run(source, move_forward).findings if "is a message" in f.message]
    assert found.replacement == "command = Twist(linear=Vector3(x=pace))"


@pytest.mark.parametrize(
    ("made", "fix"),
    [
        ("Twist(forward, turn)", "command = Twist(linear=forward, angular=turn)"),
        ("Twist(forward, angular=turn)", "command = Twist(linear=forward, angular=turn)"),
        ("Twist(forward, turn, spare)", None),  # more arguments than fields
    ],
)
def test_a_message_made_with_positional_arguments_names_its_fields(
    move_forward: tuple[Capability, SkillSpec], made: str, fix: str | None
) -> None:
    # ev70 cap2skill mapping: Vector3(0.0, 0.0, bearing) raised TypeError in its run
    source = GOOD.replace(
        "        command = Twist()\n        command.linear.x = speed",
        f"        forward = turn = spare = Vector3()\n        command = {made}",
    )
    report = run(source, move_forward)
    (found,) = [f for f in report.findings if "positional arguments" in f.message]
    assert found.check == "grounding"
    assert found.message.endswith(
        "a ROS 2 message takes its fields as keywords only (it raises TypeError): name them, "
        + ("Twist(linear=..., angular=...)" if "angular" not in made else "Twist(linear=...)")
    )
    assert found.replacement == fix


@pytest.mark.parametrize(
    ("given", "fix"),
    [
        ("self.odom_msg", "self.odom_msg.pose.pose.orientation"),
        ("odom", "odom.pose.pose.orientation"),
        ("self.odom_msg.pose.pose.orientation", None),  # already the quaternion
    ],
)
def test_the_heading_helper_handed_a_whole_message_gets_its_orientation(
    move_forward: tuple[Capability, SkillSpec], given: str, fix: str | None
) -> None:
    helper = "    def _yaw(self, q) -> float:\n        return 0.0\n\n    @execute\n"
    source = GOOD.replace("    @execute\n", helper, 1).replace(
        "self.start_x = self.odom_msg.pose.pose.position.x",
        f"odom = self.odom_msg\n        self.start_x = self._yaw({given})",
    )
    found = [f for f in run(source, move_forward).findings if "_yaw" in f.message]
    if fix is None:
        assert found == []
        return
    (finding,) = found
    assert finding.message == (
        f"self._yaw() takes an orientation quaternion, and {given} is a whole "
        f"nav_msgs/msg/Odometry: its orientation is {fix}"
    )
    assert finding.replacement == f"self.start_x = self._yaw({fix})"


def test_the_heading_helper_handed_a_message_by_keyword_gets_its_orientation(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    helper = "    def _yaw(self, q) -> float:\n        return 0.0\n\n    @execute\n"
    source = GOOD.replace("    @execute\n", helper, 1).replace(
        "self.start_x = self.odom_msg.pose.pose.position.x",
        "self.start_x = self._yaw(q=self.odom_msg)",
    )
    (finding,) = [f for f in run(source, move_forward).findings if "_yaw" in f.message]
    assert finding.replacement == "self.start_x = self._yaw(q=self.odom_msg.pose.pose.orientation)"


def test_a_field_one_level_further_down_is_named_and_put_in_the_statement(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "self.start_x = self.odom_msg.pose.pose.position.x",
        "self.start_x = self.odom_msg.pose.position.x + self.odom_msg.pose.position.y",
    )
    report = run(source, move_forward)
    found = [f for f in report.findings if f.check == "grounding"]
    assert [f.message for f in found] == [
        "nav_msgs/msg/Odometry has no field 'position' in pose (fields: covariance, pose); "
        "it is self.odom_msg.pose.pose.position." + axis
        for axis in "xy"
    ]
    assert {f.replacement for f in found} == {
        "self.start_x = self.odom_msg.pose.pose.position.x + self.odom_msg.pose.pose.position.y"
    }


@pytest.mark.parametrize(
    ("held", "read", "fix"),
    [
        (  # ev70 MR-1 set-velocity: the run found it, the checks did not
            "twist = self.odom_msg.twist",
            "twist.linear.x",
            "twist.twist.linear.x",
        ),
        ("stamp = self.odom_msg.header.stamp", "stamp.secs", "stamp.sec"),
        ("self.moved = self.odom_msg.pose", "self.moved.position.x", "self.moved.pose.position.x"),
    ],
)
def test_a_field_of_a_part_of_a_message_held_in_a_name_is_checked(
    move_forward: tuple[Capability, SkillSpec], held: str, read: str, fix: str
) -> None:
    source = GOOD.replace(
        "self.start_x = self.odom_msg.pose.pose.position.x",
        f"{held}\n        self.start_x = {read}",
    )
    found = [f for f in run(source, move_forward).findings if f.check == "grounding"]
    assert [f.replacement for f in found] == [f"self.start_x = {fix}"]
    root = held.split(" = ", maxsplit=1)[0]
    assert f", and {root} holds its " in found[0].message
    assert found[0].message.endswith(f"; it is {fix}")


def test_a_made_up_part_of_a_message_is_found_once(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "self.start_x = self.odom_msg.pose.pose.position.x",
        "twist = self.odom_msg.velocity\n        self.start_x = twist.linear.x",
    )
    found = [f for f in run(source, move_forward).findings if f.check == "grounding"]
    assert [f.message.split(" (")[0] for f in found] == [
        "nav_msgs/msg/Odometry has no field 'velocity' in the message"
    ]


@pytest.mark.parametrize(
    ("written", "meant"),
    [
        ("self.odom_msg.header.stamp.secs", "self.odom_msg.header.stamp.sec"),
        ("self.odom_msg.twist.angular.yaw_rate", "self.odom_msg.twist.twist.angular.z"),
        ("self.odom_msg.twist.twist.angular.roll", "self.odom_msg.twist.twist.angular.x"),
    ],
    ids=["ros1-time", "axis-and-level", "axis"],
)
def test_a_field_named_as_ros_1_or_by_its_axis_is_put_as_the_message_names_it(
    move_forward: tuple[Capability, SkillSpec], written: str, meant: str
) -> None:
    source = GOOD.replace(
        "self.start_x = self.odom_msg.pose.pose.position.x", f"self.start_x = {written}"
    )
    (found,) = [f for f in run(source, move_forward).findings if f.check == "grounding"]
    assert found.message.endswith("; it is " + meant)
    assert found.replacement == f"self.start_x = {meant}"


def test_the_angle_about_an_axis_of_a_quaternion_is_no_field_and_gets_no_fix(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "self.start_x = self.odom_msg.pose.pose.position.x",
        "self.start_x = self.odom_msg.pose.pose.orientation.yaw",
    )
    (found,) = [f for f in run(source, move_forward).findings if f.check == "grounding"]
    assert "has no field 'yaw' in pose.pose.orientation (fields: w, x, y, z)" in found.message
    assert found.replacement is None


@pytest.mark.parametrize(
    ("seconds", "fields"),
    [
        ("2.5", "sec=2, nanosec=500000000"),
        ("0.0", "sec=0, nanosec=0"),
        (
            "self.in_linear_velocity",
            "sec=int(self.in_linear_velocity), nanosec=int(self.in_linear_velocity % 1 * 1e9)",
        ),
    ],
)
def test_a_duration_message_made_from_seconds_is_split_into_its_two_fields(
    move_forward: tuple[Capability, SkillSpec], seconds: str, fields: str
) -> None:
    source = GOOD.replace(
        "        self.start_x = self.odom_msg.pose.pose.position.x",
        "        self.start_x = self.odom_msg.pose.pose.position.x\n"
        f"        self.period = Duration(seconds={seconds})",
        1,
    ).replace(
        "from geometry_msgs.msg import Twist",
        "from builtin_interfaces.msg import Duration\nfrom geometry_msgs.msg import Twist",
    )
    report = check_on_mr1(source, move_forward)
    (found,) = [f for f in report.findings if f.check == "grounding"]
    assert found.message.startswith(
        "builtin_interfaces/msg/Duration has no field 'seconds' (fields: nanosec, sec; both "
        f"integers): it is Duration({fields})"
    )
    assert found.replacement == f"self.period = Duration({fields})"


def test_the_singular_of_an_array_field_in_a_constructor_is_put_as_the_field(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "        self.start_x = self.odom_msg.pose.pose.position.x",
        "        self.start_x = self.odom_msg.pose.pose.position.x\n"
        "        point = JointTrajectoryPoint(position=[self.start_x], velocity=[0.0])",
        1,
    ).replace(
        "from geometry_msgs.msg import Twist",
        "from geometry_msgs.msg import Twist\nfrom trajectory_msgs.msg import JointTrajectoryPoint",
    )
    report = check_on_mr1(source, move_forward)
    found = [f for f in report.findings if f.check == "grounding"]
    made = "point = JointTrajectoryPoint(positions=[self.start_x], velocities=[0.0])"
    assert [(f.message.split(" (fields")[0], f.replacement) for f in found] == [
        ("trajectory_msgs/msg/JointTrajectoryPoint has no field 'position' in the message", made),
        ("trajectory_msgs/msg/JointTrajectoryPoint has no field 'velocity' in the message", made),
    ]


def with_backup(execute: str, helpers: str = "") -> str:
    """GOOD with the BackUp action imported, ``helpers`` (methods) before its states and
    ``execute`` (statements) at the end of its execute state."""
    return (
        GOOD.replace(
            "from geometry_msgs.msg import Twist",
            "from geometry_msgs.msg import Twist\nfrom nav2_msgs.action import BackUp",
        )
        .replace("    @starting\n", helpers + "    @starting\n")
        .replace(
            "        self.out_distance = self._travelled()\n",
            "        self.out_distance = self._travelled()\n" + execute,
        )
    )


BACKUP_RESULT = (
    '    def _backup_result(self, timeout: float) -> "BackUp.Result":\n'
    "        return BackUp.Result()\n\n"
)
"""A result helper as the skeleton writes it: annotated with what it returns, as text."""


def test_a_result_from_a_method_annotated_to_return_it_has_its_fields_checked(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = with_backup(
        "        result = self._backup_result(5.0)\n"
        "        if not result.success:\n"
        "            raise RuntimeError(f'backed up for {result.total_elapsed_time}')\n",
        BACKUP_RESULT,
    )
    report = check_on_mr1(source, move_forward)
    (found,) = [f for f in report.findings if f.check == "grounding"]
    assert found.message.startswith(
        "nav2_msgs/action/BackUp.Result has no field 'success' in the message"
    )
    # The helper raises when the goal did not succeed: the guard that raises on a made-up
    # outcome field comes to nothing.
    assert found.message.endswith(
        "the helper that returned result raises RuntimeError when the goal did not succeed, "
        "so this test is not needed"
    )
    assert found.replacement == ""


@pytest.mark.parametrize(
    ("guard", "replacement"),
    [
        # a positive test comes to its body
        (
            "        if result.success:\n            self.out_distance = 1.0\n",
            "self.out_distance = 1.0",
        ),
        # a negative test comes to its else; what a failed goal would do never runs
        (
            "        if not result.success:\n            raise RuntimeError('no')\n"
            "        else:\n            self.out_distance = 1.0\n",
            "self.out_distance = 1.0",
        ),
        (
            "        if not result.success:\n            self.out_distance = 0.0\n"
            "            raise RuntimeError('no')\n",
            "",
        ),
        # a test of more than the field is the model's to repair
        (
            "        if result.success and self.in_distance > 0.0:\n"
            "            self.out_distance = 1.0\n",
            None,
        ),
    ],
)
def test_a_guard_on_a_made_up_outcome_field_of_a_checked_result(
    move_forward: tuple[Capability, SkillSpec], guard: str, replacement: str | None
) -> None:
    source = with_backup("        result = self._backup_result(5.0)\n" + guard, BACKUP_RESULT)
    (found,) = [f for f in check_on_mr1(source, move_forward).findings if f.check == "grounding"]
    assert found.replacement == replacement


def test_a_made_up_field_of_a_result_nothing_checked_keeps_its_guard(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # A result built here, not returned by a helper that raises on failure.
    source = with_backup(
        "        result = BackUp.Result()\n"
        "        if not result.success:\n            raise RuntimeError('no')\n"
    )
    (found,) = [f for f in check_on_mr1(source, move_forward).findings if f.check == "grounding"]
    assert "not needed" not in found.message
    assert found.replacement is None


def test_waiting_for_the_result_of_a_goal_nothing_sends_is_an_error(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    helpers = (
        "    def _send_backup_goal(self, goal, timeout: float) -> None:\n"
        "        self.backup_goal = goal\n\n" + BACKUP_RESULT
    )
    waits = with_backup("        self._backup_result(5.0)\n", helpers)
    (found,) = [
        f for f in check_on_mr1(waits, move_forward).findings if "nothing sends" in f.message
    ]
    assert found.severity == "error"
    assert "send it first with self._send_backup_goal(goal, timeout)" in found.message
    sends = waits.replace(
        "        self._backup_result(5.0)\n",
        "        self._send_backup_goal(BackUp.Goal(), 5.0)\n        self._backup_result(5.0)\n",
    )
    assert not [
        f for f in check_on_mr1(sends, move_forward).findings if "nothing sends" in f.message
    ]


def test_overwriting_an_input_is_an_error(move_forward: tuple[Capability, SkillSpec]) -> None:
    source = GOOD.replace(
        "        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)",
        "        self.in_linear_velocity = min(abs(self.in_linear_velocity), 0.8)\n"
        "        speed = self.in_linear_velocity",
    )
    found = [f for f in run(source, move_forward).findings if f.check == "inputs"]
    assert [f.severity for f in found] == ["error", "error"]
    assert all(
        "self.in_linear_velocity holds the capability input inLinearVelocity" in f.message
        and f.message.endswith("execute works on the local copy linear_velocity instead")
        for f in found
    )
    # The fix keeps the state's arithmetic on a copy: the first statement that uses the
    # input makes it, each later one reads or writes the copy.
    assert [f.replacement for f in found] == [
        "linear_velocity = self.in_linear_velocity\n"
        "linear_velocity = min(abs(linear_velocity), 0.8)",
        "speed = linear_velocity",
    ]


def test_an_input_overwritten_in_a_for_loop_is_an_error_without_a_fix(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)",
        "        for _ in range(2):\n"
        "            self.in_linear_velocity = self.in_linear_velocity / 2\n"
        "        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)",
    )
    (found,) = [f for f in run(source, move_forward).findings if f.check == "inputs"]
    write = "            self.in_linear_velocity = self.in_linear_velocity / 2"
    assert found.line == source.splitlines().index(write) + 1
    assert found.replacement is None
    assert found.message.endswith("keep a derived value in a local variable")


def test_an_input_no_method_reads_is_an_error_at_its_getter(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)",
        "        speed = self.LINEAR_VELOCITY_MAX",
    )
    (found,) = [f for f in run(source, move_forward).findings if f.check == "inputs"]
    assert found.severity == "error"
    assert (
        found.line
        == source.splitlines().index(
            '    @skill_parameter(is_required=True, name="inLinearVelocity", description="Speed [m/s].")'
        )
        + 1
    )
    assert found.message.startswith(
        "input inLinearVelocity is never read: no method uses self.in_linear_velocity"
    )


@pytest.mark.parametrize(
    ("uses", "error"),
    [
        ("        speed = self.LINEAR_VELOCITY_MAX", True),
        (  # ev72: the local copied onto itself, which reads nothing
            "        linear_velocity = linear_velocity\n        speed = self.LINEAR_VELOCITY_MAX",
            True,
        ),
        ("        speed = min(abs(linear_velocity), self.LINEAR_VELOCITY_MAX)", False),
    ],
)
def test_an_input_copied_into_a_local_that_nothing_reads_is_still_ignored(
    move_forward: tuple[Capability, SkillSpec], uses: str, error: bool
) -> None:
    source = GOOD.replace(
        "        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)",
        f"        linear_velocity = self.in_linear_velocity\n{uses}",
    )
    found = [f.message for f in run(source, move_forward).findings if f.check == "inputs"]
    assert found == (
        [
            "input inLinearVelocity is never used: execute copies self.in_linear_velocity into "
            "linear_velocity and nothing reads linear_velocity, so the skill ignores the value "
            "it is given; use linear_velocity (float, m/s) where the skill needs it"
        ]
        if error
        else []
    )


@pytest.mark.parametrize(
    ("refusal", "error"),
    [
        (
            "        if self.in_linear_velocity <= 0.0:\n            raise ValueError('no speed')\n",
            True,
        ),
        (  # logged, then refused; the message reads it too
            "        if self.in_linear_velocity <= 0.0:\n"
            "            self.node.get_logger().error(f'{self.in_linear_velocity}')\n"
            "            raise ValueError(f'bad speed {self.in_linear_velocity}')\n",
            True,
        ),
        (  # a test with another way out is behaviour, not a refusal
            "        if self.in_linear_velocity <= 0.0:\n            return\n",
            False,
        ),
        (  # ev72: refused through a local copy
            "        limit = self.in_linear_velocity\n"
            "        if limit <= 0.0:\n"
            "            raise ValueError(f'bad speed {limit}')\n",
            True,
        ),
        (  # a copy the refusal tests and the motion uses
            "        limit = self.in_linear_velocity\n"
            "        if limit <= 0.0:\n"
            "            raise ValueError(f'bad speed {limit}')\n"
            "        print(limit)\n",
            False,
        ),
    ],
)
def test_an_input_only_tested_to_refuse_bad_values_is_never_used(
    move_forward: tuple[Capability, SkillSpec], refusal: str, error: bool
) -> None:
    source = GOOD.replace(
        "        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)\n",
        f"{refusal}        speed = self.LINEAR_VELOCITY_MAX\n",
    )
    found = [f.message for f in run(source, move_forward).findings if f.check == "inputs"]
    assert found == (
        [
            "input inLinearVelocity is never used: execute only tests self.in_linear_velocity "
            "to refuse a bad value, and nothing the skill does depends on it; use "
            "self.in_linear_velocity (float, m/s) where the skill needs it"
        ]
        if error
        else []
    )


def test_an_output_no_method_sets_is_an_error_once_every_state_is_written(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    never_set = GOOD.replace("        self.out_distance = self._travelled()\n", "")
    assert never_set != GOOD
    (found,) = [f for f in run(never_set, move_forward).findings if f.check == "outputs"]
    assert found.message.startswith("output outDistance is never set")
    # what to store, as the capability says it, and where the skill can read it
    assert found.message.endswith(
        "store the value it reports (float, m; abs(outDistance - inDistance) <= 0.02) in "
        "self.out_distance before execute ends; the skill can read it from "
        "self.odom_msg.pose.pose.position (the distance travelled: math.hypot of its change in "
        "x and y since execute began)"
    )
    # A skeleton's states are still to be written: what they will set is not known yet.
    unwritten = never_set.replace(
        '        """Halt the base."""\n        self.cmd_vel_publisher.publish(Twist())',
        '        """Halt the base."""\n        raise NotImplementedError',
    )
    assert "NotImplementedError" in unwritten
    assert not [f for f in run(unwritten, move_forward).findings if f.check == "outputs"]


def test_a_handle_made_again_in_another_state_is_an_error(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "        self.start_x = self.odom_msg.pose.pose.position.x",
        '        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)\n'
        "        self.start_x = self.odom_msg.pose.pose.position.x",
        1,
    )
    (found,) = [f for f in run(source, move_forward).findings if f.check == "handles"]
    assert found.message.startswith(
        "self.cmd_vel_publisher is made in starting already; use that handle"
    )
    assert found.replacement == ""  # without it, the state uses the first handle


@pytest.mark.parametrize(
    "lookup", ["self.tf_buffer.lookup_transform(", "self._transform("], ids=["buffer", "helper"]
)
def test_a_transform_lookup_gives_a_transform_stamped_whose_fields_are_checked(
    lookup: str,
) -> None:
    skill = SHIPPED_CAPABILITIES / "skills" / "get_position.py"
    source = (
        skill.read_text(encoding="utf-8")
        .replace("self.tf_buffer.lookup_transform(", lookup, 1)
        .replace("translation = transform.transform.translation", "translation = transform.pose")
    )
    catalog = mr1_catalog()
    report = check_skill(
        source,
        capability=load_capability(SHIPPED_CAPABILITIES / "get-position.ttl").capability,
        spec=load_spec(SHIPPED_CAPABILITIES / "get-position.spec.yaml"),
        catalog=catalog,
    )
    assert messages(report, "grounding") == [
        "geometry_msgs/msg/TransformStamped has no field 'pose' in the message "
        "(fields: child_frame_id, header, transform)"
    ]


@pytest.mark.parametrize(
    ("written", "meant"),
    [
        ("transform.orientation", "transform.transform.rotation"),
        ("transform.position", "transform.transform.translation"),
    ],
)
def test_a_poses_own_field_asked_of_a_transform_is_put_as_the_transform_holds_it(
    written: str, meant: str
) -> None:
    skill = SHIPPED_CAPABILITIES / "skills" / "get_position.py"
    source = (
        skill.read_text(encoding="utf-8")
        .replace("q = transform.transform.rotation", f"q = {written}")
        .replace("translation = transform.transform.translation", f"translation = {written}")
    )
    report = check_skill(
        source,
        capability=load_capability(SHIPPED_CAPABILITIES / "get-position.ttl").capability,
        spec=load_spec(SHIPPED_CAPABILITIES / "get-position.spec.yaml"),
        catalog=mr1_catalog(),
    )
    field = written.rsplit(".", 1)[1]
    found = [f for f in report.findings if f"no field {field!r}" in f.message]
    assert found
    assert all(f.message.endswith(f"; it is {meant}") for f in found)


@pytest.mark.parametrize(
    ("given", "fix"),
    [
        ("self.odom_msg", "self._yaw(self.odom_msg.pose.pose.orientation)"),
        ("odom.pose.pose.orientation", "self._yaw(odom.pose.pose.orientation)"),
        ("0.5", None),
        ("self._yaw(odom.pose.pose.orientation)", None),  # already the heading
    ],
)
def test_the_goal_helper_handed_an_orientation_for_its_heading_gets_the_yaw_of_it(
    move_forward: tuple[Capability, SkillSpec], given: str, fix: str | None
) -> None:
    helper = (
        "    def _pose_goal(self, frame, x, y, yaw):\n        return None\n\n"
        "    def _yaw(self, q) -> float:\n        return 0.0\n\n    @execute\n"
    )
    source = GOOD.replace("    @execute\n", helper, 1).replace(
        "self.start_x = self.odom_msg.pose.pose.position.x",
        "odom = self.odom_msg\n        self.start_x = odom.pose.pose.position.x\n"
        f"        self.goal = self._pose_goal('map', 1.0, 2.0, {given})",
    )
    found = [f for f in run(source, move_forward).findings if "_pose_goal" in f.message]
    if fix is None:
        assert found == []
        return
    (finding,) = found
    assert finding.message == (
        f"self._pose_goal() takes the heading as an angle in radians, and {given} is an "
        f"orientation: {fix} is its heading"
    )
    assert finding.replacement == f"self.goal = self._pose_goal('map', 1.0, 2.0, {fix})"


_START = "        self.start_x = self.odom_msg.pose.pose.position.x"


@pytest.mark.parametrize(
    ("made", "cancelled", "expected", "replacement"),
    [
        (
            "        self.node.create_timer(0.05, self._travelled)\n",
            "",
            "the timer is not kept on the skill, so nothing cancels it",
            "self.travelled_timer = self.node.create_timer(0.05, self._travelled)",
        ),
        (
            "        self.timer = self.node.create_timer(0.05, self._travelled)\n",
            "",
            "self.timer is never cancelled",
            None,
        ),
        (
            "        self.timer = self.node.create_timer(0.05, self._travelled)\n",
            "        self.timer.cancel()\n",
            None,
            None,
        ),
        (
            "        timer = self.node.create_timer(0.05, self._travelled)\n"
            "        timer.cancel()\n",
            "",
            None,
            None,
        ),
    ],
    ids=["not kept", "never cancelled", "cancelled in stopping", "local, cancelled"],
)
def test_a_timer_must_be_kept_and_cancelled(
    move_forward: tuple[Capability, SkillSpec],
    made: str,
    cancelled: str,
    expected: str | None,
    replacement: str | None,
) -> None:
    source = GOOD.replace(_START, made + _START, 1).replace(
        '        """Halt the base."""\n', '        """Halt the base."""\n' + cancelled, 1
    )
    found = [f for f in run(source, move_forward).findings if f.check == "handles"]
    if expected is None:
        assert found == []
    else:
        assert [f.replacement for f in found] == [replacement]
        assert found[0].message.startswith(expected)


def test_a_tf2_listener_counts_as_using_the_transform_tree(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "import rclpy\n",
        "import rclpy\nfrom tf2_ros import Buffer, TransformListener\n",
    ).replace(
        "    def starting(self) -> None:\n",
        "    def starting(self) -> None:\n"
        "        self.tf_listener = TransformListener(Buffer(), self.node)\n",
    )
    assert "TransformListener(Buffer()" in source
    capability, spec = move_forward
    tf = CatalogEntry(name="/tf", kind="topic", type_name="tf2_msgs/msg/TFMessage")
    with_tf = Catalog(entries={**CATALOG.entries, "/tf": tf}, fields=CATALOG.fields)
    report = check_skill(
        source,
        capability=capability,
        spec=spec,
        catalog=with_tf,
        retrieved=["/cmd_vel", "/odom", "/tf"],
    )
    assert not any("/tf" in m for m in messages(report))
    # On a robot without a transform tree the listener would never hear anything.
    without = messages(run(source, move_forward), "grounding")
    assert any(m.startswith("topic /tf does not exist on this robot") for m in without)


def test_an_error_caught_and_ignored_where_the_spec_says_abort_is_an_error(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    old = "        deadline = time.time() + 2.0\n"
    assert old in GOOD
    swallowing = (
        "        try:\n"
        "            self._check_distance()\n"
        "        except ValueError as error:\n"
        "            self.node.get_logger().error(str(error))\n"
    )
    found = run(GOOD.replace(old, swallowing + old), move_forward).findings
    failures = [f for f in found if f.check == "failures"]
    assert [(f.severity, f.message) for f in failures] == [
        (
            "error",
            "the specification says @starting aborts, but this handler catches ValueError and "
            "carries on: log it if you like, then raise (a state that raises aborts the skill)",
        )
    ]
    reraising = swallowing + "            raise\n"
    found = run(GOOD.replace(old, reraising + old), move_forward).findings
    assert not [f for f in found if f.check == "failures"]


def test_an_error_ignored_where_the_spec_does_not_say_abort_is_a_warning(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    old = '        """Log requested and travelled distance."""\n'
    assert old in GOOD
    swallowing = old + (
        "        try:\n"
        "            self._check_distance()\n"
        "        except Exception:\n"
        "            return\n"
    )
    failures = [
        f
        for f in run(GOOD.replace(old, swallowing), move_forward).findings
        if f.check == "failures"
    ]
    assert [(f.severity, f.message) for f in failures] == [
        (
            "warning",
            "this handler catches Exception in @completing and carries on; check that the "
            "skill should go on after it",
        )
    ]


def test_a_halting_state_that_logs_a_failure_and_goes_on_halting_is_not_flagged(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    halt = '        """Halt the base."""\n'
    assert halt in GOOD
    logging = halt + (
        "        try:\n"
        "            self._travelled()\n"
        "        except RuntimeError as error:\n"
        "            self.node.get_logger().error(str(error))\n"
    )
    findings = run(GOOD.replace(halt, logging), move_forward).findings
    assert [f for f in findings if f.check == "failures"] == []


def test_an_aborting_state_the_spec_lacks_is_welcome(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    halt = "    @stopping\n"
    aborting = (
        "    @aborting\n    def aborting(self) -> None:\n"
        "        self.cmd_vel_publisher.publish(Twist())\n\n"
    )
    findings = run(GOOD.replace(halt, aborting + halt), move_forward).findings
    assert not [f for f in findings if "aborting" in f.message], findings


def test_a_zero_twist_made_of_numbers_is_pointed_to_twist_and_its_publish_suggested(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        '        """Halt the base."""\n        self.cmd_vel_publisher.publish(Twist())',
        '        """Halt the base."""\n'
        "        self.cmd_vel_publisher.publish(Twist(angular=0.0, linear=0.0))",
    )
    assert "Twist(angular=0.0, linear=0.0)" in source
    found = [f for f in run(source, move_forward).findings if "is a message" in f.message]
    assert len(found) == 2
    assert all(
        f.message.endswith("; a zero command is Twist(), every field of it is 0") for f in found
    )
    assert {f.replacement for f in found} == {"self.cmd_vel_publisher.publish(Twist())"}


def test_a_constant_a_message_type_does_not_declare_is_an_error(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "        self.cmd_vel_publisher.publish(Twist())\n\n    @resetting",
        "        self.cmd_vel_publisher.publish(Twist(linear=Twist.STOP))\n\n    @resetting",
        1,
    )
    report = check_on_mr1(source, move_forward)
    assert messages(report, "grounding") == [
        "geometry_msgs/msg/Twist has no constant 'STOP' (its constants: none); the skill's "
        "own: self.LINEAR_VELOCITY_MAX"
    ]
    assert [f.replacement for f in report.findings] == [None]  # no constant of the skill stops


def test_a_made_up_constant_naming_a_limit_of_the_skill_is_that_limit(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)",
        "speed = min(abs(self.in_linear_velocity), Twist.MAX_SPEED)",
        1,
    )
    report = check_on_mr1(source, move_forward)
    (found,) = report.findings
    assert found.message.startswith("geometry_msgs/msg/Twist has no constant 'MAX_SPEED'")
    assert found.replacement == (
        "speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)"
    )


def test_a_message_published_on_the_wrong_handle_goes_to_the_one_of_its_type(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # a Panther's model published its Twist on the arm's Float64MultiArray controller topic
    source = (
        GOOD.replace(
            '        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)\n',
            '        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)\n'
            "        self.arm_publisher = self.node.create_publisher(\n"
            '            Float64MultiArray, "/forward_velocity_controller/commands", 10\n'
            "        )\n",
        )
        .replace(
            "            self.cmd_vel_publisher.publish(command)",
            "            self.arm_publisher.publish(command)",
        )
        .replace(
            "from geometry_msgs.msg import Twist",
            "from geometry_msgs.msg import Twist\nfrom std_msgs.msg import Float64MultiArray",
        )
    )
    report = check_on_mr1(source, move_forward)
    (found,) = [f for f in report.findings if "takes a" in f.message]
    assert found.message == (
        "self.arm_publisher.publish takes a std_msgs/msg/Float64MultiArray, not a "
        "geometry_msgs/msg/Twist; self.cmd_vel_publisher takes a geometry_msgs/msg/Twist: "
        "publish it there"
    )
    assert found.replacement == "self.cmd_vel_publisher.publish(command)"
    # a subscription of the type is not somewhere to publish
    no_publisher = source.replace(
        'self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)',
        'self.cmd_vel_publisher = self.node.create_subscription(Twist, "/cmd_vel", print, 10)',
    )
    (unfixed,) = [
        f for f in check_on_mr1(no_publisher, move_forward).findings if "takes a" in f.message
    ]
    assert unfixed.replacement is None


def test_a_message_of_another_type_handed_to_a_handle_is_an_error_and_wrapped_when_it_fits() -> (
    None
):
    skill = SHIPPED_CAPABILITIES / "skills" / "navigate_to_point.py"
    source = (
        skill.read_text(encoding="utf-8")
        .replace(
            "from geometry_msgs.msg import Twist",
            "from geometry_msgs.msg import PoseStamped, Twist",
        )
        .replace("send_goal_async(goal, feedback", "send_goal_async(target, feedback")
        .replace(
            "        goal = NavigateToPose.Goal()\n",
            "        goal = NavigateToPose.Goal()\n        target = PoseStamped()\n",
        )
        .replace(
            "self.cmd_vel_publisher.publish(Twist())",
            "self.cmd_vel_publisher.publish(PoseStamped())",
        )
    )
    catalog = mr1_catalog()
    report = check_skill(
        source,
        capability=load_capability(SHIPPED_CAPABILITIES / "navigate-to-point.ttl").capability,
        spec=load_spec(SHIPPED_CAPABILITIES / "navigate-to-point.spec.yaml"),
        catalog=catalog,
    )
    found = [f for f in report.findings if "takes a" in f.message]
    assert [f.message for f in found] == [
        "self.navigate_to_pose_client.send_goal_async takes a "
        "nav2_msgs/action/NavigateToPose.Goal, not a geometry_msgs/msg/PoseStamped: put it in "
        "one, NavigateToPose.Goal(pose=target)",
        "self.cmd_vel_publisher.publish takes a geometry_msgs/msg/Twist, not a "
        "geometry_msgs/msg/PoseStamped",
    ]
    assert found[0].replacement is not None
    assert "send_goal_async(NavigateToPose.Goal(pose=target), feedback_callback=" in (
        found[0].replacement
    )


def test_list_methods_of_an_array_of_messages_are_not_taken_for_fields(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    inventory = load_inventory(SHIPPED_CAPABILITIES / "recordings" / "mr1")
    catalog = catalog_from_inventory(inventory)
    source = GOOD.replace(
        "        self.start_x = self.odom_msg.pose.pose.position.x",
        "        self.start_x = self.odom_msg.pose.pose.position.x\n"
        "        goal = MoveGroup.Goal()\n"
        "        goal.request.goal_constraints.append(Constraints())\n"
        "        goal.request.goal_constraints[0].position_constraints.clear()\n"
        "        goal.request.goal_constraints.push(Constraints())",
        1,
    ).replace(
        "from geometry_msgs.msg import Twist",
        "from geometry_msgs.msg import Twist\n"
        "from moveit_msgs.action import MoveGroup\n"
        "from moveit_msgs.msg import Constraints",
    )
    capability, spec = move_forward
    report = check_skill(
        source, capability=capability, spec=spec, catalog=catalog, retrieved=["/cmd_vel", "/odom"]
    )
    found = [f.message for f in report.findings if f.check == "grounding"]
    assert len(found) == 1
    assert "has no field 'push' in request.goal_constraints (fields: " in found[0]
    assert "append" not in found[0]


@pytest.mark.parametrize(
    ("store", "error"),
    [
        ("        self.out_distance = 0.0", True),  # ev51-ev57 cap2skill move-forward
        ("        self.out_distance = -1", True),
        ("        self.out_distance = self._travelled()", False),
        ("        self.out_distance = 0.0\n        self.out_distance += self._travelled()", False),
    ],
)
def test_an_output_only_ever_set_to_a_number_written_out_is_an_error_at_its_getter(
    move_forward: tuple[Capability, SkillSpec], store: str, error: bool
) -> None:
    source = GOOD.replace("        self.out_distance = self._travelled()", store)
    found = [f for f in run(source, move_forward).findings if f.check == "outputs"]
    if not error:
        assert found == []
        return
    (finding,) = found
    assert finding.severity == "error"
    assert finding.message.startswith("output outDistance is only ever set to ")
    assert finding.message.endswith(
        "; the skill can read it from self.odom_msg.pose.pose.position (the distance "
        "travelled: math.hypot of its change in x and y since execute began)"
    )
    # generation takes it as an output never set: the repair goes on from the end of execute
    assert _unset_output(finding) == "out_distance"


@pytest.mark.parametrize(
    ("before", "local"),
    [
        ("        out_distance = self._travelled()\n", "out_distance"),  # ev69 cap2skill
        ("        distance = self._travelled()\n", "distance"),
        (  # a copy of an input is not what the output measures
            "        distance = self.in_distance\n        out_distance = self._travelled()\n",
            "out_distance",
        ),
        ("        out_distance = 0.0\n", None),  # a number: nothing worked out
        ("        distance = self.in_distance\n", None),  # only a copy of an input
    ],
)
def test_an_output_set_to_a_number_after_a_local_of_its_name_was_worked_out_stores_the_local(
    move_forward: tuple[Capability, SkillSpec], before: str, local: str | None
) -> None:
    source = GOOD.replace(
        "        self.out_distance = self._travelled()\n",
        f"{before}        self.out_distance = 0.0\n",
    )
    (finding,) = [f for f in run(source, move_forward).findings if f.check == "outputs"]
    flagged = source.splitlines()[finding.line - 1]
    if local is None:  # the finding stays at the getter, with nothing to put in place
        assert finding.replacement is None
        assert "@skill_output" in flagged
        return
    assert flagged == "        self.out_distance = 0.0"
    assert finding.message.endswith(
        f"execute works out {local} and then stores 0.0 in its place; store {local}"
    )
    assert finding.replacement == f"self.out_distance = {local}"


@pytest.mark.parametrize(
    ("stores", "fix"),
    [
        (  # ev72 MR-1 collision avoidance: the helper gave the distance, the bearing stayed 0.0
            "        self.out_distance = self._closest_reading(self.scan_msg)[0]\n"
            "        self.out_angle = 0.0\n",
            "self.out_angle = self._closest_reading(self.scan_msg)[1]",
        ),
        (
            "        _, bearing = self._closest_reading(self.scan_msg)\n"
            "        self.out_angle = bearing\n"
            "        self.out_distance = 0.0\n",
            "self.out_distance = self._closest_reading(self.scan_msg)[0]",
        ),
    ],
)
def test_an_output_set_to_a_number_beside_the_nearest_reading_helper_stores_its_answer(
    stores: str, fix: str
) -> None:
    capability = load_capability(
        SHIPPED_CAPABILITIES / "get-distance-to-nearest-object.ttl"
    ).capability
    spec = load_spec(SHIPPED_CAPABILITIES / "get-distance-to-nearest-object.spec.yaml")
    source = (SHIPPED_CAPABILITIES / "skills" / "get_distance_to_nearest_object.py").read_text()
    start = source.index("        scan = self.scan_msg\n")
    end = source.index("    @completing")
    helper = "    def _closest_reading(self, scan):\n        return 0.0, 0.0\n\n"
    source = source[:start] + stores + "\n" + helper + source[end:]
    findings = check_skill(source, capability=capability, spec=spec).findings
    (finding,) = [f for f in findings if f.check == "outputs"]
    assert source.splitlines()[finding.line - 1].endswith(" = 0.0")
    assert "finds the nearest reading with _closest_reading() and then stores 0.0" in (
        finding.message
    )
    assert finding.replacement == fix


def test_an_output_the_model_asserts_may_be_set_to_that_number(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # outLinearVelocity = 0.0 is an Assurance: the skill reports the stop it promised
    source = GOOD.replace(
        "        self.out_linear_velocity = self.odom_msg.twist.twist.linear.x",
        "        self.out_linear_velocity = 0.0",
    )
    assert [f for f in run(source, move_forward).findings if f.check == "outputs"] == []


def test_a_command_built_and_never_published_is_an_error(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace("            self.cmd_vel_publisher.publish(command)\n", "")
    (finding,) = [f for f in run(source, move_forward).findings if f.check == "unsent"]
    assert finding.severity == "error"
    assert finding.message.startswith("command, a Twist message built on line ")
    assert finding.message.endswith(
        "publish it with self.cmd_vel_publisher.publish(command) once it is complete"
    )
    assert finding.replacement == (
        "command.linear.x = speed\nself.cmd_vel_publisher.publish(command)"
    )


def test_a_bound_or_tolerance_the_input_is_held_to_is_no_stand_in_for_it(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    """``min(self.in_linear_velocity, self.MAX_SPEED)`` and a tolerance compared with the
    input's value limit the input; a number used in its place is still a stand-in."""
    held = GOOD.replace(
        "    LINEAR_VELOCITY_MAX = 0.8  # resource requirement: linearVelocity <= 0.8 m/s\n",
        "    LINEAR_VELOCITY_MAX = 0.5\n",
    )
    assert "min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)" in held
    assert [f for f in run(held, move_forward).findings if f.code == "SW501"] == []
    instead = held.replace(
        "min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)", "self.LINEAR_VELOCITY_MAX"
    )
    [stand_in] = [f for f in run(instead, move_forward).findings if f.code == "SW501"]
    assert stand_in.data["input"] == "inLinearVelocity"


def test_a_limit_assigned_to_the_input_under_a_test_of_it_is_a_clamp_not_a_stand_in(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    """``if self.in_linear_velocity > 0.5: self.in_linear_velocity = self.MAX`` saturates
    the input at the capability's limit, as ``min`` does; the same assignment unguarded
    replaces the input whatever its value."""
    lowered = GOOD.replace(
        "    LINEAR_VELOCITY_MAX = 0.8  # resource requirement: linearVelocity <= 0.8 m/s\n",
        "    LINEAR_VELOCITY_MAX = 0.5\n",
    )
    clamp = "min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)"
    assert clamp in lowered
    guarded = lowered.replace(
        f"speed = {clamp}",
        "if self.in_linear_velocity > 0.5:\n"
        "            self.in_linear_velocity = self.LINEAR_VELOCITY_MAX\n"
        "        speed = abs(self.in_linear_velocity)",
    )
    assert [f for f in run(guarded, move_forward).findings if f.code == "SW501"] == []
    unguarded = lowered.replace(
        f"speed = {clamp}",
        "self.in_linear_velocity = self.LINEAR_VELOCITY_MAX\n"
        "        speed = abs(self.in_linear_velocity)",
    )
    [stand_in] = [f for f in run(unguarded, move_forward).findings if f.code == "SW501"]
    assert stand_in.data["input"] == "inLinearVelocity"


def test_an_input_read_through_its_own_getter_is_read(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    """pySkillUp's getter is a plain method: ``self.get_in_linear_velocity()`` in execute
    reads the attribute it returns; the same value read from nowhere is never read."""
    read = "min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)"
    assert read in GOOD
    through_getter = GOOD.replace(
        read, "min(abs(self.get_in_linear_velocity()), self.LINEAR_VELOCITY_MAX)"
    )
    assert [f for f in run(through_getter, move_forward).findings if f.code == "SW505"] == []
    ignored = GOOD.replace(read, "self.LINEAR_VELOCITY_MAX")
    [never] = [f for f in run(ignored, move_forward).findings if f.code == "SW505"]
    assert never.data["attribute"] == "in_linear_velocity"
