"""Speed of the MuJoCo validation: the world alone, and whole validations of the MR-1 skills.

1. The world alone, in each shipped world, driven by a fixed script (drive and turn in the
   open floor and the corridor, a navigation goal around the shelf in the walled room),
   against a graph host that only collects what is published: virtual seconds per CPU
   second of this process (it runs alone in it, and CPU time does not depend on what else
   the machine runs). Compared with the alternative of evaluating the lidar's rangefinders at every
   physics step (MuJoCo's default for sensors) instead of only when a scan is due.
2. Whole validations of the nine shipped skills (``capabilities/skills``) in their
   scenarios: the skill runs in the sandboxed child in lockstep with the world. Per
   scenario: virtual seconds of its runs, wall seconds of those runs, and real time
   factors in wall time and in CPU time (this process and the children; wall time on a
   shared machine depends on what else runs); per skill, the whole
   validation time (``validate_skill`` from its start to the verdicts: scenarios read,
   worlds built, children started, runs, oracles). Compared, skill by skill in the same
   run, with the alternative of no kernel sandbox (``ChildPool(isolated=False)``, what
   ``--unsafe-no-isolation`` runs): what bubblewrap's namespaces, the read-only root,
   Landlock and seccomp cost. Both must reach the same verdicts. Each build validates the nine
   skills with one pool of children (as a caller validating several skills should); the
   start of a fork server, which a validation with its own pool waits for, is printed too.

    python bench/bench_sim.py [--worlds-only]
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

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


@dataclass
class _Validation:
    """One skill's validation: per scenario (virtual s, wall s of its runs, CPU s, verdicts),
    and the whole validation's wall and CPU seconds."""

    scenarios: dict[str, tuple[float, float, float, list[str]]]
    wall: float
    cpu: float


def _validate(skill: Path, inventory: object, children: Any) -> _Validation:
    from skillwright.capability.reader import load_capability
    from skillwright.sim.validate import validate_skill

    model = ROOT / "capabilities" / f"{skill.stem.replace('_', '-')}.ttl"
    capability = load_capability(model).capability
    cpu_started = time.process_time()
    report = validate_skill(
        skill,
        capability,
        inventory,  # type: ignore[arg-type]
        plot=False,
        children=children,
    )
    host_cpu = time.process_time() - cpu_started
    rows: dict[str, tuple[float, float, float, list[str]]] = {}
    children_cpu = 0.0
    for scenario in report.scenarios:
        virtual = sum(e.virtual_seconds for e in scenario.episodes)
        wall = sum(e.wall_seconds for e in scenario.episodes)
        child = sum(e.child_cpu_seconds for e in scenario.episodes)
        children_cpu += child
        verdicts = [
            f"{e.episode}/{v.oracle}/{v.passed}" for e in scenario.episodes for v in e.verdicts
        ]
        rows[f"{skill.stem} / {scenario.name}"] = (
            virtual,
            wall,
            scenario.host_cpu_seconds + child,
            verdicts,
        )
    return _Validation(rows, report.wall_seconds, host_cpu + children_cpu)


def _fork_server_start() -> tuple[float, float]:
    """Wall seconds from starting a fork server to its first child, and its CPU seconds."""
    from skillwright.runtime.sandbox import ForkServer

    started = time.perf_counter()
    server = ForkServer()
    child = server.fork()
    wall = time.perf_counter() - started
    cpu = server.cpu_seconds() or 0.0
    child.close()
    server.close()
    return wall, cpu


def part_two() -> None:
    from skillwright.interfaces.load import discover_path
    from skillwright.runtime.sandbox import ChildPool

    print(
        "\n2. whole validations of the nine MR-1 skills: in the kernel sandbox (namespaces, "
        "read-only root,\n   Landlock, seccomp) against without it (--unsafe-no-isolation), "
        "skill by skill in the same run;\n   each validates the nine skills with one pool of "
        "children, as a session validating several\n   skills does"
    )
    inventory = discover_path(ROOT / "capabilities" / "recordings" / "mr1")
    skills = sorted((ROOT / "capabilities" / "skills").glob("*.py"))
    now: dict[str, _Validation] = {}
    before: dict[str, _Validation] = {}
    with ChildPool() as new_pool, ChildPool(isolated=False) as old_pool:
        # The first validation in a process imports MuJoCo and reads the recording, and
        # each pool starts its fork server: warm up.
        _validate(skills[0], inventory, new_pool)
        _validate(skills[0], inventory, old_pool)
        for skill in skills:
            before[skill.stem] = _validate(skill, inventory, old_pool)
            now[skill.stem] = _validate(skill, inventory, new_pool)
    print(
        f"   {'skill / scenario':46s} {'virtual':>8s} {'wall':>7s} {'x wall':>7s} "
        f"{'x cpu':>6s} | {'no sandbox':>8s} {'x wall':>7s} {'x cpu':>6s} | {'ratio':>6s} same"
    )
    sums = [0.0] * 5
    for skill in skills:
        for name, (virtual, wall, cpu, verdicts) in now[skill.stem].scenarios.items():
            _, old_wall, old_cpu, old_verdicts = before[skill.stem].scenarios[name]
            same = "yes" if verdicts == old_verdicts else "NO"
            print(
                f"   {name:46s} {virtual:7.2f}s {wall:6.2f}s {virtual / wall:6.1f}x "
                f"{virtual / cpu:5.1f}x | {old_wall:7.2f}s {virtual / old_wall:6.1f}x "
                f"{virtual / old_cpu:5.1f}x | {old_wall / wall:5.2f}x {same}"
            )
            for index, value in enumerate((virtual, wall, cpu, old_wall, old_cpu)):
                sums[index] += value
    virtual, wall, cpu, old_wall, old_cpu = sums
    print(
        f"\n   all scenarios: {virtual:.1f} s virtual; {wall:.2f} s wall ({virtual / wall:.1f}x "
        f"real time), {cpu:.2f} s CPU ({virtual / cpu:.1f}x); without the sandbox "
        f"{old_wall:.2f} s wall ({virtual / old_wall:.1f}x), {old_cpu:.2f} s CPU "
        f"({virtual / old_cpu:.1f}x); the sandbox costs {wall / old_wall:.2f}x the wall time"
    )
    print(
        "\n   validation time per skill (validate_skill from start to verdicts; CPU of this "
        "process and the children)"
    )
    print(f"   {'skill':32s} {'wall':>7s} {'cpu':>7s} | {'no sandbox':>8s} {'cpu':>7s} | ratio")
    totals = [0.0] * 4
    for skill in skills:
        new, old = now[skill.stem], before[skill.stem]
        print(
            f"   {skill.stem:32s} {new.wall:6.2f}s {new.cpu:6.2f}s | {old.wall:7.2f}s "
            f"{old.cpu:6.2f}s | {old.wall / new.wall:5.2f}x"
        )
        for index, value in enumerate((new.wall, new.cpu, old.wall, old.cpu)):
            totals[index] += value
    new_wall, new_cpu, old_wall, old_cpu = totals
    print(
        f"   {'all nine':32s} {new_wall:6.2f}s {new_cpu:6.2f}s | {old_wall:7.2f}s "
        f"{old_cpu:6.2f}s | {old_wall / new_wall:5.2f}x"
    )
    boot_wall, boot_cpu = min(_fork_server_start() for _ in range(3))
    print(
        f"   a validation with a pool of its own (skillwright validate) also waits once for "
        f"its fork\n   server: {boot_wall * 1000:.0f} ms wall, {boot_cpu * 1000:.0f} ms CPU "
        "(best of 3), partly while it reads its scenarios"
    )
    print(
        "   (the lockstep keeps one core busy at a time, so on a quiet machine the wall time of "
        "a run\n   is close to the CPU time of host and child; x cpu is what a quiet machine "
        "shows)"
    )


if __name__ == "__main__":
    part_one()
    if "--worlds-only" not in sys.argv:
        part_two()
