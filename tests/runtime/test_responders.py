"""Scripted servers answer with what reads as success by ROS conventions."""

from __future__ import annotations

from skillwright.interfaces.inventory import Inventory
from skillwright.runtime.responders import ScriptedService, success_message
from skillwright.runtime.scenario import ServiceScript
from skillwright.runtime.typesys import TypeRegistry


def test_success_sets_result_flags_and_success_codes(mr1_inventory: Inventory) -> None:
    registry = TypeRegistry(mr1_inventory)
    assert success_message(registry, "nav2_msgs/srv/SaveMap_Response") == {"result": True}
    moveit = success_message(registry, "moveit_msgs/action/MoveGroup_Result")
    assert moveit["error_code"]["val"] == 1
    assert moveit["planning_time"] == 0.0


def test_a_scripted_response_overrides_the_success_defaults(mr1_inventory: Inventory) -> None:
    registry = TypeRegistry(mr1_inventory)
    service = ScriptedService(
        registry, "nav2_msgs/srv/SaveMap", ServiceScript(response={"result": False}, delay=0.7)
    )

    reply = service({})

    assert (reply.response, reply.delay) == ({"result": False}, 0.7)
    silent = ScriptedService(registry, "nav2_msgs/srv/SaveMap", ServiceScript(respond=False))
    assert silent({}).response is None
