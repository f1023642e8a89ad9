"""Recall of the retrieval stage on the labelled sets, held at a documented floor.

The floors are the measured numbers of the current ranking (``bench/bench_retrieval.py``
prints the full table). A change that finds fewer needed interfaces fails here; a change
that finds more should raise the floor in the same commit.
"""

from __future__ import annotations

from collections.abc import Sequence

import pytest

from skillwright.capability import Capability
from skillwright.interfaces.inventory import Inventory
from skillwright.retrieval.retrieve import Embedder, candidates, rank_interfaces
from skillwright.spec import SkillSpec
from tests.retrieval.labelled import (
    SETS,
    WRITTEN,
    LabelledSet,
    described_robots,
    load_set,
    measure,
)


@pytest.fixture(params=SETS)
def any_set(request: pytest.FixtureRequest) -> LabelledSet:
    if request.param != "mr1":  # the paper's capabilities live in ../shared; skip without it
        request.getfixturevalue("shared_data")
    return load_set(request.param)


def lexical(inventory: Inventory, capability: Capability, spec: SkillSpec, k: int) -> list[str]:
    return [h.name for h in rank_interfaces(inventory, capability, spec, k=k)]


def test_every_labelled_interface_is_a_candidate_of_its_inventory(
    any_set: LabelledSet,
) -> None:
    names = {i.name for i in candidates(any_set.inventory)}
    for case in any_set.cases:
        for need in case.needs:
            assert set(need) <= names, f"{any_set.name} {case.name}: {need}"


def test_every_capability_is_labelled_or_said_to_be_unserved(any_set: LabelledSet) -> None:
    assert len(any_set.cases) + len(any_set.unserved) == 9
    assert all(case.needs and case.spec.states for case in any_set.cases)


def test_the_papers_robot_has_107_interfaces_and_few_candidates(shared_data: object) -> None:
    inventory = load_set("cap2skill").inventory
    assert len(inventory.interfaces) == 107
    cmd_vel = inventory.interface("/cmd_vel")
    assert cmd_vel.type_name == "geometry_msgs/msg/Twist"
    fields = cmd_vel.definitions["message"].fields or []
    assert [f.name for f in fields] == ["linear", "angular"]
    assert [f.name for f in fields[0].fields] == ["x", "y", "z"]
    action = inventory.interface("/joint_trajectory_controller/follow_joint_trajectory")
    assert set(action.definitions) == {"goal", "result", "feedback"}
    # parameter services are infrastructure by our rules, and so not candidates
    assert len(candidates(inventory)) < 40


def test_the_filtered_report_keeps_the_papers_33_with_their_descriptions(
    shared_data: object,
) -> None:
    inventory = load_set("cap2skill-filtered").inventory
    assert len(candidates(inventory)) == 33
    odom = inventory.interface("/odom")
    assert odom.description is not None
    assert "position and velocity" in odom.description.purpose


# (set, k, needs found at least). Needs: mr1 22, cap2skill 18 (both settings), tb4 16,
# tiago 19, ur5e 2, go2 16, rosbotxl 19, husky 19, stretch3 26, locobot 19, mur620 19, rbkairos
# 19, kmriiwa 21, tb3manip 20, hsr 22, jetrover 20, spot 27, omronmoma 20, scoutpiper 20,
# panther 20, mmo700nav 23. At k=4 the MR-1's mapping
# needs 6 interfaces, so 20 of its 22 needs are attainable (the Stretch's mapping 5, so 25 of
# 26, the MMO-700's 5, so 22 of 23); every need of the other robots is. Before facets and coverage (pooled query, relevance order) the lexical numbers at k=4 were 14, 15 and 16;
# before the type semantics (words only) mr1 18, tb4 13, tiago 12, ur5e 2, go2 10. The
# ROSbot XL was labelled before anything ranked it: 17 at k=4 with the rules of that day,
# 18 with the display rule, 19 once the map service ranked behind the map topic. The Husky
# (Clearpath's a200_0000 namespace, a Kinova arm) was labelled by a helper who saw no ranking
# and scored first at 9/19/19 with the rules of 36af37b: nothing was tuned to it. The
# Stretch 3 (labelled the same way; its base listens on /stretch/cmd_vel only in navigation
# mode, and Nav2's behaviours publish a /cmd_vel nobody reads) scored 5/12/13 of 26 (25 fit);
# once its file says who reads and writes its three Twist topics, as a live graph shows it,
# and an unreached command topic gives way, 9/18/19. The six left at k=4 are the driver's
# navigation-mode switch (a Trigger service no spec mentions), one pose and the arm's stop.
# Two mobile manipulators of the held-out kind were labelled blind the same way: a LoCoBot
# (Create 3 base, Nav2 and SLAM Toolbox at the root, the driver under /locobot) scored
# 9/19/19 of 19 at first; a match MuR620 (MiR base, two UR10e, Jazzy, stamped velocity, four
# scans) 8/16/16 of 19, all three misses the half-view /mur620a/b_scan winning a tie with the
# merged /mur620a/scan by the alphabet; with the plainer name first among equals, 9/19/19.
# Two more, labelled blind the same way: a Robotnik RB-KAIROS+ (Jazzy simulation, everything
# under /robot, stamped and unstamped base velocity) scored 9/19/19 of 19 at first; a KUKA KMR
# iiwa (NTNU's Foxy stack: a Java bridge's /cmd_vel and /odom, two 270-degree scans merged
# into /scan_concatenated, the arm planned by a vendor action /moveit/frame) 7/16/20 of 21;
# once a merged stream has its parts' evidence and goes first among equals, 8/17/20. The four
# left at k=4: the planner action and the arm's String stop "a0 0", which only its docs
# explain, the arm's status, and the merged scan for mapping behind Nav2's action.
# Two more, blind: a TurtleBot3 with an OpenMANIPULATOR-X (ROBOTIS's Humble stack) scored
# 9/20/20 of 20 at first; a Toyota HSR (Toyota's own Jazzy stack: its navigation's
# /move_base/move, RRT planner services, 597 interfaces) 7/13/16 of 22: SLAM Toolbox's /map
# lost to its navigation's /dynamic_obstacle_map and /static_distance_ros_map, whose extra
# words matched the mapping spec by chance. A topic under its type's conventional name
# (map, scan, odom, cmd_vel) now caps the scores of its same-type neighbours: 7/14/17, the
# paper's filtered robot 9 at k=1 (/scan before /scan2), nothing else moves. A Hiwonder
# JetRover (the vendor's image: a servo-bus arm behind its own kinematics node), blind,
# 7/18/18 of 20 before and after that rule: its arm's servo topics rank nowhere. Then two
# more, blind, with that rule: a Spot with its arm 7/14/15 of 27 (six of the misses are the
# stand or power-on call it needs before it moves, which no spec mentions) and an OMRON
# LD-250 with a TM12X arm 9/19/19 of 20. A point cloud's "points" then stopped counting as
# the point a capability moves to: HSR 7/14/17 -> 7/15/19, JetRover 7/18/18 -> 8/18/18, Go2
# 5/13/15 -> 6/13/15, the others as they were; and Cartographer's scan_matched_points2 (its
# matcher's copy of one scan) auxiliary: Spot 7/14/15 -> 7/15/18. Then two more, blind, with
# those rules: an AgileX Scout 2.0 with a PiPER arm (the vendor's driver names, SLAM Toolbox,
# Nav2, an Ouster) 9/20/20 of 20, and a Husarion Panther with a UR5e (everything of the base
# under /panther, 616 interfaces) 9/19/19 of 20; its miss is the arm's hard stop, UR's
# /dashboard_client/stop. The written robots then showed their types' fields as a live graph
# does (Nav2's, MoveIt's, the vendors', from robots/definitions): over the eighteen 144/306/319
# names-only, 145/307/319 with fields. ROSbot XL 9/19/19 -> 9/18/19 and Stretch 9/18/19 ->
# 9/17/19 (collision avoidance's odometry one place behind NavigateToPose, whose feedback's
# navigation_time matched the spec's time), KMR iiwa 8/17/20 -> 8/18/20, HSR 7/15/19 ->
# 8/16/19, Spot 7/15/18 -> 8/16/18, JetRover 8/18/18 -> 7/18/18. NAMES_ONLY_FLOORS keeps the
# names-only numbers at k=4. A Neobotix MMO-700 in Gazebo with Nav2 (Neobotix's local
# planner), SLAM Toolbox and MoveIt for a UR10 (the paper's robot with the stacks of the robot
# this project is judged on) was labelled blind by a helper and scored 9/20/20 of 23 at first
# contact, nothing changed for it; its mapping needs 5 (22 attainable at k=4). Its labels count
# both 170-degree scanners as needed where nothing merges them; the three misses were /scan2,
# left out because one scan of the type covered the evidence (duplicate_type_factor), where
# the paper's robot's labels take either scanner. Once the parts of a split view (names that
# differ by a number or a side, nothing merging them) no longer count as alternatives to each
# other, 9/22/23: mapping's /scan2 is 8th, behind /map and SLAM's services; nothing else moved
# (the paper's robot keeps 9/18/18, its mapping now /tf, /scan, /scan2, /cmd_vel).
LEXICAL_FLOORS = [
    ("mr1", 1, 9),
    ("mr1", 4, 20),
    ("mr1", 8, 22),
    ("cap2skill", 1, 9),
    ("cap2skill", 4, 18),
    ("cap2skill", 8, 18),
    ("cap2skill-filtered", 1, 9),
    ("cap2skill-filtered", 4, 18),
    ("cap2skill-filtered", 8, 18),
    ("tb4", 1, 8),
    ("tb4", 4, 16),
    ("tb4", 8, 16),
    ("tiago", 1, 9),
    ("tiago", 4, 19),
    ("tiago", 8, 19),
    ("ur5e", 4, 2),
    ("go2", 1, 6),
    ("go2", 4, 13),
    ("go2", 8, 15),
    ("rosbotxl", 1, 9),
    ("rosbotxl", 4, 18),
    ("rosbotxl", 8, 19),
    ("husky", 1, 9),
    ("husky", 4, 19),
    ("husky", 8, 19),
    ("stretch3", 1, 9),
    ("stretch3", 4, 17),
    ("stretch3", 8, 19),
    ("locobot", 1, 9),
    ("locobot", 4, 19),
    ("locobot", 8, 19),
    ("mur620", 1, 9),
    ("mur620", 4, 19),
    ("mur620", 8, 19),
    ("rbkairos", 1, 9),
    ("rbkairos", 4, 19),
    ("rbkairos", 8, 19),
    ("kmriiwa", 1, 8),
    ("kmriiwa", 4, 18),
    ("kmriiwa", 8, 20),
    ("tb3manip", 1, 9),
    ("tb3manip", 4, 20),
    ("tb3manip", 8, 20),
    ("hsr", 1, 8),
    ("hsr", 4, 16),
    ("hsr", 8, 19),
    ("jetrover", 1, 7),
    ("jetrover", 4, 18),
    ("jetrover", 8, 18),
    ("spot", 1, 8),
    ("spot", 4, 16),
    ("spot", 8, 18),
    ("omronmoma", 1, 9),
    ("omronmoma", 4, 19),
    ("omronmoma", 8, 19),
    ("scoutpiper", 1, 9),
    ("scoutpiper", 4, 20),
    ("scoutpiper", 8, 20),
    ("panther", 1, 9),
    ("panther", 4, 19),
    ("panther", 8, 19),
    ("mmo700nav", 1, 9),
    ("mmo700nav", 4, 22),
    ("mmo700nav", 8, 23),
]

NAMES_ONLY_FLOORS = [
    ("tb4", 16),
    ("tiago", 19),
    ("ur5e", 2),
    ("go2", 13),
    ("rosbotxl", 19),
    ("husky", 19),
    ("stretch3", 18),
    ("locobot", 19),
    ("mur620", 19),
    ("rbkairos", 19),
    ("kmriiwa", 17),
    ("tb3manip", 20),
    ("hsr", 15),
    ("jetrover", 18),
    ("spot", 15),
    ("omronmoma", 19),
    ("scoutpiper", 20),
    ("panther", 19),
    ("mmo700nav", 22),
]
"""Recall@4 of the written robots when they name their types only, as a recording without
schemas or a report of names shows them."""

REPORT_FLOORS = [
    ("tb4", 16),
    ("tiago", 19),
    ("ur5e", 2),
    ("go2", 13),
    ("rosbotxl", 18),
    ("husky", 19),
    ("stretch3", 11),
    ("locobot", 18),
    ("mur620", 19),
    ("rbkairos", 19),
    ("kmriiwa", 18),
    ("tb3manip", 20),
    ("hsr", 16),
    ("jetrover", 18),
    ("spot", 11),
    ("omronmoma", 19),
    ("scoutpiper", 20),
    ("panther", 19),
    ("mmo700nav", 22),
]
"""Recall@4 of the written robots read from the reference tool's report of their graphs, the
form the robot this retrieval is judged on comes in. A report has no endpoint counts, so a
command topic nobody reads or a measured one nobody publishes looks as live as the rest: the
Stretch's Nav2 /cmd_vel (its driver reads /stretch/cmd_vel) 17 -> 11, the Spot's Nav2 /odom
(Spot publishes /odometry) 16 -> 11, the LoCoBot's root /cmd_vel 19 -> 18. The others score
as their live graphs do."""

DESCRIBED_FLOORS = [
    ("go2", 13),
    ("kmriiwa", 18),
    ("mmo700nav", 22),
    ("tb3manip", 20),
    ("tiago", 19),
]
"""Recall@4 of the written robots whose candidates carry the local model's free-text
descriptions (``bench/describe_robots.py``), as a report with descriptions carries them: what
they score without them, since the written words are not weighed. With the text in place of
the rules' description (before) they found 8, 15, 15, 14 and 16."""

HYBRID_FLOORS = [
    ("mr1", 4, 18),
    ("mr1", 8, 18),
    ("cap2skill", 4, 18),
    ("cap2skill-filtered", 4, 18),
]


@pytest.mark.parametrize(("name", "k", "floor"), LEXICAL_FLOORS)
def test_lexical_recall_stays_at_or_above_its_floor(
    name: str, k: int, floor: int, request: pytest.FixtureRequest
) -> None:
    if name != "mr1":
        request.getfixturevalue("shared_data")
    recall = measure(load_set(name), lexical, k)
    assert recall.found >= floor, recall.misses


def test_every_written_robot_has_a_names_only_floor() -> None:
    assert sorted(name for name, _ in NAMES_ONLY_FLOORS) == sorted(WRITTEN)


@pytest.mark.parametrize(("name", "floor"), NAMES_ONLY_FLOORS)
def test_lexical_recall_of_names_only_robots_stays_at_or_above_its_floor(
    name: str, floor: int, shared_data: object
) -> None:
    recall = measure(load_set(name, live=False), lexical, 4)
    assert recall.found >= floor, recall.misses


@pytest.mark.parametrize(("name", "floor"), REPORT_FLOORS)
def test_lexical_recall_of_robots_read_from_a_report_stays_at_or_above_its_floor(
    name: str, floor: int, shared_data: object
) -> None:
    labelled = load_set(name, report=True)
    assert all(i.endpoints is None for i in labelled.inventory.interfaces)
    recall = measure(labelled, lexical, 4)
    assert recall.found >= floor, recall.misses


def test_every_written_robot_has_a_report_floor() -> None:
    assert sorted(name for name, _ in REPORT_FLOORS) == sorted(WRITTEN)


def test_every_described_robot_has_a_floor_and_every_candidate_a_description() -> None:
    assert sorted(name for name, _ in DESCRIBED_FLOORS) == described_robots()
    for name in described_robots():
        for interface in candidates(load_set(name, described=True).inventory):
            assert interface.description is not None, f"{name}: {interface.name}"
            assert interface.description.engine == "report"
            assert interface.description.purpose, f"{name}: {interface.name}"


@pytest.mark.parametrize(("name", "floor"), DESCRIBED_FLOORS)
def test_lexical_recall_of_described_robots_stays_at_or_above_its_floor(
    name: str, floor: int, shared_data: object
) -> None:
    recall = measure(load_set(name, described=True), lexical, 4)
    assert recall.found >= floor, recall.misses


@pytest.fixture(scope="module")
def minilm(tmp_path_factory: pytest.TempPathFactory) -> Embedder:
    from skillwright.llm.config import load_registry
    from skillwright.llm.embeddings import load_embedder

    # a fresh cache: vectors come from the model, and each text is embedded once
    embedder = load_embedder(load_registry(), cache=tmp_path_factory.mktemp("embeddings"))

    def embed(texts: Sequence[str]) -> Sequence[Sequence[float]]:
        return embedder.embed(texts)  # type: ignore[return-value]

    return embed


@pytest.mark.slow
@pytest.mark.parametrize(("name", "k", "floor"), HYBRID_FLOORS)
def test_hybrid_recall_with_minilm_stays_at_or_above_its_floor(
    name: str, k: int, floor: int, minilm: Embedder, request: pytest.FixtureRequest
) -> None:
    if name != "mr1":
        request.getfixturevalue("shared_data")

    def hybrid(inventory: Inventory, capability: Capability, spec: SkillSpec, k: int) -> list[str]:
        return [h.name for h in rank_interfaces(inventory, capability, spec, k=k, embed=minilm)]

    recall = measure(load_set(name), hybrid, k)
    assert recall.found >= floor, recall.misses


@pytest.mark.parametrize("distro", ["humble", "jazzy"])
def test_every_written_definition_parses_with_its_fields_two_levels_down(distro: str) -> None:
    from tests.retrieval.robots import LiveStore, written_texts

    store = LiveStore(distro)
    parts = {"/msg/": ("",), "/srv/": ("_Request", "_Response")}
    for type_name in written_texts(distro):
        suffixes = parts.get(type_name[type_name.index("/") : type_name.rindex("/") + 1])
        for suffix in suffixes or ("_Goal", "_Result", "_Feedback"):
            definition = store.definition(type_name + suffix)
            assert definition is not None, type_name + suffix
            assert not [n for n in definition.notes if "not a ROS 2 type" in n], type_name
