"""Speed of the MuJoCo validation: the world alone, and whole validations of the MR-1 skills.

1. The world alone, in each shipped world, driven by a fixed script (drive and turn in the
   open floor and the corridor, a navigation goal around the shelf in the walled room),
   against a graph host that only collects what is published: virtual seconds per CPU
   second of this process (it runs alone in it, and CPU time does not depend on what else
   the machine runs). Compared with the alternative of evaluating the lidar's rangefinders at every
   physics step (MuJoCo's default for sensors) instead of only when a scan is due.
2. Whole validations of the nine shipped skills (``capabilities/skills``) in their
   scenarios: the skill runs in the sandboxed child in lockstep with the world. Per scenario:
   virtual seconds of both runs, wall seconds, CPU seconds of this process and of the child,
   and, of this process's CPU time, the world's own (physics, sensors, controllers) and the
   host's taking of its messages (``host.publish``). Real time factors are given in wall
   time and in CPU time, since wall time on a shared machine depends on what else runs.

    python bench/bench_sim.py [--worlds-only]
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

VIRTUAL = 30.0


def _drive(host: object, world: object, name: str) -> None:
    """The script of part 1."""
    twist = {"linear": {"x": 0.5, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.0}}
    if name == "walled_room":
        pose = {
            "header": {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": "map"},
            "pose": {"position": {"x": 6.5, "y": 0.3, "z": 0.0}, "orientation": {"w": 1.0}},
        }
        host.send_goal("/navigate_to_pose", {"pose": pose, "behavior_tree": ""})  # type: ignore[attr-defined]
        host.run_until(VIRTUAL)  # type: ignore[attr-defined]
        return
    for step in range(int(VIRTUAL)):
        twist["angular"]["z"] = 0.4 * math.sin(step / 3.0)
        host.skill_publishes("/cmd_vel", twist)  # type: ignore[attr-defined]
        host.run_until(step + 1.0)  # type: ignore[attr-defined]


def _world_alone(every_step: bool, name: str) -> float:
    from tests.sim.fakes import FakeHost

    from skillwright.interfaces.load import discover_path
    from skillwright.sim.assets import resolve_world
    from skillwright.sim.bindings import bind_interfaces, recorded_facts
    from skillwright.sim.world import MujocoWorld, WorldConfig

    inventory = discover_path(ROOT / "capabilities" / "recordings" / "mr1")
    bindings = bind_interfaces(inventory)
    facts = recorded_facts(inventory, bindings)
    start = (0.0, 0.3, 0.0) if name == "walled_room" else (0.0, 0.0, 0.0)
    world = MujocoWorld(WorldConfig(resolve_world(name), start, seed=1), bindings, facts)
    if every_step:
        world.model.opt.disableflags &= ~world._sensor_flag
    host = FakeHost(inventory)
    host.attach(world)
    began = time.process_time()
    _drive(host, world, name)
    return VIRTUAL / (time.process_time() - began)


def part_one() -> None:
    print(
        f"1. the world alone, {VIRTUAL:.0f} s virtual per run "
        "(virtual seconds per CPU second, best of 3)"
    )
    header = f"{'lidar at scan times':>20s} {'rangefinders every step':>24s} {'ratio':>7s}"
    print(f"   {'world':14s} {header}")
    for name in ("open_floor", "corridor", "walled_room"):
        lazy = max(_world_alone(False, name) for _ in range(3))
        eager = max(_world_alone(True, name) for _ in range(3))
        print(f"   {name:14s} {lazy:19.1f}x {eager:23.1f}x {lazy / eager:6.2f}x")


def part_two() -> None:
    from skillwright.capability.reader import load_capability
    from skillwright.interfaces.load import discover_path
    from skillwright.sim.validate import validate_skill

    inventory = discover_path(ROOT / "capabilities" / "recordings" / "mr1")
    print("\n2. whole validations of the nine MR-1 skills (both runs of each scenario)")
    print(
        f"   {'skill / scenario':46s} {'virtual':>8s} {'wall':>7s} {'x wall':>7s} {'host cpu':>9s} "
        f"{'child cpu':>9s} {'x cpu':>6s} {'world':>6s} {'publish':>8s}"
    )
    total_virtual = total_wall = total_cpu = 0.0
    for skill in sorted((ROOT / "capabilities" / "skills").glob("*.py")):
        model = ROOT / "capabilities" / f"{skill.stem.replace('_', '-')}.ttl"
        capability = load_capability(model).capability
        began_wall, began_cpu = time.perf_counter(), time.process_time()
        report = validate_skill(skill, capability, inventory)
        skill_wall = time.perf_counter() - began_wall
        skill_cpu = time.process_time() - began_cpu
        for scenario in report.scenarios:
            virtual = sum(e.virtual_seconds for e in scenario.episodes)
            wall = sum(e.wall_seconds for e in scenario.episodes)
            world = sum(e.world_cpu_seconds for e in scenario.episodes)
            child = sum(e.child_cpu_seconds for e in scenario.episodes)
            host = scenario.host_cpu_seconds
            publish = sum(e.publish_seconds for e in scenario.episodes)
            total_virtual += virtual
            total_wall += wall
            total_cpu += host + child
            print(
                f"   {skill.stem + ' / ' + scenario.name:46s} {virtual:7.1f}s {wall:6.1f}s "
                f"{virtual / wall:6.1f}x {host:8.2f}s {child:8.2f}s "
                f"{virtual / max(host + child, 1e-9):5.1f}x {world - publish:5.2f}s {publish:7.2f}s"
            )
        verdict = "passed" if report.passed else "failed"
        print(
            f"   {skill.stem:46s} validated in {skill_wall:.1f} s wall, {skill_cpu:.1f} s CPU "
            f"of this process ({verdict})"
        )
    print(
        f"\n   all: {total_virtual:.1f} s virtual in {total_wall:.1f} s wall "
        f"({total_virtual / total_wall:.1f}x real time), {total_cpu:.1f} s CPU "
        f"({total_virtual / total_cpu:.1f}x real time in CPU time)"
    )


if __name__ == "__main__":
    part_one()
    if "--worlds-only" not in sys.argv:
        part_two()
