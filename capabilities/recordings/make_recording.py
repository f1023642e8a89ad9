"""Write the MR-1 demo recording: a rosbag2 folder ``mr1/`` with one MCAP file.

Run from the repository root:  python capabilities/recordings/make_recording.py [OUT_DIR]
(OUT_DIR defaults to capabilities/recordings/mr1).

The bag looks like ``ros2 bag record --all`` (topics, hidden action topics and service
events) on the MR-1 running ROS 2 Jazzy for 3 s, from 2026-01-15T10:00:00Z:

* MCAP profile ``ros2``, zstd chunks, message/chunk indexes, statistics, summary offsets,
  a ``rosbag2`` metadata record, and ``metadata.yaml`` (rosbag2 format version 8).
* One schema per type, encoding ``ros2msg``; the data is the full definition text as
  rosbag2's LocalMessageDefinitionSource builds it: the root definition, then for every
  dependency (depth first, sorted per level, each once) a line of 80 ``=`` and
  ``MSG: pkg/Type`` followed by that type's text.
* Services are recorded as ``<service>/_service_event`` channels of type
  ``pkg/srv/Name_Event``.  As in rosbag2 Jazzy (see the service-event bags in
  ../shared/data/mcap/rosbag2), their schema holds the raw ``.srv`` text (request ``---``
  response) followed by the ``MSG:`` blocks of the types it uses.
* Actions appear as ``<action>/_action/feedback`` (``pkg/action/Name_FeedbackMessage``),
  ``<action>/_action/status`` (``action_msgs/msg/GoalStatusArray``) and the service events
  of ``_action/send_goal``, ``_action/get_result`` (``pkg/action/Name_SendGoal_Event``,
  ``..._GetResult_Event``) and ``_action/cancel_goal`` (``action_msgs/srv/CancelGoal_Event``).
  Feedback and goal/result events carry the raw ``.action`` text (goal ``---`` result
  ``---`` feedback) plus ``MSG:`` blocks, the same convention as services.  (rosbag2 Jazzy
  itself leaves these definitions empty; rosbag2 Kilted+ writes the same text behind an
  ``ACTION:`` delimiter line.)
* Channel metadata: ``offered_qos_profiles`` (rosbag2's YAML) and ``topic_type_hash``
  (RIHS01, computed here as rosidl does).

Messages are CDR encoded with mcap-ros2-support.  Everything is deterministic: fixed start
time, fixed seed, sorted iteration, so two runs give byte-identical files.
Needs: mcap, mcap-ros2-support (zstandard comes with mcap's zstd support), pyyaml.
"""

from __future__ import annotations

import hashlib
import json
import math
import random
import re
import sys
from pathlib import Path

import yaml
from mcap.writer import CompressionType, Writer
from mcap_ros2._dynamic import serialize_dynamic

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from ros_definitions import DEFINITIONS  # noqa: E402

START_NS = 1768471200 * 10**9  # 2026-01-15T10:00:00Z
DURATION_S = 3.0
SEED = 20260115
BAG_DIR = HERE / "mr1"
MCAP_NAME = "mr1_0.mcap"
SEP = "=" * 80 + "\n"
PRIMITIVES = {"bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16",
              "uint16", "int32", "uint32", "int64", "uint64", "string", "wstring"}

# ------------------------------------------------------------------ definition text


def _split_type(full: str) -> tuple[str, str, str]:
    pkg, ns, name = full.split("/")
    return pkg, ns, name


def _lookup_dep(dep: str) -> str:
    """'geometry_msgs/Pose' -> definition text (dependencies are always messages)."""
    pkg, name = dep.split("/")
    return DEFINITIONS[f"{pkg}/msg/{name}"]


_FIELD_TYPE_RE = re.compile(r"(?:^|\n)\s*([a-zA-Z0-9_/]+)(?:\[[^\]]*\])?\s+")


def _deps(text: str, pkg: str) -> list[str]:
    """Dependencies as rosbag2 parses them (regex over the text, sorted, unique)."""
    found = set()
    for match in _FIELD_TYPE_RE.finditer(text):
        typ = match.group(1)
        if typ in PRIMITIVES:
            continue
        found.add(typ if "/" in typ else f"{pkg}/{typ}")
    return sorted(found)


def full_text(root_text: str, pkg: str) -> str:
    seen: set[str] = set()

    def rec(text: str, context: str) -> str:
        out = text
        for dep in _deps(text, context):
            if dep in seen:
                continue
            seen.add(dep)
            out += "\n" + SEP + f"MSG: {dep}\n" + rec(_lookup_dep(dep), dep.split("/")[0])
        return out

    return rec(root_text, pkg)


# ------------------------------------------------------------------ parsed field lists
# A normalised model of every (also generated) message type: list of
# (field type, array spec, name); types fully qualified as pkg/ns/Name.

def _parse_fields(text: str, pkg: str, ns_of_bare: str) -> list[tuple[str, str, str]]:
    fields = []
    for raw in text.splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        typ, rest = line.split(None, 1)
        name = rest.split()[0]
        if "=" in name:  # a constant: "uint8 NAME=value"
            continue
        array = ""
        if "[" in typ:
            typ, array = typ.split("[", 1)
            array = "[" + array
        bound = ""
        if typ.startswith("string<="):
            bound, typ = typ[len("string<="):], "string"
        if typ not in PRIMITIVES:
            if "/" in typ:
                p, n = typ.split("/")
                typ = f"{p}/msg/{n}"
            else:
                typ = f"{pkg}/{ns_of_bare}/{typ}" if ns_of_bare != "msg" else f"{pkg}/msg/{typ}"
        elif bound:
            typ = f"string<={bound}"
        fields.append((typ, array, name))
    return fields


MODEL: dict[str, list[tuple[str, str, str]]] = {}


def _build_model() -> None:
    for full, text in DEFINITIONS.items():
        pkg, ns, name = _split_type(full)
        if ns == "msg":
            MODEL[full] = _parse_fields(text, pkg, "msg")
        elif ns == "srv":
            req, resp = text.split("\n---\n") if "\n---\n" in text else ("", text.split("---\n", 1)[1])
            if text.startswith("---"):
                req, resp = "", text.split("---\n", 1)[1]
            MODEL[f"{full}_Request"] = _parse_fields(req, pkg, "msg")
            MODEL[f"{full}_Response"] = _parse_fields(resp, pkg, "msg")
            MODEL[f"{full}_Event"] = _event_fields(full)
        elif ns == "action":
            goal, result, feedback = _split_action(text)
            MODEL[f"{full}_Goal"] = _parse_fields(goal, pkg, "msg")
            MODEL[f"{full}_Result"] = _parse_fields(result, pkg, "msg")
            MODEL[f"{full}_Feedback"] = _parse_fields(feedback, pkg, "msg")
            uuid = "unique_identifier_msgs/msg/UUID"
            MODEL[f"{full}_FeedbackMessage"] = [(uuid, "", "goal_id"), (f"{full}_Feedback", "", "feedback")]
            MODEL[f"{full}_SendGoal_Request"] = [(uuid, "", "goal_id"), (f"{full}_Goal", "", "goal")]
            MODEL[f"{full}_SendGoal_Response"] = [("bool", "", "accepted"),
                                                  ("builtin_interfaces/msg/Time", "", "stamp")]
            MODEL[f"{full}_SendGoal_Event"] = _event_fields(f"{full}_SendGoal")
            MODEL[f"{full}_GetResult_Request"] = [(uuid, "", "goal_id")]
            MODEL[f"{full}_GetResult_Response"] = [("int8", "", "status"), (f"{full}_Result", "", "result")]
            MODEL[f"{full}_GetResult_Event"] = _event_fields(f"{full}_GetResult")


def _split_action(text: str) -> tuple[str, str, str]:
    parts = re.split(r"(?m)^---\s*$\n?", text)
    assert len(parts) == 3, text
    return parts[0], parts[1], parts[2]


def _event_fields(service: str) -> list[tuple[str, str, str]]:
    return [("service_msgs/msg/ServiceEventInfo", "", "info"),
            (f"{service}_Request", "[<=1]", "request"),
            (f"{service}_Response", "[<=1]", "response")]


def _refs(root: str) -> list[str]:
    out: list[str] = []

    def rec(t: str) -> None:
        for typ, _, _ in MODEL[t]:
            if typ in MODEL and typ not in out:
                out.append(typ)
                rec(typ)

    rec(root)
    return out


# ------------------------------------------------------------------ RIHS01 type hash
_TID = {"int8": 2, "uint8": 3, "int16": 4, "uint16": 5, "int32": 6, "uint32": 7, "int64": 8,
        "uint64": 9, "float32": 10, "float64": 11, "bool": 15, "byte": 16,
        # .msg "char" is an alias of uint8 in rosidl (checked: this gives the hash real
        # rosbag2 stored for example_interfaces/srv/AddTwoInts_Event in ../shared)
        "char": 3,
        "string": 17, "wstring": 18}


def _hash_field(typ: str, array: str, name: str) -> dict:
    increment = capacity = string_capacity = 0
    nested = ""
    if array.startswith("[<="):
        increment, capacity = 96, int(array[3:-1])
    elif array == "[]":
        increment = 144
    elif array:
        increment, capacity = 48, int(array[1:-1])
    if typ in MODEL:
        tid, nested = 1, typ
    elif typ.startswith("string<="):
        tid, string_capacity = 21, int(typ[len("string<="):])
    else:
        tid = _TID[typ]
    return {"name": name, "type": {"type_id": tid + increment, "capacity": capacity,
                                   "string_capacity": string_capacity,
                                   "nested_type_name": nested}}


def _hash_struct(t: str) -> dict:
    fields = MODEL[t] or [("uint8", "", "structure_needs_at_least_one_member")]
    return {"type_name": t, "fields": [_hash_field(*f) for f in fields]}


def rihs01(t: str) -> str:
    doc = {"type_description": _hash_struct(t),
           "referenced_type_descriptions": [_hash_struct(r) for r in sorted(set(_refs(t)))]}
    return "RIHS01_" + hashlib.sha256(json.dumps(doc).encode()).hexdigest()


# ------------------------------------------------------------------ CDR encoders


def _ser_name(t: str) -> str:
    # rosidl's parser rejects "_" in type names; these names never leave this module
    pkg, ns, name = t.split("/")
    return f"{pkg}/{ns.capitalize()}{name.replace('_', '')}"


def _ser_text(t: str) -> str:
    """Expanded, constant-free definition only used to build the CDR encoder."""
    def body(x: str) -> str:
        lines = []
        for typ, array, name in MODEL[x]:
            typ = _ser_name(typ) if typ in MODEL else typ
            lines.append(f"{typ}{array} {name}")
        return "\n".join(lines) + "\n"

    out = body(t)
    for ref in _refs(t):
        out += SEP + f"MSG: {_ser_name(ref)}\n" + body(ref)
    return out


_ENCODERS: dict[str, object] = {}


def encode(t: str, msg: dict) -> bytes:
    if t not in _ENCODERS:
        _ENCODERS[t] = serialize_dynamic(_ser_name(t), _ser_text(t))[_ser_name(t)]
    return _ENCODERS[t](msg)


# ------------------------------------------------------------------ schemas per channel type


def schema_text(channel_type: str) -> str:
    """The definition text rosbag2 stores for a channel type."""
    if channel_type in DEFINITIONS:  # a plain message
        pkg = channel_type.split("/")[0]
        return full_text(DEFINITIONS[channel_type], pkg)
    m = re.fullmatch(r"(\w+)/srv/(\w+)_Event", channel_type)
    if m:
        return full_text(DEFINITIONS[f"{m[1]}/srv/{m[2]}"], m[1])
    m = re.fullmatch(r"(\w+)/action/(\w+?)_(FeedbackMessage|SendGoal_Event|GetResult_Event)",
                     channel_type)
    if m:
        return full_text(DEFINITIONS[f"{m[1]}/action/{m[2]}"], m[1])
    raise KeyError(channel_type)


# ------------------------------------------------------------------ QoS strings
_INF = "    sec: 9223372036\n    nsec: 854775807"


def qos(reliability: int = 1, durability: int = 2, depth: int = 0, lifespan: str = _INF,
        count: int = 1) -> str:
    one = (f"- history: 3\n  depth: {depth}\n  reliability: {reliability}\n"
           f"  durability: {durability}\n  deadline:\n{_INF}\n  lifespan:\n{lifespan}\n"
           f"  liveliness: 1\n  liveliness_lease_duration:\n{_INF}\n"
           "  avoid_ros_namespace_conventions: false")
    return "\n".join([one] * count)


TRANSIENT = {"/map", "/map_metadata", "/tf_static", "/robot_description",
             "/local_costmap/costmap", "/global_costmap/costmap"}
BEST_EFFORT = {"/scan", "/imu/data"}


def topic_qos(name: str) -> str:
    if name == "/rosout":
        return qos(1, 1, lifespan="    sec: 10\n    nsec: 0")
    if name.endswith("/_service_event") or name.endswith("/_action/status"):
        return qos(1, 1)
    if name in TRANSIENT:
        return qos(1, 1)
    if name in BEST_EFFORT:
        return qos(2, 2)
    return qos(1, 2)


# ------------------------------------------------------------------ message content helpers


def stamp(t_ns: int) -> dict:
    return {"sec": t_ns // 10**9, "nanosec": t_ns % 10**9}


def header(t_ns: int, frame: str) -> dict:
    return {"stamp": stamp(t_ns), "frame_id": frame}


def quat_yaw(yaw: float) -> dict:
    return {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2), "w": math.cos(yaw / 2)}


def vec(x=0.0, y=0.0, z=0.0) -> dict:
    return {"x": x, "y": y, "z": z}


def pose(x, y, yaw) -> dict:
    return {"position": vec(x, y, 0.0), "orientation": quat_yaw(yaw)}


def tfs(t_ns, parent, child, x, y, z, yaw) -> dict:
    return {"header": header(t_ns, parent), "child_frame_id": child,
            "transform": {"translation": vec(x, y, z), "rotation": quat_yaw(yaw)}}


def uuid_of(n: int) -> dict:
    return {"uuid": list(hashlib.md5(f"mr1-goal-{n}".encode()).digest())}


def gid(n: int) -> list[int]:
    # char[16]; mcap-ros2-support writes char as int8, so pass the same bytes signed
    return [b - 256 if b > 127 else b for b in hashlib.md5(f"mr1-client-{n}".encode()).digest()]


def event(kind: int, t_ns: int, client: int, seq: int, request=None, response=None) -> dict:
    return {"info": {"event_type": kind, "stamp": stamp(t_ns), "client_gid": gid(client),
                     "sequence_number": seq},
            "request": [request] if request is not None else [],
            "response": [response] if response is not None else []}


ZERO_COV = [0.0] * 36
ARM_JOINTS = [f"mr1_arm_joint_{i}" for i in range(1, 7)]
WHEELS = ["wheel_front_left_joint", "wheel_front_right_joint", "wheel_rear_left_joint",
          "wheel_rear_right_joint"]
SPEED = 0.3  # m/s, the base drives slowly forward along +x of odom
START_X_MAP, START_Y_MAP, MAP_YAW = 1.20, 0.85, 0.0
ARM_HOME = [0.0, -0.9, 1.4, 0.0, 1.1, 0.0]


def base_x(t_s: float) -> float:
    return SPEED * t_s


def grid(width: int, height: int, resolution: float, ox: float, oy: float, t_ns: int,
         frame: str, cell) -> dict:
    data = [cell(i % width, i // width) for i in range(width * height)]
    return {"header": header(t_ns, frame),
            "info": {"map_load_time": stamp(t_ns), "resolution": resolution, "width": width,
                     "height": height, "origin": pose(ox, oy, 0.0)},
            "data": data}


def room_cell(ix: int, iy: int) -> int:
    """A 10 m x 6 m room seen from inside: walls occupied, the rest free or unknown."""
    if ix in (0, 1, 198, 199) or iy in (0, 1, 118, 119):
        return 100
    if 120 <= ix <= 128 and 40 <= iy <= 52:  # a shelf in the room
        return 100
    if ix > 170 and iy > 90:
        return -1
    return 0


URDF = """<?xml version="1.0"?>
<robot name="mr1">
  <link name="base_footprint"/>
  <link name="base_link"/>
  <joint name="base_joint" type="fixed"><parent link="base_footprint"/><child link="base_link"/>
    <origin xyz="0 0 0.12"/></joint>
  <link name="laser_link"/>
  <joint name="laser_joint" type="fixed"><parent link="base_link"/><child link="laser_link"/>
    <origin xyz="0.28 0 0.18"/></joint>
  <link name="imu_link"/>
  <joint name="imu_joint" type="fixed"><parent link="base_link"/><child link="imu_link"/></joint>
  <link name="arm_base_link"/>
  <joint name="arm_mount_joint" type="fixed"><parent link="base_link"/><child link="arm_base_link"/>
    <origin xyz="0.05 0 0.32"/></joint>
""" + "".join(
    f"""  <link name="mr1_arm_link_{i}"/>
  <joint name="mr1_arm_joint_{i}" type="revolute"><parent link="{'arm_base_link' if i == 1 else f'mr1_arm_link_{i-1}'}"/>
    <child link="mr1_arm_link_{i}"/><limit lower="-3.14" upper="3.14" effort="40" velocity="1.5"/></joint>
""" for i in range(1, 7)) + """  <link name="tool0"/>
  <joint name="tool0_joint" type="fixed"><parent link="mr1_arm_link_6"/><child link="tool0"/></joint>
</robot>
"""


# ------------------------------------------------------------------ the recording


def load_interfaces() -> list[dict]:
    with open(HERE / "mr1_interfaces.yaml", encoding="utf-8") as f:
        return yaml.safe_load(f)["interfaces"]


def channels_for(interfaces: list[dict]) -> dict[str, str]:
    """Recorded channel name -> channel type."""
    out: dict[str, str] = {}
    for itf in interfaces:
        name, typ = itf["name"], itf["type"]
        if itf["kind"] == "topic":
            out[name] = typ
        elif itf["kind"] == "service":
            out[f"{name}/_service_event"] = f"{typ}_Event"
        else:
            out[f"{name}/_action/feedback"] = f"{typ}_FeedbackMessage"
            out[f"{name}/_action/status"] = "action_msgs/msg/GoalStatusArray"
            out[f"{name}/_action/send_goal/_service_event"] = f"{typ}_SendGoal_Event"
            out[f"{name}/_action/get_result/_service_event"] = f"{typ}_GetResult_Event"
            out[f"{name}/_action/cancel_goal/_service_event"] = "action_msgs/srv/CancelGoal_Event"
    return out


def periodic(rate: float, offset_ns: int = 0):
    if rate <= 0:
        return []
    period = int(round(1e9 / rate))
    return [START_NS + offset_ns + k * period for k in range(int(DURATION_S * rate))
            if offset_ns + k * period < DURATION_S * 1e9]


def generate(interfaces: list[dict]) -> list[tuple[int, str, dict]]:
    rng = random.Random(SEED)
    rate = {i["name"]: i.get("rate_hz", 0) for i in interfaces if i["kind"] == "topic"}
    msgs: list[tuple[int, str, dict]] = []

    def add(t, topic, msg):
        msgs.append((t, topic, msg))

    n = lambda s: rng.gauss(0.0, s)  # noqa: E731
    twist = {"linear": vec(SPEED), "angular": vec()}
    for t in periodic(rate["/cmd_vel_nav"], 3_000_000):
        add(t, "/cmd_vel_nav", twist)
    for t in periodic(rate["/cmd_vel"], 4_000_000):
        add(t, "/cmd_vel", twist)
    for t in periodic(rate["/odom"], 1_000_000):
        ts = (t - START_NS) / 1e9
        cov = ZERO_COV.copy()
        for i, v in enumerate((1e-3, 1e-3, 1e6, 1e6, 1e6, 2e-3)):
            cov[i * 7] = v
        add(t, "/odom", {"header": header(t, "odom"), "child_frame_id": "base_link",
                         "pose": {"pose": pose(base_x(ts), n(0.0005), n(0.0005)), "covariance": cov},
                         "twist": {"twist": {"linear": vec(SPEED + n(0.004), n(0.002)),
                                             "angular": vec(0, 0, n(0.003))}, "covariance": cov}})
        add(t + 200_000, "/tf", {"transforms": [
            tfs(t, "odom", "base_link", base_x(ts), 0.0, 0.0, 0.0)]})
    for t in periodic(rate["/imu/data"], 2_000_000):
        add(t, "/imu/data", {"header": header(t, "imu_link"), "orientation": quat_yaw(n(0.001)),
                             "orientation_covariance": [1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 1e-4],
                             "angular_velocity": vec(n(0.002), n(0.002), n(0.003)),
                             "angular_velocity_covariance": [4e-6, 0, 0, 0, 4e-6, 0, 0, 0, 4e-6],
                             "linear_acceleration": vec(n(0.02), n(0.02), 9.81 + n(0.02)),
                             "linear_acceleration_covariance": [1e-3, 0, 0, 0, 1e-3, 0, 0, 0, 1e-3]})
    beams = 360
    for t in periodic(rate["/scan"], 7_000_000):
        ts = (t - START_NS) / 1e9
        wall = 4.6 - base_x(ts)  # a wall ahead, perpendicular to the heading
        ranges = []
        for i in range(beams):
            a = -math.pi + i * (2 * math.pi / beams)
            r = float("inf")
            if math.cos(a) > 1e-6:
                r = min(r, wall / math.cos(a))
            if math.sin(a) > 1e-6:
                r = min(r, 2.1 / math.sin(a))  # side wall on the left
            if math.sin(a) < -1e-6:
                r = min(r, 1.9 / -math.sin(a))  # side wall on the right
            if math.cos(a) < -1e-6:
                r = min(r, (1.2 + base_x(ts)) / -math.cos(a))
            r = r + n(0.01) if r < 12.0 else float("inf")
            ranges.append(round(r, 3))
        add(t, "/scan", {"header": header(t, "laser_link"), "angle_min": -math.pi,
                         "angle_max": math.pi - 2 * math.pi / beams,
                         "angle_increment": 2 * math.pi / beams, "time_increment": 0.1 / beams,
                         "scan_time": 0.1, "range_min": 0.05, "range_max": 12.0,
                         "ranges": ranges, "intensities": []})
    for t in periodic(rate["/joint_states"], 5_000_000):
        ts = (t - START_NS) / 1e9
        wheel = SPEED / 0.05 * ts
        add(t, "/joint_states", {"header": header(t, ""), "name": ARM_JOINTS + WHEELS,
                                 "position": [q + n(1e-4) for q in ARM_HOME] + [wheel] * 4,
                                 "velocity": [0.0] * 6 + [SPEED / 0.05] * 4,
                                 "effort": [0.0, 3.1, 5.4, 0.4, 0.9, 0.0] + [1.2] * 4})
    for t in periodic(rate["/pose"], 9_000_000):
        ts = (t - START_NS) / 1e9
        cov = ZERO_COV.copy()
        cov[0] = cov[7] = 0.004
        cov[35] = 0.002
        add(t, "/pose", {"header": header(t, "map"),
                         "pose": {"pose": pose(START_X_MAP + base_x(ts) + n(0.01), START_Y_MAP + n(0.01), MAP_YAW),
                                  "covariance": cov}})
        add(t + 300_000, "/tf", {"transforms": [
            tfs(t, "map", "odom", START_X_MAP + n(0.005), START_Y_MAP + n(0.005), 0.0, MAP_YAW)]})
    t0 = START_NS + 12_000_000
    add(t0, "/tf_static", {"transforms": [
        tfs(t0, "base_footprint", "base_link", 0, 0, 0.12, 0),
        tfs(t0, "base_link", "laser_link", 0.28, 0, 0.18, 0),
        tfs(t0, "base_link", "imu_link", 0, 0, 0, 0),
        tfs(t0, "base_link", "arm_base_link", 0.05, 0, 0.32, 0)]})
    add(t0 + 1_000_000, "/robot_description", {"data": URDF})
    t_map = START_NS + 40_000_000
    room = grid(200, 120, 0.05, -1.5, -2.0, t_map, "map", room_cell)
    add(t_map, "/map", room)
    add(t_map + 100_000, "/map_metadata", room["info"])
    add(START_NS + 60_000_000, "/global_costmap/costmap",
        grid(100, 60, 0.1, -1.5, -2.0, START_NS + 60_000_000, "map",
             lambda x, y: 100 if x in (0, 99) or y in (0, 59) or (60 <= x <= 64 and 20 <= y <= 26) else 0))
    add(START_NS + 80_000_000, "/local_costmap/costmap",
        grid(60, 60, 0.05, -1.5, -1.5, START_NS + 80_000_000, "odom",
             lambda x, y: 99 if abs(x - 30) + abs(y - 30) > 40 else 0))
    for t in periodic(rate["/local_costmap/published_footprint"], 11_000_000):
        ts = (t - START_NS) / 1e9
        x = base_x(ts)
        pts = [vec(x + 0.35, 0.27), vec(x + 0.35, -0.27), vec(x - 0.35, -0.27), vec(x - 0.35, 0.27)]
        add(t, "/local_costmap/published_footprint",
            {"header": header(t, "odom"), "polygon": {"points": pts}})
    for t in periodic(rate["/battery_state"], 15_000_000):
        add(t, "/battery_state", {
            "header": header(t, "base_link"), "voltage": 25.1, "temperature": 31.5, "current": -6.2,
            "charge": 14.8, "capacity": 20.0, "design_capacity": 20.0, "percentage": 0.74,
            "power_supply_status": 2, "power_supply_health": 1, "power_supply_technology": 2,
            "present": True, "cell_voltage": [3.59] * 7, "cell_temperature": [31.5] * 7,
            "location": "base", "serial_number": "MR1-BAT-0042"})
    for t in periodic(rate["/diagnostics"], 17_000_000):
        add(t, "/diagnostics", {"header": header(t, ""), "status": [
            {"level": 0, "name": "mr1_base_driver: motors", "message": "OK", "hardware_id": "mr1-base",
             "values": [{"key": "max_linear_velocity", "value": "0.8"},
                        {"key": "max_angular_velocity", "value": "1.2"}]},
            {"level": 0, "name": "mr1_lidar: scan rate", "message": "10.0 Hz", "hardware_id": "mr1-lidar",
             "values": [{"key": "range_max", "value": "12.0"}]}]})
    for k, t in enumerate(periodic(rate["/bond"], 19_000_000)):
        node = ["controller_server", "planner_server", "bt_navigator", "behavior_server"][k % 4]
        add(t, "/bond", {"header": header(t, ""), "id": node, "instance_id": f"{node}-7f3a{k % 4}",
                         "active": True, "heartbeat_timeout": 4.0, "heartbeat_period": 0.1})
    logs = [("bt_navigator", "Begin navigating from current location (1.20, 0.85) to (4.00, 0.85)"),
            ("planner_server", "Computed a path with 57 poses in 0.012 s"),
            ("controller_server", "Received a goal, begin computing control effort."),
            ("controller_server", "Passing new path to controller."),
            ("slam_toolbox", "Processed scan 1843; map updated"),
            ("move_group", "Ready to take commands for planning group mr1_arm.")]
    for k, t in enumerate(periodic(rate["/rosout"], 23_000_000)):
        node, text = logs[k % len(logs)]
        add(t, "/rosout", {"stamp": stamp(t), "level": 20, "name": node, "msg": text,
                           "file": "", "function": "", "line": 0})
    for t in periodic(rate["/parameter_events"], 29_000_000):
        add(t, "/parameter_events", {"stamp": stamp(t), "node": "/controller_server",
                                     "new_parameters": [], "deleted_parameters": [],
                                     "changed_parameters": [{"name": "FollowPath.max_vel_x", "value": {
                                         "type": 3, "bool_value": False, "integer_value": 0,
                                         "double_value": 0.8, "string_value": "", "byte_array_value": [],
                                         "bool_array_value": [], "integer_array_value": [],
                                         "double_array_value": [], "string_array_value": []}}]})
    # ---- navigation to (4.0, 0.85): send_goal, planner call, follow_path feedback, status
    goal = {"header": header(START_NS + 100_000_000, "map"), "pose": pose(4.0, START_Y_MAP, 0.0)}
    t = START_NS + 100_000_000
    req = {"goal_id": uuid_of(1), "goal": {"pose": goal, "behavior_tree": ""}}
    resp = {"accepted": True, "stamp": stamp(t + 400_000)}
    ev = "/navigate_to_pose/_action/send_goal/_service_event"
    add(t, ev, event(1, t, 1, 1, request=req))
    add(t + 500_000, ev, event(2, t + 500_000, 1, 1, response=resp))
    nav_status = lambda s, tt: {"status_list": [{"goal_info": {"goal_id": uuid_of(1), "stamp": stamp(t + 400_000)}, "status": s}]}  # noqa: E731
    add(t + 600_000, "/navigate_to_pose/_action/status", nav_status(1, t))
    add(t + 2_000_000, "/navigate_to_pose/_action/status", nav_status(2, t))
    tp = t + 5_000_000
    path_poses = [{"header": header(tp, "map"), "pose": pose(START_X_MAP + 0.05 * k, START_Y_MAP, 0.0)}
                  for k in range(57)]
    path = {"header": header(tp, "map"), "poses": path_poses}
    ev = "/compute_path_to_pose/_action/send_goal/_service_event"
    pgoal = {"goal": goal, "start": {"header": header(0, ""), "pose": pose(0, 0, 0)},
             "planner_id": "GridBased", "use_start": False}
    add(tp, ev, event(1, tp, 2, 1, request={"goal_id": uuid_of(2), "goal": pgoal}))
    add(tp + 300_000, ev, event(2, tp + 300_000, 2, 1, response={"accepted": True, "stamp": stamp(tp + 200_000)}))
    ev = "/compute_path_to_pose/_action/get_result/_service_event"
    add(tp + 600_000, ev, event(1, tp + 600_000, 2, 2, request={"goal_id": uuid_of(2)}))
    add(tp + 17_000_000, ev, event(2, tp + 17_000_000, 2, 2, response={
        "status": 4, "result": {"path": path, "planning_time": {"sec": 0, "nanosec": 12_000_000},
                                "error_code": 0, "error_msg": ""}}))
    add(tp + 17_500_000, "/compute_path_to_pose/_action/status", {"status_list": [
        {"goal_info": {"goal_id": uuid_of(2), "stamp": stamp(tp + 200_000)}, "status": 4}]})
    for tt in periodic(rate["/plan"], 18_000_000):
        add(tt, "/plan", path)
    tf_ = tp + 19_000_000
    ev = "/follow_path/_action/send_goal/_service_event"
    add(tf_, ev, event(1, tf_, 3, 1, request={"goal_id": uuid_of(3), "goal": {
        "path": path, "controller_id": "FollowPath", "goal_checker_id": "general_goal_checker"}}))
    add(tf_ + 400_000, ev, event(2, tf_ + 400_000, 3, 1, response={"accepted": True, "stamp": stamp(tf_ + 300_000)}))
    add(tf_ + 600_000, "/follow_path/_action/status", {"status_list": [
        {"goal_info": {"goal_id": uuid_of(3), "stamp": stamp(tf_ + 300_000)}, "status": 2}]})
    for tt in periodic(5, 150_000_000):
        ts = (tt - START_NS) / 1e9
        remaining = 4.0 - (START_X_MAP + base_x(ts))
        add(tt, "/follow_path/_action/feedback", {"goal_id": uuid_of(3), "feedback": {
            "distance_to_goal": remaining, "speed": SPEED}})
        add(tt + 1_000_000, "/navigate_to_pose/_action/feedback", {"goal_id": uuid_of(1), "feedback": {
            "current_pose": {"header": header(tt, "map"), "pose": pose(START_X_MAP + base_x(ts), START_Y_MAP, 0.0)},
            "navigation_time": {"sec": int(ts - 0.1), "nanosec": int(((ts - 0.1) % 1) * 1e9)},
            "estimated_time_remaining": {"sec": int(remaining / SPEED), "nanosec": int(((remaining / SPEED) % 1) * 1e9)},
            "number_of_recoveries": 0, "distance_remaining": remaining}})
    # ---- a few plain service calls (server-side events: request received, response sent)
    ts = START_NS + 700_000_000
    ev = "/controller_manager/list_controllers/_service_event"
    ctrl = lambda name, typ, claimed: {  # noqa: E731
        "name": name, "state": "active", "type": typ, "claimed_interfaces": claimed,
        "required_command_interfaces": claimed, "required_state_interfaces": [],
        "is_chainable": False, "is_chained": False, "reference_interfaces": [], "chain_connections": []}
    add(ts, ev, event(1, ts, 4, 1, request={}))
    add(ts + 800_000, ev, event(2, ts + 800_000, 4, 1, response={"controller": [
        ctrl("joint_state_broadcaster", "joint_state_broadcaster/JointStateBroadcaster", []),
        ctrl("arm_controller", "joint_trajectory_controller/JointTrajectoryController",
             [f"{j}/position" for j in ARM_JOINTS]),
        ctrl("gripper_controller", "position_controllers/GripperActionController",
             ["mr1_gripper_finger_joint/position"])]}))
    ts = START_NS + 1_300_000_000
    ev = "/compute_fk/_service_event"
    robot_state = {"joint_state": {"header": header(ts, "arm_base_link"), "name": ARM_JOINTS,
                                   "position": ARM_HOME, "velocity": [], "effort": []},
                   "multi_dof_joint_state": {"header": header(0, ""), "joint_names": [], "transforms": [],
                                             "twist": [], "wrench": []},
                   "attached_collision_objects": [], "is_diff": False}
    add(ts, ev, event(1, ts, 5, 1, request={"header": header(ts, "arm_base_link"),
                                            "fk_link_names": ["tool0"], "robot_state": robot_state}))
    add(ts + 1_500_000, ev, event(2, ts + 1_500_000, 5, 1, response={
        "pose_stamped": [{"header": header(ts, "arm_base_link"), "pose": {
            "position": vec(0.412, 0.0, 0.287), "orientation": {"x": 0.0, "y": 0.7071, "z": 0.0, "w": 0.7071}}}],
        "fk_link_names": ["tool0"], "error_code": {"val": 1, "message": "", "source": ""}}))
    ts = START_NS + 1_900_000_000
    ev = "/controller_server/get_state/_service_event"
    add(ts, ev, event(1, ts, 6, 1, request={}))
    add(ts + 200_000, ev, event(2, ts + 200_000, 6, 1, response={"current_state": {"id": 3, "label": "active"}}))
    ts = START_NS + 2_400_000_000
    ev = "/slam_toolbox/get_parameters/_service_event"
    add(ts, ev, event(1, ts, 7, 1, request={"names": ["resolution", "max_laser_range", "mode"]}))
    pv = lambda typ, d=0.0, s="": {"type": typ, "bool_value": False, "integer_value": 0, "double_value": d,  # noqa: E731
                                   "string_value": s, "byte_array_value": [], "bool_array_value": [],
                                   "integer_array_value": [], "double_array_value": [], "string_array_value": []}
    add(ts + 300_000, ev, event(2, ts + 300_000, 7, 1, response={"values": [
        pv(3, 0.05), pv(3, 12.0), pv(4, s="mapping")]}))
    msgs.sort(key=lambda m: (m[0], m[1]))
    return msgs


def metadata_yaml(channels: dict[str, str], counts: dict[str, int], hashes: dict[str, str],
                  start: int, duration: int, total: int, indent: str = "") -> str:
    lines = ["rosbag2_bagfile_information:", "  version: 8", "  storage_identifier: mcap",
             "  duration:", f"    nanoseconds: {duration}", "  starting_time:",
             f"    nanoseconds_since_epoch: {start}", f"  message_count: {total}",
             "  topics_with_message_count:"]
    for name in sorted(channels):
        q = json.dumps(topic_qos(name))
        lines += ["    - topic_metadata:", f"        name: {name}", f"        type: {channels[name]}",
                  "        serialization_format: cdr", f"        offered_qos_profiles: {q}",
                  f"        type_description_hash: {hashes[channels[name]]}",
                  f"      message_count: {counts[name]}"]
    lines += ['  compression_format: ""', '  compression_mode: ""', "  relative_file_paths:",
              f"    - {MCAP_NAME}", "  files:", f"    - path: {MCAP_NAME}", "      starting_time:",
              f"        nanoseconds_since_epoch: {start}", "      duration:",
              f"        nanoseconds: {duration}", f"      message_count: {total}",
              "  custom_data: ~", "  ros_distro: jazzy"]
    return "\n".join(lines) + "\n"


def main(bag_dir: Path = BAG_DIR) -> None:
    _build_model()
    interfaces = load_interfaces()
    channels = channels_for(interfaces)
    messages = generate(interfaces)
    unknown = {topic for _, topic, _ in messages} - set(channels)
    assert not unknown, unknown
    hashes = {typ: rihs01(typ) for typ in sorted(set(channels.values()))}
    counts = {name: 0 for name in channels}
    for _, topic, _ in messages:
        counts[topic] += 1
    start = messages[0][0]
    duration = messages[-1][0] - start
    bag_dir.mkdir(parents=True, exist_ok=True)
    with open(bag_dir / MCAP_NAME, "wb") as f:
        writer = Writer(f, chunk_size=256 * 1024, compression=CompressionType.ZSTD)
        writer.start(profile="ros2", library="skillwright make_recording.py (mcap python)")
        schema_ids: dict[str, int] = {}
        channel_ids: dict[str, int] = {}
        for name in sorted(channels):
            typ = channels[name]
            if typ not in schema_ids:
                schema_ids[typ] = writer.register_schema(typ, "ros2msg", schema_text(typ).encode())
            channel_ids[name] = writer.register_channel(
                name, "cdr", schema_ids[typ],
                {"offered_qos_profiles": topic_qos(name), "topic_type_hash": hashes[typ]})
        for seq, (t, topic, msg) in enumerate(messages):
            writer.add_message(channel_ids[topic], t, encode(channels[topic], msg), t, sequence=0)
        writer.add_metadata("rosbag2", {"serialized_metadata": metadata_yaml(
            channels, counts, hashes, start, duration, len(messages))})
        writer.finish()
    (bag_dir / "metadata.yaml").write_text(
        metadata_yaml(channels, counts, hashes, start, duration, len(messages)), encoding="utf-8")
    print(f"wrote {bag_dir / MCAP_NAME}: {len(channels)} channels, {len(messages)} messages")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else BAG_DIR)
