"""ros2msg definitions parse into field trees: types, arrays, bounds, defaults, constants."""

from __future__ import annotations

import pytest

from skillwright.interfaces.ros2msg import (
    definition_from_text,
    normalize_type_name,
    split_service,
)

SEPARATOR = "=" * 80


@pytest.mark.parametrize(
    ("line", "expected"),
    [
        ("int32 x", ("int32", "none", None, None, None)),
        ("int32[] xs", ("int32", "unbounded", None, None, None)),
        ("int32[3] xs", ("int32", "fixed", 3, None, None)),
        ("int32[<=5] xs", ("int32", "bounded", 5, None, None)),
        ("string<=10 s", ("string", "none", None, 10, None)),
        ("string<=10[<=4] s", ("string", "bounded", 4, 10, None)),
        ("wstring w", ("wstring", "none", None, None, None)),
        ("float64 x 1.5", ("float64", "none", None, None, 1.5)),
        ("int8 x -0x10", ("int8", "none", None, None, -16)),
        ("bool b true", ("bool", "none", None, None, True)),
        ("string s 'a # not a comment'", ("string", "none", None, None, "a # not a comment")),
        ('string s "q\\"uote"  # comment', ("string", "none", None, None, 'q"uote')),
        ("int32[] xs [1, -2, 3]", ("int32", "unbounded", None, None, [1, -2, 3])),
        ("string[2] ss ['a,b', \"c\"]", ("string", "fixed", 2, None, ["a,b", "c"])),
        ("float32[<=2] fs [1.0, 2.5]", ("float32", "bounded", 2, None, [1.0, 2.5])),
    ],
)
def test_field_line_parses(line: str, expected: tuple[object, ...]) -> None:
    definition = definition_from_text("pkg/msg/T", line)
    assert definition.notes == []
    (field,) = definition.fields or []
    assert (
        field.base_type,
        field.array,
        field.array_size,
        field.string_bound,
        field.default,
    ) == expected
    assert field.builtin


@pytest.mark.parametrize(
    ("line", "name", "value"),
    [
        ("int32 MAX=5", "MAX", 5),
        ("uint8 REQUEST_SENT = 0", "REQUEST_SENT", 0),
        ("float64 PI=3.14 # approx", "PI", 3.14),
        ('string GREETING="hi # there"', "GREETING", "hi # there"),
        ("bool FLAG=false", "FLAG", False),
    ],
)
def test_constant_line_parses(line: str, name: str, value: object) -> None:
    definition = definition_from_text("pkg/msg/T", line)
    assert definition.fields == []
    assert [(c.name, c.value) for c in definition.constants] == [(name, value)]


def test_nested_blocks_expand_with_and_without_msg_namespace() -> None:
    text = "\n".join(
        [
            "# a pose",
            "geometry_msgs/Point position",
            "geometry_msgs/msg/Quaternion orientation",
            "Extra[2] extras",
            SEPARATOR,
            "MSG: geometry_msgs/Point",
            "float64 x",
            "float64 y",
            "float64 z",
            SEPARATOR,
            "MSG: geometry_msgs/msg/Quaternion",
            "float64 x",
            "float64 y",
            "float64 z",
            "float64 w 1.0",
            SEPARATOR,
            "MSG: demo/Extra",
            "uint8 KIND_A=1",
            "uint8 kind",
        ]
    )
    definition = definition_from_text("demo/Pose", text)
    assert definition.type_name == "demo/msg/Pose"
    assert definition.notes == []
    position, orientation, extras = definition.fields or []
    assert position.base_type == "geometry_msgs/msg/Point"
    assert [f.name for f in position.fields] == ["x", "y", "z"]
    assert orientation.fields[-1].default == 1.0
    assert extras.base_type == "demo/msg/Extra"
    assert (extras.array, extras.array_size) == ("fixed", 2)
    assert [c.name for c in extras.constants] == ["KIND_A"]


def test_missing_dependency_is_unresolved_with_a_note() -> None:
    definition = definition_from_text("demo/msg/A", "other_pkg/Thing thing")
    (field,) = definition.fields or []
    assert not field.resolved
    assert field.fields == []
    assert definition.notes == [
        "field 'thing': definition of other_pkg/msg/Thing is not in the schema"
    ]


def test_self_reference_stops_instead_of_recursing_forever() -> None:
    text = f"Node child\n{SEPARATOR}\nMSG: demo/Node\nNode child"
    definition = definition_from_text("demo/msg/Node", text)
    depth = 0
    field = (definition.fields or [])[0]
    while field.fields:
        field = field.fields[0]
        depth += 1
    assert not field.resolved
    assert depth < 30


def test_malformed_lines_become_notes_not_errors() -> None:
    definition = definition_from_text("demo/msg/Bad", "int32\nint32 9lives\nfloat64 ok\nx!y z")
    assert [(f.name, f.resolved) for f in definition.fields or []] == [("ok", True), ("z", False)]
    assert len(definition.notes) == 3
    assert "not a ROS 2 type" in definition.notes[-1]


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("std_msgs/String", "std_msgs/msg/String"),
        ("std_msgs/msg/String", "std_msgs/msg/String"),
        ("example_interfaces/srv/AddTwoInts_Event", "example_interfaces/srv/AddTwoInts_Event"),
        ("Header", "std_msgs/msg/Header"),
    ],
)
def test_type_names_normalize(name: str, expected: str) -> None:
    assert normalize_type_name(name) == expected


def test_bare_type_takes_the_package_of_its_block() -> None:
    assert normalize_type_name("Goal", "demo") == "demo/msg/Goal"


def test_srv_text_splits_at_the_dashes() -> None:
    assert split_service("int64 a\nint64 b\n---\nint64 sum\n") == ("int64 a\nint64 b", "int64 sum")
    assert split_service("int64 a\n---\n") == ("int64 a", "")
    assert split_service("int64 a") is None


def test_dashes_inside_dependency_blocks_do_not_split() -> None:
    text = f"Inner a\n{SEPARATOR}\nMSG: demo/Inner\n---\nint32 x"
    assert split_service(text) is None
