"""What running a skill in the sandbox costs, against starting a bare Python process.

Measured in the same run:

* the floor: ``python -I -S -c pass`` (a process and an interpreter, nothing else);
* sandbox start-up: from starting the child to the skill's first state (namespaces,
  rlimits, audit hook, the stand-ins and pySkillUp imported, the skill loaded and made);
* a trivial skill's whole run (all states, the trace, the cleanup) through ``run_skill``;
* a motion skill (move_forward, 0.5 m in the kinematic world, normal and Stop runs):
  how much faster than real time the lockstep simulation runs.

The target is at most 1 s of overhead per run. Medians of several runs; CPU times come
from the child's resource use, so a busy machine shows in wall times only.

    python bench/bench_run.py
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RECORDING = ROOT / "capabilities" / "recordings" / "mr1"
SKILLS = ROOT / "capabilities" / "skills"
ROUNDS = 5

TRIVIAL = """
from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface


@skill(skill_interface=SkillInterface.REST, skill_iri="urn:a", module_iri="urn:b",
       capability_iri="urn:c", description="does nothing")
class Trivial(ROS2Skill):
    def __init__(self) -> None:
        super().__init__("trivial")

    @starting
    def starting(self) -> None:
        self.node.get_logger().info("starting")

    @execute
    def execute(self) -> None:
        self.node.get_logger().info("execute")

    @completing
    def completing(self) -> None:
        self.node.get_logger().info("completing")

    @resetting
    def resetting(self) -> None:
        self.node.get_logger().info("resetting")
"""


def _row(label: str, seconds: float, note: str = "") -> None:
    print(f"{label:46s} {seconds * 1000:8.1f} ms" + (f"  ({note})" if note else ""))


def _floor() -> float:
    started = time.perf_counter()
    subprocess.run([sys.executable, "-I", "-S", "-c", "pass"], check=True)
    return time.perf_counter() - started


def main() -> None:
    from skillwright.interfaces.load import load_inventory
    from skillwright.runtime.run import run_skill
    from skillwright.runtime.scenario import RunScenario, load_scenario

    inventory = load_inventory(RECORDING)
    quiet = RunScenario(settle=0.0, stop_run="never")
    run_skill(Path("trivial.py"), inventory, source=TRIVIAL, scenario=quiet)  # warm caches

    floors = [_floor() for _ in range(ROUNDS)]
    walls, startups, cpus = [], [], []
    for _ in range(ROUNDS):
        started = time.perf_counter()
        report = run_skill(Path("trivial.py"), inventory, source=TRIVIAL, scenario=quiet)
        walls.append(time.perf_counter() - started)
        episode = report.trace.episodes[0]
        assert report.passed, report.findings
        assert len(episode.states) == 4, episode.states
        startups.append(episode.startup_seconds)
        cpus.append(episode.resources.get("cpu_seconds", float("nan")))

    floor = statistics.median(floors)
    wall = statistics.median(walls)
    startup = statistics.median(startups)
    _row("bare interpreter start (python -I -S -c pass)", floor)
    _row("sandbox start-up to the first state", startup, f"{startup / floor:.1f}x the floor")
    _row("trivial skill, whole run", wall, f"{wall / floor:.1f}x the floor")
    _row("  child CPU per run", statistics.median(cpus))
    print(f"{'target <= 1 s of overhead per run':46s} {'met' if wall <= 1.0 else 'NOT met'}")

    skill = SKILLS / "move_forward.py"
    scenario = load_scenario(skill.with_suffix(".scenario.yaml"))
    motion_walls, simulated = [], []
    for _ in range(3):
        started = time.perf_counter()
        report = run_skill(skill, inventory, scenario=scenario)
        motion_walls.append(time.perf_counter() - started)
        assert report.passed, report.findings
        simulated.append(sum(e.virtual_seconds for e in report.trace.episodes))
    motion = statistics.median(motion_walls)
    virtual = statistics.median(simulated)
    _row(
        "move_forward 0.5 m, normal and Stop runs",
        motion,
        f"for {virtual:.2f} s simulated, {virtual / motion:.1f}x real time",
    )


if __name__ == "__main__":
    main()
