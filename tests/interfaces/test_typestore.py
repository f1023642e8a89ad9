"""Missing definitions are filled in from the offline type stores, never invented."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest

from skillwright.errors import OperationCancelledError
from skillwright.interfaces.inventory import Interface, MessageDefinition
from skillwright.interfaces.sources.report import inventory_from_report
from skillwright.interfaces.typestore import (
    TypeStore,
    fill_missing_definitions,
    missing_roles,
)


def _topic(type_name: str, name: str = "/t") -> Interface:
    return Interface(name=name, kind="topic", type_name=type_name)


def test_standard_message_is_filled_in_with_nested_types_expanded() -> None:
    twist = _topic("geometry_msgs/msg/Twist", "/cmd_vel")
    assert fill_missing_definitions([twist]) == 1
    definition = twist.definitions["message"]
    assert definition.origin == "type_store"
    assert definition.notes[0].startswith("filled in from the offline ROS 2 Jazzy type store")
    linear = (definition.fields or [])[0]
    assert (linear.name, linear.base_type, linear.resolved) == (
        "linear",
        "geometry_msgs/msg/Vector3",
        True,
    )
    assert [f.name for f in linear.fields] == ["x", "y", "z"]
    assert twist.notes == []


def test_constants_come_with_the_definition() -> None:
    transition = _topic("lifecycle_msgs/msg/Transition")
    fill_missing_definitions([transition])
    constants = {c.name: c.value for c in transition.definitions["message"].constants}
    assert constants["TRANSITION_ACTIVATE"] == 3


@pytest.mark.parametrize(
    ("distro", "store"),
    [(None, "Jazzy"), ("humble", "Humble"), ("Jazzy", "Jazzy"), ("rolling", "Jazzy")],
)
def test_the_store_of_the_sources_distribution_is_used(distro: str | None, store: str) -> None:
    header = _topic("std_msgs/msg/Header")
    fill_missing_definitions([header], distro)
    assert f"ROS 2 {store} type store" in header.definitions["message"].notes[0]


def test_a_type_missing_from_the_sources_distribution_comes_from_a_fallback() -> None:
    # service_msgs appeared after Humble.
    definition = TypeStore("humble").definition("service_msgs/msg/ServiceEventInfo")
    assert definition is not None
    assert "Jazzy type store" in definition.notes[0]
    assert "the source's distribution humble does not define the type" in definition.notes[0]


def test_unknown_type_is_marked_unknown_without_fields() -> None:
    custom = _topic("acme_msgs/msg/Gripper", "/gripper")
    assert fill_missing_definitions([custom]) == 0
    assert custom.definitions == {}
    assert custom.notes == [
        "definition unknown: acme_msgs/msg/Gripper is not in the offline type stores "
        "(Jazzy, Humble)"
    ]
    fill_missing_definitions([custom])
    assert len(custom.notes) == 1  # filling twice does not repeat the note


def test_a_core_service_is_filled_in_from_the_installed_interface_packages() -> None:
    trigger = Interface(name="/x", kind="service", type_name="std_srvs/srv/Trigger")
    assert fill_missing_definitions([trigger]) == 2
    response = trigger.definitions["response"]
    assert [f.name for f in response.fields or []] == ["success", "message"]
    assert response.notes[0] == "filled in from the installed ROS 2 Jazzy interface packages"
    assert trigger.notes == []


def test_an_action_outside_the_core_packages_names_its_interface_type() -> None:
    interface = Interface(name="/x", kind="action", type_name="nav2_msgs/action/NavigateToPose")
    fill_missing_definitions([interface])
    assert interface.definitions == {}
    assert interface.notes == [
        "definition unknown: nav2_msgs/action/NavigateToPose is not in the offline type "
        "stores (Jazzy, Humble)"
    ]


def test_only_missing_roles_are_looked_up() -> None:
    present = MessageDefinition(type_name="p/srv/S_Request", encoding="ros2msg", raw="int8 a")
    service = Interface(
        name="/s", kind="service", type_name="p/srv/S", definitions={"request": present}
    )
    assert missing_roles(service) == [("response", "p/srv/S_Response")]
    other_form = Interface(
        name="/e",
        kind="service",
        type_name="p/srv/E",
        definitions={
            "event": MessageDefinition(type_name="p/srv/E_Event", encoding="ros2idl", raw="x")
        },
    )
    assert missing_roles(other_form) == []
    assert missing_roles(Interface(name="/n", kind="topic", type_name="")) == []


def test_empty_recorded_definition_is_replaced_and_its_note_kept() -> None:
    empty = MessageDefinition(
        type_name="std_msgs/msg/String",
        encoding="ros2msg",
        raw="",
        notes=["the recording stored an empty definition for this type"],
    )
    chatter = Interface(
        name="/chatter",
        kind="topic",
        type_name="std_msgs/msg/String",
        definitions={"message": empty},
    )
    assert fill_missing_definitions([chatter]) == 1
    definition = chatter.definitions["message"]
    assert [f.name for f in definition.fields or []] == ["data"]
    assert definition.notes[-1] == "the recording stored an empty definition for this type"


def test_report_entry_without_details_gets_the_standard_definition() -> None:
    document = {
        "ros2_control_entities": [
            {
                "name": "/scan",
                "type": "topic",
                "interfaces": [{"name": "sensor_msgs/msg/LaserScan"}],
            }
        ]
    }
    scan = inventory_from_report(document, "r.json").interfaces[0]
    definition = scan.definitions["message"]
    assert definition.origin == "type_store"
    assert "ranges" in [f.name for f in definition.fields or []]
    assert "the report gives no definition of sensor_msgs/msg/LaserScan" in scan.notes


def test_bag_without_schemas_gets_definitions_from_the_store(tmp_path: Path) -> None:
    pytest.importorskip("mcap")
    from skillwright.interfaces.sources.bag import discover_bag
    from tests.interfaces.sources.recordings import Topic, write_recording

    folder = tmp_path / "bag"
    folder.mkdir()
    write_recording(
        folder / "bag_0.mcap",
        [
            Topic("/odom", "nav_msgs/msg/Odometry", schemaless=True),
            Topic("/chatter", "std_msgs/msg/String", ""),
            Topic("/grip", "acme_msgs/msg/Grip", schemaless=True),
        ],
    )
    (folder / "metadata.yaml").write_text(
        """rosbag2_bagfile_information:
  version: 8
  storage_identifier: mcap
  ros_distro: humble
  relative_file_paths: [bag_0.mcap]
  topics_with_message_count:
    - topic_metadata: {name: /odom, type: nav_msgs/msg/Odometry, serialization_format: cdr}
      message_count: 3
    - topic_metadata: {name: /grip, type: acme_msgs/msg/Grip, serialization_format: cdr}
      message_count: 3
""",
        encoding="utf-8",
    )
    inventory = discover_bag(folder)
    assert (
        "2 definition(s) filled in from the offline type stores" in inventory.sources[0].notes[-1]
    )
    odom = inventory.interface("/odom")
    assert odom.type_name == "nav_msgs/msg/Odometry"
    definition = odom.definitions["message"]
    assert definition.origin == "type_store"
    assert "ROS 2 Humble type store" in definition.notes[0]
    assert "/odom: recorded without a schema" in odom.notes
    chatter = inventory.interface("/chatter").definitions["message"]
    assert (chatter.origin, [f.name for f in chatter.fields or []]) == ("type_store", ["data"])
    grip = inventory.interface("/grip")
    assert grip.definitions == {}
    assert grip.notes[-1].startswith("definition unknown: acme_msgs/msg/Grip")
    assert "(Humble, Jazzy)" in grip.notes[-1]


def test_filling_stops_between_interfaces_once_cancelled() -> None:
    class CountingStore(TypeStore):
        """The Jazzy store, cancelling the job after its first answer."""

        def __init__(self, cancel: threading.Event) -> None:
            super().__init__("jazzy")
            self.cancel = cancel
            self.asked: list[str] = []

        def definition(self, type_name: str) -> MessageDefinition | None:
            self.asked.append(type_name)
            self.cancel.set()
            return super().definition(type_name)

    cancel = threading.Event()
    store = CountingStore(cancel)
    interfaces = [_topic("geometry_msgs/msg/Twist", "/a"), _topic("std_msgs/msg/String", "/b")]
    with pytest.raises(OperationCancelledError):
        fill_missing_definitions(interfaces, store=store, cancel=cancel)
    assert store.asked == ["geometry_msgs/msg/Twist"]
    assert interfaces[1].definitions == {}
