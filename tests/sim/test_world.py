"""The MuJoCo world against a test graph host: sensors, drive, contacts, motions, maps."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from skillwright.interfaces.inventory import Inventory
from skillwright.runtime.api import GoalStatus
from skillwright.sim.assets import resolve_world
from skillwright.sim.bindings import bind_interfaces, recorded_facts
from skillwright.sim.world import MujocoWorld, Noise, WorldConfig
from tests.sim.fakes import FakeHost

FORWARD = {"linear": {"x": 0.5, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.0}}
STOP = {"linear": {"x": 0.0, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.0}}


def _world(
    inventory: Inventory,
    world: str,
    start: tuple[float, float, float] = (0.0, 0.0, 0.0),
    *,
    seed: int = 0,
    noise: Noise | None = None,
    output_dir: Path | None = None,
) -> tuple[MujocoWorld, FakeHost]:
    bindings = bind_interfaces(inventory)
    facts = recorded_facts(inventory, bindings)
    config = WorldConfig(resolve_world(world), start, seed, noise or Noise(), output_dir)
    instance = MujocoWorld(config, bindings, facts)
    host = FakeHost(inventory)
    host.attach(instance)
    return instance, host


def _pose(goal_x: float, goal_y: float) -> dict[str, object]:
    return {
        "header": {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": "map"},
        "pose": {
            "position": {"x": goal_x, "y": goal_y, "z": 0.0},
            "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0},
        },
    }


def test_a_velocity_command_drives_the_base_and_odometry_follows(mr1_inventory: Inventory) -> None:
    world, host = _world(mr1_inventory, "open_floor", (1.0, 2.0, math.pi / 2))
    assert {"/odom", "/scan", "/tf", "/tf_static", "/map", "/imu/data", "/pose"} <= host.owned
    host.run_until(0.5)
    host.skill_publishes("/cmd_vel", FORWARD)
    host.run_until(0.7)
    # 1 m/s^2 in the driver, then the wheels' and the chassis' own lag.
    assert 0.1 < world.truth.at(0.7).vx < 0.2
    host.run_until(3.0)
    host.skill_publishes("/cmd_vel", STOP)
    host.run_until(4.0)
    end = world.truth.at(4.0)
    assert end.x == pytest.approx(1.0, abs=0.01)
    assert end.y - 2.0 == pytest.approx(0.5 * 2.5, abs=0.05)
    assert end.speed < 0.01
    odometry = host.messages("/odom")
    assert len(odometry) == pytest.approx(4.0 * 50, abs=1)
    last = odometry[-1][1]
    assert last["header"]["frame_id"] == "odom"
    assert last["child_frame_id"] == "base_link"
    # Odometry starts at the start pose and measures along the base's own heading.
    assert last["pose"]["pose"]["position"]["x"] == pytest.approx(end.y - 2.0, abs=0.02)
    assert [c.vx for c in world.truth.commands] == [0.5, 0.0]
    static = host.messages("/tf_static")[0][1]["transforms"]
    laser = next(t for t in static if t["child_frame_id"] == "laser_link")
    assert laser["header"]["frame_id"] == "base_link"
    assert laser["transform"]["translation"] == pytest.approx({"x": 0.28, "y": 0.0, "z": 0.18})


def test_scans_have_the_recorded_geometry_and_see_the_corridor(mr1_inventory: Inventory) -> None:
    world, host = _world(mr1_inventory, "corridor", noise=Noise.none())
    host.run_until(0.25)
    scans = host.messages("/scan")
    assert [round(t, 3) for t, _ in scans] == [0.107, 0.207]
    scan = scans[-1][1]
    assert len(scan["ranges"]) == 360
    assert scan["header"]["frame_id"] == "laser_link"
    ahead = scan["ranges"][180]
    left = scan["ranges"][270]
    behind = scan["ranges"][0]
    assert ahead == pytest.approx(4.0 - 0.28, abs=0.005)
    assert left == pytest.approx(1.0, abs=0.005)
    assert behind == math.inf
    assert world.truth.nearest[-1][1] == pytest.approx(1.0, abs=0.005)
    # The truth keeps each scan without noise: its range to the left is the left wall's.
    assert world.truth.range_toward(0.25, math.pi / 2) == pytest.approx(left, abs=1e-6)


def test_a_lidar_with_dropouts_reports_some_beams_as_nan_or_zero(mr1_inventory: Inventory) -> None:
    def ranges(noise: Noise) -> list[float]:
        _, host = _world(mr1_inventory, "walled_room", (7.5, 2.0, math.pi / 2), seed=3, noise=noise)
        host.run_until(0.25)
        return list(host.messages("/scan")[-1][1]["ranges"])

    clean = ranges(Noise())
    dropped = ranges(Noise(scan_invalid=0.2))
    nan = sum(math.isnan(r) for r in dropped)
    zero = sum(r == 0.0 for r in dropped)
    # about 36 of each in 360 beams
    assert 20 < nan < 55, nan
    assert 20 < zero < 55, zero
    assert not any(math.isnan(r) or r == 0.0 for r in clean)
    # The other beams keep the noise they would have had.
    kept = [(a, b) for a, b in zip(clean, dropped, strict=True) if not math.isnan(b) and b != 0.0]
    assert all(a == b for a, b in kept)


def test_driving_into_the_obstacle_is_a_contact_and_the_chassis_stops_at_it(
    mr1_inventory: Inventory,
) -> None:
    world, host = _world(mr1_inventory, "corridor", (2.5, 0.0, 0.0))
    host.skill_publishes("/cmd_vel", FORWARD)
    host.run_until(5.0)
    contacts = world.truth.contacts
    assert contacts
    assert contacts[0].geom == "obstacle"
    assert world.truth.at(5.0).x == pytest.approx(4.0 - 0.35, abs=0.02)
    odometry = host.messages("/odom")[-1][1]["pose"]["pose"]["position"]["x"]
    assert odometry > 4.0 - 0.35 - 2.5 + 0.3, "the wheels slip on: odometry runs ahead"


def test_navigation_goes_around_the_shelf_to_the_goal(mr1_inventory: Inventory) -> None:
    world, host = _world(mr1_inventory, "walled_room", (0.0, 0.3, 0.0))
    host.run_until(0.2)
    goal = host.send_goal("/navigate_to_pose", {"pose": _pose(6.5, 0.3), "behavior_tree": ""})
    host.run_until(40.0)
    events = host.goals[goal.goal_id]
    assert events.accepted
    assert events.status == GoalStatus.SUCCEEDED
    end = world.truth.at(events.finished_at or 0.0)
    assert math.hypot(end.x - 6.5, end.y - 0.3) <= 0.1
    assert world.truth.contacts == []
    assert min(s.y for s in world.truth.samples) < -0.3, (
        "the path leaves the line through the shelf"
    )
    assert events.feedback
    assert events.feedback[-1]["distance_remaining"] < 0.5
    assert max(s.speed for s in world.truth.samples) <= 0.52


def test_a_goal_inside_the_shelf_is_aborted_and_a_cancelled_goal_stops_the_base(
    mr1_inventory: Inventory,
) -> None:
    world, host = _world(mr1_inventory, "walled_room", (0.0, 0.3, 0.0))
    blocked = host.send_goal("/navigate_to_pose", {"pose": _pose(4.7, 0.3), "behavior_tree": ""})
    assert host.goals[blocked.goal_id].status == GoalStatus.ABORTED
    goal = host.send_goal("/navigate_to_pose", {"pose": _pose(0.0, 3.0), "behavior_tree": ""})
    host.run_until(2.0)
    assert host.cancel(goal)
    assert host.goals[goal.goal_id].status == GoalStatus.CANCELED
    host.run_until(3.0)
    assert world.truth.at(3.0).speed < 0.01
    assert world.truth.goals_active_at(3.0) == []


def test_spin_turns_by_the_target_angle(mr1_inventory: Inventory) -> None:
    world, host = _world(mr1_inventory, "open_floor")
    goal = host.send_goal(
        "/spin", {"target_yaw": -1.5, "time_allowance": {"sec": 10, "nanosec": 0}}
    )
    host.run_until(6.0)
    assert host.goals[goal.goal_id].status == GoalStatus.SUCCEEDED
    assert world.truth.at(6.0).yaw == pytest.approx(-1.5, abs=0.03)


@pytest.mark.parametrize(
    ("group", "target", "code"),
    [
        ("mr1_arm", (0.4, 0.2, 0.3), 1),
        ("mr1_arm", (0.8, 0.5, 0.3), -31),
        ("arm", (0.4, 0.2, 0.3), -15),
    ],
)
def test_the_arm_moves_its_tool_to_targets_within_reach_only(
    mr1_inventory: Inventory, group: str, target: tuple[float, float, float], code: int
) -> None:
    world, host = _world(mr1_inventory, "open_floor")
    region = {"primitive_poses": [{"position": dict(zip("xyz", target, strict=True))}]}
    constraint = {
        "header": {"frame_id": "arm_base_link"},
        "link_name": "tool0",
        "constraint_region": region,
    }
    request = {
        "request": {
            "group_name": group,
            "goal_constraints": [{"position_constraints": [constraint]}],
            "max_velocity_scaling_factor": 0.3,
        },
        "planning_options": {"plan_only": False},
    }
    goal = host.send_goal("/move_action", request)
    host.run_until(5.0)
    events = host.goals[goal.goal_id]
    assert events.result is not None
    assert events.result["error_code"]["val"] == code
    if code == 1:
        assert events.status == GoalStatus.SUCCEEDED
        assert world.arm is not None
        assert world.arm.tcp == pytest.approx(target)
        tf = [
            t
            for _, m in host.messages("/tf")
            for t in m["transforms"]
            if t["child_frame_id"] == "tool0"
        ]
        assert tf[-1]["transform"]["translation"] == pytest.approx(
            dict(zip("xyz", target, strict=True))
        )
        fk = host.call(
            "/compute_fk", {"header": {"frame_id": "arm_base_link"}, "fk_link_names": ["tool0"]}
        )
        assert fk["error_code"]["val"] == 1
        assert fk["pose_stamped"][0]["pose"]["position"]["z"] == pytest.approx(target[2])
    else:
        assert events.status == GoalStatus.ABORTED


def test_the_map_grows_from_the_lidar_and_saves_to_the_run_folder(
    mr1_inventory: Inventory, tmp_path: Path
) -> None:
    world, host = _world(mr1_inventory, "walled_room", (0.0, 0.0, 0.0), output_dir=tmp_path)
    host.run_until(2.1)
    grid = host.messages("/map")[-1][1]
    assert grid["info"]["resolution"] == pytest.approx(0.05)
    assert grid["info"]["width"] * 0.05 == pytest.approx(9.9, abs=0.15)
    assert 100 in grid["data"]
    assert 0 in grid["data"]
    answer = host.call("/map_saver/save_map", {"map_url": "../../etc/room", "map_topic": "/map"})
    assert answer["result"] is True
    assert sorted(p.name for p in tmp_path.iterdir()) == ["room.pgm", "room.yaml"]
    assert (tmp_path / "room.pgm").read_bytes().startswith(b"P5\n")
    assert world.truth.saved_maps[0]["name"] == "room"


def test_a_seed_makes_the_noise_repeat_and_another_seed_changes_it(
    mr1_inventory: Inventory,
) -> None:
    def ranges(seed: int) -> list[float]:
        _, host = _world(mr1_inventory, "corridor", seed=seed)
        host.run_until(0.15)
        return list(host.messages("/scan")[0][1]["ranges"])

    assert ranges(3) == ranges(3)
    assert ranges(3) != ranges(4)


def test_the_papers_robot_runs_in_the_same_worlds(shared_data: Path) -> None:
    from skillwright.interfaces.load import load_inventory

    inventory = load_inventory(
        shared_data / "cap2skill" / "interface-reports" / "ros2_system_report.json"
    )
    world, host = _world(inventory, "corridor")
    host.skill_publishes("/cmd_vel", FORWARD)
    host.run_until(1.0)
    published = {topic for _, topic, _ in host.published}
    assert {"/odom", "/scan", "/scan2", "/tf", "/tf_static"} <= published
    transforms = [t["header"]["frame_id"] for _, m in host.messages("/tf") for t in m["transforms"]]
    assert "map" not in transforms, "the paper's robot has no localisation"
    assert world.truth.at(1.0).x > 0.2
    # What the oracles need to judge it by what it can know.
    assert world.truth.localised is False
    assert world.truth.map_savers == []
    assert world.truth.noise["scan"] == Noise().scan
    assert world.truth.odometry_period == pytest.approx(0.02)


def test_the_mr1_localises_and_its_world_says_what_it_serves(mr1_inventory: Inventory) -> None:
    world, _host = _world(mr1_inventory, "open_floor", noise=Noise(scan=0.05))
    bindings = bind_interfaces(mr1_inventory)
    assert world.truth.localised is bindings.has_localisation
    assert world.truth.noise["scan"] == 0.05
    savers = sorted(n for n, k in bindings.services.items() if k.endswith("save_map"))
    assert world.truth.map_savers == savers


def test_the_papers_two_corner_scanners_each_see_one_half_and_the_truth_sees_both(
    shared_data: Path,
) -> None:
    from skillwright.interfaces.load import load_inventory

    inventory = load_inventory(
        shared_data / "cap2skill" / "interface-reports" / "ros2_system_report.json"
    )
    # near the west wall, facing east: the nearest obstacle is behind, on the rear scanner's side
    world, host = _world(inventory, "walled_room", (0.0, 1.0, 0.0), noise=Noise(scan=0.0))
    host.run_until(0.5)
    front, rear = host.messages("/scan")[-1][1], host.messages("/scan2")[-1][1]
    assert len(front["ranges"]) == len(rear["ranges"]) == 180
    assert math.degrees(front["angle_min"]) == pytest.approx(-90)
    assert math.degrees(rear["angle_min"]) == pytest.approx(90)
    nearest = world.truth.nearest_at(0.5)
    assert nearest is not None
    distance, bearing = nearest
    assert distance == pytest.approx(min(rear["ranges"]), abs=1e-3)
    assert distance < min(front["ranges"]) - 0.5
    assert abs(math.degrees(bearing)) > 150


def test_the_same_seed_and_commands_give_the_same_run(mr1_inventory: Inventory) -> None:
    def run() -> list[tuple[float, ...]]:
        world, host = _world(mr1_inventory, "corridor", (2.0, 0.2, 0.1), seed=9)
        host.skill_publishes("/cmd_vel", FORWARD)
        host.run_until(4.0)
        odometry = [m["pose"]["pose"]["position"]["x"] for _, m in host.messages("/odom")]
        return [(s.t, s.x, s.y, s.yaw) for s in world.truth.samples] + [tuple(odometry)]

    assert run() == run()


def test_worlds_from_one_file_share_its_compilation_but_not_their_model(
    mr1_inventory: Inventory,
) -> None:
    first, _ = _world(mr1_inventory, "corridor")
    second, _ = _world(mr1_inventory, "corridor")
    assert second.model is not first.model
    assert second.model.nsensor == first.model.nsensor == 360
    first.model.opt.timestep = 0.5
    assert second.model.opt.timestep == pytest.approx(0.01)


def test_a_world_file_changed_on_disk_is_compiled_again(
    mr1_inventory: Inventory, tmp_path: Path
) -> None:
    folder = tmp_path / "worlds"
    folder.mkdir()
    (tmp_path / "mr1.xml").write_bytes(
        (resolve_world("open_floor").parent.parent / "mr1.xml").read_bytes()
    )
    world_file = folder / "room.xml"
    original = resolve_world("open_floor").read_text(encoding="utf-8")
    world_file.write_text(original, encoding="utf-8")
    bindings = bind_interfaces(mr1_inventory)
    facts = recorded_facts(mr1_inventory, bindings)
    empty = MujocoWorld(WorldConfig(world_file), bindings, facts)
    box = '<geom name="box" type="box" size="0.2 0.2 0.2" pos="2 0 0.2"/>\n  </worldbody>'
    world_file.write_text(original.replace("</worldbody>", box), encoding="utf-8")
    boxed = MujocoWorld(WorldConfig(world_file), bindings, facts)
    assert boxed.model.ngeom == empty.model.ngeom + 1


def test_messages_nobody_receives_are_not_made_but_the_world_runs_the_same(
    mr1_inventory: Inventory,
) -> None:
    def run(listening: set[str] | None) -> tuple[MujocoWorld, FakeHost]:
        world, host = _world(mr1_inventory, "corridor", (2.0, 0.2, 0.1), seed=9)
        host.listening = listening
        host.skill_publishes("/cmd_vel", FORWARD)
        host.run_until(2.0)
        return world, host

    everything, all_host = run(None)
    odometry_only, host = run({"/odom"})
    assert {topic for _, topic, _ in host.published} == {"/odom"}
    assert host.messages("/odom") == all_host.messages("/odom")
    # The lidar still measured (ground truth, map) and drew its noise at every scan.
    assert odometry_only.truth.nearest == everything.truth.nearest
    assert odometry_only.truth.samples == everything.truth.samples


def test_the_map_is_traced_only_when_someone_needs_it_and_comes_out_the_same(
    mr1_inventory: Inventory,
) -> None:
    def run(listening: set[str] | None) -> MujocoWorld:
        world, host = _world(mr1_inventory, "walled_room", (0.0, 0.3, 0.0), seed=4)
        host.listening = listening
        host.skill_publishes("/cmd_vel", FORWARD)
        host.run_until(3.0)
        return world

    published = run(None)
    unwatched = run({"/odom"})
    assert published.truth.extents, "publishing the map traced it"
    assert unwatched.truth.extents == [], "nobody asked for the map yet"
    assert unwatched.truth.extent_at(3.0) == published.truth.extent_at(3.0)
    assert len(unwatched.truth.extents) >= 3
    assert unwatched.truth.extents == published.truth.extents


def test_the_arm_serves_the_groups_of_the_robots_recorded_srdf(mr1_inventory: Inventory) -> None:
    bindings = bind_interfaces(mr1_inventory)
    facts = recorded_facts(mr1_inventory, bindings)
    facts.arm_groups = {"manipulator": "tool0"}
    world = MujocoWorld(WorldConfig(resolve_world("open_floor")), bindings, facts)
    host = FakeHost(mr1_inventory)
    host.attach(world)
    codes = {}
    for group in ("manipulator", "mr1_arm"):
        region = {"primitive_poses": [{"position": {"x": 0.4, "y": 0.0, "z": 0.3}}]}
        constraint = {"header": {"frame_id": "arm_base_link"}, "link_name": "tool0"}
        request = {
            "request": {
                "group_name": group,
                "goal_constraints": [
                    {"position_constraints": [{**constraint, "constraint_region": region}]}
                ],
            },
        }
        goal = host.send_goal("/move_action", request)
        host.run_until(host.now + 3.0)
        result = host.goals[goal.goal_id].result
        assert result is not None
        codes[group] = result["error_code"]["val"]
    assert codes == {"manipulator": 1, "mr1_arm": -15}
    reasons = [g.get("reason", "") for g in world.truth.goals if g.get("outcome") == "aborted"]
    assert "the robot's groups are 'manipulator'" in reasons[-1]
