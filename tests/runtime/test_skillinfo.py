"""Reading a skill's runnable shape from its source."""

from __future__ import annotations

import pytest

from skillwright.runtime.skillinfo import SkillSourceError, read_skill
from tests.runtime.conftest import skill_path

TEMPLATE = """
@skill(capability_iri="x")
class Demo(ROS2Skill):
    @skill_parameter(is_required=True, name="inSpeed")
    def get_in_speed(self) -> float:
        return float(self.in_speed)

    @skill_parameter(is_required=False, name="inMode")
    def get_in_mode(self) -> str:
        return "fast"

    @skill_output(is_required=True, name="outSpeed")
    def get_out_speed(self) -> float:
        return self.out_speed

    @execute
    def execute(self) -> None:
        self.out_speed = self.in_speed
"""


def test_getters_give_their_attribute_annotation_and_line() -> None:
    info = read_skill(TEMPLATE)

    assert info.class_name == "Demo"
    speed, mode = info.parameters
    assert (speed.name, speed.attr, speed.annotation, speed.required, speed.line) == (
        "inSpeed",
        "in_speed",
        "float",
        True,
        5,
    )
    assert (mode.attr, mode.required) == (None, False)
    assert [(o.name, o.attr) for o in info.outputs] == [("outSpeed", "out_speed")]
    assert info.states == {"execute": 17}


def test_a_shipped_skill_has_every_state_its_spec_names() -> None:
    info = read_skill(skill_path("collision_avoidance").read_text(encoding="utf-8"))
    assert set(info.states) == {
        "starting",
        "execute",
        "completing",
        "stopping",
        "aborting",
        "resetting",
    }
    assert len(info.parameters) == 5


@pytest.mark.parametrize(
    ("source", "check", "line"),
    [
        ("def broken(:\n", "run.syntax", 1),
        ("class Plain:\n    pass\n", "run.structure", 0),
        ("@skill()\nclass NoExecute(ROS2Skill):\n    pass\n", "run.structure", 2),
    ],
)
def test_sources_without_a_runnable_skill_say_why(source: str, check: str, line: int) -> None:
    with pytest.raises(SkillSourceError) as raised:
        read_skill(source)
    assert (raised.value.rule.group, raised.value.line) == (check, line)


_CALLBACKS = """
@skill(skill_interface=None, skill_iri="urn:s", module_iri="urn:m", capability_iri="urn:c")
class Subject(ROS2Skill):
    @execute
    def execute(self):
        self.node.create_subscription(Odometry, "odom", self.on_odom, 10)
        self.node.create_timer(0.1, lambda: self.tick())
        future = self.client.call_async(request)
        def done(f):
            self.out_done = True
        future.add_done_callback(done)
        self.node.create_subscription(LaserScan, "scan", lambda m: setattr(self, "x", 1), 10)
        self.in_state = 1

    def on_odom(self, msg):
        self.out_x = msg.pose.pose.position.x
        self._remember(msg)

    def _remember(self, msg):
        self.last_odom = msg

    def tick(self):
        self.ticks = 1

    def unused(self):
        self.never = 1
"""


def test_the_attributes_callbacks_assign_are_known() -> None:
    """Methods handed to rclpy (directly, in a lambda, or a nested function) and the
    methods they call; not what a state or an unused method assigns itself."""
    info = read_skill(_CALLBACKS)
    assert info.callback_stores == {"out_x", "last_odom", "ticks", "out_done"}
