"""Reference-tool reports import into inventories: all three shapes, definitions, descriptions."""

from __future__ import annotations

import json
import threading
from pathlib import Path
from typing import Any

import pytest

from skillwright.errors import FileFormatError, OperationCancelledError
from skillwright.interfaces.inventory import Description, MessageField
from skillwright.interfaces.load import discover_path
from skillwright.interfaces.sources.report import (
    definitions_from_details,
    description_from_text,
    description_to_text,
    details_from_definitions,
    inventory_from_report,
    read_report,
)

REPORTS = Path("cap2skill") / "interface-reports"


@pytest.fixture
def raw_report(shared_data: Path) -> Path:
    return shared_data / REPORTS / "ros2_system_report.json"


@pytest.fixture
def described_report(shared_data: Path) -> Path:
    return shared_data / REPORTS / "ros2_system_report_with_descriptions.json"


def _field(fields: list[MessageField] | None, path: str) -> MessageField:
    """The field at a dotted path (``points.time_from_start.sec``)."""
    current = fields or []
    found: MessageField | None = None
    for name in path.split("."):
        found = next(f for f in current if f.name == name)
        current = found.fields
    assert found is not None
    return found


def _unresolved(fields: list[MessageField] | None) -> list[str]:
    out = []
    for field in fields or []:
        if not field.resolved:
            out.append(field.name)
        out.extend(f"{field.name}.{name}" for name in _unresolved(field.fields))
    return out


def test_raw_report_imports_every_topic_service_and_action(raw_report: Path) -> None:
    inventory = read_report(raw_report)
    kinds = [i.kind for i in inventory.interfaces]
    assert (kinds.count("topic"), kinds.count("service"), kinds.count("action")) == (18, 88, 1)
    source = inventory.sources[0]
    assert (source.kind, source.captured_at) == ("report", "2025-03-04 13:46:42")
    assert inventory.resource.name == "ros2_system_report"
    # Every nested type the report expands is resolved: nothing is left unexpanded.
    for interface in inventory.interfaces:
        expected = {"topic": 1, "service": 2, "action": 3}[interface.kind]
        assert len(interface.definitions) == expected, interface.name
        for definition in interface.definitions.values():
            assert _unresolved(definition.fields) == [], (interface.name, definition.notes)


def test_report_details_become_nested_field_trees(raw_report: Path) -> None:
    inventory = read_report(raw_report)
    twist = inventory.interface("/cmd_vel").definitions["message"]
    assert twist.type_name == "geometry_msgs/msg/Twist"
    assert [f.name for f in twist.fields or []] == ["linear", "angular"]
    linear = _field(twist.fields, "linear")
    assert linear.base_type == "geometry_msgs/msg/Vector3"
    assert [f.name for f in linear.fields] == ["x", "y", "z"]
    assert "MSG: geometry_msgs/msg/Vector3" in twist.raw

    action = inventory.interface("/joint_trajectory_controller/follow_joint_trajectory")
    assert action.type_name == "control_msgs/action/FollowJointTrajectory"
    goal = action.definitions["goal"]
    assert goal.type_name == "control_msgs/action/FollowJointTrajectory_Goal"
    sec = _field(goal.fields, "trajectory.points.time_from_start.sec")
    assert (sec.type, sec.builtin) == ("int32", True)
    points = _field(goal.fields, "trajectory.points")
    assert (points.base_type, points.array) == (
        "trajectory_msgs/msg/JointTrajectoryPoint",
        "unbounded",
    )
    rotation_w = _field(goal.fields, "multi_dof_trajectory.points.transforms.rotation.w")
    assert rotation_w.default == 1.0
    tolerance = _field(goal.fields, "component_path_tolerance")
    assert [c.name for c in tolerance.constants][:2] == ["X_AXIS", "Y_AXIS"]
    result = action.definitions["result"]
    assert {c.name: c.value for c in result.constants}["INVALID_GOAL"] == -1
    feedback = action.definitions["feedback"]
    assert [f.name for f in feedback.fields or []][:3] == ["header", "joint_names", "desired"]


def test_service_details_split_into_request_and_response(raw_report: Path) -> None:
    inventory = read_report(raw_report)
    effort = inventory.interface("/apply_joint_effort", "service")
    request, response = effort.definitions["request"], effort.definitions["response"]
    assert request.type_name == "gazebo_msgs/srv/ApplyJointEffort_Request"
    assert [f.name for f in request.fields or []] == [
        "joint_name",
        "effort",
        "start_time",
        "duration",
    ]
    assert [f.name for f in response.fields or []] == ["success", "status_message"]
    # Gazebo's own services are simulator tooling (interfaces/infrastructure.py).
    assert effort.infrastructure is not None
    assert effort.infrastructure.rule == "simulator_services"
    assert inventory.interface("/cmd_vel", "topic").infrastructure is None
    parameters = inventory.interface("/gazebo/describe_parameters", "service")
    assert parameters.infrastructure is not None
    assert parameters.infrastructure.rule == "parameter_services"


def test_report_with_descriptions_imports_each_description(described_report: Path) -> None:
    inventory = read_report(described_report)
    assert len(inventory.interfaces) == 33
    assert all(i.description is not None for i in inventory.interfaces)
    assert inventory.sources[0].captured_at is None
    description = inventory.interface("/cmd_vel").description
    assert description is not None
    assert description.engine == "report"
    assert description.purpose.startswith("The `/cmd_vel` topic is used to command the velocity")
    assert (
        description.module
        == "This element relates to the motion control module of the mobile robot."
    )
    assert len(description.tasks) == 1
    assert description.tasks[0].startswith("The `/cmd_vel` topic is crucial for tasks")
    assert description.used_by[0].startswith("It is commonly used in ROS2 systems")
    # Two purpose items are joined into one text; two task items stay two.
    trajectory = inventory.interface("/joint_trajectory_controller/joint_trajectory").description
    assert trajectory is not None
    assert "It is typically used for controlling the movement" in trajectory.purpose
    assert len(trajectory.tasks) == 2


def test_the_rest_services_answer_reads_as_the_saved_report_it_was_made_from(
    described_report: Path, tmp_path: Path
) -> None:
    # /generate-system-report/ answers {"control_entities": [...]}: the same entries, and
    # an empty description where the tool wrote none
    saved = json.loads(described_report.read_text(encoding="utf-8"))
    entries = saved["ros2_control_entities"]
    entries[0] = {**entries[0], "description": ""}
    answered = tmp_path / "api_documentation.json"
    answered.write_text(json.dumps({"control_entities": entries}), encoding="utf-8")
    inventory = read_report(answered)
    expected = inventory_from_report({"ros2_control_entities": entries}, "same")
    assert inventory.interfaces == expected.interfaces
    assert len(inventory.interfaces) == 33
    assert inventory.interface(entries[0]["name"]).description is None
    assert discover_path(answered).interfaces == inventory.interfaces


@pytest.mark.parametrize(
    ("document", "message"),
    [
        ({"control_entities": {"topics": []}}, r"r\.json: control_entities: expected a list"),
        (
            {"control_entities": [{"name": "/a", "type": "topic"}]},
            r"r\.json: control_entities\[0\]\.interfaces: expected a list",
        ),
        ({"entities": []}, r"no 'ros2_control_entities' or 'control_entities'"),
    ],
)
def test_a_bad_rest_answer_is_named_by_file_and_json_path(document: Any, message: str) -> None:
    with pytest.raises(FileFormatError, match=message):
        inventory_from_report(document, "r.json")


def _report(entries: list[dict[str, Any]]) -> dict[str, Any]:
    return {"timestamp": "2025-01-01 00:00:00", "ros2_control_entities": {"topics": entries}}


def test_entry_with_several_types_gives_one_interface_per_type() -> None:
    document = _report(
        [
            {
                "name": "/data",
                "type": "topic",
                "interfaces": [
                    {"name": "std_msgs/msg/String", "details": "string data"},
                    {"name": "std_msgs/msg/Int32", "details": "int32 data"},
                ],
            }
        ]
    )
    inventory = inventory_from_report(document, "two.json")
    assert [(i.name, i.type_name) for i in inventory.interfaces] == [
        ("/data", "std_msgs/msg/String"),
        ("/data", "std_msgs/msg/Int32"),
    ]
    assert all("the report gives it 2 types" in i.notes[-1] for i in inventory.interfaces)
    int_field = (inventory.interfaces[1].definitions["message"].fields or [])[0]
    assert (int_field.name, int_field.type) == ("data", "int32")


@pytest.mark.parametrize(
    "interface",
    [
        {"name": "pkg/msg/T"},
        {"name": "pkg/msg/T", "details": None},
        {"name": "pkg/msg/T", "details": "  "},
    ],
)
def test_entry_without_details_has_no_invented_definition(interface: dict[str, Any]) -> None:
    document = _report([{"name": "/t", "type": "topic", "interfaces": [interface]}])
    entry = inventory_from_report(document, "r.json").interfaces[0]
    assert entry.type_name == "pkg/msg/T"
    assert entry.definitions == {}
    assert "the report gives no definition of pkg/msg/T" in entry.notes


def test_short_type_names_get_the_namespace_of_their_kind() -> None:
    document = {
        "ros2_control_entities": [
            {
                "name": "/s",
                "type": "service",
                "interfaces": [{"name": "pkg/Reset", "details": "---\nbool ok"}],
            }
        ]
    }
    entry = inventory_from_report(document, "flat.json").interfaces[0]
    assert entry.type_name == "pkg/srv/Reset"
    assert entry.definitions["request"].fields == []
    assert [f.name for f in entry.definitions["response"].fields or []] == ["ok"]


def test_details_with_the_wrong_number_of_parts_are_kept_whole() -> None:
    definitions, notes = definitions_from_details("service", "pkg/srv/S", "int32 a")
    assert list(definitions) == ["details"]
    assert definitions["details"].raw == "int32 a"
    assert "has 1 part(s) between `---` lines, a service has 2" in notes[0]
    assert details_from_definitions("service", definitions) == "int32 a"


@pytest.mark.parametrize(
    ("document", "message"),
    [
        ({"ros2_control_entities": 3}, r"r\.json: ros2_control_entities: expected an object"),
        (
            {"ros2_control_entities": {"nodes": []}},
            r"ros2_control_entities\.nodes: unknown section",
        ),
        (
            {"ros2_control_entities": {"topics": {}}},
            r"ros2_control_entities\.topics: expected a list",
        ),
        (
            {"ros2_control_entities": {"topics": [5]}},
            r"ros2_control_entities\.topics\[0\]: expected an object",
        ),
        (
            {"ros2_control_entities": {"topics": [{"type": "topic", "interfaces": []}]}},
            r"ros2_control_entities\.topics\[0\]\.name: expected a non-empty string, found null",
        ),
        (
            {"ros2_control_entities": [{"name": "/a", "type": "node", "interfaces": []}]},
            r"ros2_control_entities\[0\]\.type: \"node\" is not topic, service or action",
        ),
        (
            {
                "ros2_control_entities": {
                    "services": [{"name": "/a", "type": "topic", "interfaces": []}]
                }
            },
            r"services\[0\]\.type: a topic in the services section",
        ),
        (
            {"ros2_control_entities": [{"name": "/a", "type": "topic"}]},
            r"ros2_control_entities\[0\]\.interfaces: expected a list",
        ),
        (
            {
                "ros2_control_entities": [
                    {"name": "/a", "type": "topic", "interfaces": [{"details": "x"}]}
                ]
            },
            r"ros2_control_entities\[0\]\.interfaces\[0\]\.name: expected a non-empty string",
        ),
        (
            {
                "ros2_control_entities": [
                    {
                        "name": "/a",
                        "type": "topic",
                        "interfaces": [{"name": "p/msg/T", "details": 4}],
                    }
                ]
            },
            r"interfaces\[0\]\.details: expected a string or null",
        ),
        (
            {
                "ros2_control_entities": [
                    {"name": "/a", "type": "topic", "description": [], "interfaces": []}
                ]
            },
            r"ros2_control_entities\[0\]\.description: expected a string",
        ),
    ],
)
def test_bad_report_entries_are_named_by_file_and_json_path(document: Any, message: str) -> None:
    with pytest.raises(FileFormatError, match=message):
        inventory_from_report(document, "r.json")


def test_report_file_with_a_syntax_error_names_line_and_column(tmp_path: Path) -> None:
    path = tmp_path / "broken.json"
    path.write_text('{"ros2_control_entities": [\n  {"name": }\n]}', encoding="utf-8")
    with pytest.raises(FileFormatError, match=r"broken\.json:2:12: JSON syntax error"):
        read_report(path)


# --- the text of `ros2 interface show` -------------------------------------------------


@pytest.mark.parametrize(
    ("line", "shown"),
    [
        ("float64 x", "float64 x"),
        ("", None),
        ("# a comment", None),
        ("#", "#"),  # rosidl reduces it to nothing, so ros2cli does not see a comment
        ("##", "##"),
        ("# [m]", "# [m]"),  # only a unit: nothing left either
        ("string name  # The name", "string name  #"),  # ros2cli cuts one character late
        ("string name  #The name", "string name"),
        ("string name        #", "string name        #"),
        ("float64 d  # distance [m]", "float64 d  #"),
        ("uint8 A=1  # constants keep comments", "uint8 A=1  # constants keep comments"),
        ("    # indented comment", "    # indented comment"),
        ("float64 x 0", "float64 x 0"),
    ],
)
def test_nested_lines_are_shown_as_ros2cli_shows_them(line: str, shown: str | None) -> None:
    from skillwright.interfaces.sources.report import _shown_nested

    assert _shown_nested(line) == shown
    if shown is not None:
        assert _shown_nested(shown) == shown  # its own output is a fixed point


def test_details_keep_blank_lines_between_blocks() -> None:
    details = "std_msgs/Header header\n\tint32 a\n\n# next\nint32 b\n\n---\nbool ok"
    definitions, notes = definitions_from_details("service", "p/srv/S", details)
    assert notes == []
    assert details_from_definitions("service", definitions) == details
    request = definitions["request"]
    assert [f.name for f in request.fields or []] == ["header", "b"]
    assert _field(request.fields, "header").base_type == "std_msgs/msg/Header"


def test_fields_of_the_same_package_resolve_inside_nested_types() -> None:
    details = "geometry_msgs/Pose pose\n\tPoint position\n\t\tfloat64 x\n\tQuaternion orientation\n\t\tfloat64 w 1"
    definitions, _ = definitions_from_details("topic", "nav_msgs/msg/Goal", details)
    fields = definitions["message"].fields
    assert _field(fields, "pose.position").base_type == "geometry_msgs/msg/Point"
    assert _field(fields, "pose.orientation.w").default == 1.0


# --- descriptions ----------------------------------------------------------------------


def test_description_sections_map_to_purpose_module_tasks_and_users() -> None:
    text = (
        "**Purpose of the ROS2 Element:**\n- Moves the base.\n  Continued here.\n\n"
        "### Mobile Robot Module:\n   - Base motion.\n\n"
        "Relevance for Specific Tasks:\n    - Drive.\n    - Stop.\n\n"
        "Usage in the ROS2 System:\n    - Teleop.\n"
    )
    description = description_from_text(text)
    assert description == Description(
        purpose="Moves the base. Continued here.",
        module="Base motion.",
        tasks=["Drive.", "Stop."],
        used_by=["Teleop."],
        engine="report",
    )


def test_description_without_sections_keeps_its_text_as_purpose() -> None:
    description = description_from_text("Publishes the laser scan.")
    assert description.purpose == "Publishes the laser scan."
    assert description.module == "other"
    assert description.tasks == []


def test_description_text_reads_back_to_the_same_description() -> None:
    description = Description(
        purpose="Commands velocity.",
        module="base motion",
        tasks=["drive", "rotate"],
        used_by=["skills"],
        key_fields=["linear.x"],
        engine="report",
    )
    text = description_to_text(description)
    assert text.startswith(
        "Purpose of the ROS2 Element:\n    - Commands velocity.\n\nMobile Robot Module:"
    )
    assert "Key Fields:\n    - linear.x" in text
    assert description_from_text(text) == description


def test_report_json_is_detected_by_load_inventory(raw_report: Path, tmp_path: Path) -> None:
    from skillwright.interfaces.load import load_inventory

    assert load_inventory(raw_report) == read_report(raw_report)
    # Detected by content, not by name.
    copy = tmp_path / "report.txt"
    copy.write_text(raw_report.read_text(encoding="utf-8"), encoding="utf-8")
    assert len(load_inventory(copy).interfaces) == 107
    other = tmp_path / "other.json"
    other.write_text(json.dumps({"a": 1}), encoding="utf-8")
    with pytest.raises(FileFormatError, match=r"neither a skillwright inventory .* nor a report"):
        load_inventory(other)


def test_a_cancelled_import_stops_between_entries(monkeypatch: pytest.MonkeyPatch) -> None:
    from skillwright.interfaces.sources import report

    cancel = threading.Event()
    imported: list[str] = []
    real = report._interfaces_of

    def import_then_cancel(entry: dict[str, Any], *args: Any) -> Any:
        imported.append(entry["name"])
        cancel.set()  # Esc while the first entry is being read
        return real(entry, *args)

    monkeypatch.setattr(report, "_interfaces_of", import_then_cancel)
    entries = [
        {"name": name, "type": "topic", "interfaces": [{"name": "std_msgs/msg/String"}]}
        for name in ("/a", "/b", "/c")
    ]
    with pytest.raises(OperationCancelledError, match=r"reading r\.json cancelled"):
        inventory_from_report(_report(entries), "r.json", cancel=cancel)
    assert imported == ["/a"]
