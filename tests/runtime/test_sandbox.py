"""The audit hook reports what a hostile skill tried at its line, and nothing is left behind.

That the host stays untouched, with the hook as shipped and switched off, is
``test_containment.py``'s to show.
"""

from __future__ import annotations

import os
import signal
from pathlib import Path

import pytest

from skillwright.interfaces.inventory import Inventory
from skillwright.runtime.run import run_skill
from skillwright.runtime.sandbox import ChildPool
from tests.conftest import REPO_ROOT
from tests.runtime.conftest import processes_with, quick

ADVERSARIAL = Path(__file__).parent / "adversarial"
CORPUS = sorted(ADVERSARIAL.glob("*.py"))
MARK = "# finding: "


def _expected(source: str) -> tuple[str, int]:
    for number, line in enumerate(source.splitlines(), start=1):
        if MARK in line:
            return line.split(MARK, 1)[1].strip(), number
    raise AssertionError("an adversarial skill marks its offending line with '# finding: <check>'")


@pytest.mark.parametrize("path", CORPUS, ids=lambda p: p.stem)
def test_hostile_skill_is_contained_and_reported_at_its_line(
    path: Path, mr1_inventory: Inventory
) -> None:
    source = path.read_text(encoding="utf-8")
    source = source.replace("{repo}", str(REPO_ROOT)).replace("{home}", str(Path.home()))
    check, line = _expected(source)
    home_before = sorted(p.name for p in Path.home().iterdir())

    report = run_skill(path, mr1_inventory, source=source, scenario=quick())

    assert any(f.check == check and f.line == line for f in report.findings), report.findings
    episode = report.trace.episodes[0]
    assert episode.isolation["sandbox"]
    assert processes_with(episode.isolation["sandbox"]) == []
    assert not Path(episode.isolation["folder"]).exists()
    assert not (REPO_ROOT / "pwned-by-skill.txt").exists()
    assert sorted(p.name for p in Path.home().iterdir()) == home_before


def test_an_endless_loop_is_interrupted_and_the_stop_path_still_runs(
    mr1_inventory: Inventory,
) -> None:
    path = ADVERSARIAL / "endless_loop.py"
    source = path.read_text(encoding="utf-8").replace(
        "    @execute",
        "    @stopping\n    def stopping(self) -> None:\n        self.count = 0\n\n    @execute",
    )

    report = run_skill(path, mr1_inventory, source=source, scenario=quick())

    states = [(s.name, s.outcome, s.detail) for s in report.trace.episodes[0].states]
    assert ("execute", "interrupted", "busy") in states
    assert ("stopping", "done", None) in states


FRESH = """
import rclpy
from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface


@skill(skill_interface=SkillInterface.REST, skill_iri="urn:a", module_iri="urn:b",
       capability_iri="urn:c", description="marks the stand-ins")
class Marker(ROS2Skill):
    def __init__(self) -> None:
        super().__init__("marker")

    @execute
    def execute(self) -> None:
        self.node.get_logger().info("marked" if hasattr(rclpy, "left_behind") else "fresh")
        rclpy.left_behind = True
"""


def test_children_of_one_fork_server_start_from_untouched_modules(
    mr1_inventory: Inventory, tmp_path: Path
) -> None:
    skill = tmp_path / "marker.py"
    skill.write_text(FRESH, encoding="utf-8")
    with ChildPool() as children:
        reports = [
            run_skill(skill, mr1_inventory, scenario=quick(), children=children) for _ in range(2)
        ]
        server = children.server
        assert server is not None
        marker = server.marker
        assert processes_with(marker) != []
    logs = [e["text"] for r in reports for e in r.trace.episodes[0].events if e["kind"] == "log"]
    assert logs == ["fresh", "fresh"]
    folders = {r.trace.episodes[0].isolation["folder"] for r in reports}
    assert len(folders) == 2, "each child has a folder of its own"
    assert processes_with(marker) == [], "closing the pool ends the fork server and its children"


def test_a_fork_server_killed_from_outside_is_replaced(
    mr1_inventory: Inventory, tmp_path: Path
) -> None:
    skill = tmp_path / "marker.py"
    skill.write_text(FRESH, encoding="utf-8")
    with ChildPool(ahead=False) as children:
        first = run_skill(skill, mr1_inventory, scenario=quick(), children=children)
        server = children.server
        assert server is not None
        os.killpg(server.process.pid, signal.SIGKILL)
        server.process.wait(timeout=10)
        second = run_skill(skill, mr1_inventory, scenario=quick(), children=children)
        assert children.server is not server
    assert first.findings == second.findings == []
    assert processes_with(server.marker) == []
