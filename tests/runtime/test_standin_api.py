"""The stand-ins' API as read from their source is the API their live objects have, and the
static checks accept exactly it."""

from __future__ import annotations

import inspect
import sys
from collections.abc import Iterator
from typing import Any

import pytest

from skillwright.runtime import standin_api
from skillwright.runtime.sandbox import CHILD_ROOT
from skillwright.validation import names


class _Wire:
    """The host's side of the wire, answering nothing."""

    def notify(self, op: str, **fields: Any) -> None:
        return None

    def request(self, op: str, **fields: Any) -> dict[str, Any]:
        return {}


class _Catalog:
    """Message classes by type name, with nothing in them but their name."""

    def get(self, type_name: str) -> type:
        return type(type_name.rsplit("/", 1)[-1], (), {"_type_name": type_name})


def _interface(type_name: str, **nested: type) -> type:
    return type(type_name.rsplit("/", 1)[-1], (), {"_type_name": type_name, **nested})


@pytest.fixture(scope="module")
def live() -> Iterator[dict[str, Any]]:
    """One live object of every kind in :data:`standin_api.HANDLES`, made by the stand-ins
    under a child core that talks to nobody."""
    sys.path.insert(0, str(CHILD_ROOT))
    own = ("rclpy", "tf2_ros", "pyskillup", "_skillwright_child")
    try:
        from _skillwright_child import core as child_core

        child_core.CORE = child_core.Core(_Wire(), "skill.py", 0)  # type: ignore[arg-type]
        child_core.CORE.catalog = _Catalog()  # type: ignore[assignment]
        import rclpy
        from pyskillup.decorator_check.decorator_check import ROS2Skill
        from rclpy.action.client import ActionClient, ClientGoalHandle
        from rclpy.task import Future
        from rclpy.time import Time
        from tf2_ros import Buffer, TransformListener

        skill = ROS2Skill("probe")
        node = skill.node
        action = _interface("nav2_msgs/action/NavigateToPose", Goal=object)
        client = ActionClient(node, action, "/navigate_to_pose")
        buffer = Buffer()
        yield {
            "node": node,
            "publisher": node.create_publisher(_interface("geometry_msgs/msg/Twist"), "/c", 10),
            "subscription": node.create_subscription(
                _interface("nav_msgs/msg/Odometry"), "/odom", print, 10
            ),
            "client": node.create_client(_interface("std_srvs/srv/Trigger"), "/trigger"),
            "action_client": client,
            "goal_handle": ClientGoalHandle(client, 1, True, {}),
            "future": Future(),
            "timer": node.create_timer(0.1, None),
            "rate": node.create_rate(10),
            "time": Time(),
            "logger": node.get_logger(),
            "tf_listener": TransformListener(buffer, node),
            "tf_buffer": buffer,
            "skill_base": skill,
        }
        rclpy.shutdown()
    finally:
        sys.path.remove(str(CHILD_ROOT))
        for name in [m for m in sys.modules if m.split(".")[0] in own]:
            del sys.modules[name]


def _public(instance: object) -> set[str]:
    return {n for n in dir(instance) if not n.startswith("_")}


@pytest.mark.parametrize("kind", sorted(standin_api.HANDLES))
def test_the_api_read_from_the_source_is_what_the_live_object_has(
    live: dict[str, Any], kind: str
) -> None:
    assert standin_api.members(kind) == _public(live[kind])


@pytest.mark.parametrize("kind", sorted(names.RCLPY_API))
def test_the_checks_accept_exactly_what_the_stand_in_has(live: dict[str, Any], kind: str) -> None:
    assert names.RCLPY_API[kind] == _public(live[kind])


@pytest.mark.parametrize(
    ("kind", "method"),
    [
        ("client", "call_async"),
        ("client", "call"),
        ("action_client", "send_goal_async"),
        ("publisher", "publish"),
        ("node", "create_subscription"),
        ("tf_buffer", "lookup_transform"),
    ],
)
def test_a_signature_read_from_the_source_is_the_live_methods(
    live: dict[str, Any], kind: str, method: str
) -> None:
    real = inspect.signature(getattr(live[kind], method))
    read = standin_api.signature(kind, method)

    assert [(p.name, p.kind) for p in read.parameters.values()] == [
        (p.name, p.kind) for p in real.parameters.values()
    ]
    assert [repr(p.default) for p in read.parameters.values()] == [
        repr(p.default) for p in real.parameters.values()
    ]


def test_what_pyskillup_star_imports_is_its_decorators_and_the_packml_states() -> None:
    exported = standin_api.exported("pyskillup.decorators.decorators")

    assert {"skill", "skill_parameter", "skill_output", "execute", "stopping"} <= set(exported)
    assert frozenset(exported) == names.PYSKILLUP_NAMES


def test_an_unknown_class_or_method_is_a_lookup_error() -> None:
    with pytest.raises(LookupError, match="no method"):
        standin_api.signature("node", "spin_forever")
