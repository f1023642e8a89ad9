"""The facts of a skill file the static checks share, worked out once."""

from __future__ import annotations

import ast
import textwrap

from skillwright.capability.model import Capability
from skillwright.spec.model import SkillSpec
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import statement_holding

NO_CAPABILITY = Capability(iri="urn:test#none", name="none", label="None", kinds=[])
"""A capability without inputs or outputs, for checks that do not read one."""


def facts_of(
    source: str,
    *,
    capability: Capability | None = None,
    spec: SkillSpec | None = None,
) -> SkillFacts:
    """The facts of ``source`` with its first class as the skill's (the checks' tests write
    classes without pySkillUp's decorator), against ``capability`` and ``spec`` (none with
    neither inputs nor states by default)."""
    tree = ast.parse(source)
    skill = next(n for n in tree.body if isinstance(n, ast.ClassDef))
    return SkillFacts(
        source=source,
        tree=tree,
        skill=skill,
        capability=capability or NO_CAPABILITY,
        spec=spec or SkillSpec(name="skill", description="", skill_interface="REST", states={}),
    )


SKILL = textwrap.dedent(
    '''
    from geometry_msgs.msg import Twist
    from nav_msgs.msg import Odometry
    from example_interfaces.srv import Trigger
    from nav2_msgs.action import NavigateToPose


    @skill(capability_iri="urn:x#c", skill_iri="urn:x#s")
    class Skill(ROS2Skill):
        def __init__(self) -> None:
            self.odom_msg: Odometry | None = None
            self.goal_x: float = 0.0

        @skill_parameter(name="inGoalX")
        def get_goal_x(self) -> float:
            return float(self.goal_x)

        @starting
        def starting(self) -> None:
            self.cmd_vel_publisher = self.node.create_publisher(Twist, "cmd_vel", 10)
            self.odom_subscription = self.node.create_subscription(
                msg_type=Odometry, topic="/odom", callback=self._on_odom, qos_profile=10
            )
            self.client = self.node.create_client(Trigger, "/reset")
            self.navigate_client = ActionClient(
                self.node, action_type=NavigateToPose, action_name="/navigate_to_pose"
            )
            self.tf_listener = TransformListener(self.tf_buffer, self.node)
            self.started = self.node.get_clock().now()

        @execute
        def execute(self) -> None:
            self._wait_until(lambda: self.odom_msg is not None, 2.0, "odom_msg")
            x = self.odom_msg.pose.pose.position.x
            if x == self.goal_x:
                self.cmd_vel_publisher.publish(Twist())

        def _on_odom(self, msg: Odometry) -> None:
            self.odom_msg = msg
            self.count = 1

        def _wait_until(self, condition, timeout: float, what: str) -> None:
            """Waits."""
    '''
)


def _facts() -> SkillFacts:
    return SkillFacts.build(
        SKILL,
        capability=NO_CAPABILITY,
        spec=SkillSpec(name="s", description="", skill_interface="REST", states={}),
    )


def test_the_skill_class_its_methods_and_states_are_found_by_their_decorators() -> None:
    facts = _facts()
    assert facts.skill is not None
    assert facts.skill.name == "Skill"
    assert facts.decorator is not None
    assert list(facts.methods) == [
        "__init__",
        "get_goal_x",
        "starting",
        "execute",
        "_on_odom",
        "_wait_until",
    ]
    assert {state: m.name for state, m in facts.states.items()} == {
        "starting": "starting",
        "execute": "execute",
    }
    assert [g.annotation.name for g in facts.getters] == ["inGoalX"]
    assert facts.parameter_attributes == {"goal_x"}


def test_handles_are_read_by_position_or_by_keyword_as_rclpy_takes_them() -> None:
    facts = _facts()
    made = {h.target: h.made for h in facts.handles}
    assert {target: m.kind for target, m in made.items()} == {
        "self.cmd_vel_publisher": "publisher",
        "self.odom_subscription": "subscription",
        "self.client": "client",
        "self.navigate_client": "action_client",
        "self.tf_listener": "tf_listener",
    }
    assert made["self.cmd_vel_publisher"].name == "/cmd_vel"
    assert made["self.odom_subscription"].type_name == "nav_msgs/msg/Odometry"
    assert made["self.odom_subscription"].callback == "_on_odom"
    assert made["self.navigate_client"].type_name == "nav2_msgs/action/NavigateToPose"
    assert made["self.navigate_client"].name == "/navigate_to_pose"
    assert [(u.name, u.kind) for u in facts.interface_uses] == [
        ("/cmd_vel", "topic"),
        ("/odom", "topic"),
        ("/reset", "service"),
        ("/navigate_to_pose", "action"),
        ("/tf", "topic"),
    ]
    assert facts.kinds["started"] == "time"
    assert facts.kinds["cmd_vel_publisher"] == "publisher"


def test_latest_messages_callbacks_and_readings() -> None:
    facts = _facts()
    assert facts.latest_messages == {"odom_msg": "Odometry"}
    assert facts.callbacks == {"_on_odom"}
    assert facts.callback_stores == {"odom_msg", "count"}
    assert facts.kept_messages("_on_odom") == {"odom_msg"}
    compare = next(n for n in facts.nodes if isinstance(n, ast.Compare))
    assert facts.is_measured(compare.left)
    assert not facts.is_measured(compare.comparators[0])


def test_a_helper_argument_is_bound_as_python_binds_it() -> None:
    facts = _facts()
    wait = next(c for c in facts.calls(facts.tree) if ast.unparse(c.func) == "self._wait_until")
    assert ast.unparse(facts.helper_argument(wait, "timeout") or ast.Constant(None)) == "2.0"
    transform = ast.parse('self._transform("map", "base_link", timeout=1.0)', mode="eval").body
    assert isinstance(transform, ast.Call)
    assert ast.unparse(facts.helper_argument(transform, "source_frame") or transform) == (
        "'base_link'"
    )
    assert ast.unparse(facts.helper_argument(transform, "timeout") or transform) == "1.0"


def test_the_statement_holding_a_node_is_the_one_the_tree_walk_finds() -> None:
    facts = _facts()
    shared = (ast.expr_context, ast.operator, ast.boolop, ast.unaryop, ast.cmpop)
    for node in (n for n in facts.walk(facts.tree) if not isinstance(n, shared)):
        for root in (facts.tree, *facts.functions):
            assert facts.statement_holding(node, root) is statement_holding(root, node)
