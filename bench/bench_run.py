"""What running a skill in the sandbox costs, against starting a bare Python process.

Measured in the same run:

* the floor: ``python -I -S -c pass`` (a process and an interpreter, nothing else);
* sandbox start-up: from starting the child to the skill's first state (its own
  confinement, rlimits, audit hook, the skill loaded and made);
* a trivial skill's whole run (a fork server started in bubblewrap's namespaces, the
  child, all states, the trace, the cleanup) through ``run_skill``, against the same run
  without the kernel sandbox (``--unsafe-no-isolation``: a plain fork server);
* the nine MR-1 skills (``capabilities/skills``) in their run scenarios (the kinematic
  world), normal and Stop runs, one ``ChildPool`` for all: wall time and how much faster
  than real time the lockstep simulation runs, in the kernel sandbox against without it.

The targets: at most 1 s of overhead per run, a trivial run in the sandbox at most 1.5x
what it costs without, the nine skills at least 20x real time. Medians of several runs;
CPU times come from the child's resource use, so a busy machine shows in wall times only.

    python bench/bench_run.py
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

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
    floors = [_floor() for _ in range(ROUNDS)]
    floor = statistics.median(floors)
    _row("bare interpreter start (python -I -S -c pass)", floor)
    trivial: dict[bool, float] = {}
    for isolated in (True, False):
        # warm caches (the sandbox's library list, the stand-ins' bytecode)
        run_skill(Path("trivial.py"), inventory, source=TRIVIAL, scenario=quiet, isolated=isolated)
        walls, startups, cpus = [], [], []
        for _ in range(ROUNDS):
            started = time.perf_counter()
            report = run_skill(
                Path("trivial.py"), inventory, source=TRIVIAL, scenario=quiet, isolated=isolated
            )
            walls.append(time.perf_counter() - started)
            episode = report.trace.episodes[0]
            assert report.passed, report.findings
            assert len(episode.states) == 4, episode.states
            startups.append(episode.startup_seconds)
            cpus.append(episode.resources.get("cpu_seconds", float("nan")))
        label = "in the kernel sandbox" if isolated else "without it (--unsafe-no-isolation)"
        print(label)
        wall = trivial[isolated] = statistics.median(walls)
        startup = statistics.median(startups)
        _row("  sandbox start-up to the first state", startup, f"{startup / floor:.1f}x the floor")
        _row("  trivial skill, whole run", wall, f"{wall / floor:.1f}x the floor")
        _row("  child CPU per run", statistics.median(cpus))
    _layers()
    print(
        f"{'the kernel sandbox costs a trivial run':46s} {trivial[True] / trivial[False]:8.2f}x "
        "(target <= 1.5x; <= 1 s of overhead per run: "
        f"{'met' if trivial[True] <= 1.0 else 'NOT met'})"
    )

    print(
        "\nthe nine MR-1 skills in their run scenarios (all runs of each, one pool for all, each "
        "child\nbooted while the previous run goes on): in the kernel sandbox against without it"
    )
    print(
        f"{'skill':26s} {'virtual':>8s} {'sandbox':>8s} {'x real':>7s} {'without':>10s} "
        f"{'x real':>7s} {'ratio':>6s}"
    )
    totals = [0.0, 0.0, 0.0]
    runs = {
        isolated: _run_all(inventory, load_scenario, run_skill, isolated)
        for isolated in (False, True)
    }
    for name, (virtual, wall) in runs[True].items():
        _, old_wall = runs[False][name]
        print(
            f"{name:26s} {virtual:7.2f}s {wall:7.2f}s {virtual / wall:6.1f}x {old_wall:9.2f}s "
            f"{virtual / old_wall:6.1f}x {wall / old_wall:5.2f}x"
        )
        totals = [totals[0] + virtual, totals[1] + wall, totals[2] + old_wall]
    virtual, wall, old_wall = totals
    print(
        f"{'all':26s} {virtual:7.2f}s {wall:7.2f}s {virtual / wall:6.1f}x {old_wall:9.2f}s "
        f"{virtual / old_wall:6.1f}x {wall / old_wall:5.2f}x (target >= 20x real time)"
    )


def _fork_server_start(isolated: bool) -> float:
    """Wall seconds from starting a fork server to its first word."""
    from skillwright.runtime.sandbox import ForkServer

    started = time.perf_counter()
    server = ForkServer(isolated=isolated)
    server.wait_ready()
    wall = time.perf_counter() - started
    server.close()
    return wall


def _confinement() -> float:
    """Seconds a just-forked process takes to confine itself (Landlock and the three
    seccomp programs, as a child does without bubblewrap's base already loaded)."""
    import json
    import os

    from skillwright._core import confine_child
    from skillwright.runtime.isolation import layout

    readable = layout().readable()
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:
        started = time.perf_counter()
        confine_child(os.getpid(), readable, ["/dev/null"], True)
        os.write(write_end, json.dumps(time.perf_counter() - started).encode())
        os._exit(0)
    os.close(write_end)
    seconds = float(json.loads(os.read(read_end, 64)))
    os.close(read_end)
    os.waitpid(pid, 0)
    return seconds


def _layers() -> None:
    """What each layer of the sandbox costs: bubblewrap (namespaces, the read-only root,
    the user map, the base seccomp programs) once per fork server, and a child's own
    confinement once per run."""
    with_bwrap = statistics.median(_fork_server_start(True) for _ in range(ROUNDS))
    without = statistics.median(_fork_server_start(False) for _ in range(ROUNDS))
    _row("fork server start in bubblewrap (once a pool)", with_bwrap)
    _row("  without it", without, f"bubblewrap adds {(with_bwrap - without) * 1000:.1f} ms")
    _row(
        "a child's Landlock + seccomp (once a run)",
        statistics.median(_confinement() for _ in range(ROUNDS)),
    )


def _run_all(
    inventory: Any, load_scenario: Any, run_skill: Any, isolated: bool
) -> dict[str, tuple[float, float]]:
    """Skill -> (virtual s, wall s) of its whole run, each skill in its shipped scenario."""
    from skillwright.runtime.sandbox import ChildPool

    rows = {}
    with ChildPool(isolated=isolated) as children:
        for skill in sorted(SKILLS.glob("*.py")):
            scenario = load_scenario(skill.with_suffix(".scenario.yaml"))
            started = time.perf_counter()
            report = run_skill(skill, inventory, scenario=scenario, children=children)
            wall = time.perf_counter() - started
            assert report.passed, (skill.name, report.findings)
            rows[skill.stem] = (sum(e.virtual_seconds for e in report.trace.episodes), wall)
    return rows


if __name__ == "__main__":
    main()
