"""Ranking a robot's interfaces for a capability."""

from __future__ import annotations

import re
import threading
from collections.abc import Sequence
from functools import cache
from typing import Literal

import pytest

from skillwright.capability import Capability, load_capability
from skillwright.capability.model import DataElement, Parameter
from skillwright.errors import OperationCancelledError
from skillwright.interfaces.inventory import (
    Endpoints,
    Interface,
    InterfaceKind,
    Inventory,
    Resource,
)
from skillwright.interfaces.load import load_inventory
from skillwright.retrieval.retrieve import Ranking, rank_interfaces, twin_notes
from skillwright.spec import SkillSpec, load_spec, parse_spec
from tests.conftest import SHIPPED_CAPABILITIES


@cache
def mr1() -> Inventory:
    return load_inventory(SHIPPED_CAPABILITIES / "recordings" / "mr1")


def ranked(stem: str, **kwargs: object) -> list[str]:
    capability = load_capability(SHIPPED_CAPABILITIES / f"{stem}.ttl").capability
    spec = load_spec(SHIPPED_CAPABILITIES / f"{stem}.spec.yaml")
    return [h.name for h in rank_interfaces(mr1(), capability, spec, **kwargs)]  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("stem", "needed"),
    [
        ("move-forward", {"/cmd_vel", "/odom"}),
        ("set-velocity", {"/cmd_vel", "/odom"}),
        ("get-distance-to-nearest-object", {"/scan"}),
        ("collision-avoidance", {"/scan", "/cmd_vel"}),
        ("navigate-to-point", {"/navigate_to_pose", "/cmd_vel"}),
        ("move-to-point", {"/move_action"}),
    ],
)
def test_lexical_ranking_finds_the_obvious_interfaces(stem: str, needed: set[str]) -> None:
    assert needed <= set(ranked(stem))


def test_k_limits_the_hits_and_scores_descend() -> None:
    capability = load_capability(SHIPPED_CAPABILITIES / "rotate.ttl").capability
    hits = rank_interfaces(mr1(), capability, k=6)
    assert len(hits) == 6
    assert all(h.reason for h in hits)
    assert [h.dense for h in hits] == [None] * 6
    assert rank_interfaces(mr1(), capability, k=0) == []


def test_infrastructure_is_left_out_unless_asked_for() -> None:
    everything = ranked("set-velocity", k=500)
    assert "/rosout" not in everything
    assert "/controller_server/get_parameters" not in everything
    with_infrastructure = ranked("set-velocity", k=500, include_infrastructure=True)
    assert "/rosout" in with_infrastructure


def test_near_duplicates_do_not_crowd_out_other_needs() -> None:
    hits = ranked("set-velocity")
    assert hits.index("/odom") < 3
    assert not {"/cmd_vel", "/cmd_vel_nav"} <= set(hits[:2])


def test_a_map_pose_and_tf_are_one_need_so_the_stop_command_keeps_its_place() -> None:
    hits = ranked("navigate-to-point")
    assert "/tf" in hits
    assert "/pose" not in hits  # the same map -> base_link pose as tf
    assert "/cmd_vel" in hits  # the stopping state's zero velocity
    assert "/cmd_vel_nav" not in hits  # Nav2's own velocity into the smoother


def test_an_embedder_is_mixed_in_when_given() -> None:
    capability = load_capability(SHIPPED_CAPABILITIES / "get-position.ttl").capability

    def fake_embed(texts: Sequence[str]) -> list[list[float]]:
        # a stand-in model that finds every query text like SLAM's pose topic and nothing else
        interface = ("topic ", "service ", "action ")
        return [
            [0.0, 1.0] if t.startswith(interface) and "/pose " not in t else [1.0, 0.0]
            for t in texts
        ]

    dense_only = rank_interfaces(
        mr1(), capability, embed=fake_embed, ranking=Ranking(dense_weight=1.0)
    )
    assert dense_only[0].name == "/pose"
    assert dense_only[0].dense == 1.0
    assert "similar text" in dense_only[0].reason
    mixed = rank_interfaces(mr1(), capability, embed=fake_embed)
    assert all(h.dense is not None for h in mixed)


def test_reciprocal_rank_fusion_is_available_for_comparison() -> None:
    capability = load_capability(SHIPPED_CAPABILITIES / "rotate.ttl").capability

    def fake_embed(texts: Sequence[str]) -> list[list[float]]:
        return [[1.0, 0.0] if "turn" in t.lower() else [0.6, 0.8] for t in texts]

    hits = rank_interfaces(
        mr1(), capability, embed=fake_embed, ranking=Ranking(fusion="rrf", dense_weight=0.5)
    )
    assert len(hits) == 4
    assert "/cmd_vel" in [h.name for h in hits]


def test_scores_descend_and_each_reason_names_its_evidence() -> None:
    capability = load_capability(SHIPPED_CAPABILITIES / "move-forward.ttl").capability
    spec = load_spec(SHIPPED_CAPABILITIES / "move-forward.spec.yaml")
    hits = rank_interfaces(mr1(), capability, spec, k=8)
    scores = [h.score for h in hits]
    assert scores == sorted(scores, reverse=True)
    by_name = {h.name: h for h in hits}
    assert "capability moveForward" in by_name["/odom"].reason
    assert "odometry" in by_name["/odom"].reason
    assert by_name["/odom"].facets[0] == "capability"


def stop_inventory() -> Inventory:
    """A base with a velocity command, odometry, and a goal topic and action to confuse it."""

    def topic(name: str, type_name: str) -> Interface:
        return Interface(name=name, kind="topic", type_name=type_name)

    return Inventory(
        resource=Resource(name="base"),
        interfaces=[
            topic("/cmd_vel", "geometry_msgs/msg/Twist"),
            topic("/odom", "nav_msgs/msg/Odometry"),
            topic("/goal_pose", "geometry_msgs/msg/PoseStamped"),
            topic("/plan", "nav_msgs/msg/Path"),
            topic("/amcl_pose", "geometry_msgs/msg/PoseWithCovarianceStamped"),
            Interface(
                name="/navigate_to_pose",
                kind="action",
                type_name="nav2_msgs/action/NavigateToPose",
            ),
            Interface(
                name="/compute_path_to_pose",
                kind="action",
                type_name="nav2_msgs/action/ComputePathToPose",
            ),
        ],
    )


def navigate_capability() -> Capability:
    return Capability(
        iri="http://example.org/navigate",
        name="navigate",
        label="Navigate",
        kinds=["CaSk:ProvidedCapability"],
        comment="I navigate the base to a goal position with the navigation stack.",
    )


def navigate_spec() -> SkillSpec:
    return parse_spec(
        {
            "name": "navigate",
            "description": "Navigate the base to a goal pose, planning a path.",
            "skill_interface": "REST",
            "states": {
                "execute": "Send the navigation goal pose and wait for the result.",
                "stopping": "Cancel the goal. Publish a zero velocity command.",
            },
        }
    )


def test_a_stop_sentence_wins_the_velocity_command_a_place() -> None:
    hits = rank_interfaces(stop_inventory(), navigate_capability(), navigate_spec(), k=3)
    names = [h.name for h in hits]
    assert names[0] == "/navigate_to_pose"
    assert "/cmd_vel" in names
    [command] = [h for h in hits if h.name == "/cmd_vel"]
    assert command.facets[0] == "state:stopping.2"
    assert command.reason.startswith("the stopping state: command")


def test_without_coverage_the_goal_variants_crowd_out_the_stop_command() -> None:
    hits = rank_interfaces(
        stop_inventory(),
        navigate_capability(),
        navigate_spec(),
        k=3,
        ranking=Ranking(coverage=0.0, facets=False),
    )
    assert "/cmd_vel" not in [h.name for h in hits]


def behaviour_inventory() -> Inventory:
    """A base whose Nav2 behaviours and limits share words with a move-forward capability."""

    def make(name: str, kind: InterfaceKind, type_name: str) -> Interface:
        return Interface(name=name, kind=kind, type_name=type_name)

    return Inventory(
        resource=Resource(name="base"),
        interfaces=[
            make("/cmd_vel", "topic", "geometry_msgs/msg/Twist"),
            make("/odom", "topic", "nav_msgs/msg/Odometry"),
            make("/backup", "action", "nav2_msgs/action/BackUp"),
            make("/drive_on_heading", "action", "nav2_msgs/action/DriveOnHeading"),
            make("/speed_limit", "topic", "nav2_msgs/msg/SpeedLimit"),
        ],
    )


def parameter(name: str, unit: str, definition: str) -> Parameter:
    direction: Literal["input", "output"] = "input" if name.startswith("in") else "output"
    element = DataElement(name=name, unit=unit, definition=definition)
    return Parameter(
        iri=f"http://example.org/{name}",
        name=name,
        direction=direction,
        kind="VDI3682:Information",
        components=[element],
    )


def provided(
    name: str, comment: str, inputs: list[Parameter], outputs: list[Parameter]
) -> Capability:
    """A provided capability of the base, as a model would state it."""
    label = " ".join(w.lower() for w in re.findall(r"[A-Z]?[a-z]+", name)).capitalize()
    return Capability(
        iri=f"http://example.org/{name}",
        name=name,
        label=label,
        kinds=["CaSk:ProvidedCapability"],
        comment=comment,
        inputs=inputs,
        outputs=outputs,
    )


def forward_capability() -> Capability:
    return provided(
        "moveForward",
        "I drive the base forward by a distance at a speed, then stop.",
        [parameter("inDistance", "m", "The distance to drive.")],
        [
            parameter("outDistance", "m", "The distance to drive."),
            parameter("outVelocity", "m/s", "The velocity reached."),
        ],
    )


def test_direct_interfaces_beat_composite_behaviours_that_share_the_words() -> None:
    hits = rank_interfaces(behaviour_inventory(), forward_capability(), k=2)
    assert [h.name for h in hits] == ["/cmd_vel", "/odom"]


def test_a_command_topic_the_live_graph_shows_nobody_reading_gives_way() -> None:
    # A Stretch: Nav2's behaviour server publishes /cmd_vel, which nothing reads; the driver
    # listens on /stretch/cmd_vel.
    base = behaviour_inventory()
    dead = base.interface("/cmd_vel").model_copy(
        update={"endpoints": Endpoints(publishers=1, subscribers=0)}
    )
    driver = Interface(
        name="/stretch/cmd_vel",
        kind="topic",
        type_name="geometry_msgs/msg/Twist",
        endpoints=Endpoints(publishers=2, subscribers=1),
    )
    others = [i for i in base.interfaces if i.name != "/cmd_vel"]
    inventory = base.model_copy(update={"interfaces": [dead, driver, *others]})
    hits = [h.name for h in rank_interfaces(inventory, forward_capability(), k=2)]
    assert hits == ["/stretch/cmd_vel", "/odom"]
    counted = Ranking(unreached_factor=1.0)
    ranked = rank_interfaces(inventory, forward_capability(), k=2, ranking=counted)
    assert ranked[0].name == "/cmd_vel"  # by its name alone it looks like the base's command


def test_without_the_type_prior_a_behaviour_wins_a_place() -> None:
    flat = Ranking(neutral_factor=1.0, auxiliary_factor=1.0)
    hits = rank_interfaces(behaviour_inventory(), forward_capability(), k=2, ranking=flat)
    assert [h.name for h in hits] == ["/cmd_vel", "/drive_on_heading"]


def test_a_cancel_during_embedding_stops_the_ranking_before_scoring(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from skillwright.retrieval import retrieve

    capability = load_capability(SHIPPED_CAPABILITIES / "rotate.ttl").capability
    cancel = threading.Event()

    def embed_then_cancel(texts: Sequence[str]) -> list[list[float]]:
        cancel.set()  # Esc while the model embeds
        return [[1.0, 0.0] for _ in texts]

    scored: list[object] = []
    monkeypatch.setattr(retrieve, "_facet_scores", lambda *args: scored.append(args))
    with pytest.raises(OperationCancelledError, match="ranking the interfaces cancelled"):
        rank_interfaces(mr1(), capability, embed=embed_then_cancel, cancel=cancel)
    assert scored == []


def test_a_cancel_set_before_ranking_embeds_nothing() -> None:
    capability = load_capability(SHIPPED_CAPABILITIES / "rotate.ttl").capability
    cancel = threading.Event()
    cancel.set()
    embedded: list[Sequence[str]] = []

    def embed(texts: Sequence[str]) -> list[list[float]]:
        embedded.append(texts)
        return [[1.0, 0.0] for _ in texts]

    with pytest.raises(OperationCancelledError):
        rank_interfaces(mr1(), capability, embed=embed, cancel=cancel)
    assert embedded == []


def topics(type_name: str, *names: str) -> list[Interface]:
    """Topics of one type."""
    return [Interface(name=n, kind="topic", type_name=type_name) for n in names]


def test_among_equal_scores_the_plainer_name_wins_not_the_alphabet() -> None:
    # A MuR620: front and back scanners see half the room each, the merged /scan all of it.
    # Their words the query knows are the same, so their scores are equal.
    scans = topics(
        "sensor_msgs/msg/LaserScan", "/mur620a/b_scan", "/mur620a/f_scan", "/mur620a/scan"
    )
    inventory = Inventory(resource=Resource(name="mur620"), interfaces=scans)
    capability = provided(
        "getDistanceToNearestObject",
        "I measure the distance to the nearest object around the robot.",
        [],
        [parameter("outDistance", "m", "The distance to the nearest object.")],
    )
    hits = rank_interfaces(inventory, capability, k=3)
    assert len({round(h.lexical, 9) for h in hits}) == 1
    assert hits[0].name == "/mur620a/scan"


def test_a_scan_that_merges_its_neighbours_has_their_evidence_and_goes_first() -> None:
    # A KMR iiwa: two 270-degree scanners (/scan, /scan_2) and the concatenator's merged scan.
    # Among equals the plainer /scan would win; the merged one goes first. A camera's cloud
    # in another namespace is not a part of the merged cloud.
    inventory = Inventory(
        resource=Resource(name="kmriiwa"),
        interfaces=topics("sensor_msgs/msg/LaserScan", "/scan", "/scan_2", "/scan_concatenated")
        + topics("sensor_msgs/msg/PointCloud2", "/camera/pointcloud", "/pc_concatenated"),
    )
    capability = provided(
        "getDistanceToNearestObject",
        "I measure the distance to the nearest object around the robot with a laser scan.",
        [],
        [parameter("outDistance", "m", "The distance to the nearest object.")],
    )
    hits = rank_interfaces(inventory, capability, k=5)
    names = [h.name for h in hits]
    assert names[0] == "/scan_concatenated"
    assert names.index("/pc_concatenated") > names.index("/scan_concatenated")


def test_a_map_under_its_conventional_name_outranks_variants_that_share_words_by_chance() -> None:
    # A Toyota HSR: SLAM Toolbox's /map beside its navigation's obstacle and distance maps,
    # whose extra words match a mapping capability that explores a distance around obstacles.
    # A costmap in its own namespace is not a variant of /map: its words keep their weight.
    inventory = Inventory(
        resource=Resource(name="hsr"),
        interfaces=topics(
            "nav_msgs/msg/OccupancyGrid",
            "/map",
            "/dynamic_obstacle_map",
            "/static_distance_map",
            "/global_costmap/obstacle_costmap",
        ),
    )
    capability = provided(
        "mapping",
        "I map the surroundings up to a distance, driving around obstacles.",
        [parameter("inDistance", "m", "The distance to explore.")],
        [parameter("outMap", "", "The map of the obstacles.")],
    )
    names = [h.name for h in rank_interfaces(inventory, capability, k=4)]
    assert names.index("/map") < names.index("/dynamic_obstacle_map")
    assert names.index("/map") < names.index("/static_distance_map")


def test_the_second_scanner_of_a_split_view_follows_the_first_but_a_version_does_not() -> None:
    # An MMO-700: two scanners on opposite corners, each seeing one half around the robot,
    # and SLAM Toolbox's copy of the scans it used; a TIAGo-like /scan_raw beside /scan is
    # the same view before filtering, an alternative to it.
    inventory = Inventory(
        resource=Resource(name="mmo700"),
        interfaces=topics(
            "sensor_msgs/msg/LaserScan",
            "/scan",
            "/scan2",
            "/scan_raw",
            "/slam_toolbox/scan_visualization",
        )
        + topics("nav_msgs/msg/Odometry", "/odom"),
    )
    capability = provided(
        "getDistanceToNearestObject",
        "I measure the distance to the nearest object around the robot.",
        [],
        [parameter("outDistance", "m", "The distance to the nearest object.")],
    )
    hits = {h.name: h for h in rank_interfaces(inventory, capability, k=5)}
    assert list(hits)[:3] == ["/scan", "/odom", "/scan2"]
    assert hits["/scan2"].score > 0.1
    assert hits["/scan2"].reason.startswith("another side of the view of /scan; ")
    assert "another side" not in hits["/odom"].reason + hits["/scan_raw"].reason
    assert hits["/scan_raw"].score == hits["/slam_toolbox/scan_visualization"].score == 0
    # counted as alternatives, the second scanner gains as little as the versions
    alike = rank_interfaces(inventory, capability, k=5, ranking=Ranking(split_view_factor=0))
    assert {h.name: h.score for h in alike}["/scan2"] == 0


def _stretch_without_counts() -> Inventory:
    """The Stretch of the test above as a report lists it: no endpoint counts."""
    base = behaviour_inventory()
    driver = Interface(name="/stretch/cmd_vel", kind="topic", type_name="geometry_msgs/msg/Twist")
    return base.model_copy(update={"interfaces": [*base.interfaces, driver]})


def test_a_command_topic_a_list_without_counts_cannot_tell_apart_is_named_a_twin() -> None:
    hits = rank_interfaces(_stretch_without_counts(), forward_capability(), k=2)
    assert [h.name for h in hits] == ["/cmd_vel", "/odom"]
    assert hits[0].twins == ("/stretch/cmd_vel",)
    assert hits[1].twins == ()
    [note] = twin_notes(hits)
    assert note.startswith("/cmd_vel (geometry_msgs/msg/Twist) was chosen over /stretch/cmd_vel")
    assert "`ros2 topic info -v /cmd_vel`" in note
    assert note.endswith("generate with --drop /cmd_vel --pin /stretch/cmd_vel")


def test_counts_or_another_type_make_no_twins() -> None:
    # the live graph's counts tell the two apart (the test above ranks the driver's first)
    counted = _stretch_without_counts()
    counted = counted.model_copy(
        update={
            "interfaces": [
                i.model_copy(update={"endpoints": Endpoints(publishers=1, subscribers=1)})
                for i in counted.interfaces
            ]
        }
    )
    assert all(not h.twins for h in rank_interfaces(counted, forward_capability(), k=4))
    # a behaviour action and a velocity topic are not twins, nor is a plain Twist without
    # a competitor in the list
    assert all(not h.twins for h in rank_interfaces(behaviour_inventory(), forward_capability()))
