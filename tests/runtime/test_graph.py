"""The simulated graph: replay, QoS, latching, checks of the skill's endpoints, responders,
and the world plug-in hooks, driven as the child would drive them."""

from __future__ import annotations

import itertools
from typing import Any

import pytest

from skillwright.interfaces.inventory import Inventory
from skillwright.runtime.api import ActionGoal, GoalStatus, ServiceReply
from skillwright.runtime.graph import GraphHost, SentMessageError
from skillwright.runtime.recorder import Recorder
from skillwright.runtime.run import recording_files
from skillwright.runtime.scenario import ActionScript, RunScenario, ServiceScript, TopicScript
from tests.runtime.conftest import MR1_RECORDING

_ids = itertools.count(1)


def make_graph(inventory: Inventory, **scenario: Any) -> tuple[GraphHost, Recorder]:
    recorder = Recorder()
    graph = GraphHost(
        inventory,
        _registry(inventory),
        recorder,
        RunScenario.model_validate(scenario),
        recording=recording_files(MR1_RECORDING),
        epoch_ns=inventory.sources[0].start_time_ns or 0,
    )
    return graph, recorder


_REGISTRIES: dict[int, Any] = {}


def _registry(inventory: Inventory) -> Any:
    from skillwright.runtime.typesys import TypeRegistry

    if id(inventory) not in _REGISTRIES:
        _REGISTRIES[id(inventory)] = TypeRegistry(inventory)
    return _REGISTRIES[id(inventory)]


def endpoint(graph: GraphHost, kind: str, name: str, type_name: str, **qos: str) -> int:
    handle = next(_ids)
    graph.child_endpoint(
        {"id": handle, "kind": kind, "name": name, "type": type_name, "qos": qos, "line": 7}
    )
    return handle


def deliveries_until(graph: GraphHost, until: float) -> list[tuple[float, dict[str, Any]]]:
    seen = []
    while graph.now < until:
        for delivery in graph.advance(until, cap=100.0):
            seen.append((delivery.pop("t"), delivery))
    return seen


def test_replay_delivers_recorded_messages_in_time_order_and_loops_with_later_stamps(
    mr1_inventory: Inventory,
) -> None:
    graph, _ = make_graph(mr1_inventory)
    odom = endpoint(graph, "subscription", "/odom", "nav_msgs/msg/Odometry", reliability="reliable")

    seen = deliveries_until(graph, 3.2)

    times = [t for t, d in seen if d["id"] == odom]
    assert times == sorted(times)
    assert 155 <= len(times) <= 162  # 50 Hz for 3 s, then the start of the second loop
    stamps = [d["data"]["header"]["stamp"] for _, d in seen]
    seconds = [s["sec"] + s["nanosec"] / 1e9 for s in stamps]
    assert seconds == sorted(seconds)


def test_a_reliable_subscription_to_a_best_effort_topic_gets_nothing_and_a_finding(
    mr1_inventory: Inventory,
) -> None:
    graph, recorder = make_graph(mr1_inventory)
    endpoint(graph, "subscription", "/scan", "sensor_msgs/msg/LaserScan", reliability="reliable")

    assert deliveries_until(graph, 0.5) == []
    assert [(f.check, f.line) for f in recorder.findings] == [("run.qos", 7)]
    assert "qos_profile_sensor_data" in recorder.findings[0].message


def test_a_late_transient_local_subscription_gets_the_latched_message(
    mr1_inventory: Inventory,
) -> None:
    graph, _ = make_graph(mr1_inventory)
    deliveries_until(graph, 1.0)

    late = endpoint(
        graph,
        "subscription",
        "/tf_static",
        "tf2_msgs/msg/TFMessage",
        reliability="reliable",
        durability="transient_local",
    )
    volatile = endpoint(
        graph, "subscription", "/map", "nav_msgs/msg/OccupancyGrid", reliability="reliable"
    )

    first = graph.advance(1.0, cap=100.0)
    assert [(d["id"], d["t"]) for d in first] == [(late, 1.0)]
    assert {t["child_frame_id"] for t in first[0]["data"]["transforms"]} >= {
        "base_link",
        "laser_link",
    }
    assert volatile not in [d["id"] for d in first]


@pytest.mark.parametrize(
    ("kind", "name", "type_name", "check", "words"),
    [
        (
            "publisher",
            "/cmd_vell",
            "geometry_msgs/msg/Twist",
            "run.topic",
            "did you mean /cmd_vel?",
        ),
        (
            "publisher",
            "/cmd_vel",
            "geometry_msgs/msg/TwistStamped",
            "run.type",
            "its type is geometry_msgs/msg/Twist",
        ),
        (
            "subscription",
            "/navigate_to_pose",
            "nav_msgs/msg/Odometry",
            "run.topic",
            "is an action of the robot, not a topic",
        ),
        (
            "client",
            "/map_saver/save",
            "nav2_msgs/srv/SaveMap",
            "run.service",
            "did you mean /map_saver/save_map?",
        ),
        (
            "action_client",
            "/navigate_to_pose",
            "nav2_msgs/action/Spin",
            "run.type",
            "NavigateToPose",
        ),
    ],
)
def test_endpoints_the_robot_does_not_have_are_findings_at_their_line(
    mr1_inventory: Inventory, kind: str, name: str, type_name: str, check: str, words: str
) -> None:
    graph, recorder = make_graph(mr1_inventory)

    endpoint(graph, kind, name, type_name, reliability="reliable")

    assert [(f.check, f.line) for f in recorder.findings] == [(check, 7)]
    assert words in recorder.findings[0].message


def test_a_silent_scripted_topic_delivers_nothing_and_a_scripted_one_its_message(
    mr1_inventory: Inventory,
) -> None:
    graph, _ = make_graph(
        mr1_inventory,
        topics={
            "/odom": TopicScript(silent=True),
            "/battery_state": TopicScript(rate_hz=2.0, message={"percentage": 0.1}),
        },
    )
    endpoint(graph, "subscription", "/odom", "nav_msgs/msg/Odometry", reliability="reliable")
    battery = endpoint(
        graph,
        "subscription",
        "/battery_state",
        "sensor_msgs/msg/BatteryState",
        reliability="reliable",
    )

    seen = deliveries_until(graph, 1.2)

    assert [(t, d["id"]) for t, d in seen] == [(0.5, battery), (1.0, battery)]
    assert seen[0][1]["data"]["percentage"] == pytest.approx(0.1)


def test_the_skills_publications_are_checked_recorded_and_looped_back(
    mr1_inventory: Inventory,
) -> None:
    graph, recorder = make_graph(mr1_inventory)
    publisher = endpoint(graph, "publisher", "/cmd_vel", "geometry_msgs/msg/Twist")
    own = endpoint(
        graph, "subscription", "/cmd_vel", "geometry_msgs/msg/Twist", reliability="reliable"
    )

    graph.child_publish(publisher, {"linear": {"x": 0.5, "y": 0.0, "z": 0.0}}, 12, "execute")

    assert graph.advance(None, cap=0.0) == [
        {
            "id": own,
            "data": graph.registry.conform("geometry_msgs/msg/Twist", {"linear": {"x": 0.5}}),
            "t": 0.0,
        }
    ]
    assert graph.published["/cmd_vel"][0][1]["angular"] == {"x": 0.0, "y": 0.0, "z": 0.0}
    assert any(e["kind"] == "publish" and e["line"] == 12 for e in recorder.entries)
    with pytest.raises(SentMessageError, match="no field 'speed'"):
        graph.child_publish(publisher, {"speed": 1.0}, 13, "execute")


def test_a_sent_message_of_the_wrong_type_names_the_field_and_both_types(
    mr1_inventory: Inventory,
) -> None:
    graph, _ = make_graph(mr1_inventory)
    publisher = endpoint(graph, "publisher", "/cmd_vel", "geometry_msgs/msg/Twist")
    with pytest.raises(SentMessageError) as raised:
        graph.child_publish(publisher, {"linear": {"x": "fast"}}, 14, "execute")
    assert str(raised.value) == (
        "message on /cmd_vel.linear.x: expected a number (float64), got str"
    )
    assert graph.published.get("/cmd_vel") is None


def test_services_answer_with_success_after_their_delay_unless_scripted_otherwise(
    mr1_inventory: Inventory,
) -> None:
    graph, _ = make_graph(
        mr1_inventory,
        services={
            "/slam_toolbox/save_map": ServiceScript(respond=False),
            "/compute_fk": ServiceScript(available=False),
        },
    )
    saver = endpoint(graph, "client", "/map_saver/save_map", "nav2_msgs/srv/SaveMap")
    slam = endpoint(graph, "client", "/slam_toolbox/save_map", "slam_toolbox/srv/SaveMap")

    graph.child_call(saver, 1, {"map_url": "x"}, 20)
    graph.child_call(slam, 1, {}, 21)

    answers = deliveries_until(graph, 1.0)
    assert [(t, d["id"], d["data"]) for t, d in answers] == [(0.05, saver, {"result": True})]
    assert graph.exists("service", "/map_saver/save_map")
    assert not graph.exists("service", "/compute_fk")


def test_actions_accept_send_feedback_and_succeed_or_reject_as_scripted(
    mr1_inventory: Inventory,
) -> None:
    graph, recorder = make_graph(mr1_inventory, actions={"/spin": ActionScript(accept=False)})
    nav = endpoint(graph, "action_client", "/navigate_to_pose", "nav2_msgs/action/NavigateToPose")
    spin = endpoint(graph, "action_client", "/spin", "nav2_msgs/action/Spin")

    graph.child_goal(nav, 1, {"pose": {"header": {"frame_id": "map"}}}, True, 30)
    graph.child_goal(spin, 1, {}, False, 31)
    seen = deliveries_until(graph, 2.0)

    kinds = [(d["id"], d.get("kind"), d.get("accepted", d.get("status"))) for _, d in seen]
    assert (nav, "accepted", True) in kinds
    assert (spin, "accepted", False) in kinds
    assert (nav, "feedback", None) in kinds
    assert kinds[-1] == (nav, "result", GoalStatus.SUCCEEDED)
    assert [e["status"] for e in recorder.entries if e["kind"] == "result"] == ["succeeded"]


def test_cancelling_an_active_goal_is_accepted_and_ends_it(mr1_inventory: Inventory) -> None:
    graph, _ = make_graph(
        mr1_inventory, actions={"/navigate_to_pose": ActionScript(outcome="never")}
    )
    nav = endpoint(graph, "action_client", "/navigate_to_pose", "nav2_msgs/action/NavigateToPose")
    graph.child_goal(nav, 1, {}, False, 30)
    deliveries_until(graph, 0.5)
    assert [g.action for g, _ in graph.active_goals()] == ["/navigate_to_pose"]

    graph.child_cancel(nav, 1, 40)
    seen = deliveries_until(graph, 1.0)

    assert {"id": nav, "kind": "cancel", "goal": 1, "return_code": 0} in [d for _, d in seen]
    assert seen[-1][1]["status"] == GoalStatus.CANCELED
    assert graph.active_goals() == []


class _World:
    """A world that owns /odom, echoes /cmd_vel into it and serves one service."""

    def __init__(self) -> None:
        self.commands: list[tuple[float, float]] = []
        self.closed = False

    def attach(self, host: GraphHost) -> None:
        self.host = host
        self.next = 0.0
        host.own_topic("/odom")
        host.on_publish("/cmd_vel", lambda t, m: self.commands.append((t, m["linear"]["x"])))
        host.serve_service(
            "/compute_fk", lambda request: ServiceReply({"fk_link_names": ["tool0"]}, delay=0.5)
        )
        host.serve_action("/spin", _Rejecting())

    def next_event(self) -> float | None:
        return self.next

    def advance(self, until: float) -> None:
        if until >= self.next:
            odom = self.host.message("nav_msgs/msg/Odometry")
            odom["twist"]["twist"]["linear"]["x"] = self.commands[-1][1] if self.commands else 0.0
            self.host.publish("/odom", odom)
            self.next += 0.25

    def close(self) -> None:
        self.closed = True


class _Rejecting:
    def on_goal(self, goal: ActionGoal) -> None:
        goal.reject()

    def on_cancel(self, goal: ActionGoal) -> bool:
        return False


def test_a_world_replaces_replay_watches_commands_and_serves_interfaces(
    mr1_inventory: Inventory,
) -> None:
    graph, _ = make_graph(mr1_inventory)
    world = _World()
    graph.attach_world(world)
    odom = endpoint(graph, "subscription", "/odom", "nav_msgs/msg/Odometry", reliability="reliable")
    publisher = endpoint(graph, "publisher", "/cmd_vel", "geometry_msgs/msg/Twist")
    fk = endpoint(graph, "client", "/compute_fk", "moveit_msgs/srv/GetPositionFK")
    spin = endpoint(graph, "action_client", "/spin", "nav2_msgs/action/Spin")

    deliveries_until(graph, 0.3)
    graph.child_publish(publisher, {"linear": {"x": 0.4}}, 50, "execute")
    graph.child_call(fk, 1, {}, 51)
    graph.child_goal(spin, 1, {}, False, 52)
    seen = deliveries_until(graph, 1.0)

    odom_times = [t for t, d in seen if d["id"] == odom]
    assert odom_times == [0.5, 0.75, 1.0]
    assert [d["data"]["twist"]["twist"]["linear"]["x"] for t, d in seen if d["id"] == odom] == [
        0.4,
        0.4,
        0.4,
    ]
    assert world.commands == [(0.3, 0.4)]
    assert [(t, d["data"]["fk_link_names"]) for t, d in seen if d["id"] == fk] == [(0.8, ["tool0"])]
    assert [d["accepted"] for t, d in seen if d["id"] == spin] == [False]
    graph.close()
    assert world.closed


def test_world_messages_must_fit_the_topics_type(mr1_inventory: Inventory) -> None:
    graph, _ = make_graph(mr1_inventory)

    with pytest.raises(ValueError, match="Odometry has no field 'velocity'"):
        graph.publish("/odom", {"velocity": 1.0})
    with pytest.raises(ValueError, match="no topic /odometry"):
        graph.publish("/odometry", {})
    assert graph.stamp(1.5) == {"sec": 1768471201, "nanosec": 501000000}


def _odometry_times(inventory: Inventory, traffic: str, subscribe_at: float) -> list[float]:
    graph, _ = make_graph(inventory, traffic=traffic)
    deliveries_until(graph, subscribe_at)
    odom = endpoint(graph, "subscription", "/odom", "nav_msgs/msg/Odometry", reliability="reliable")
    seen = deliveries_until(graph, 7.0)
    return [t for t, d in seen if d["id"] == odom]


@pytest.mark.parametrize("subscribe_at", [0.0, 1.3, 4.05])
def test_a_topic_subscribed_late_is_replayed_from_where_the_recording_is_then(
    mr1_inventory: Inventory, subscribe_at: float
) -> None:
    # `all` replays every recorded topic from the start, as the robot publishes them;
    # `subscribed` starts reading a topic only when someone subscribes to it.
    everything = _odometry_times(mr1_inventory, "all", subscribe_at)
    subscribed = _odometry_times(mr1_inventory, "subscribed", subscribe_at)
    assert subscribed == everything
    assert subscribed[0] >= subscribe_at
    assert len(subscribed) == pytest.approx((7.0 - subscribe_at) * 50, abs=2)


def test_a_topic_is_wanted_while_someone_subscribes_and_always_when_latched(
    mr1_inventory: Inventory,
) -> None:
    graph, _ = make_graph(mr1_inventory)
    assert not graph.wants("/odom")
    assert graph.wants("/tf_static"), "latched: its last message waits for later subscribers"
    assert graph.wants("/no_such_topic"), "publishing there must still be refused"
    odom = endpoint(graph, "subscription", "/odom", "nav_msgs/msg/Odometry", reliability="reliable")
    assert graph.wants("/odom")
    graph.child_destroy(odom)
    assert not graph.wants("/odom")
    everything, _ = make_graph(mr1_inventory, traffic="all")
    assert everything.wants("/odom")
