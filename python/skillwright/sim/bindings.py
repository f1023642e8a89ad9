"""Which of the robot's interfaces the simulated world serves, found by type and role.

The world never assumes topic names: it reads the inventory. The base's velocity command
is the Twist topic named like a command (``cmd_vel``); odometry, lidar scans, IMU, pose
and map topics are found by their message types; navigation and arm motions by their
action types; map saving and forward kinematics by their service types. Rates come from
the recording's traffic where it has them (snapped to the nominal rate a driver is set
to), else from typical values. Scan geometry and frame names come from the first message
of the recording itself when the inventory was made from one (see :func:`recorded_facts`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from skillwright.interfaces.inventory import Interface, Inventory
from skillwright.interfaces.roles import TWIST_TYPES, command_topic
from skillwright.retrieval.semantics import split_view
from skillwright.runtime.motion import ACTION_TYPES

__all__ = [
    "Bindings",
    "RecordedFacts",
    "ScanGeometry",
    "bind_interfaces",
    "nominal_rate",
    "recorded_facts",
]

SERVICE_TYPES: dict[str, str] = {
    "nav2_msgs/srv/SaveMap": "nav2_save_map",
    "slam_toolbox/srv/SaveMap": "slam_save_map",
    "moveit_msgs/srv/GetPositionFK": "compute_fk",
}
_COMMON_RATES = (0.2, 0.5, 1, 2, 5, 10, 15, 20, 25, 30, 40, 50, 60, 100, 200, 250, 500, 1000)
DEFAULT_RATES = {
    "odometry": 50.0,
    "scan": 10.0,
    "imu": 50.0,
    "pose": 5.0,
    "map": 0.5,
    "tf_static": 0.5,
}


def nominal_rate(measured: float | None, default: float) -> float:
    """The rate a driver was set to, from a rate measured over a short recording.

    ``49.93`` -> ``50``; a rate not within 10 % of a common one is kept as measured.
    """
    if measured is None or not math.isfinite(measured) or measured <= 0:
        return default
    best = min(_COMMON_RATES, key=lambda rate: abs(rate - measured) / rate)
    return float(best) if abs(best - measured) / best <= 0.1 else measured


@dataclass(frozen=True)
class ScanGeometry:
    """The beams of a 2-D lidar as its LaserScan messages describe them."""

    angle_min: float = -math.pi
    angle_increment: float = 2 * math.pi / 360
    count: int = 360
    range_min: float = 0.05
    range_max: float = 12.0
    scan_time: float = 0.1
    frame_id: str = "laser_link"
    recorded: bool = False
    """True when taken from a recorded message, False for the defaults."""

    @property
    def angle_max(self) -> float:
        """Bearing of the last beam."""
        return self.angle_min + (self.count - 1) * self.angle_increment


@dataclass
class RecordedFacts:
    """What the first recorded messages say about the robot."""

    scans: dict[str, ScanGeometry] = field(default_factory=dict)
    """Scan geometry per LaserScan topic."""
    odom_frame: str | None = None
    base_frame: str | None = None
    map_frame: str | None = None
    map_resolution: float | None = None
    arm_groups: dict[str, str | None] = field(default_factory=dict)
    """The planning groups of the robot's semantic description (SRDF, as MoveIt's
    move_group publishes it on ``robot_description_semantic``), each with the tip link of
    its chain (``None`` when the group is not a chain); empty when none was recorded."""
    notes: list[str] = field(default_factory=list)


@dataclass
class Bindings:
    """The robot's interfaces the world takes over, by role."""

    command_topic: str | None = None
    command_stamped: bool = False
    odometry_topics: list[str] = field(default_factory=list)
    scan_topics: list[str] = field(default_factory=list)
    imu_topics: list[str] = field(default_factory=list)
    pose_topics: list[str] = field(default_factory=list)
    tf_topic: str | None = None
    tf_static_topic: str | None = None
    map_topic: str | None = None
    map_metadata_topic: str | None = None
    actions: dict[str, str] = field(default_factory=dict)
    """Action name -> what the world does for it (a value of :data:`ACTION_TYPES`)."""
    action_types: dict[str, str] = field(default_factory=dict)
    services: dict[str, str] = field(default_factory=dict)
    """Service name -> what the world does for it."""
    service_types: dict[str, str] = field(default_factory=dict)
    rates: dict[str, float] = field(default_factory=dict)
    """Publication rate per topic the world publishes [Hz]."""
    notes: list[str] = field(default_factory=list)

    @property
    def has_localisation(self) -> bool:
        """Whether the robot has a map frame (SLAM or a localiser publishes pose or map)."""
        return bool(self.pose_topics) or self.map_topic is not None

    def owned_topics(self) -> list[str]:
        """Every topic the world publishes."""
        topics = [
            *self.odometry_topics,
            *self.scan_topics,
            *self.imu_topics,
            *self.pose_topics,
            self.tf_topic,
            self.tf_static_topic,
            self.map_topic,
            self.map_metadata_topic,
        ]
        return [t for t in topics if t is not None]


def _segment(name: str) -> str:
    return name.rstrip("/").rsplit("/", 1)[-1]


def _rate(interface: Interface) -> float | None:
    return None if interface.traffic is None else interface.traffic.rate_hz


def bind_interfaces(inventory: Inventory) -> Bindings:
    """Find the interfaces the world serves in ``inventory``."""
    topics = [i for i in inventory.interfaces if i.kind == "topic"]
    bindings = Bindings()
    twists = {t.name: t for t in topics if t.type_name in TWIST_TYPES}
    command = command_topic(twists)
    if command is not None:
        bindings.command_topic = command
        bindings.command_stamped = twists[command].type_name.endswith("TwistStamped")
    else:
        bindings.notes.append(
            "no velocity command topic (a Twist named like cmd_vel): skills cannot move the base"
        )
    by_type: dict[str, list[Interface]] = {}
    for topic in topics:
        by_type.setdefault(topic.type_name, []).append(topic)

    def names(type_name: str, role: str) -> list[str]:
        found = sorted(by_type.get(type_name, []), key=lambda i: i.name)
        for interface in found:
            bindings.rates[interface.name] = nominal_rate(_rate(interface), DEFAULT_RATES[role])
        return [i.name for i in found]

    bindings.odometry_topics = names("nav_msgs/msg/Odometry", "odometry")
    bindings.scan_topics = names("sensor_msgs/msg/LaserScan", "scan")
    bindings.imu_topics = names("sensor_msgs/msg/Imu", "imu")
    bindings.pose_topics = names("geometry_msgs/msg/PoseWithCovarianceStamped", "pose")
    for topic in by_type.get("tf2_msgs/msg/TFMessage", []):
        if _segment(topic.name) == "tf":
            bindings.tf_topic = topic.name
        elif _segment(topic.name) == "tf_static":
            bindings.tf_static_topic = topic.name
            bindings.rates[topic.name] = DEFAULT_RATES["tf_static"]
    grids = [g for g in by_type.get("nav_msgs/msg/OccupancyGrid", []) if _segment(g.name) == "map"]
    if grids:
        grid = min(grids, key=lambda g: len(g.name))
        bindings.map_topic = grid.name
        bindings.rates[grid.name] = nominal_rate(_rate(grid), DEFAULT_RATES["map"])
        for meta in by_type.get("nav_msgs/msg/MapMetaData", []):
            bindings.map_metadata_topic = meta.name
            bindings.rates[meta.name] = bindings.rates[grid.name]
            break
    for interface in inventory.interfaces:
        if interface.kind == "action" and interface.type_name in ACTION_TYPES:
            bindings.actions[interface.name] = ACTION_TYPES[interface.type_name]
            bindings.action_types[interface.name] = interface.type_name
        elif interface.kind == "service" and interface.type_name in SERVICE_TYPES:
            bindings.services[interface.name] = SERVICE_TYPES[interface.type_name]
            bindings.service_types[interface.name] = interface.type_name
    if not bindings.odometry_topics:
        bindings.notes.append("no Odometry topic: the world publishes no odometry")
    if not bindings.scan_topics:
        bindings.notes.append("no LaserScan topic: the world publishes no scans")
    return bindings


def split_views(topics: list[str]) -> list[list[str]]:
    """The scan topics grouped into views: the scanners of one split view together (see
    :func:`~skillwright.retrieval.semantics.split_view`: ``/scan`` and ``/scan2`` on opposite
    corners), every other topic alone; each group in name order."""
    scans = [Interface(name=t, kind="topic", type_name=_LASER_SCAN) for t in sorted(topics)]
    groups: list[list[Interface]] = []
    for scan in scans:
        group = next((g for g in groups if all(split_view(scan, o) for o in g)), None)
        if group is None:
            groups.append([scan])
        else:
            group.append(scan)
    return [[i.name for i in group] for group in groups]


def default_geometries(topics: list[str]) -> dict[str, ScanGeometry]:
    """Scan geometry for topics without a recorded message: a full turn for a scanner of its
    own; for the ``n`` scanners of a split view, one ``n``-th of the turn each, in name order
    from the front half (``/scan``) on, so that each sees what the others do not, as the
    MMO-700's two corner scanners do. A skill that reads one of them misses what is on the
    others' sides."""
    full = ScanGeometry()
    out: dict[str, ScanGeometry] = {}
    for group in split_views(topics):
        share = len(group)
        for index, topic in enumerate(group):
            out[topic] = (
                full
                if share == 1
                else dataclasses.replace(
                    full,
                    angle_min=-math.pi / share + index * 2 * math.pi / share,
                    count=full.count // share,
                )
            )
    return out


def _sector_notes(geometries: dict[str, ScanGeometry]) -> list[str]:
    return [
        f"{topic}: one scanner of a split view; it sees from "
        f"{math.degrees(g.angle_min):.0f} to {math.degrees(g.angle_max):.0f} degrees only"
        for topic, g in geometries.items()
        if g.count < ScanGeometry().count
    ]


_LASER_SCAN = "sensor_msgs/msg/LaserScan"


def _recording_path(inventory: Inventory, recording: Path | None) -> Path | None:
    if recording is not None:
        from skillwright.runtime.run import recording_files

        files = recording_files(recording)
        return files[0] if files else None
    for source in inventory.sources:
        if source.kind not in ("mcap", "rosbag2"):
            continue
        for file in source.files:
            path = Path(file.path)
            if path.is_file():
                return path
    return None


def _first_messages(
    path: Path, topics: dict[str, str], inventory: Inventory
) -> dict[str, dict[str, Any]]:
    """The first message on each of ``topics`` (name -> type), decoded to a dict."""
    from skillwright.runtime.recorded import MessageDecoder, merged_messages
    from skillwright.runtime.typesys import registry_for

    decoder = MessageDecoder(registry_for(inventory))
    found: dict[str, dict[str, Any]] = {}
    for _time, topic, payload in merged_messages([path], set(topics)):
        if topic in found:
            continue
        found[topic] = decoder.decode(topics[topic], payload)
        if len(found) == len(topics):
            break
    return found


_STRING = "std_msgs/msg/String"


def semantic_topic(inventory: Inventory) -> str | None:
    """The topic the robot's SRDF is published on: a ``std_msgs/msg/String`` topic named
    ``robot_description_semantic`` (move_group publishes it so since ROS 2 Iron)."""
    names = [
        i.name
        for i in inventory.interfaces
        if i.kind == "topic"
        and i.type_name == _STRING
        and _segment(i.name) == "robot_description_semantic"
    ]
    return min(names, key=len, default=None)


def srdf_groups(text: str) -> dict[str, str | None]:
    """Planning group -> the tip link of its chain (``None``: not a chain), from an SRDF
    document (``<group name=...><chain base_link=... tip_link=.../></group>``); a group
    made of other groups takes the tip of the first of them that is a chain. Empty when the
    text is not an SRDF."""
    from xml.etree import ElementTree

    try:
        root = ElementTree.fromstring(text)
    except ElementTree.ParseError:
        return {}
    groups: dict[str, str | None] = {}
    members: dict[str, list[str]] = {}
    for group in root.findall("group"):
        name = group.get("name")
        if not name:
            continue
        chain = group.find("chain")
        groups[name] = chain.get("tip_link") if chain is not None else None
        members[name] = [g.get("name") or "" for g in group.findall("group")]
    for name, parts in members.items():
        if groups[name] is None:
            groups[name] = next((groups[p] for p in parts if groups.get(p)), None)
    return groups


def recorded_facts(
    inventory: Inventory, bindings: Bindings, recording: Path | None = None
) -> RecordedFacts:
    """Scan geometry and frame names from ``recording``, else from the recording the
    inventory was made from.

    Sources without messages (a report, a live graph) or a recording that is no longer where
    the inventory says give the defaults, with a note saying so.
    """
    facts = RecordedFacts()
    path = _recording_path(inventory, recording)
    wanted = dict.fromkeys(bindings.scan_topics, "sensor_msgs/msg/LaserScan")
    wanted.update(dict.fromkeys(bindings.odometry_topics, "nav_msgs/msg/Odometry"))
    if bindings.map_topic:
        wanted[bindings.map_topic] = "nav_msgs/msg/OccupancyGrid"
    semantic = semantic_topic(inventory)
    if semantic is not None:
        wanted[semantic] = _STRING
    defaults = default_geometries(bindings.scan_topics)
    if path is None or not wanted:
        if bindings.scan_topics:
            facts.notes.append(
                "scan geometry and frames: defaults (360 beams over a full turn, 0.05-12 m, "
                "frame laser_link), as the interface source holds no recorded messages"
            )
        facts.scans = dict(defaults)
        facts.notes += _sector_notes(defaults)
        return facts
    try:
        first = _first_messages(path, wanted, inventory)
    except (OSError, ValueError, KeyError) as error:  # a damaged recording: defaults
        facts.notes.append(f"{path}: recorded messages unreadable ({error}); defaults used")
        first = {}
    for topic in bindings.scan_topics:
        if topic not in first:
            facts.scans[topic] = defaults[topic]
            facts.notes.append(f"{topic}: no recorded scan; default geometry used")
            facts.notes += _sector_notes({topic: defaults[topic]})
            continue
        scan = first[topic]
        count = len(scan["ranges"])
        facts.scans[topic] = ScanGeometry(
            angle_min=float(scan["angle_min"]),
            angle_increment=float(scan["angle_increment"]),
            count=count if count > 0 else 360,
            range_min=float(scan["range_min"]),
            range_max=float(scan["range_max"]),
            scan_time=float(scan["scan_time"]) or 0.1,
            frame_id=str(scan["header"]["frame_id"]) or "laser_link",
            recorded=count > 0,
        )
    for topic in bindings.odometry_topics:
        if topic in first:
            odometry = first[topic]
            facts.odom_frame = str(odometry["header"]["frame_id"]) or None
            facts.base_frame = str(odometry["child_frame_id"]) or None
            break
    if bindings.map_topic and bindings.map_topic in first:
        grid = first[bindings.map_topic]
        facts.map_frame = str(grid["header"]["frame_id"]) or None
        facts.map_resolution = float(grid["info"]["resolution"]) or None
    if semantic is not None and semantic in first:
        facts.arm_groups = srdf_groups(str(first[semantic].get("data", "")))
    return facts
