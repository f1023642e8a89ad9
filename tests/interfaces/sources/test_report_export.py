"""Inventories export to the reference tool's report shape and come back unchanged."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from skillwright.interfaces.inventory import (
    Description,
    Interface,
    Inventory,
    MessageDefinition,
    Resource,
    Source,
)
from skillwright.interfaces.load import load_inventory
from skillwright.interfaces.sources.report import (
    inventory_from_report,
    read_report,
    report_from_inventory,
    report_text,
)
from tests.conftest import SHIPPED_CAPABILITIES

REPORTS = Path("cap2skill") / "interface-reports"
RECORDING = SHIPPED_CAPABILITIES / "recordings" / "mr1"


def _reimport(inventory: Inventory, tmp_path: Path) -> Inventory:
    text, _ = report_text(inventory)
    path = tmp_path / "exported.json"
    path.write_text(text, encoding="utf-8")
    return read_report(path)


def test_raw_report_exports_back_to_the_same_bytes(shared_data: Path) -> None:
    path = shared_data / REPORTS / "ros2_system_report.json"
    text, notes = report_text(read_report(path))
    assert notes == []
    assert text == path.read_text(encoding="utf-8")


@pytest.mark.parametrize(
    "name", ["ros2_system_report.json", "ros2_system_report_with_descriptions.json"]
)
def test_report_round_trip_loses_nothing(shared_data: Path, tmp_path: Path, name: str) -> None:
    first = read_report(shared_data / REPORTS / name)
    second = _reimport(first, tmp_path)
    third = _reimport(second, tmp_path)
    assert second.interfaces == first.interfaces
    assert third.interfaces == first.interfaces


def test_exported_descriptions_use_the_reference_sections(shared_data: Path) -> None:
    path = shared_data / REPORTS / "ros2_system_report_with_descriptions.json"
    original = {e["name"]: e for e in json.loads(path.read_text())["ros2_control_entities"]}
    document, _ = report_from_inventory(read_report(path))
    entities = document["ros2_control_entities"]
    assert [len(entities[s]) for s in ("topics", "services", "actions")] == [13, 19, 1]
    cmd_vel = entities["topics"][0]
    assert list(cmd_vel) == ["name", "type", "description", "interfaces"]
    assert cmd_vel["description"].split("\n")[0] == "Purpose of the ROS2 Element:"
    # The words of every description survive (only bullet layout may change).
    for section in entities.values():
        for entry in section:
            assert entry["description"].split() != []
            words = [w for w in original[entry["name"]]["description"].split() if w != "-"]
            assert [w for w in entry["description"].split() if w != "-"] == words
            assert entry["interfaces"] == original[entry["name"]]["interfaces"]


def test_recording_exports_to_a_report_that_keeps_types_and_definitions(tmp_path: Path) -> None:
    recorded = load_inventory(RECORDING)
    document, notes = report_from_inventory(recorded)
    assert document["timestamp"] == "2026-01-15 10:00:00"
    reimported = _reimport(recorded, tmp_path)
    assert [(i.kind, i.name, i.type_name) for i in reimported.interfaces] == [
        (i.kind, i.name, i.type_name) for i in recorded.interfaces
    ]
    exported = 0
    for before, after in zip(recorded.interfaces, reimported.interfaces, strict=True):
        if not after.definitions:
            assert any(before.name in note for note in notes)
            continue
        exported += 1
        assert sorted(after.definitions) == sorted(before.definitions)
        for role, definition in before.definitions.items():
            assert after.definitions[role].fields == definition.fields, (before.name, role)
            assert after.definitions[role].constants == definition.constants
    assert exported == len(recorded.interfaces)
    # Nested comments are left out, as `ros2 interface show` does.
    odom = next(e for e in document["ros2_control_entities"]["topics"] if e["name"] == "/odom")
    details = odom["interfaces"][0]["details"]
    assert "\tstd_msgs/Header header" not in details
    assert "\n\tbuiltin_interfaces/Time stamp\n\t\tint32 sec\n" in details
    assert not any(
        line.lstrip("\t").startswith("#") for line in details.split("\n") if line.startswith("\t")
    )


def _interface(name: str, type_name: str, text: str) -> Interface:
    return Interface(
        name=name,
        kind="topic",
        type_name=type_name,
        definitions={
            "message": MessageDefinition(
                type_name=type_name, encoding="ros2msg", raw=text, fields=[]
            )
        },
    )


def test_one_name_with_two_types_becomes_one_entry_with_two_interfaces() -> None:
    from skillwright.interfaces.ros2msg import definition_from_text

    a = _interface("/x", "p/msg/A", "int8 a")
    a.definitions["message"] = definition_from_text("p/msg/A", "int8 a")
    b = _interface("/x", "p/msg/B", "int8 b")
    b.definitions["message"] = definition_from_text("p/msg/B", "int8 b")
    a.description = Description(purpose="Both.", module="other", engine="rules")
    inventory = Inventory(resource=Resource(name="r"), interfaces=[a, b])
    document, notes = report_from_inventory(inventory)
    assert notes == []
    (entry,) = document["ros2_control_entities"]["topics"]
    assert entry["interfaces"] == [
        {"name": "p/msg/A", "details": "int8 a"},
        {"name": "p/msg/B", "details": "int8 b"},
    ]
    back = inventory_from_report(document, "r.json")
    assert [i.type_name for i in back.interfaces] == ["p/msg/A", "p/msg/B"]
    assert back.interfaces[1].description is not None
    assert back.interfaces[1].description.purpose == "Both."


def test_definitions_that_cannot_be_shown_leave_details_empty_with_a_note() -> None:
    idl = Interface(
        name="/idl",
        kind="topic",
        type_name="p/msg/I",
        definitions={
            "message": MessageDefinition(
                type_name="p/msg/I", encoding="ros2idl", raw="module p {};"
            )
        },
    )
    missing = Interface(name="/s", kind="service", type_name="p/srv/S")
    untyped = Interface(name="/a", kind="action", type_name="")
    inventory = Inventory(resource=Resource(name="r"), interfaces=[idl, missing, untyped])
    document, notes = report_from_inventory(inventory)
    details = [
        entry["interfaces"][0]["details"]
        for section in document["ros2_control_entities"].values()
        for entry in section
    ]
    assert details == ["", ""]
    assert notes == [
        "topic /idl: no complete ros2msg definition of p/msg/I; its details are left empty",
        "service /s: no complete ros2msg definition of p/srv/S; its details are left empty",
        "action /a: type unknown; left out",
    ]
    assert document["ros2_control_entities"]["actions"] == []


def test_timestamp_comes_from_the_capture_time_or_the_first_message() -> None:
    inventory = Inventory(
        resource=Resource(name="r"),
        sources=[Source(kind="report", location="a.json", captured_at="2024-05-06 07:08:09")],
    )
    assert report_from_inventory(inventory)[0]["timestamp"] == "2024-05-06 07:08:09"
    inventory.sources = [Source(kind="mcap", location="b.mcap", start_time_ns=86_400 * 10**9)]
    assert report_from_inventory(inventory)[0]["timestamp"] == "1970-01-02 00:00:00"
