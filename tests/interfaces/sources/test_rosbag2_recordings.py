"""Real rosbag2 recordings (ros2/rosbag2 test data) yield the right interfaces and types."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from skillwright.interfaces.inventory import Inventory
from skillwright.interfaces.sources.bag import discover_bag
from tests.conftest import SHARED

ROSBAG2 = SHARED / "data" / "mcap" / "rosbag2"
FOLDERS = sorted(p.parent for p in ROSBAG2.glob("**/metadata.yaml"))
CPP_BAGS = ROSBAG2 / "rosbag2_cpp" / "test" / "rosbag2_cpp" / "bags"
TESTS = ROSBAG2 / "rosbag2_tests" / "resources" / "mcap"
PY = ROSBAG2 / "rosbag2_py" / "test" / "resources" / "mcap"


def _interfaces(inventory: Inventory) -> dict[tuple[str, str], tuple[str, int | None]]:
    return {
        (i.kind, i.name): (i.type_name, i.traffic.message_count if i.traffic else None)
        for i in inventory.interfaces
    }


def _metadata_topics(folder: Path) -> dict[str, tuple[str, int]]:
    info: dict[str, Any] = yaml.safe_load((folder / "metadata.yaml").read_text())[
        "rosbag2_bagfile_information"
    ]
    out = {}
    for item in info["topics_with_message_count"]:
        topic = item["topic_metadata"]
        out[topic["name"]] = (topic["type"], item["message_count"])
    return out


def _normalized(type_name: str) -> str:
    parts = type_name.split("/")
    return f"{parts[0]}/msg/{parts[1]}" if len(parts) == 2 else type_name


@pytest.mark.parametrize("mode", ["auto", "scan", "full"])
@pytest.mark.parametrize("folder", FOLDERS, ids=[f.name for f in FOLDERS])
def test_bag_folder_matches_its_metadata_yaml(folder: Path, mode: str, shared_data: Path) -> None:
    inventory = discover_bag(folder, mode)  # type: ignore[arg-type]
    recorded = {
        c.topic: (c.type_name, c.message_count) for i in inventory.interfaces for c in i.channels
    }
    expected = {
        name: (_normalized(type_name), count)
        for name, (type_name, count) in _metadata_topics(folder).items()
    }
    assert recorded == expected
    assert not inventory.sources[0].partial
    assert inventory.sources[0].kind == "rosbag2"


def test_every_recording_is_covered(shared_data: Path) -> None:
    assert len(FOLDERS) == 10
    assert len(list(CPP_BAGS.glob("*.mcap"))) == 3


def test_service_only_bag_has_one_service_with_request_and_response(shared_data: Path) -> None:
    inventory = discover_bag(CPP_BAGS / "only_services.mcap")
    assert _interfaces(inventory) == {
        ("service", "/add_two_ints"): ("example_interfaces/srv/AddTwoInts", 12)
    }
    service = inventory.interfaces[0]
    assert [f.name for f in service.definitions["request"].fields or []] == ["a", "b"]
    assert [f.name for f in service.definitions["response"].fields or []] == ["sum"]
    assert service.qos[0].reliability == "reliable"
    assert service.qos[0].durability == "transient_local"


def test_topics_and_services_bag(shared_data: Path) -> None:
    inventory = discover_bag(CPP_BAGS / "topics_and_services.mcap")
    assert _interfaces(inventory) == {
        ("topic", "/events/write_split"): ("rosbag2_interfaces/msg/WriteSplitEvent", 0),
        ("topic", "/parameter_events"): ("rcl_interfaces/msg/ParameterEvent", 7),
        ("topic", "/rosout"): ("rcl_interfaces/msg/Log", 0),
        ("service", "/add_two_ints"): ("example_interfaces/srv/AddTwoInts", 6),
        ("service", "/add_two_ints2"): ("example_interfaces/srv/AddTwoInts", 0),
    }
    flagged = {i.name for i in inventory.interfaces if i.infrastructure is not None}
    assert flagged == {"/events/write_split", "/parameter_events", "/rosout"}
    assert inventory.sources[0].kind == "mcap"


def test_only_topics_bag_expands_nested_definitions(shared_data: Path) -> None:
    inventory = discover_bag(CPP_BAGS / "only_topics.mcap")
    events = inventory.interface("/parameter_events").definitions["message"]
    fields = {f.name: f for f in events.fields or []}
    assert fields["stamp"].base_type == "builtin_interfaces/msg/Time"
    assert [f.name for f in fields["stamp"].fields] == ["sec", "nanosec"]
    new_parameters = fields["new_parameters"]
    assert new_parameters.array == "unbounded"
    value = {f.name: f for f in new_parameters.fields}["value"]
    assert value.base_type == "rcl_interfaces/msg/ParameterValue"
    assert all(f.resolved for f in value.fields)
    log = inventory.interface("/rosout").definitions["message"]
    assert {c.name: c.value for c in log.constants}["ERROR"] == 40


def test_service_event_bag_with_topics(shared_data: Path) -> None:
    inventory = discover_bag(TESTS / "bag_with_topics_and_service_events")
    assert _interfaces(inventory) == {
        ("topic", "/events/write_split"): ("rosbag2_interfaces/msg/WriteSplitEvent", 0),
        ("topic", "/test_topic1"): ("test_msgs/msg/Strings", 1),
        ("topic", "/test_topic2"): ("test_msgs/msg/Strings", 1),
        ("service", "/test_service1"): ("test_msgs/srv/BasicTypes", 4),
        ("service", "/test_service2"): ("test_msgs/srv/BasicTypes", 4),
    }
    strings = inventory.interface("/test_topic1").definitions["message"]
    defaults = {f.name: f.default for f in strings.fields or []}
    assert defaults["string_value_default4"] == "Hello'world!"
    assert defaults["bounded_string_value_default5"] == 'Hello"world!'
    assert [c.name for c in strings.constants] == ["STRING_CONST"]
    request = inventory.interface("/test_service1").definitions["request"]
    assert len(request.fields or []) == 14


def test_split_bag_folder_merges_five_files(shared_data: Path) -> None:
    inventory = discover_bag(PY / "wbag")
    assert len(inventory.sources[0].files) == 5
    assert sorted(i.name for i in inventory.interfaces) == [
        "AAA",
        "BBB",
        "CCC",
        "DDD",
        "EEE",
        "FFF",
        "GGG",
        "HHH",
    ]
    assert inventory.sources[0].message_count == sum(
        i.traffic.message_count for i in inventory.interfaces if i.traffic
    )


def test_folder_without_metadata_yaml_reads_every_split(shared_data: Path) -> None:
    inventory = discover_bag(PY / "reindex_test_bags" / "multiple_files")
    assert _interfaces(inventory) == {("topic", "/chatter"): ("std_msgs/msg/String", 3177)}
    assert len(inventory.sources[0].files) == 3


def test_wrong_serialization_format_is_kept_with_a_note(shared_data: Path) -> None:
    inventory = discover_bag(TESTS / "wrong_rmw_test")
    assert _interfaces(inventory) == {
        ("topic", "/array_topic"): ("test_msgs/msg/Arrays", 4),
        ("topic", "/test_topic"): ("test_msgs/msg/BasicTypes", 3),
    }
    for entry in inventory.interfaces:
        assert entry.channels[0].message_encoding == "wrong_format"
        assert any("wrong_format" in note for note in entry.notes)
    arrays = {
        f.name: f for f in inventory.interface("/array_topic").definitions["message"].fields or []
    }
    assert (arrays["bool_values"].array, arrays["bool_values"].array_size) == ("fixed", 3)
    assert arrays["uint64_values_default"].default == [0, 1, 18446744073709551615]


def test_schema_name_without_msg_is_normalized(shared_data: Path) -> None:
    folder = ROSBAG2 / "rosbag2_transport" / "test" / "resources" / "mcap" / "test_bag_for_seek"
    inventory = discover_bag(folder)
    topic = inventory.interface("topic1")
    assert topic.type_name == "test_msgs/msg/BasicTypes"
    assert topic.definitions["message"].type_name == "test_msgs/msg/BasicTypes"
    assert len(topic.definitions["message"].fields or []) == 13
