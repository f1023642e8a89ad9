"""Labelled retrieval sets and recall measurement, shared by the tests and the benchmark.

A labelled set (``tests/retrieval/labels/*.yaml``) names, for each capability, the
interfaces a correct skill needs on one robot: ``required`` ones, and ``alternatives``
groups of which any one member is enough. Each required interface and each group is one
*need*. ``recall@k`` counts the needs with a member among the first ``k`` hits.

A capability can need more interfaces than ``k`` (the MR-1's mapping needs six); those
needs cannot all be found at that ``k`` by any ranking, so :class:`Recall` also reports
the *attainable* count, ``min(needs, k)`` summed over the capabilities.

The paper's robot is read from its Cap2Skill reports by the report import. Nineteen more robots,
written down from public sources (``tests/retrieval/robots``), run the paper's nine
capabilities and specs, as the robot this retrieval is judged on does: a TurtleBot 4 with Nav2,
PAL TIAGo (a mobile manipulator with Nav2, SLAM Toolbox, MoveIt and ros2_control), a UR5e arm,
a Unitree Go2 whose names are not English words, a Husarion ROSbot XL with an
OpenMANIPULATOR-X (a second mobile manipulator of that kind, with other vendors' names), a
Clearpath Husky with a Kinova arm whose every name sits under the robot's serial
(``/a200_0000/...``), a Hello Robot Stretch 3, whose one driver node moves base and arm and
takes base velocity only in navigation mode, an Interbotix LoCoBot (a Create 3 base, Nav2 at the
root, the driver under ``/locobot``), a match MuR620 (a MiR base with two UR10e arms, four
scans), a Robotnik RB-KAIROS+ (a mecanum base with a UR arm, everything under ``/robot``) and a
KUKA KMR iiwa on a research stack (a Java bridge's own topics, two scanners merged into one,
an arm planned through a vendor action), a TurtleBot3 with an OpenMANIPULATOR-X on ROBOTIS's
own Humble stack (Cartographer, Nav2, MoveIt) and a Toyota HSR on Toyota's own Jazzy stack
(its navigation, planner services and names, 597 interfaces) and a Hiwonder JetRover on the
vendor's image (a servo bus arm behind its own kinematics node, ``/controller/cmd_vel``,
``/odom_raw``), a Boston Dynamics Spot with its arm (the spot_ros2 driver, a Velodyne,
Cartographer and Nav2; it must stand up before it moves), an OMRON LD-250 with a TM12X arm
(Nav2, SLAM Toolbox, MoveIt), an AgileX Scout 2.0 with a PiPER arm (the vendor's own driver
names, SLAM Toolbox, Nav2, an Ouster) and a Husarion Panther with a UR5e (the base under
``/panther``, UR's driver and MoveIt at the root, 616 interfaces) and a Neobotix MMO-700 in
Gazebo, the paper's robot with Nav2, SLAM Toolbox and MoveIt running. The last fourteen were
labelled by someone who saw no ranking of them. Only the capabilities a robot can serve are labelled; the label files say why
the others are left out.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import yaml

from skillwright.capability import Capability, load_capability
from skillwright.interfaces.inventory import Inventory, Relevance
from skillwright.interfaces.load import load_inventory
from skillwright.interfaces.sources.report import (
    description_from_text,
    inventory_from_report,
    read_report,
    report_from_inventory,
)
from skillwright.spec import SkillSpec, load_spec
from tests.conftest import REPO_ROOT, SHARED
from tests.retrieval.robots import robot_inventory

LABELS = Path(__file__).resolve().parent / "labels"
DESCRIBED_DIR = Path(__file__).resolve().parent / "robots" / "described"
"""The local model's free-text descriptions of written robots' candidates
(``bench/describe_robots.py``), in the four-section layout of a report with descriptions."""

WRITTEN = (
    "tb4",
    "tiago",
    "ur5e",
    "go2",
    "rosbotxl",
    "husky",
    "stretch3",
    "locobot",
    "mur620",
    "rbkairos",
    "kmriiwa",
    "tb3manip",
    "hsr",
    "jetrover",
    "spot",
    "omronmoma",
    "scoutpiper",
    "panther",
    "mmo700nav",
)
"""The robots of ``tests/retrieval/robots``: graphs written from public sources."""

SETS = ("mr1", "cap2skill", "cap2skill-filtered", *WRITTEN)
"""The labelled settings: our MR-1 recording; the paper's robot with its full report
(infrastructure left out by our rules); the same robot with only the 33 interfaces the
paper's relevance filter kept, carrying the paper's LLM-written descriptions; and the
robots of :data:`WRITTEN`."""

ROBOTS = {"mr1": "mr1", "cap2skill": "mmo700", "cap2skill-filtered": "mmo700"} | {
    name: name for name in WRITTEN
}
"""The robot of each set (the two Cap2Skill settings share one), for leave-one-robot-out."""

Ranker = Callable[[Inventory, Capability, SkillSpec, int], Sequence[str]]
"""(inventory, capability, spec, k) -> interface names, best first."""


@dataclass(frozen=True)
class Case:
    """One capability with the interfaces its skill needs."""

    name: str
    capability: Capability
    spec: SkillSpec
    required: tuple[str, ...]
    alternatives: tuple[tuple[str, ...], ...]

    @property
    def needs(self) -> list[tuple[str, ...]]:
        """Each need as the names that satisfy it."""
        return [(name,) for name in self.required] + list(self.alternatives)


@dataclass(frozen=True)
class LabelledSet:
    """A robot's inventory and the labelled capabilities."""

    name: str
    inventory: Inventory
    cases: tuple[Case, ...]
    unserved: tuple[str, ...] = ()
    """Capabilities the robot cannot serve (left out of the cases)."""

    @property
    def need_count(self) -> int:
        """Needs over all cases."""
        return sum(len(c.needs) for c in self.cases)


@dataclass
class Recall:
    """How many needs a ranking found in its first ``k`` hits."""

    k: int
    found: int = 0
    total: int = 0
    attainable: int = 0
    misses: list[str] = field(default_factory=list)

    def __str__(self) -> str:
        return f"{self.found}/{self.total}"


def measure(labelled: LabelledSet, rank: Ranker, k: int) -> Recall:
    """Recall@k of ``rank`` over the set; ``misses`` names each need not found."""
    result = Recall(k)
    for case in labelled.cases:
        hits = list(rank(labelled.inventory, case.capability, case.spec, k))[:k]
        result.total += len(case.needs)
        result.attainable += min(len(case.needs), k)
        for need in case.needs:
            if any(name in hits for name in need):
                result.found += 1
            else:
                result.misses.append(f"{case.name}: {'|'.join(need)}")
    return result


def described_robots() -> list[str]:
    """The written robots the local model has described (see :data:`DESCRIBED_DIR`)."""
    return sorted(p.stem for p in DESCRIBED_DIR.glob("*.json"))


def _described(inventory: Inventory, name: str) -> Inventory:
    """The inventory with the model's descriptions, read as a report's are (engine
    ``report``), on every interface they cover."""
    document = json.loads((DESCRIBED_DIR / f"{name}.json").read_text(encoding="utf-8"))
    texts: dict[str, str] = document["descriptions"]
    interfaces = [
        i.model_copy(update={"description": description_from_text(texts[f"{i.kind} {i.name}"])})
        if f"{i.kind} {i.name}" in texts
        else i
        for i in inventory.interfaces
    ]
    return inventory.model_copy(update={"interfaces": interfaces})


def _through_a_report(inventory: Inventory, name: str) -> Inventory:
    """The inventory as the reference tool's report of it reads back: no endpoint counts
    and no traffic, and a type's definition only where ``ros2 interface show`` would give it
    whole."""
    document, _ = report_from_inventory(inventory)
    return inventory_from_report(document, f"{name} as a report")


@cache
def load_set(
    name: str, live: bool = True, described: bool = False, report: bool = False
) -> LabelledSet:
    """One of :data:`SETS`; the Cap2Skill ones need ``../shared/data``. A written robot shows
    its types' fields as a live graph would (``live``), or names its types only; with
    ``described`` its candidates carry the local model's free-text descriptions, as a
    report with descriptions would (:func:`described_robots` have them); with ``report`` it
    is read from the reference tool's report of its graph, as the robot this retrieval is
    judged on is."""
    label_file = "cap2skill.yaml" if name.startswith("cap2skill") else f"{name}.yaml"
    document = yaml.safe_load((LABELS / label_file).read_text(encoding="utf-8"))
    root = REPO_ROOT if name == "mr1" else SHARED / "data"
    if "robot_file" in document:
        inventory = robot_inventory(document["robot_file"], live=live)
        if described:
            inventory = _described(inventory, name)
        if report:
            inventory = _through_a_report(inventory, name)
    elif name == "mr1":
        inventory = load_inventory(root / document["inventory"])
    elif name == "cap2skill":
        inventory = read_report(root / document["inventory"])
    else:
        inventory = _kept_by_the_papers_filter(read_report(root / document["filtered_inventory"]))
    cases = []
    for stem, entry in document["capabilities"].items():
        names = {"name": stem, "snake": stem.replace("-", "_")}
        capability = load_capability(root / document["models"].format(**names)).capability
        spec = load_spec(root / document["specs"].format(**names))
        cases.append(
            Case(
                name=stem,
                capability=capability,
                spec=spec,
                required=tuple(entry["required"] or {}),
                alternatives=tuple(tuple(group) for group in entry["alternatives"] or []),
            )
        )
    return LabelledSet(name, inventory, tuple(cases), tuple(document.get("unserved") or {}))


_KEPT = Relevance(
    relevant=True,
    category="control",
    reason="kept by the paper's LLM relevance filter",
    engine="report",
)


def _kept_by_the_papers_filter(inventory: Inventory) -> Inventory:
    """Every interface of the filtered report is a candidate, whatever our rules say."""
    interfaces = [i.model_copy(update={"relevance": _KEPT}) for i in inventory.interfaces]
    return inventory.model_copy(update={"interfaces": interfaces})
