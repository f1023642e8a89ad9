"""The MR-1 in MuJoCo as a world plug-in of the simulated runtime.

:class:`MujocoWorld` implements :class:`~skillwright.runtime.api.WorldPlugin`: the runtime
attaches it to its graph host and advances it in virtual time, in lockstep with the skill.
It takes over the robot's sensor topics (found by type in the inventory, see
:mod:`skillwright.sim.bindings`), drives the base from the velocity command topic, serves
the motion actions (:mod:`skillwright.runtime.motion`) and map saving, and records ground truth
(:mod:`skillwright.sim.truth`) for the oracles.

Physics steps at the model's timestep (10 ms; the driver runs every 20 ms). Publications
happen at their own rates and virtual times: odometry and its ``odom -> base`` transform,
scans (the lidar's rangefinders are evaluated only when a scan is due, not at every step,
which makes the world about twice as fast), IMU, the localisation pose with
``map -> odom``, the occupancy map and the static transforms.

A message nobody would receive (no subscription, not latched) is not made: the host says
so (``host.wants``). What the world computes for itself still happens at the same times — the
lidar's ranges for the ground truth and the map, the noise drawn for every sensor — so a run
is the same whoever listens.

Noise is Gaussian, seeded: odometry integrates noisy wheel speeds, so it drifts a little and
slips when the chassis is pushed against something; scans, IMU and the localisation pose get
their own noise. The map frame is the world frame; the odometry frame starts at the start
pose.
"""

from __future__ import annotations

import copy
import functools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from skillwright.errors import FileFormatError
from skillwright.runtime.motion import (
    ArmConfig,
    ArmServer,
    BaseMotionServer,
    Command,
    NavConfig,
    fill,
)
from skillwright.sim.bindings import Bindings, RecordedFacts, ScanGeometry, split_views
from skillwright.sim.drive import DriveLimits, DriverState, MecanumKinematics
from skillwright.sim.truth import CommandRecord, ContactRecord, GroundTruth, Sample, Sweep

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from skillwright.runtime.graph import GraphHost

__all__ = ["MujocoWorld", "Noise", "WorldConfig", "quaternion"]

Message = dict[str, Any]
_ROBOT_BODY = "base_footprint"
_WHEELS = (
    "wheel_front_left_motor",
    "wheel_front_right_motor",
    "wheel_rear_left_motor",
    "wheel_rear_right_motor",
)
_TRACTION = ("traction_x", "traction_y", "traction_yaw")
_SCAN_OFFSET = 0.007
"""Scans come a few milliseconds after odometry, as on the robot, so they do not coincide."""


@dataclass(frozen=True)
class Noise:
    """Standard deviations of the simulated sensors' noise."""

    odometry_linear: float = 0.004
    """Wheel speed noise, as base velocity [m/s]."""
    odometry_angular: float = 0.003
    """Wheel speed noise, as yaw rate [rad/s]."""
    scan: float = 0.01
    """Range noise [m]."""
    imu: float = 0.003
    """Yaw rate noise [rad/s]."""
    localisation: float = 0.005
    """Noise of the localisation pose and of ``map -> odom`` [m]; a tenth of it in rad."""
    scan_invalid: float = 0.0
    """Share of a scan's beams reported as invalid, half as NaN and half as 0.0 (below
    ``range_min``), as lidar drivers report dropouts; none by default."""

    @classmethod
    def none(cls) -> Noise:
        """No noise at all."""
        return cls(0.0, 0.0, 0.0, 0.0, 0.0)


@dataclass
class WorldConfig:
    """Everything that makes one run's world."""

    world_file: Path
    start: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """x, y [m] and heading [rad] of the base in the map frame."""
    seed: int = 0
    noise: Noise = field(default_factory=Noise)
    output_dir: Path | None = None
    """Where maps saved through the map-saver services are written (``None``: not written)."""


def quaternion(yaw: float) -> Message:
    """A ``geometry_msgs/Quaternion`` for a rotation about z."""
    return {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2.0), "w": math.cos(yaw / 2.0)}


def _vector(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> Message:
    return {"x": x, "y": y, "z": z}


def _covariance(diagonal: tuple[float, float, float, float, float, float]) -> list[float]:
    values = [0.0] * 36
    for index, value in enumerate(diagonal):
        values[index * 7] = value
    return values


_COMPILED: dict[
    tuple[Any, ...], tuple[Any, dict[str, tuple[int, ScanGeometry]], tuple[str, ...]]
] = {}
"""Compiled models by MJCF text and scan geometry (see :meth:`MujocoWorld._model`)."""
_COMPILED_SIZE = 8


def _mjcf_texts(path: Path) -> tuple[tuple[str, bytes], ...] | None:
    """The bytes of an MJCF file and of the files it includes (MuJoCo resolves includes
    from the top file's folder), or ``None`` when one cannot be read (nothing is cached;
    loading reports the problem)."""
    from xml.etree import ElementTree

    texts: list[tuple[str, bytes]] = []
    pending = [path]
    try:
        while pending:
            current = pending.pop()
            data = current.read_bytes()
            texts.append((str(current.resolve()), data))
            if len(texts) > 64:
                return None
            for element in ElementTree.fromstring(data).iter("include"):
                name = element.get("file")
                if name:
                    pending.append(path.parent / name)
    except (OSError, ElementTree.ParseError):
        return None
    return tuple(texts)


@dataclass
class _Stream:
    """Something published periodically."""

    name: str
    period: float
    next_t: float
    emit: Callable[[float], None]


class MujocoWorld:
    """The robot in a MuJoCo world, publishing and serving through the runtime's graph host."""

    def __init__(self, config: WorldConfig, bindings: Bindings, facts: RecordedFacts) -> None:
        import mujoco
        import numpy as np

        self.config = config
        self.bindings = bindings
        self.facts = facts
        self.truth = GroundTruth(start=config.start)
        self.notes: list[str] = [*bindings.notes, *facts.notes]
        self._mj = mujoco
        self._np = np
        self._rng = np.random.default_rng(config.seed)
        # Dropouts draw from their own stream: every other noise stays what it was.
        self._dropouts = np.random.default_rng([config.seed, 1])
        self.model, self._beams = self._model(config.world_file)
        self.data = mujoco.MjData(self.model)
        self.dt = float(self.model.opt.timestep)
        # The base driver runs at 50 Hz (several physics steps per period), as a motor
        # controller's velocity loop on a CAN bus does.
        self.control_period = self.dt * max(1, round(0.02 / self.dt))
        self._next_control = 0.0
        self._sensor_flag = int(mujoco.mjtDisableBit.mjDSBL_SENSOR)
        self.model.opt.disableflags |= self._sensor_flag
        self._init_ids()
        x, y, yaw = config.start
        self.data.qpos[self._qpos] = (x, y, yaw)
        mujoco.mj_forward(self.model, self.data)
        self.kinematics, self.driver, self.nav_config = self._drive()
        self._describe_robot(config, bindings)
        self.frames = self._frames()
        self.map_frame = facts.map_frame or "map"
        self.odom_frame = facts.odom_frame or "odom"
        self.base_frame = facts.base_frame or "base_link"
        # Odometry starts at the start pose: its frame is where the robot was switched on.
        self.odom = [0.0, 0.0, 0.0]
        self._odom_twist = Command()
        self._last_velocity = Command()
        self._touching: set[int] = set()
        self._blocked: tuple[Any, Any] | None = None
        self._map: Any = None
        self._map_scans: list[tuple[ScanGeometry, tuple[float, float, float], Any, Any, float]] = []
        self.truth.catch_up = self._catch_up_map
        self._map_pose: dict[str, tuple[float, float, float]] = {}
        self._map_updates = 0
        self._map_published = -1
        self.host: GraphHost | None = None
        self.streams: list[_Stream] = []
        self.base_server = BaseMotionServer(self, self.nav_config)
        self.arm: ArmServer | None = None
        # Clocks read with perf_counter only: a CPU-time clock is a system call, and at
        # thousands of reads per virtual second it cost more than the exchange it measured
        # (each call is a point where a busy machine takes the core away).
        self.wall_seconds = 0.0
        """Wall time spent in :meth:`advance`."""
        self.publish_seconds = 0.0
        """Of that, wall time the host took to take the world's messages (``host.publish``)."""
        self._record()

    def _drive(self) -> tuple[MecanumKinematics, DriverState, NavConfig]:
        """The base driver and the navigation controller's limits, from the model's numbers."""
        radius = self._numeric("drive_wheel_radius", 1)[0]
        half_length, half_width = self._numeric("drive_wheel_offsets", 2)
        accel = self._numeric("drive_accel_max", 3)
        kinematics = MecanumKinematics(radius, half_length, half_width)
        driver = DriverState(
            kinematics,
            DriveLimits(
                wheel_speed_max=self._numeric("drive_wheel_speed_max", 1)[0],
                accel_linear=accel[0],
                accel_lateral=accel[1],
                accel_angular=accel[2],
                command_timeout=self._numeric("drive_cmd_timeout", 1)[0],
            ),
        )
        nav_speed = self._numeric("nav_speed_max", 2)
        nav_tolerance = self._numeric("nav_goal_tolerance", 2)
        nav = NavConfig(
            speed_max=nav_speed[0],
            yaw_rate_max=nav_speed[1],
            accel=accel[0],
            yaw_accel=accel[2],
            xy_tolerance=nav_tolerance[0],
            yaw_tolerance=nav_tolerance[1],
        )
        return kinematics, driver, nav

    # --- model -------------------------------------------------------------------------
    def _model(self, path: Path) -> tuple[Any, dict[str, tuple[int, ScanGeometry]]]:
        """A private copy of the compiled model of ``path`` with this robot's lidar beams.

        Compiling the beams' sites and sensors costs more than a short run; a validation
        makes a world per run from the same few files, so compiled models are kept, keyed
        by the MJCF text (with its includes) and the scan geometry, and copied per world.
        """
        scans = tuple(
            (t, self.facts.scans.get(t, ScanGeometry())) for t in self.bindings.scan_topics
        )
        key = (_mjcf_texts(path), scans)
        cached = _COMPILED.get(key) if key[0] is not None else None
        if cached is None:
            notes_before = len(self.notes)
            model, beams = self._load(path)
            cached = (model, beams, tuple(self.notes[notes_before:]))
            if key[0] is not None:
                if len(_COMPILED) >= _COMPILED_SIZE:
                    _COMPILED.pop(next(iter(_COMPILED)))
                _COMPILED[key] = cached
        else:
            self.notes.extend(cached[2])
        model, beams, _notes = cached
        return copy.copy(model), dict(beams)

    def _load(self, path: Path) -> tuple[Any, dict[str, tuple[int, ScanGeometry]]]:
        """The world's model with one rangefinder per lidar beam of every scan topic."""
        mujoco = self._mj
        try:
            spec = mujoco.MjSpec.from_file(str(path))
        except Exception as error:
            raise FileFormatError(f"{path}: not a loadable MJCF world: {error}") from error
        spec_body = spec.body(_ROBOT_BODY)
        if spec_body is None:
            raise FileFormatError(
                f"{path}: has no body named {_ROBOT_BODY!r} (include sim/mr1.xml)"
            )
        beams: dict[str, tuple[int, ScanGeometry]] = {}
        sensor_count = 0
        for topic in self.bindings.scan_topics:
            geometry = self.facts.scans.get(topic, ScanGeometry())
            site = spec.site(geometry.frame_id)
            if site is None:
                self.notes.append(
                    f"{topic}: the robot model has no site {geometry.frame_id!r}; the lidar sits "
                    "at laser_link"
                )
                site = spec.site("laser_link")
            base_yaw = 2.0 * math.atan2(float(site.quat[3]), float(site.quat[0]))
            for index in range(geometry.count):
                angle = base_yaw + geometry.angle_min + index * geometry.angle_increment
                name = f"{topic}#beam{index}"
                beam = spec_body.add_site(name=name, pos=list(site.pos))
                beam.alt.type = mujoco.mjtOrientation.mjORIENTATION_ZAXIS
                beam.alt.zaxis = [math.cos(angle), math.sin(angle), 0.0]
                spec.add_sensor(
                    name=f"{topic}#range{index}",
                    type=mujoco.mjtSensor.mjSENS_RANGEFINDER,
                    objtype=mujoco.mjtObj.mjOBJ_SITE,
                    objname=name,
                    cutoff=geometry.range_max,
                    intprm=[1 << int(mujoco.mjtRayDataField.mjRAYDATA_DIST), 0, 0],
                )
            beams[topic] = (sensor_count, geometry)
            sensor_count += geometry.count
        try:
            model = spec.compile()
        except Exception as error:
            raise FileFormatError(f"{path}: the MJCF world does not compile: {error}") from error
        return model, beams

    def _init_ids(self) -> None:
        mujoco, model = self._mj, self.model
        self._body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, _ROBOT_BODY)
        joints = ("base_x", "base_y", "base_yaw")
        ids = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, j) for j in joints]
        if min(ids) < 0:
            raise FileFormatError(
                "the robot model lacks the planar joints base_x, base_y, base_yaw"
            )
        self._qpos = [int(model.jnt_qposadr[j]) for j in ids]
        self._dof = [int(model.jnt_dofadr[j]) for j in ids]
        actuators = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, a) for a in _WHEELS]
        traction = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, a) for a in _TRACTION]
        if min(actuators + traction) < 0:
            raise FileFormatError("the robot model lacks its wheel motors or traction servos")
        self._wheel_act = actuators
        self._wheel_dof = [int(model.jnt_dofadr[model.actuator_trnid[a, 0]]) for a in actuators]
        self._traction = traction
        robot = set()
        for body in range(model.nbody):
            b = body
            while b > 0 and b != self._body:
                b = int(model.body_parentid[b])
            if b == self._body:
                robot.add(body)
        self._robot_geoms = {g for g in range(model.ngeom) if int(model.geom_bodyid[g]) in robot}
        self._chassis = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "chassis")
        if self._chassis < 0:
            raise FileFormatError("the robot model has no geom named 'chassis' (its footprint)")

    def _describe_robot(self, config: WorldConfig, bindings: Bindings) -> None:
        """What the oracles need to know of the robot beside its motion: whether it can
        localise, how hard it brakes, its sensors' rates and noise, its odometry's period and
        its map savers."""
        self.truth.braking = self.driver.limits.accel_linear
        scan_rates = [bindings.rates[t] for t in bindings.scan_topics]
        self.truth.reaction = 1.0 / min(scan_rates) if scan_rates else 0.1
        self.truth.localised = bindings.has_localisation
        noise = config.noise
        self.truth.noise = {
            "scan": noise.scan,
            "odometry_linear": noise.odometry_linear,
            "odometry_angular": noise.odometry_angular,
            "localisation": noise.localisation,
        }
        # The odometry integrates the noisy wheel speeds once per driver period.
        self.truth.odometry_period = self.control_period
        self.truth.map_savers = sorted(
            name
            for name, kind in bindings.services.items()
            if kind in ("nav2_save_map", "slam_save_map")
        )

    def _numeric(self, name: str, size: int) -> list[float]:
        mujoco, model = self._mj, self.model
        index = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, name)
        if index < 0:
            raise FileFormatError(f"the robot model has no custom numeric {name!r}")
        start = int(model.numeric_adr[index])
        values = [
            float(v) for v in model.numeric_data[start : start + int(model.numeric_size[index])]
        ]
        if len(values) < size:
            raise FileFormatError(f"custom numeric {name!r} needs {size} values, has {len(values)}")
        return values[:size]

    def _text(self, name: str, default: str) -> str:
        mujoco, model = self._mj, self.model
        index = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TEXT, name)
        if index < 0:
            return default
        start = int(model.text_adr[index])
        raw = bytes(model.text_data[start : start + int(model.text_size[index])])
        return raw.split(b"\0", 1)[0].decode("utf-8")

    def _frames(self) -> dict[str, tuple[float, float, float]]:
        """Offsets of the robot's frames (its named sites) from the base body."""
        model = self.model
        frames: dict[str, tuple[float, float, float]] = {}
        for site in range(model.nsite):
            name = self._mj.mj_id2name(model, self._mj.mjtObj.mjOBJ_SITE, site)
            if not name or "#" in name or int(model.site_bodyid[site]) != self._body:
                continue
            x, y, z = (float(v) for v in model.site_pos[site])
            frames[name] = (x, y, z)
        return frames

    # --- the plug-in API ----------------------------------------------------------------
    def attach(self, host: GraphHost) -> None:
        """Take over the robot's sensor topics, listen to its command, serve its actions."""
        self.host = host
        bindings = self.bindings
        for topic in bindings.owned_topics():
            host.own_topic(topic)
        if bindings.command_topic:
            host.on_publish(bindings.command_topic, self._on_command)
        for name, kind in bindings.actions.items():
            type_name = bindings.action_types[name]
            if kind == "move_group":
                self.arm = ArmServer(self, self._arm_config(), self._arm_frames().get)
                host.serve_action(name, self.arm.handler(type_name))
            else:
                host.serve_action(name, self.base_server.handler(kind, type_name))
        for name, kind in bindings.services.items():
            type_name = bindings.service_types[name]
            if kind in ("nav2_save_map", "slam_save_map"):
                host.serve_service(name, self._map_saver(kind, type_name))
            elif kind == "compute_fk":
                host.serve_service(name, self._forward_kinematics(type_name))
        self._make_streams()

    def next_event(self) -> float | None:
        """The next publication or controller period."""
        times = [s.next_t for s in self.streams]
        for server in (self.base_server, self.arm):
            if server is not None and server.next_tick is not None:
                times.append(server.next_tick)
        return min(times) if times else None

    def advance(self, until: float) -> None:
        """Step physics to ``until``, running controllers and publishing what falls due."""
        started = time.perf_counter()
        try:
            self._advance(until)
        finally:
            self.wall_seconds += time.perf_counter() - started

    def _advance(self, until: float) -> None:
        while True:
            due = self.next_event()
            if due is None or due > until + 1e-9:
                break
            self._step_to(due)
            for server in (self.base_server, self.arm):
                if (
                    server is not None
                    and server.next_tick is not None
                    and server.next_tick <= due + 1e-9
                ):
                    server.tick()
            for stream in self.streams:
                if stream.next_t <= due + 1e-9:
                    stream.emit(due)
                    stream.next_t += stream.period
        self._step_to(until)

    def close(self) -> None:
        """Nothing outlives the run but the ground truth."""
        self.host = None
        self.streams = []

    # --- what the controllers need (MotionWorld) -----------------------------------------
    @property
    def now(self) -> float:
        """Virtual time: the host's once attached (physics moves in whole steps behind it)."""
        return self.host.now if self.host is not None else float(self.data.time)

    def base_pose(self) -> tuple[float, float, float]:
        """True pose of the base in the map frame."""
        x, y, yaw = self.data.qpos[self._qpos].tolist()
        return x, y, yaw

    def base_velocity(self) -> Command:
        """True velocity of the base in its own frame."""
        vx, vy, wz = self.data.qvel[self._dof].tolist()
        yaw = self.data.qpos.item(self._qpos[2])
        c, s = math.cos(yaw), math.sin(yaw)
        return Command(vx=c * vx + s * vy, vy=-s * vx + c * vy, wz=wz)

    def drive(self, command: Command) -> None:
        """A command from the world's own controllers (navigation)."""
        self.driver.receive(command, self.now)
        self.truth.drive.append((self.now, command.vx, command.vy, command.wz, "world"))

    def plan(
        self, start: tuple[float, float], goal: tuple[float, float]
    ) -> list[tuple[float, float]] | None:
        """A collision-free path for the base's centre, or ``None``."""
        from skillwright.sim.grid import plan_path

        frame, blocked = self._planning_grid(start, goal)
        return plan_path(blocked, frame, start, goal)

    def to_map(
        self, frame: str, x: float, y: float, yaw: float
    ) -> tuple[float, float, float] | None:
        """A pose given in ``frame`` (map or odometry frame), in the map frame."""
        if frame in (self.map_frame, ""):
            return (x, y, yaw)
        if frame == self.odom_frame:
            sx, sy, syaw = self._odom_origin()
            c, s = math.cos(syaw), math.sin(syaw)
            return (sx + c * x - s * y, sy + s * x + c * y, yaw + syaw)
        return None

    def message(self, type_name: str) -> Message:
        """A message of that type at its defaults (from the host)."""
        assert self.host is not None
        return self.host.message(type_name)

    def pose_stamped(self, x: float, y: float, yaw: float) -> Message:
        """A ``geometry_msgs/PoseStamped`` in the map frame at the current time."""
        return {
            "header": self._header(self.now, self.map_frame),
            "pose": {"position": _vector(x, y, 0.0), "orientation": quaternion(yaw)},
        }

    def record_goal(self, entry: dict[str, Any]) -> None:
        """Log a motion goal's progress in the ground truth and the run's trace."""
        self.truth.goals.append(entry)
        if self.host is not None:
            self.host.record("goal", {k: v for k, v in entry.items() if k != "goal"})

    # --- physics ------------------------------------------------------------------------
    def _step_to(self, t: float) -> None:
        step, model, data = self._mj.mj_step, self.model, self.data
        half = self.dt / 2.0
        while True:
            # Reading MjData's fields is a call into the bindings: read each once per step.
            ahead = data.time + half
            if ahead > t:
                break
            if ahead >= self._next_control:
                self._control()
            step(model, data)
            if data.ncon:
                self._contacts()
            elif self._touching:
                self._touching = set()

    def _control(self) -> None:
        """One period of the base driver: wheel commands, traction, odometry, ground truth."""
        data = self.data
        now = float(data.time)
        self._next_control = now + self.control_period
        wheels = self.driver.step(now, self.control_period)
        measured = tuple(data.qvel[self._wheel_dof].tolist())
        body = self.kinematics.body_velocity(measured)
        self._integrate_odometry(body)
        for actuator, speed in zip(self._wheel_act, wheels, strict=True):
            data.ctrl[actuator] = speed
        yaw = data.qpos.item(self._qpos[2])
        c, s = math.cos(yaw), math.sin(yaw)
        data.ctrl[self._traction[0]] = c * body.vx - s * body.vy
        data.ctrl[self._traction[1]] = s * body.vx + c * body.vy
        data.ctrl[self._traction[2]] = body.wz
        self._record()

    def _integrate_odometry(self, body: Command) -> None:
        noise = self.config.noise
        rng = self._rng
        vx = body.vx + (rng.normal(0.0, noise.odometry_linear) if noise.odometry_linear else 0.0)
        vy = body.vy + (rng.normal(0.0, noise.odometry_linear) if noise.odometry_linear else 0.0)
        wz = body.wz + (rng.normal(0.0, noise.odometry_angular) if noise.odometry_angular else 0.0)
        x, y, yaw = self.odom
        dt = self.control_period
        mid = yaw + wz * dt / 2.0
        c, s = math.cos(mid), math.sin(mid)
        self.odom = [x + (c * vx - s * vy) * dt, y + (s * vx + c * vy) * dt, yaw + wz * dt]
        self._odom_twist = Command(vx, vy, wz)

    def _contacts(self) -> None:
        data, model = self.data, self.model
        touching: set[int] = set()
        for index in range(int(data.ncon)):
            g1, g2 = (int(g) for g in data.contact.geom[index])
            ours, other = (g1, g2) if g1 in self._robot_geoms else (g2, g1)
            if ours not in self._robot_geoms or other in self._robot_geoms:
                continue
            new = other not in self._touching and other not in touching
            touching.add(other)
            if new:
                name = (
                    self._mj.mj_id2name(model, self._mj.mjtObj.mjOBJ_GEOM, other) or f"geom {other}"
                )
                x, y = (float(v) for v in data.contact.pos[index][:2])
                self.truth.contacts.append(ContactRecord(float(data.time), name, x, y))
                if self.host is not None:
                    self.host.record("contact", {"with": name, "x": x, "y": y})
        self._touching = touching

    def _record(self) -> None:
        x, y, yaw = self.base_pose()
        velocity = self.base_velocity()
        physics_time = float(self.data.time)
        command = self.driver.target(physics_time)
        tcp = self.arm.tcp if self.arm is not None else (0.0, 0.0, 0.0)
        self.truth.add(
            Sample(
                t=physics_time,
                x=x,
                y=y,
                yaw=yaw,
                vx=velocity.vx,
                vy=velocity.vy,
                wz=velocity.wz,
                command=(command.vx, command.vy, command.wz),
                tcp=tcp,
            )
        )

    # --- commands -----------------------------------------------------------------------
    def _on_command(self, t: float, message: Message) -> None:
        twist = message.get("twist", message) if self.bindings.command_stamped else message
        linear = twist.get("linear") or {}
        angular = twist.get("angular") or {}
        command = Command(
            vx=float(linear.get("x", 0.0) or 0.0),
            vy=float(linear.get("y", 0.0) or 0.0),
            wz=float(angular.get("z", 0.0) or 0.0),
        )
        topic = self.bindings.command_topic or ""
        self.truth.commands.append(CommandRecord(t, topic, command.vx, command.vy, command.wz))
        self.truth.drive.append((t, command.vx, command.vy, command.wz, "skill"))
        self.driver.receive(command, t)

    # --- publications -------------------------------------------------------------------
    def _header(self, t: float, frame: str) -> Message:
        assert self.host is not None
        return {"stamp": self.host.stamp(t), "frame_id": frame}

    def _make_streams(self) -> None:
        b = self.bindings
        streams: list[_Stream] = []

        def add(name: str, rate: float, offset: float, emit: Callable[[float], None]) -> None:
            period = 1.0 / rate
            streams.append(_Stream(name, period, period + offset, emit))

        tf_with_odometry = bool(b.tf_topic)
        for index, topic in enumerate(b.odometry_topics):
            add(
                topic,
                b.rates[topic],
                0.0,
                self._odometry_emitter(topic, tf_with_odometry and index == 0),
            )
        if b.tf_topic and not b.odometry_topics:
            add(b.tf_topic, 50.0, 0.0, self._publish_base_tf)
        for index, topic in enumerate(b.scan_topics):
            add(topic, b.rates[topic], _SCAN_OFFSET + 0.001 * index, self._scan_emitter(topic))
        for topic in b.imu_topics:
            add(topic, b.rates[topic], 0.002, self._imu_emitter(topic))
        if b.has_localisation and b.tf_topic:
            rate = b.rates[b.pose_topics[0]] if b.pose_topics else 5.0
            add(f"{b.tf_topic}#map", rate, 0.009, self._map_tf_emitter())
        for topic in b.pose_topics:
            add(topic, b.rates[topic], 0.009, self._pose_emitter(topic))
        if b.map_topic:
            add(b.map_topic, b.rates[b.map_topic], 0.04, self._map_emitter())
        if b.tf_static_topic:
            static = self._tf_static_message()
            topic = b.tf_static_topic
            period = 1.0 / b.rates[topic]

            def publish_static(_t: float) -> None:
                if self._wanted(topic):
                    self._publish(topic, static)

            # Once at once, so a listener started at the beginning has the robot's frames.
            streams.append(_Stream(topic, period, 0.012, publish_static))
        self.streams = streams

    def _wanted(self, topic: str) -> bool:
        """Whether a message on ``topic`` would reach anyone now (else it is not made)."""
        return self.host is not None and self.host.wants(topic)

    def _publish(self, topic: str, message: Message) -> None:
        assert self.host is not None
        started = time.perf_counter()
        self.host.publish(topic, message)
        self.publish_seconds += time.perf_counter() - started

    def _odom_origin(self) -> tuple[float, float, float]:
        """Pose of the odometry frame in the map frame (true pose minus odometry)."""
        x, y, yaw = self.base_pose()
        ox, oy, oyaw = self.odom
        syaw = yaw - oyaw
        c, s = math.cos(syaw), math.sin(syaw)
        return (x - (c * ox - s * oy), y - (s * ox + c * oy), syaw)

    def _base_offset(self) -> tuple[float, float, float]:
        return self.frames.get(self.base_frame, (0.0, 0.0, 0.0))

    def _transform(
        self, t: float, parent: str, child: str, x: float, y: float, z: float, yaw: float
    ) -> Message:
        return {
            "header": self._header(t, parent),
            "child_frame_id": child,
            "transform": {"translation": _vector(x, y, z), "rotation": quaternion(yaw)},
        }

    def _odometry_emitter(self, topic: str, with_tf: bool) -> Callable[[float], None]:
        covariance = _covariance((1e-3, 1e-3, 1e6, 1e6, 1e6, 2e-3))

        def emit(t: float) -> None:
            if self._wanted(topic):
                x, y, yaw = self.odom
                twist = self._odom_twist
                self._publish(
                    topic,
                    {
                        "header": self._header(t, self.odom_frame),
                        "child_frame_id": self.base_frame,
                        "pose": {
                            "pose": {
                                "position": _vector(x, y, 0.0),
                                "orientation": quaternion(yaw),
                            },
                            "covariance": covariance,
                        },
                        "twist": {
                            "twist": {
                                "linear": _vector(twist.vx, twist.vy),
                                "angular": _vector(z=twist.wz),
                            },
                            "covariance": covariance,
                        },
                    },
                )
            if with_tf:
                self._publish_base_tf(t)

        return emit

    def _publish_base_tf(self, t: float) -> None:
        assert self.bindings.tf_topic is not None
        if not self._wanted(self.bindings.tf_topic):
            return
        x, y, yaw = self.odom
        transforms = [self._transform(t, self.odom_frame, self.base_frame, x, y, 0.0, yaw)]
        if self.arm is not None and self.arm.config.tip_link is not None:
            tx, ty, tz = self.arm.tcp
            transforms.append(
                self._transform(
                    t, self.arm.config.base_frame, self.arm.config.tip_link, tx, ty, tz, 0.0
                )
            )
        self._publish(self.bindings.tf_topic, {"transforms": transforms})

    def _map_tf_emitter(self) -> Callable[[float], None]:
        def emit(t: float) -> None:
            assert self.bindings.tf_topic is not None
            sx, sy, syaw = self._odom_origin()
            sigma = self.config.noise.localisation
            if sigma:
                sx += self._rng.normal(0.0, sigma)
                sy += self._rng.normal(0.0, sigma)
                syaw += self._rng.normal(0.0, sigma / 10.0)
            if not self._wanted(self.bindings.tf_topic):
                return
            message = {
                "transforms": [
                    self._transform(t, self.map_frame, self.odom_frame, sx, sy, 0.0, syaw)
                ]
            }
            self._publish(self.bindings.tf_topic, message)

        return emit

    def _pose_emitter(self, topic: str) -> Callable[[float], None]:
        def emit(t: float) -> None:
            x, y, yaw = self.base_pose()
            sigma = self.config.noise.localisation
            if sigma:
                x += self._rng.normal(0.0, sigma)
                y += self._rng.normal(0.0, sigma)
                yaw += self._rng.normal(0.0, sigma / 10.0)
            if not self._wanted(topic):
                return
            self._publish(
                topic,
                {
                    "header": self._header(t, self.map_frame),
                    "pose": {
                        "pose": {"position": _vector(x, y, 0.0), "orientation": quaternion(yaw)},
                        "covariance": _covariance((0.004, 0.004, 0.0, 0.0, 0.0, 0.002)),
                    },
                },
            )

        return emit

    def _imu_emitter(self, topic: str) -> Callable[[float], None]:
        def emit(t: float) -> None:
            _x, _y, yaw = self.base_pose()
            velocity = self.base_velocity()
            previous = self._last_velocity
            period = 1.0 / self.bindings.rates[topic]
            ax = (velocity.vx - previous.vx) / period
            ay = (velocity.vy - previous.vy) / period
            self._last_velocity = velocity
            sigma = self.config.noise.imu
            wz = velocity.wz + (self._rng.normal(0.0, sigma) if sigma else 0.0)
            if not self._wanted(topic):
                return
            self._publish(
                topic,
                {
                    "header": self._header(
                        t, "imu_link" if "imu_link" in self.frames else self.base_frame
                    ),
                    "orientation": quaternion(yaw),
                    "orientation_covariance": [1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 1e-4],
                    "angular_velocity": _vector(z=wz),
                    "angular_velocity_covariance": [4e-6, 0, 0, 0, 4e-6, 0, 0, 0, 4e-6],
                    "linear_acceleration": _vector(ax, ay, 9.81),
                    "linear_acceleration_covariance": [1e-3, 0, 0, 0, 1e-3, 0, 0, 0, 1e-3],
                },
            )

        return emit

    def scan(self, topic: str) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Bearings and true ranges (no noise; ``inf``: no return) of ``topic``'s lidar now."""
        mujoco, model, data, np = self._mj, self.model, self.data, self._np
        first, geometry = self._beams[topic]
        flags = model.opt.disableflags
        model.opt.disableflags = flags & ~self._sensor_flag
        mujoco.mj_kinematics(model, data)
        mujoco.mj_sensorPos(model, data)
        model.opt.disableflags = flags
        ranges = np.array(data.sensordata[first : first + geometry.count], dtype=np.float64)
        ranges[(ranges < 0) | (ranges > geometry.range_max)] = np.inf
        angles = geometry.angle_min + np.arange(geometry.count) * geometry.angle_increment
        return angles, ranges

    @functools.cached_property
    def _views(self) -> dict[str, list[str]]:
        """The scanners of each scan topic's view: itself alone, or the parts of its split
        view."""
        return {t: group for group in split_views(self.bindings.scan_topics) for t in group}

    def _nearest_seen(self, topic: str, angles: Any, ranges: Any) -> tuple[float, float]:
        """Distance and bearing of the nearest return the robot's view holds now: ``topic``'s
        scan, and each other scanner of its split view (which sees another side)."""
        np = self._np
        views = [(angles, ranges)] + [self.scan(o) for o in self._views[topic] if o != topic]
        best = (math.inf, 0.0)
        for bearings, distances in views:
            finite = np.isfinite(distances)
            if finite.any():
                index = int(np.argmin(np.where(finite, distances, np.inf)))
                if float(distances[index]) < best[0]:
                    bearing = math.remainder(float(bearings[index]), 2 * math.pi)
                    best = (float(distances[index]), bearing)
        return best

    def _laser_pose(self, geometry: ScanGeometry) -> tuple[float, float, float]:
        x, y, yaw = self.base_pose()
        ox, oy, _ = self.frames.get(
            geometry.frame_id, self.frames.get("laser_link", (0.0, 0.0, 0.0))
        )
        c, s = math.cos(yaw), math.sin(yaw)
        return (x + c * ox - s * oy, y + s * ox + c * oy, yaw)

    def _scan_emitter(self, topic: str) -> Callable[[float], None]:
        np = self._np
        _first, geometry = self._beams[topic]

        def emit(t: float) -> None:
            angles, ranges = self.scan(topic)
            finite = np.isfinite(ranges)
            self.truth.nearest.append((t, *self._nearest_seen(topic, angles, ranges)))
            self.truth.sweeps.append(Sweep(t, geometry.angle_min, geometry.angle_increment, ranges))
            if self.bindings.map_topic and topic in self._views[self.bindings.scan_topics[0]]:
                self._integrate_map(topic, geometry, angles, ranges, t)
            sigma = self.config.noise.scan
            # Drawn whether or not the scan is sent: the noise of later messages stays the same.
            noise = (
                self._rng.normal(0.0, sigma, int(finite.sum())) if sigma and finite.any() else None
            )
            if not self._wanted(topic):
                return
            noisy = ranges.copy()
            if noise is not None:
                noisy[finite] += noise
            noisy[finite & (noisy < geometry.range_min)] = np.inf
            share = self.config.noise.scan_invalid
            if share:
                dropped = self._dropouts.random(noisy.size) < share
                halves = self._dropouts.random(noisy.size) < 0.5
                noisy[dropped & halves] = np.nan
                noisy[dropped & ~halves] = 0.0
            self._publish(
                topic,
                {
                    "header": self._header(t, geometry.frame_id),
                    "angle_min": geometry.angle_min,
                    "angle_max": geometry.angle_max,
                    "angle_increment": geometry.angle_increment,
                    "time_increment": geometry.scan_time / max(geometry.count, 1),
                    "scan_time": geometry.scan_time,
                    "range_min": geometry.range_min,
                    "range_max": geometry.range_max,
                    "ranges": np.round(noisy, 4).tolist(),
                    "intensities": [],
                },
            )

        return emit

    # --- the map ------------------------------------------------------------------------
    def _integrate_map(
        self, topic: str, geometry: ScanGeometry, angles: Any, ranges: Any, t: float
    ) -> None:
        """Takes a scan into the map when the base has moved enough since that scanner's
        last one (each scanner of a split view adds its own side).

        The tracing itself waits until someone needs the map (its topic, a map saver, the
        oracles asking for its extent; see :meth:`_catch_up_map`): it is the dearest
        thing the world does, and most runs never look at the map.
        """
        pose = self._laser_pose(geometry)
        last = self._map_pose.get(topic)
        if last is not None:
            moved = math.hypot(pose[0] - last[0], pose[1] - last[1])
            turned = abs(math.remainder(pose[2] - last[2], 2 * math.pi))
            # slam_toolbox's defaults: a scan joins the map after 0.5 m or 0.5 rad of motion.
            if moved < 0.5 and turned < 0.5:
                return
        self._map_pose[topic] = pose
        self._map_updates += 1
        self._map_scans.append((geometry, pose, angles, ranges, t))

    def _catch_up_map(self) -> None:
        """Traces the scans taken into the map since the last time, in order."""
        from skillwright.sim.grid import GridFrame, OccupancyMap

        for geometry, pose, angles, ranges, t in self._map_scans:
            if self._map is None:
                resolution = self.facts.map_resolution or 0.05
                x0, y0, x1, y1 = self._world_bounds(margin=geometry.range_max)
                self._map = OccupancyMap(
                    GridFrame.covering(x0, y0, x1, y1, resolution), reference=self.config.start
                )
            self._map.integrate(*pose, angles, ranges, geometry.range_max)
            along, across = self._map.extent
            self.truth.extents.append((t, along, across))
        self._map_scans.clear()

    def _world_bounds(self, margin: float) -> tuple[float, float, float, float]:
        """A rectangle around the start and every static obstacle."""
        sx, sy, _ = self.config.start
        xs, ys = [sx - margin, sx + margin], [sy - margin, sy + margin]
        for geom in self._obstacle_geoms():
            cx, cy = (float(v) for v in self.data.geom_xpos[geom][:2])
            r = float(self.model.geom_rbound[geom])
            xs += [cx - r, cx + r]
            ys += [cy - r, cy + r]
        return min(xs), min(ys), max(xs), max(ys)

    def _obstacle_geoms(self) -> list[int]:
        model = self.model
        plane = int(self._mj.mjtGeom.mjGEOM_PLANE)
        return [
            g
            for g in range(model.ngeom)
            if g not in self._robot_geoms
            and int(model.geom_type[g]) != plane
            and (int(model.geom_contype[g]) or int(model.geom_conaffinity[g]))
        ]

    def _map_message(self, t: float) -> tuple[Message, Message]:
        from skillwright.sim.grid import GridFrame

        self._catch_up_map()
        if self._map is None:
            resolution = self.facts.map_resolution or 0.05
            sx, sy, _ = self.config.start
            frame = GridFrame(sx, sy, resolution, 1, 1)
            data = [-1]
        else:
            frame, states = self._map.cropped()
            data = states.ravel().tolist()
        info = {
            "map_load_time": self.host.stamp(t)
            if self.host is not None
            else {"sec": 0, "nanosec": 0},
            "resolution": frame.resolution,
            "width": frame.width,
            "height": frame.height,
            "origin": {
                "position": _vector(frame.origin_x, frame.origin_y, 0.0),
                "orientation": quaternion(0.0),
            },
        }
        return {"header": self._header(t, self.map_frame), "info": info, "data": data}, info

    def _map_emitter(self) -> Callable[[float], None]:
        def emit(t: float) -> None:
            # Like slam_toolbox, publish only a map that changed (it is latched for
            # subscribers that come later).
            if self._map_published == self._map_updates and self._map_updates:
                return
            self._map_published = self._map_updates
            assert self.bindings.map_topic is not None
            metadata = self.bindings.map_metadata_topic
            send_grid = self._wanted(self.bindings.map_topic)
            send_info = metadata is not None and self._wanted(metadata)
            if not (send_grid or send_info):
                return
            grid, info = self._map_message(t)
            if send_grid:
                self._publish(self.bindings.map_topic, grid)
            if send_info:
                assert metadata is not None
                self._publish(metadata, info)

        return emit

    def _tf_static_message(self) -> Message:
        bx, by, bz = self._base_offset()
        transforms = []
        for name, (x, y, z) in sorted(self.frames.items()):
            if name == self.base_frame:
                continue
            transforms.append(
                self._transform(0.0, self.base_frame, name, x - bx, y - by, z - bz, 0.0)
            )
        return {"transforms": transforms}

    # --- services -----------------------------------------------------------------------
    def _map_saver(self, kind: str, type_name: str) -> Callable[[Message], Message]:
        def handle(request: Message) -> Message:
            from skillwright.sim.mapfiles import save_map

            if kind == "nav2_save_map":
                url = str(request.get("map_url", ""))
            else:
                name = request.get("name") or {}
                url = str(name.get("data", "") if isinstance(name, dict) else name)
            template = self.message(f"{type_name}_Response")
            saved = None
            self._catch_up_map()
            if self._map is not None and url:
                saved = save_map(self._map, url, self.config.output_dir, self.map_frame)
            if saved is not None:
                saved["t"] = self.now
                self.truth.saved_maps.append(saved)
                if self.host is not None:
                    self.host.record("map_saved", {k: v for k, v in saved.items() if k != "t"})
            ok = saved is not None
            if kind == "nav2_save_map":
                return fill(template, {"result": ok})
            return fill(template, {"result": 0 if ok else 255})

        return handle

    def _arm_config(self) -> ArmConfig:
        """The arm as the robot's own description says: the planning groups (and their tip
        links) of its recorded SRDF where there is one, else the group and tip the world's
        robot model names."""
        home = self._numeric("arm_home", 3)
        return ArmConfig(
            group=self._text("arm_group", "arm"),
            groups=dict(self.facts.arm_groups) or None,
            tip_link=self._text("arm_tip_link", "tool0"),
            base_frame=self._text("arm_base_frame", "arm_base_link"),
            reach=self._numeric("arm_reach", 1)[0],
            speed_max=self._numeric("arm_speed_max", 1)[0],
            home=(home[0], home[1], home[2]),
        )

    def _arm_frames(self) -> dict[str, tuple[float, float, float]]:
        """Offsets to add to a point in each robot frame to express it in the arm's base."""
        base = self._text("arm_base_frame", "arm_base_link")
        ax, ay, az = self.frames.get(base, (0.0, 0.0, 0.0))
        return {name: (x - ax, y - ay, z - az) for name, (x, y, z) in self.frames.items()}

    def _forward_kinematics(self, type_name: str) -> Callable[[Message], Message]:
        def handle(request: Message) -> Message:
            template = self.message(f"{type_name}_Response")
            if self.arm is None:
                return fill(template, {"error_code": {"val": -1}})
            header = request.get("header") or {}
            frame = str(header.get("frame_id", "")) or self.arm.config.base_frame
            offsets = self._arm_frames()
            links = [str(link) for link in request.get("fk_link_names") or []]
            if frame not in offsets or any(link != self.arm.config.tip_link for link in links):
                return fill(template, {"error_code": {"val": -21}})
            fx, fy, fz = offsets[frame]
            tx, ty, tz = self.arm.tcp
            poses = [
                {
                    "header": self._header(self.now, frame),
                    "pose": {
                        "position": _vector(tx - fx, ty - fy, tz - fz),
                        "orientation": quaternion(0.0),
                    },
                }
                for _ in links
            ]
            return fill(
                template, {"pose_stamped": poses, "fk_link_names": links, "error_code": {"val": 1}}
            )

        return handle

    def obstacle_outlines(self) -> list[tuple[str, float, float, float, float, float]]:
        """Static obstacles seen from above: (``box`` or ``circle``, centre x, y, half sizes
        or radius, yaw)."""
        model, data = self.model, self.data
        box = int(self._mj.mjtGeom.mjGEOM_BOX)
        outlines = []
        for geom in self._obstacle_geoms():
            cx, cy = (float(v) for v in data.geom_xpos[geom][:2])
            size = model.geom_size[geom]
            matrix = data.geom_xmat[geom]
            yaw = math.atan2(float(matrix[3]), float(matrix[0]))
            if int(model.geom_type[geom]) == box:
                outlines.append(("box", cx, cy, float(size[0]), float(size[1]), yaw))
            else:
                outlines.append(("circle", cx, cy, float(size[0]), float(size[0]), 0.0))
        return outlines

    def footprint(self) -> tuple[float, float]:
        """Half length and half width of the chassis."""
        size = self.model.geom_size[self._chassis]
        return float(size[0]), float(size[1])

    # --- planning -----------------------------------------------------------------------
    def _planning_grid(
        self, start: tuple[float, float], goal: tuple[float, float]
    ) -> tuple[Any, Any]:
        from skillwright.sim.grid import GridFrame

        np = self._np
        if self._blocked is not None:
            frame, blocked = self._blocked
            if frame.inside(*frame.cell(*goal)) and frame.inside(*frame.cell(*start)):
                return frame, blocked
        x0, y0, x1, y1 = self._world_bounds(margin=2.0)
        x0, x1 = min(x0, goal[0] - 2.0), max(x1, goal[0] + 2.0)
        y0, y1 = min(y0, goal[1] - 2.0), max(y1, goal[1] + 2.0)
        # 10 cm cells: fine enough for a 0.54 m wide base, cheap enough to plan in Python.
        frame = GridFrame.covering(x0, y0, x1, y1, 0.1)
        xs = frame.origin_x + (np.arange(frame.width) + 0.5) * frame.resolution
        ys = frame.origin_y + (np.arange(frame.height) + 0.5) * frame.resolution
        px, py = np.meshgrid(xs, ys)
        # The base turns as it drives, so its centre keeps the chassis' circumscribed radius
        # plus a margin from every obstacle.
        half_length, half_width = self.footprint()
        radius = math.hypot(half_length, half_width) + 0.05
        blocked = np.zeros(px.shape, dtype=bool)
        for geom in self._obstacle_geoms():
            blocked |= self._footprint_distance(geom, px, py) <= radius
        self._blocked = (frame, blocked)
        return frame, blocked

    def _footprint_distance(self, geom: int, px: Any, py: Any) -> Any:
        """Distance from each point to the geom's outline in the floor plane."""
        np, model, data = self._np, self.model, self.data
        cx, cy = (float(v) for v in data.geom_xpos[geom][:2])
        kind = int(model.geom_type[geom])
        size = model.geom_size[geom]
        if kind == int(self._mj.mjtGeom.mjGEOM_BOX):
            matrix = data.geom_xmat[geom].reshape(3, 3)
            dx, dy = px - cx, py - cy
            u = np.abs(dx * matrix[0, 0] + dy * matrix[1, 0]) - float(size[0])
            v = np.abs(dx * matrix[0, 1] + dy * matrix[1, 1]) - float(size[1])
            outside = np.hypot(np.maximum(u, 0.0), np.maximum(v, 0.0))
            return outside + np.minimum(np.maximum(u, v), 0.0)
        return np.hypot(px - cx, py - cy) - float(size[0])
