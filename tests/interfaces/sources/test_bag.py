"""The bag source groups recorded channels into topics, services and actions."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright import errors
from skillwright.interfaces.sources.bag import discover_bag, parse_qos_profiles, resolve_recording
from tests.interfaces.sources.recordings import SEPARATOR, Topic, event_schema, write_recording

pytest.importorskip("mcap")

FIBONACCI_FEEDBACK = "\n".join(
    [
        "unique_identifier_msgs/UUID goal_id",
        "Fibonacci_Feedback feedback",
        SEPARATOR,
        "MSG: unique_identifier_msgs/UUID",
        "uint8[16] uuid",
        SEPARATOR,
        "MSG: example_interfaces/Fibonacci_Feedback",
        "int32[] sequence",
    ]
)


def _action_topics() -> list[Topic]:
    send_goal = event_schema(
        "example_interfaces",
        "action",
        "Fibonacci_SendGoal",
        "unique_identifier_msgs/UUID goal_id\nFibonacci_Goal goal\n"
        + SEPARATOR
        + "\nMSG: example_interfaces/action/Fibonacci_Goal\nint32 order",
        "bool accepted\nbuiltin_interfaces/Time stamp",
    )
    get_result = event_schema(
        "example_interfaces",
        "action",
        "Fibonacci_GetResult",
        "unique_identifier_msgs/UUID goal_id",
        "int8 status\nFibonacci_Result result\n"
        + SEPARATOR
        + "\nMSG: example_interfaces/action/Fibonacci_Result\nint32[] sequence",
    )
    return [
        Topic(
            "/fibonacci/_action/feedback",
            "example_interfaces/action/Fibonacci_FeedbackMessage",
            FIBONACCI_FEEDBACK,
            messages=5,
        ),
        Topic(
            "/fibonacci/_action/status",
            "action_msgs/msg/GoalStatusArray",
            "GoalStatus[] status_list",
            messages=2,
        ),
        Topic(
            "/fibonacci/_action/send_goal/_service_event",
            "example_interfaces/action/Fibonacci_SendGoal_Event",
            send_goal,
            messages=2,
        ),
        Topic(
            "/fibonacci/_action/get_result/_service_event",
            "example_interfaces/action/Fibonacci_GetResult_Event",
            get_result,
            messages=2,
        ),
        Topic(
            "/fibonacci/_action/cancel_goal/_service_event",
            "action_msgs/srv/CancelGoal_Event",
            "CancelGoal_Request[<=1] request",
            messages=0,
        ),
    ]


def test_action_parts_become_one_action_with_goal_result_and_feedback(tmp_path: Path) -> None:
    bag = write_recording(tmp_path / "action.mcap", _action_topics())
    inventory = discover_bag(bag)

    assert [(i.kind, i.name) for i in inventory.interfaces] == [("action", "/fibonacci")]
    action = inventory.interfaces[0]
    assert action.type_name == "example_interfaces/action/Fibonacci"
    assert sorted(action.definitions) == ["feedback", "goal", "result"]
    assert [f.name for f in action.definitions["goal"].fields or []] == ["order"]
    result = (action.definitions["result"].fields or [])[0]
    assert (result.name, result.array) == ("sequence", "unbounded")
    assert (
        action.definitions["feedback"].type_name == "example_interfaces/action/Fibonacci_Feedback"
    )
    assert sorted(c.role for c in action.channels) == [
        "cancel_goal",
        "feedback",
        "get_result",
        "send_goal",
        "status",
    ]
    assert action.traffic is not None
    assert action.traffic.message_count == 11


def test_expanded_service_event_schema_gives_request_and_response(tmp_path: Path) -> None:
    schema = event_schema(
        "example_interfaces", "srv", "AddTwoInts", "int64 a\nint64 b", "int64 sum"
    )
    bag = write_recording(
        tmp_path / "svc.mcap",
        [Topic("/add/_service_event", "example_interfaces/srv/AddTwoInts_Event", schema)],
    )
    service = discover_bag(bag).interface("/add", "service")
    assert service.type_name == "example_interfaces/srv/AddTwoInts"
    assert [f.name for f in service.definitions["request"].fields or []] == ["a", "b"]
    assert [f.name for f in service.definitions["response"].fields or []] == ["sum"]
    assert service.definitions["request"].type_name == "example_interfaces/srv/AddTwoInts_Request"


def test_raw_srv_text_schema_gives_request_and_response(tmp_path: Path) -> None:
    bag = write_recording(
        tmp_path / "svc.mcap",
        [
            Topic(
                "/ns/set_speed/_service_event",
                "demo/srv/SetSpeed_Event",
                "float64 speed # m/s\nstring<=8 mode 'eco'\n---\nbool ok\nstring message",
            )
        ],
    )
    service = discover_bag(bag).interface("/ns/set_speed")
    request = service.definitions["request"].fields or []
    assert [(f.name, f.string_bound, f.default) for f in request] == [
        ("speed", None, None),
        ("mode", 8, "eco"),
    ]
    assert service.definitions["response"].raw == "bool ok\nstring message"


def test_non_ros2_encodings_are_kept_raw_with_a_note(tmp_path: Path) -> None:
    bag = write_recording(
        tmp_path / "mixed.mcap",
        [
            Topic(
                "/proto",
                "demo.Pose",
                b"\x0a\x05\xff\xfe\x00",
                schema_encoding="protobuf",
                message_encoding="protobuf",
            ),
            Topic(
                "/json",
                "Pose",
                '{"type": "object"}',
                schema_encoding="jsonschema",
                message_encoding="json",
            ),
            Topic(
                "/idl",
                "demo/msg/Pose",
                "module demo { struct Pose { double x; }; };",
                schema_encoding="ros2idl",
            ),
            Topic("/raw", "", schemaless=True, message_encoding="mystery"),
        ],
    )
    inventory = discover_bag(bag)
    proto = inventory.interface("/proto").definitions["message"]
    assert proto.encoding == "protobuf"
    assert proto.fields is None
    assert any("base64" in note for note in proto.notes)
    assert inventory.interface("/json").definitions["message"].raw == '{"type": "object"}'
    idl = inventory.interface("/idl").definitions["message"]
    assert (idl.encoding, idl.fields) == ("ros2idl", None)
    raw = inventory.interface("/raw")
    assert raw.definitions == {}
    assert any("without a schema" in note for note in raw.notes)
    assert any("'mystery'" in note for note in raw.notes)


def test_topics_and_infrastructure_flags(tmp_path: Path) -> None:
    bag = write_recording(
        tmp_path / "robot.mcap",
        [
            Topic(
                "/cmd_vel",
                "geometry_msgs/msg/Twist",
                "Vector3 linear\nVector3 angular\n"
                + SEPARATOR
                + "\nMSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z",
                messages=11,
            ),
            Topic("/rosout", "rcl_interfaces/msg/Log", "uint8 level\nstring msg"),
        ],
    )
    inventory = discover_bag(bag)
    cmd_vel = inventory.interface("/cmd_vel")
    assert cmd_vel.infrastructure is None
    linear = (cmd_vel.definitions["message"].fields or [])[0]
    assert linear.base_type == "geometry_msgs/msg/Vector3"
    assert [f.name for f in linear.fields] == ["x", "y", "z"]
    assert cmd_vel.traffic is not None
    assert cmd_vel.traffic.rate_hz == pytest.approx(10.0)
    rosout = inventory.interface("/rosout")
    assert rosout.infrastructure is not None
    assert rosout.infrastructure.rule == "rosout"


def test_split_folder_without_metadata_is_merged_in_split_order(tmp_path: Path) -> None:
    folder = tmp_path / "bag"
    folder.mkdir()
    for index in (10, 2, 0):
        write_recording(
            folder / f"bag_{index}.mcap", [Topic("/scan", "sensor_msgs/LaserScan", "float32[] r")]
        )
    recording = resolve_recording(folder)
    assert [p.name for p in recording.files] == ["bag_0.mcap", "bag_2.mcap", "bag_10.mcap"]
    inventory = discover_bag(folder)
    scan = inventory.interface("/scan")
    assert scan.type_name == "sensor_msgs/msg/LaserScan"
    assert scan.traffic is not None
    assert scan.traffic.message_count == 9
    assert len(inventory.sources[0].files) == 3


def test_metadata_yaml_adds_qos_and_topics_missing_from_files(tmp_path: Path) -> None:
    folder = tmp_path / "bag"
    folder.mkdir()
    write_recording(folder / "bag_0.mcap", [Topic("/odom", "nav_msgs/msg/Odometry", "int32 x")])
    (folder / "metadata.yaml").write_text(
        """rosbag2_bagfile_information:
  version: 8
  storage_identifier: mcap
  message_count: 7
  ros_distro: jazzy
  relative_file_paths: [bag_0.mcap]
  topics_with_message_count:
    - topic_metadata:
        name: /odom
        type: nav_msgs/msg/Odometry
        serialization_format: cdr
        offered_qos_profiles: "- history: 1\\n  depth: 10\\n  reliability: 2\\n  \\
          durability: 2\\n  deadline:\\n    sec: 0\\n    nsec: 5000\\n"
      message_count: 3
    - topic_metadata:
        name: /lost
        type: std_msgs/String
        serialization_format: cdr
        offered_qos_profiles: ""
      message_count: 4
"""
    )
    inventory = discover_bag(folder)
    odom = inventory.interface("/odom")
    assert [(q.history, q.depth, q.reliability, q.deadline_ns) for q in odom.qos] == [
        ("keep_last", 10, "best_effort", 5000)
    ]
    lost = inventory.interface("/lost")
    assert lost.type_name == "std_msgs/msg/String"
    assert any("metadata.yaml" in note for note in lost.notes)
    assert inventory.sources[0].ros_distro == "jazzy"
    assert any("counts 7 messages" in note for note in inventory.sources[0].notes)


def test_qos_profiles_accept_names_as_well_as_numbers() -> None:
    profiles = parse_qos_profiles("- history: keep_all\n  reliability: RELIABLE\n")
    assert [(p.history, p.reliability) for p in profiles] == [("keep_all", "reliable")]
    assert parse_qos_profiles("{not: [a list") == []


def test_sqlite_bag_is_refused_with_advice(tmp_path: Path) -> None:
    (tmp_path / "metadata.yaml").write_text(
        "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n"
    )
    with pytest.raises(errors.FileFormatError, match="ros2 bag convert"):
        discover_bag(tmp_path)


def test_broken_metadata_yaml_names_file_and_line(tmp_path: Path) -> None:
    (tmp_path / "metadata.yaml").write_text("rosbag2_bagfile_information:\n  a: [1,\n")
    with pytest.raises(errors.FileFormatError, match=r"metadata\.yaml \(line \d+\)"):
        discover_bag(tmp_path)


def test_folder_without_recordings_is_an_invalid_argument(tmp_path: Path) -> None:
    with pytest.raises(errors.InvalidArgumentError, match=r"no \.mcap files"):
        discover_bag(tmp_path)


def test_missing_path_is_not_found(tmp_path: Path) -> None:
    with pytest.raises(errors.InputFileNotFoundError, match="nope"):
        discover_bag(tmp_path / "nope")


def test_truncated_recording_gives_a_partial_inventory(tmp_path: Path) -> None:
    bag = write_recording(
        tmp_path / "full.mcap",
        [Topic("/a", "std_msgs/msg/String", "string data", messages=400)],
    )
    data = bag.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) // 2])
    inventory = discover_bag(cut)
    source_file = inventory.sources[0].files[0]
    assert source_file.partial
    assert source_file.read_method == "scan"
    assert source_file.stopped_at is not None
    assert 0 < source_file.stopped_at.offset < len(data) // 2
    traffic = inventory.interface("/a").traffic
    assert traffic is not None
    assert 0 < traffic.message_count < 400


def _one_chunk_recording(path: Path, topics: int, messages: int) -> Path:
    """A recording in one uncompressed chunk whose channels are declared as their topics
    first publish, as a recorder does: channel records lie all through the chunk."""
    from mcap.writer import CompressionType, Writer

    with path.open("wb") as stream:
        writer = Writer(stream, compression=CompressionType.NONE, chunk_size=1 << 30)
        writer.start(profile="ros2", library="skillwright-tests")
        schema = writer.register_schema("std_msgs/msg/String", "ros2msg", b"string data")
        for topic in range(topics):
            channel = writer.register_channel(f"/sensor_{topic:02}", "cdr", schema)
            for index in range(messages):
                stamp = 1_700_000_000_000_000_000 + (topic * messages + index) * 1_000_000
                writer.add_message(channel, stamp, bytes(400), stamp, sequence=index)
        writer.finish()
    return path


@pytest.mark.parametrize("share", [50, 90])
def test_a_recording_cut_inside_its_uncompressed_chunk_keeps_the_channels_before_the_cut(
    tmp_path: Path, share: int
) -> None:
    data = _one_chunk_recording(tmp_path / "full.mcap", topics=32, messages=20).read_bytes()
    cut_at = len(data) * share // 100
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[:cut_at])
    # A channel record ends 11 bytes after its topic: the encoding "cdr" (4 + 3 bytes) and
    # an empty metadata map (4).
    intact = [
        f"/sensor_{t:02}"
        for t in range(32)
        if 0 <= data.find(f"/sensor_{t:02}".encode()) <= cut_at - len("/sensor_00") - 11
    ]
    assert 0 < len(intact) < 32
    for mode in ("auto", "scan", "full"):
        inventory = discover_bag(cut, mode)  # type: ignore[arg-type]
        assert [i.name for i in inventory.interfaces] == intact, mode
        counts = [i.traffic.message_count if i.traffic else 0 for i in inventory.interfaces]
        # Every channel before the last intact one has all its messages; the cut may fall
        # among the last one's.
        assert counts[:-1] == [20] * (len(intact) - 1)
        assert 0 <= counts[-1] <= 20
        file = inventory.sources[0].files[0]
        assert file.stopped_at is not None
        assert file.stopped_at.offset <= cut_at
        recovered = (
            f"{1 + len(intact) + sum(counts)} records were recovered "
            f"(1 schema, {len(intact)} channels, {sum(counts)} messages)"
        )
        assert recovered in file.stopped_at.message


def test_every_read_mode_gives_the_same_interfaces(tmp_path: Path) -> None:
    bag = write_recording(tmp_path / "action.mcap", _action_topics())
    dumps = {
        mode: [i.model_dump(exclude={"traffic"}) for i in discover_bag(bag, mode).interfaces]
        for mode in ("auto", "scan", "full")
    }
    assert dumps["auto"] == dumps["scan"] == dumps["full"]


def test_unreadable_split_is_skipped_with_a_note(tmp_path: Path) -> None:
    folder = tmp_path / "bag"
    folder.mkdir()
    write_recording(folder / "bag_0.mcap", [Topic("/a", "std_msgs/msg/String", "string data")])
    (folder / "bag_1.mcap").write_bytes(b"")  # the recorder died right after opening it
    inventory = discover_bag(folder)
    first, second = inventory.sources[0].files
    assert (first.read_method, second.read_method) == ("summary", "unreadable")
    assert second.partial
    assert second.stopped_at is not None
    assert "empty file" in second.stopped_at.message
    assert inventory.interface("/a").traffic is not None


def test_folder_where_no_file_is_readable_raises(tmp_path: Path) -> None:
    (tmp_path / "bag_0.mcap").write_bytes(b"not mcap")
    (tmp_path / "bag_1.mcap").write_bytes(b"")
    with pytest.raises(errors.FileFormatError, match=r"bag_0\.mcap: not an MCAP file"):
        discover_bag(tmp_path)
