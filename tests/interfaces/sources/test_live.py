"""Live discovery, driven by recorded graph answers (rclpy is not needed)."""

from __future__ import annotations

import sys
from dataclasses import dataclass, field, replace
from pathlib import Path

import pytest
from click.testing import CliRunner

from skillwright.cli import main
from skillwright.errors import InvalidArgumentError, Ros2UnavailableError
from skillwright.interfaces.inventory import Endpoints, Inventory, MessageField
from skillwright.interfaces.sources.live import (
    NOT_SETTLED,
    discover_live,
    is_hidden,
    settle,
)


@dataclass
class Frame:
    """What the graph answers during one snapshot."""

    topics: dict[str, list[str]] = field(default_factory=dict)
    services: dict[str, list[str]] = field(default_factory=dict)
    actions: dict[str, list[str]] = field(default_factory=dict)
    counts: dict[str, tuple[int, int]] = field(default_factory=dict)


@dataclass
class RecordedGraph:
    """Replays frames: each pause between snapshots moves on to the next frame."""

    frames: list[Frame]
    files: dict[str, str]
    distro: str | None = "jazzy"
    location: str = "recorded graph"
    time: float = 0.0
    index: int = 0
    asked: list[str] = field(default_factory=list)

    def now(self) -> float:
        return self.time

    def sleep(self, seconds: float) -> None:
        self.time += seconds
        self.index = min(self.index + 1, len(self.frames) - 1)

    @property
    def frame(self) -> Frame:
        return self.frames[self.index]

    def topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        return list(self.frame.topics.items())

    def service_names_and_types(self) -> list[tuple[str, list[str]]]:
        return list(self.frame.services.items())

    def action_names_and_types(self) -> list[tuple[str, list[str]]]:
        return list(self.frame.actions.items())

    def count_publishers(self, topic: str) -> int:
        return self.frame.counts.get(topic, (0, 0))[0]

    def count_subscribers(self, topic: str) -> int:
        return self.frame.counts.get(topic, (0, 0))[1]

    def interface_text(self, type_name: str) -> str | None:
        self.asked.append(type_name)
        return self.files.get(type_name)


FILES = {
    "geometry_msgs/msg/Twist": "# velocity in free space\nVector3  linear\nVector3  angular\n",
    "geometry_msgs/msg/Vector3": "float64 x\nfloat64 y\nfloat64 z\n",
    "std_srvs/srv/Trigger": "---\nbool success   # did it work\nstring message\n",
    # geometry_msgs/msg/Point is not installed: it comes from the type store.
    "demo_msgs/action/Move": "float64 distance 1.0\n---\nbool reached\n---\ngeometry_msgs/Point position\n",
}

ROBOT = Frame(
    topics={
        "/cmd_vel": ["geometry_msgs/msg/Twist"],
        "/rosout": ["rcl_interfaces/msg/Log"],
        "/move/_action/feedback": ["demo_msgs/action/Move_FeedbackMessage"],
        "/move/_action/status": ["action_msgs/msg/GoalStatusArray"],
        "/_debug/state": ["std_msgs/msg/String"],
    },
    services={
        "/reset": ["std_srvs/srv/Trigger"],
        "/driver/get_parameters": ["rcl_interfaces/srv/GetParameters"],
        "/move/_action/send_goal": ["demo_msgs/action/Move_SendGoal"],
        "/move/_action/get_result": ["demo_msgs/action/Move_GetResult"],
        "/move/_action/cancel_goal": ["action_msgs/srv/CancelGoal"],
    },
    actions={"/move": ["demo_msgs/action/Move"]},
    counts={
        "/cmd_vel": (1, 2),
        "/rosout": (3, 1),
        "/move/_action/status": (1, 2),
        "/move/_action/feedback": (1, 2),
    },
)
WITH_GRIPPER = replace(
    ROBOT,
    topics={**ROBOT.topics, "/gripper": ["acme_msgs/msg/Grip"]},
    counts={**ROBOT.counts, "/cmd_vel": (1, 3), "/gripper": (1, 0)},
)


def _discover(graph: RecordedGraph, **options: float) -> Inventory:
    return discover_live(graph, clock=graph.now, sleep=graph.sleep, **options)  # type: ignore[arg-type]


def _names(fields: list[MessageField] | None) -> list[str]:
    return [f.name for f in fields or []]


def test_topics_services_and_actions_become_inventory_entries() -> None:
    graph = RecordedGraph([ROBOT, ROBOT], FILES)
    inventory = _discover(graph)
    assert [(i.kind, i.name, i.type_name) for i in inventory.interfaces] == [
        ("topic", "/cmd_vel", "geometry_msgs/msg/Twist"),
        ("topic", "/rosout", "rcl_interfaces/msg/Log"),
        ("service", "/driver/get_parameters", "rcl_interfaces/srv/GetParameters"),
        ("service", "/reset", "std_srvs/srv/Trigger"),
        ("action", "/move", "demo_msgs/action/Move"),
    ]
    source = inventory.sources[0]
    assert (source.kind, source.location, source.ros_distro) == (
        "ros2_live",
        "recorded graph",
        "jazzy",
    )
    assert source.captured_at is not None
    assert source.notes[0] == "settled: snapshots 1 and 2 agreed (1.0 s)"
    assert any("1 hidden topic(s) and service(s)" in note for note in source.notes)

    cmd_vel = inventory.interface("/cmd_vel")
    assert cmd_vel.endpoints == Endpoints(publishers=1, subscribers=2)
    twist = cmd_vel.definitions["message"]
    assert (twist.origin, _names(twist.fields)) == ("source", ["linear", "angular"])
    assert _names((twist.fields or [])[0].fields) == ["x", "y", "z"]
    assert "MSG: geometry_msgs/msg/Vector3" in twist.raw

    reset = inventory.interface("/reset")
    assert reset.definitions["request"].fields == []
    assert _names(reset.definitions["response"].fields) == ["success", "message"]
    assert reset.endpoints is None

    move = inventory.interface("/move")
    assert move.endpoints == Endpoints(servers=1, clients=2)
    assert sorted(move.definitions) == ["feedback", "goal", "result"]
    goal = move.definitions["goal"]
    assert (goal.type_name, (goal.fields or [])[0].default) == (
        "demo_msgs/action/Move_Goal",
        1.0,
    )
    assert _names(move.definitions["result"].fields) == ["reached"]

    rosout = inventory.interface("/rosout")
    assert rosout.infrastructure is not None
    parameters = inventory.interface("/driver/get_parameters")
    assert parameters.infrastructure is not None
    assert parameters.infrastructure.rule == "parameter_services"


def test_each_type_is_fetched_once() -> None:
    graph = RecordedGraph([ROBOT, ROBOT], FILES)
    _discover(graph)
    assert len(graph.asked) == len(set(graph.asked))


def test_node_that_appears_late_is_waited_for() -> None:
    graph = RecordedGraph([ROBOT, WITH_GRIPPER, WITH_GRIPPER], FILES)
    inventory = _discover(graph)
    assert inventory.sources[0].notes[0] == "settled: snapshots 2 and 3 agreed (2.0 s)"
    assert inventory.interface("/gripper").endpoints == Endpoints(publishers=1, subscribers=0)
    assert inventory.interface("/cmd_vel").endpoints == Endpoints(publishers=1, subscribers=3)


def test_changed_counts_alone_keep_the_graph_from_settling() -> None:
    busier = replace(ROBOT, counts={**ROBOT.counts, "/cmd_vel": (2, 2)})
    graph = RecordedGraph([ROBOT, busier, busier], FILES)
    outcome = settle(
        graph, timeout=10, interval=1, max_attempts=5, clock=graph.now, sleep=graph.sleep
    )
    assert (outcome.agreed, outcome.attempts) == (True, 3)
    assert outcome.snapshot.counts["/cmd_vel"] == (2, 2)


def test_definitions_that_cannot_be_fetched_come_from_the_type_store_or_are_unknown() -> None:
    graph = RecordedGraph([WITH_GRIPPER, WITH_GRIPPER], FILES)
    inventory = _discover(graph)
    rosout = inventory.interface("/rosout")
    log = rosout.definitions["message"]
    assert log.origin == "type_store"
    assert "msg" in _names(log.fields)
    assert "the definition of rcl_interfaces/msg/Log could not be fetched from ROS 2 here" in (
        rosout.notes
    )
    gripper = inventory.interface("/gripper")
    assert gripper.definitions == {}
    assert gripper.notes[-1] == (
        "definition unknown: acme_msgs/msg/Grip is not in the offline type stores (Jazzy, Humble)"
    )
    # A standard service comes from the ROS 2 interface packages make setup installs.
    parameters = inventory.interface("/driver/get_parameters")
    assert sorted(parameters.definitions) == ["request", "response"]
    assert parameters.definitions["request"].origin == "type_store"
    assert "names" in _names(parameters.definitions["request"].fields)
    # A nested type that is not installed is expanded from the store, with a note.
    feedback = inventory.interface("/move").definitions["feedback"]
    position = (feedback.fields or [])[0]
    assert (position.base_type, position.resolved, _names(position.fields)) == (
        "geometry_msgs/msg/Point",
        True,
        ["x", "y", "z"],
    )
    assert feedback.notes[0] == (
        "geometry_msgs/msg/Point could not be fetched; taken from the offline ROS 2 Jazzy "
        "type store"
    )


def test_graph_that_never_settles_gives_the_last_snapshot_with_a_warning() -> None:
    graph = RecordedGraph([ROBOT, WITH_GRIPPER] * 20, FILES)
    inventory = _discover(graph, timeout=2.5, interval=1.0)
    note = inventory.sources[0].notes[0]
    assert note.startswith(f"{NOT_SETTLED}: no two consecutive of 4 snapshots agreed in 2.5 s")
    assert graph.time == 2.5
    # The fourth snapshot is the one with the gripper.
    assert [i.name for i in inventory.interfaces if i.kind == "topic"] == [
        "/cmd_vel",
        "/gripper",
        "/rosout",
    ]


def test_attempts_are_bounded_even_without_a_timeout() -> None:
    graph = RecordedGraph([ROBOT, WITH_GRIPPER] * 20, FILES)
    outcome = settle(
        graph, timeout=1e9, interval=1, max_attempts=6, clock=graph.now, sleep=graph.sleep
    )
    assert (outcome.agreed, outcome.attempts) == (False, 6)


def test_empty_graph_is_not_taken_for_a_settled_one() -> None:
    graph = RecordedGraph([Frame()], FILES)
    inventory = _discover(graph, timeout=3, interval=1)
    notes = inventory.sources[0].notes
    assert notes[0].startswith(NOT_SETTLED)
    assert "no topics, services or actions were seen" in notes[-1]
    assert inventory.interfaces == []


def test_action_seen_only_through_its_hidden_topics_and_services_is_listed() -> None:
    frame = replace(ROBOT, actions={})
    graph = RecordedGraph([frame, frame], FILES)
    move = _discover(graph).interface("/move", "action")
    assert move.type_name == "demo_msgs/action/Move"
    assert sorted(move.definitions) == ["feedback", "goal", "result"]


def test_topic_offered_with_two_types_gives_two_entries() -> None:
    frame = replace(
        ROBOT, topics={"/cmd_vel": ["geometry_msgs/msg/Twist", "geometry_msgs/msg/Vector3"]}
    )
    graph = RecordedGraph([frame, frame], FILES)
    entries = [i for i in _discover(graph).interfaces if i.kind == "topic"]
    assert [i.type_name for i in entries] == [
        "geometry_msgs/msg/Twist",
        "geometry_msgs/msg/Vector3",
    ]
    assert all("/cmd_vel: offered with 2 types" in i.notes for i in entries)


@pytest.mark.parametrize(
    ("name", "hidden"),
    [("/cmd_vel", False), ("/_private", True), ("/a/_action/status", True), ("/a_b/c", False)],
)
def test_hidden_names_are_those_ros2_tools_hide(name: str, hidden: bool) -> None:
    assert is_hidden(name) is hidden


def test_bad_settle_options_are_refused() -> None:
    graph = RecordedGraph([ROBOT], FILES)
    with pytest.raises(InvalidArgumentError, match="positive timeout"):
        settle(graph, timeout=0, interval=1, max_attempts=5)


# --- without ROS 2 ---------------------------------------------------------------------


def test_missing_rclpy_says_to_source_ros2(monkeypatch: pytest.MonkeyPatch) -> None:
    from skillwright.interfaces.sources.rclpy_graph import open_graph

    monkeypatch.setitem(sys.modules, "rclpy", None)
    monkeypatch.delenv("ROS_DISTRO", raising=False)
    with pytest.raises(Ros2UnavailableError, match=r"ROS 2 is not sourced: .*source /opt/ros/"):
        open_graph().__enter__()
    monkeypatch.setenv("ROS_DISTRO", "humble")
    with pytest.raises(Ros2UnavailableError, match="ROS 2 humble is sourced, but rclpy cannot"):
        open_graph().__enter__()


def test_live_command_without_ros2_is_a_one_line_error(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "rclpy", None)
    monkeypatch.delenv("ROS_DISTRO", raising=False)
    result = CliRunner().invoke(main, ["discover", "--live"])
    assert result.exit_code == 2
    assert result.stderr.count("\n") == 2  # the progress line and the error
    assert "error: ROS 2 is not sourced" in result.stderr
    assert "Traceback" not in result.output


@pytest.mark.parametrize(
    ("arguments", "message"),
    [([], "give a SOURCE"), (["x.mcap", "--live"], "not both")],
)
def test_discover_needs_exactly_one_source(arguments: list[str], message: str) -> None:
    result = CliRunner().invoke(main, ["discover", *arguments])
    assert result.exit_code == 2
    assert message in result.stderr


def test_live_command_summarises_the_graph(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    from contextlib import contextmanager

    from skillwright.interfaces.sources import rclpy_graph

    graph = RecordedGraph([ROBOT, ROBOT], FILES)

    @contextmanager
    def recorded(node_name: str = "x"):  # type: ignore[no-untyped-def]
        yield graph

    monkeypatch.setattr(rclpy_graph, "open_graph", recorded)
    target = tmp_path / "live.json"
    result = CliRunner().invoke(
        main,
        ["discover", "--live", "--timeout", "0.05", "--resource", "mr1", "-o", str(target)],
        terminal_width=200,
    )
    assert result.exit_code == 0, result.output
    assert "Source:     recorded graph (live ROS 2 graph)" in result.output
    row = next(line for line in result.output.splitlines() if "/cmd_vel" in line)
    assert "1 pub / 2 sub" in row
    move = next(line for line in result.output.splitlines() if "/move" in line)
    assert "1 srv / 2 cli" in move
    inventory = Inventory.model_validate_json(target.read_text())
    assert inventory.resource.name == "mr1"
    assert "note: settled: snapshots 1 and 2 agreed" in result.stderr
