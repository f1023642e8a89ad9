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
   and real time factors in wall time and in CPU time (wall time on a shared machine depends
   on what else runs). Compared with the alternative of starting each run's child when the
   run starts (``ChildPool(ahead=False)``) instead of while the previous run goes on; the
   oracles' verdicts of both must be the same.

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


def _validate_all(
    ahead: bool, pattern: str = "*.py"
) -> dict[str, tuple[float, float, float, list[str], bool]]:
    """Scenario -> (virtual s, wall s, CPU s of both processes, verdicts, passed) of every
    shipped skill, validated with children booted ahead or on demand."""
    from skillwright.capability.reader import load_capability
    from skillwright.interfaces.load import discover_path
    from skillwright.runtime.sandbox import ChildPool
    from skillwright.sim.validate import validate_skill

    inventory = discover_path(ROOT / "capabilities" / "recordings" / "mr1")
    rows: dict[str, tuple[float, float, float, list[str], bool]] = {}
    for skill in sorted((ROOT / "capabilities" / "skills").glob(pattern)):
        model = ROOT / "capabilities" / f"{skill.stem.replace('_', '-')}.ttl"
        capability = load_capability(model).capability
        with ChildPool(ahead=ahead) as children:
            report = validate_skill(skill, capability, inventory, plot=False, children=children)
        for scenario in report.scenarios:
            virtual = sum(e.virtual_seconds for e in scenario.episodes)
            # Per scenario, the wall time of its runs (the child's start-up and the world's
            # making included); what the validation does around them is shared by all.
            wall = sum(e.wall_seconds for e in scenario.episodes)
            cpu = scenario.host_cpu_seconds + sum(e.child_cpu_seconds for e in scenario.episodes)
            verdicts = [
                f"{e.episode}/{v.oracle}/{v.passed}" for e in scenario.episodes for v in e.verdicts
            ]
            rows[f"{skill.stem} / {scenario.name}"] = (
                virtual,
                wall,
                cpu,
                verdicts,
                report.passed,
            )
    return rows


def part_two() -> None:
    print(
        "\n2. whole validations of the nine MR-1 skills (both runs of each scenario): each run's "
        "child\n   booted while the previous run goes on (ahead) against booted when the run "
        "starts (on demand)"
    )
    # The first validation in a process also imports MuJoCo and reads the recording: warm up.
    _validate_all(True, "get_position.py")
    on_demand = _validate_all(False)
    ahead = _validate_all(True)
    print(
        f"   {'skill / scenario':46s} {'virtual':>8s} {'wall':>7s} {'x wall':>7s} {'cpu':>6s} "
        f"{'x cpu':>6s} | {'on demand':>9s} {'x wall':>7s} {'x cpu':>6s} | {'ratio':>6s} same"
    )
    sums = [0.0] * 5
    for name, (virtual, wall, cpu, verdicts, _) in ahead.items():
        _, old_wall, old_cpu, old_verdicts, _ = on_demand[name]
        same = "yes" if verdicts == old_verdicts else "NO"
        print(
            f"   {name:46s} {virtual:7.2f}s {wall:6.2f}s {virtual / wall:6.1f}x {cpu:5.2f}s "
            f"{virtual / cpu:5.1f}x | {old_wall:8.2f}s {virtual / old_wall:6.1f}x "
            f"{virtual / old_cpu:5.1f}x | {old_wall / wall:5.2f}x {same}"
        )
        for index, value in enumerate((virtual, wall, cpu, old_wall, old_cpu)):
            sums[index] += value
    virtual, wall, cpu, old_wall, old_cpu = sums
    print(
        f"\n   all: {virtual:.1f} s virtual; ahead {wall:.1f} s wall ({virtual / wall:.1f}x real "
        f"time), {cpu:.1f} s CPU ({virtual / cpu:.1f}x); on demand {old_wall:.1f} s wall "
        f"({virtual / old_wall:.1f}x), {old_cpu:.1f} s CPU ({virtual / old_cpu:.1f}x); "
        f"wall ratio {old_wall / wall:.2f}x"
    )
    print(
        "   (the lockstep keeps one core busy at a time, so on a quiet machine the wall time of "
        "a run\n   is close to the CPU time of both processes; x cpu is what a quiet machine shows)"
    )


if __name__ == "__main__":
    part_one()
    if "--worlds-only" not in sys.argv:
        part_two()
