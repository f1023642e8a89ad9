"""A position in a filtered copy is not a position in the original."""

from __future__ import annotations

import math
import textwrap

import pytest

from skillwright.rules.finding import Finding
from skillwright.validation.positions import check_filtered_positions
from tests.validation.test_loops import skill_facts

HEAD = """
class Skill:
    def _on_scan(self, msg):
        self.scan_msg = msg

"""

NEAREST = """
def execute(self):
    scan = self.scan_msg
    valid_ranges = [r for r in scan.ranges if not math.isnan(r) and r >= scan.range_min]
    min_range = min(valid_ranges)
    min_index = valid_ranges.index(min_range)
    self.out_angle = scan.angle_min + min_index * scan.angle_increment
"""
"""MR-1 get-distance-to-nearest-object as the 1.5B model wrote it (ev41-ev54), shortened."""


def _positions(execute: str) -> list[Finding]:
    return check_filtered_positions(skill_facts(HEAD, execute))


def test_the_index_of_the_nearest_kept_reading_is_asked_of_the_scan() -> None:
    [finding] = _positions(NEAREST)
    assert finding.check == "positions"
    assert finding.severity == "error"
    assert finding.message.startswith(
        "`valid_ranges.index(min_range)` is a position in valid_ranges, the elements the "
        "filter kept, not in scan.ranges"
    )
    assert finding.replacement == "min_index = scan.ranges.index(min_range)"


def _bearing(execute: str, ranges: list[float]) -> float:
    """``out_angle`` after running ``execute`` on a scan with ``ranges``."""

    class Scan:
        angle_min = -math.pi
        angle_increment = math.pi / 2
        range_min = 0.1

    scan = Scan()
    scan.ranges = ranges  # type: ignore[attr-defined]
    namespace: dict[str, object] = {"math": math}
    exec(textwrap.dedent(execute), namespace)
    skill = type("Skill", (), {"scan_msg": scan, "out_angle": None})()
    namespace["execute"](skill)  # type: ignore[operator]
    return float(skill.out_angle)


def test_the_fix_gives_the_bearing_of_the_nearest_reading() -> None:
    # A dropped reading (NaN) before the nearest: the copy's position is one short.
    ranges = [math.nan, 3.0, 1.0, 2.0]
    [finding] = _positions(NEAREST)
    assert finding.replacement is not None
    fixed = NEAREST.replace("min_index = valid_ranges.index(min_range)", finding.replacement)
    assert _bearing(NEAREST, ranges) == pytest.approx(-math.pi / 2)
    assert _bearing(fixed, ranges) == pytest.approx(0.0)


@pytest.mark.parametrize(
    "execute",
    [
        # the position indexes the copy itself
        """
        def execute(self):
            valid = [r for r in self.scan_msg.ranges if r > 0.1]
            i = valid.index(min(valid))
            self.out_distance = valid[i]
        """,
        # the copy is not a filter of another list's elements
        """
        def execute(self):
            doubled = [2 * r for r in self.scan_msg.ranges if r > 0.1]
            i = doubled.index(min(doubled))
            self.out_angle = self.scan_msg.angle_min + i * self.scan_msg.angle_increment
        """,
        # positions kept along with the values
        """
        def execute(self):
            valid = [(i, r) for i, r in enumerate(self.scan_msg.ranges) if r > 0.1]
            i = valid.index(min(valid))
            self.out_angle = self.scan_msg.angle_min + i * self.scan_msg.angle_increment
        """,
        # the position in the original list
        """
        def execute(self):
            ranges = self.scan_msg.ranges
            i = ranges.index(min(r for r in ranges if r > 0.1))
            self.out_angle = self.scan_msg.angle_min + i * self.scan_msg.angle_increment
        """,
        # the name holds another list later on
        """
        def execute(self):
            valid = [r for r in self.scan_msg.ranges if r > 0.1]
            valid = list(self.scan_msg.ranges)
            i = valid.index(min(valid))
            self.out_angle = self.scan_msg.angle_min + i * self.scan_msg.angle_increment
        """,
    ],
)
def test_positions_that_are_right_are_left_alone(execute: str) -> None:
    assert _positions(execute) == []


def test_a_list_that_cannot_be_read_again_gets_the_message_without_a_fix() -> None:
    [finding] = _positions(
        """
        def execute(self):
            valid = [r for r in self._latest_scan().ranges if r > 0.1]
            self.out_angle = 0.1 * valid.index(min(valid))
        """
    )
    assert finding.replacement is None
    assert "Ask self._latest_scan().ranges for the position" in finding.message
