"""Written methods go into the skeleton; what they need is added, what they skip is left out."""

from __future__ import annotations

import ast
from functools import cache

from skillwright.capability.reader import load_capability
from skillwright.generation.assemble import assemble, message_classes, method_spans, usage
from skillwright.generation.model import InterfaceRef, Skeleton
from skillwright.generation.skeleton import build_skeleton
from skillwright.interfaces.inventory import Inventory
from skillwright.interfaces.load import load_inventory
from skillwright.spec.loader import load_spec
from tests.conftest import SHIPPED_CAPABILITIES

CMD_VEL = InterfaceRef(
    name="/cmd_vel", kind="topic", type_name="geometry_msgs/msg/Twist", role="publish"
)
ODOM = InterfaceRef(name="/odom", kind="topic", type_name="nav_msgs/msg/Odometry", role="subscribe")
BACKUP = InterfaceRef(
    name="/backup", kind="action", type_name="nav2_msgs/action/BackUp", role="call"
)


@cache
def _inventory() -> Inventory:
    return load_inventory(SHIPPED_CAPABILITIES / "recordings" / "mr1")


def _skeleton(refs: list[InterfaceRef], helpers: tuple[str, ...] | None = None) -> Skeleton:
    load = load_capability(SHIPPED_CAPABILITIES / "move-forward.ttl")
    spec = load_spec(SHIPPED_CAPABILITIES / "move-forward.spec.yaml")
    return build_skeleton(load.capability, spec, refs, helpers=helpers)


def _method(state: str, body: str, skeleton: Skeleton | None = None) -> str:
    prologue = "" if skeleton is None else skeleton.prologues.get(state, "")
    head = f"    @{state}\n    def {state}(self) -> None:\n"
    return head + (prologue + "\n" if prologue else "") + body


EXECUTE = _method(
    "execute",
    "        start = self.odom_msg.pose.pose.position\n"
    "        command = Twist(linear=Vector3(x=0.2))\n"
    "        self.cmd_vel_publisher.publish(command)\n"
    "        self.started_at = time.monotonic()\n"
    "        self.out_distance = math.hypot(start.x, start.y)\n",
)


def test_state_bodies_go_under_the_skeletons_signature_and_docstring() -> None:
    skeleton = _skeleton([CMD_VEL, ODOM])
    result = assemble(skeleton, {"execute": EXECUTE}, {})
    tree = ast.parse(result.code)
    cls = next(n for n in tree.body if isinstance(n, ast.ClassDef))
    execute = next(n for n in cls.body if isinstance(n, ast.FunctionDef) and n.name == "execute")
    assert ast.get_docstring(execute, clean=True).startswith("Remember the odometry position")
    assert "self.cmd_vel_publisher.publish(command)" in ast.unparse(execute)
    assert result.written == ("execute",)
    assert "execute" not in result.missing
    assert "starting" in result.missing


def test_resetting_ends_with_the_skeletons_release_of_the_handles() -> None:
    skeleton = _skeleton([CMD_VEL, ODOM])
    resetting = _method("resetting", "        self._stop_base()\n        self.out_distance = 0.0\n")
    code = assemble(skeleton, {"resetting": resetting}, {}).code
    body = code[code.index("def resetting") :]
    assert body.index("self._stop_base()") < body.index("self.node.destroy_publisher")
    assert "raise NotImplementedError" not in body


def test_a_helper_annotated_with_typing_names_gets_their_import() -> None:
    skeleton = _skeleton([CMD_VEL, ODOM])
    helper = (
        "    def _nearest(self, ranges: List[float]) -> Optional[float]:\n"
        "        return min(ranges, default=None)\n"
    )
    result = assemble(skeleton, {}, {"_nearest": helper})
    assert "from typing import List" in result.code
    assert "from typing import Optional" in result.code


def test_imports_and_init_attributes_the_behaviour_needs_are_added() -> None:
    skeleton = _skeleton([CMD_VEL, ODOM])
    classes = message_classes([_inventory().interface("/cmd_vel"), _inventory().interface("/odom")])
    result = assemble(skeleton, {"execute": EXECUTE}, {}, classes=classes)
    assert "import math" in result.code
    assert "from geometry_msgs.msg import Vector3" in result.code
    assert "        self.started_at = None" in result.code
    assert "attribute self.started_at" in result.added
    ast.parse(result.code)


def test_standard_modules_and_geometry_messages_are_imported_without_an_interface() -> None:
    skeleton = _skeleton([ODOM])
    execute = _method(
        "execute",
        "        stamp = datetime.datetime.now().strftime('%H%M%S')\n"
        "        self.map_path = os.path.join(os.getcwd(), stamp)\n"
        "        self.stop_command = Twist()\n",
    )
    result = assemble(skeleton, {"execute": execute}, {})
    assert "import os" in result.code
    assert "import datetime" in result.code
    assert "from geometry_msgs.msg import Twist" in result.code
    ast.parse(result.code)


def test_usage_counts_what_the_behaviour_touches_not_the_prefilled_handles() -> None:
    skeleton = _skeleton([CMD_VEL, ODOM, BACKUP])
    starting = _method(
        "starting",
        "        self._wait_until(lambda: self.odom_msg is not None, 2.0, 'odom')\n",
        skeleton,
    )
    stopping = _method("stopping", "        self._stop_base()\n")
    used = usage(skeleton, {"starting": starting, "stopping": stopping})
    assert [i.name for i in used.interfaces] == ["/cmd_vel", "/odom"]
    # The skeleton's own completing brings the base to rest for outLinearVelocity (asserted
    # 0.0), so the settling helper is used although no written method calls it.
    assert used.helpers == ("_wait_until", "_stop_base", "_settle_base")


def test_usage_counts_the_skeletons_own_rest_lines_not_its_handle_lines() -> None:
    load = load_capability(SHIPPED_CAPABILITIES / "set-velocity.ttl")
    spec = load_spec(SHIPPED_CAPABILITIES / "set-velocity.spec.yaml")
    plain = build_skeleton(load.capability, spec, [CMD_VEL, ODOM])
    # set-velocity asserts no output: nothing of the skeleton's own counts as use.
    assert usage(plain, {}).interfaces == ()
    resting = _skeleton([CMD_VEL, ODOM])
    used = usage(resting, {})
    assert [i.name for i in used.interfaces] == ["/cmd_vel", "/odom"]
    assert used.helpers == ("_wait_until", "_stop_base", "_settle_base")


def test_a_left_out_interface_loses_the_handle_lines_the_model_was_prefilled_with() -> None:
    full = _skeleton([CMD_VEL, ODOM, BACKUP])
    starting = _method(
        "starting",
        "        self._wait_until(lambda: self.odom_msg is not None, 2.0, 'odom')\n",
        full,
    )
    assert "ActionClient(self.node, BackUp" in starting
    kept = _skeleton([CMD_VEL, ODOM], ("_wait_until", "_stop_base"))
    result = assemble(kept, {"starting": starting}, {}, prefilled=[full.prologues["starting"]])
    assert "BackUp" not in result.code
    assert 'create_subscription(\n            Odometry, "/odom"' in result.code
    assert "_result_of" not in result.code


def test_helpers_go_before_the_first_state_and_spans_find_every_method() -> None:
    skeleton = _skeleton([CMD_VEL, ODOM])
    helper = "    def _yaw(self) -> float:\n        q = self.odom_msg.pose.pose.orientation\n        return q.z\n"
    result = assemble(skeleton, {"execute": EXECUTE}, {"_yaw": helper})
    spans = method_spans(result.code, skeleton.class_name)
    assert spans["_yaw"][1] < spans["starting"][0]
    assert spans["execute"][0] < spans["execute"][1]
    first, _ = spans["execute"]
    assert result.code.splitlines()[first - 1].strip() == "@execute"


def test_an_answer_that_does_not_parse_leaves_the_state_unwritten() -> None:
    skeleton = _skeleton([CMD_VEL, ODOM])
    result = assemble(
        skeleton, {"execute": "    @execute\n    def execute(self) -> None:\n        if x\n"}, {}
    )
    assert "execute" in result.missing
    assert 'raise NotImplementedError("execute' in result.code


def test_the_release_of_a_velocity_publisher_leaves_the_base_at_rest() -> None:
    # A base driver keeps the last Twist it received: a skill that completes with the base
    # moving (a set-velocity skill's spec asks for that) and whose resetting only destroys
    # the publisher leaves the base driving on after the reset.
    code = assemble(_skeleton([CMD_VEL, ODOM]), {}, {}).code
    body = code[code.index("def resetting") :]
    release = body[body.index("if self.cmd_vel_publisher is not None:") :]
    assert release.index("self.cmd_vel_publisher.publish(Twist())") < release.index(
        "self.node.destroy_publisher(self.cmd_vel_publisher)"
    )
    assert "destroy_subscription(self.odom_subscription)" in body
    odom = body[body.index("if self.odom_subscription is not None:") :]
    assert "publish" not in odom
