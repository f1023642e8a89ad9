"""A bearing of the skeleton's closest reading must not be offset by angle_min again."""

from __future__ import annotations

import math
import textwrap
from types import SimpleNamespace

import pytest

from skillwright.generation.helpers import helper_lines
from skillwright.rules.finding import Finding
from skillwright.validation.bearings import check_bearings
from tests.validation.test_facts import facts_of

HEADER = "import math\n\n\nclass Skill:\n" + "\n".join(helper_lines("_closest_reading")) + "\n\n"


def _source(execute: str) -> str:
    return HEADER + textwrap.indent(textwrap.dedent(execute), "    ")


def _bearings(execute: str) -> list[Finding]:
    return check_bearings(facts_of(_source(execute)))


def test_the_evaluations_second_angle_min_is_an_error_with_the_bearing_as_the_fix() -> None:
    # MR-1 get-distance-to-nearest-object of the evaluation at 1840a63: off by pi
    execute = """\
    def execute(self):
        scan = self._closest_reading(self.scan_msg)
        self.out_angle = scan[1] - self.scan_msg.angle_min
        self.out_distance = scan[0]
    """
    [finding] = _bearings(execute)
    line = _source(execute).splitlines()[finding.line - 1]
    assert line.strip() == "self.out_angle = scan[1] - self.scan_msg.angle_min"
    assert finding.check == "bearings"
    assert "by self.scan_msg.angle_min again" in finding.message
    assert finding.replacement == "self.out_angle = scan[1]"


@pytest.mark.parametrize(
    ("statements", "replacement"),
    [
        (
            "distance, bearing = self._closest_reading(self.scan_msg)\n"
            "self.out_angle = math.degrees(self.scan_msg.angle_min + bearing)",
            "self.out_angle = math.degrees(bearing)",
        ),
        (
            "self.out_angle = self._closest_reading(self.scan_msg)[1] + self.scan_msg.angle_min",
            "self.out_angle = self._closest_reading(self.scan_msg)[1]",
        ),
    ],
)
def test_an_unpacked_or_direct_bearing_offset_again_is_an_error(
    statements: str, replacement: str
) -> None:
    execute = "def execute(self):\n" + textwrap.indent(statements, "    ") + "\n"
    [finding] = _bearings(execute)
    assert finding.replacement == replacement


@pytest.mark.parametrize(
    "statements",
    [
        # the bearing as it is, and the range with a margin
        "distance, bearing = self._closest_reading(self.scan_msg)\n"
        "self.out_angle = bearing\n"
        "self.out_distance = distance - 0.1",
        # angle_min with a beam angle the skill worked out itself
        "index = 3\nself.out_angle = self.scan_msg.angle_min + index * 0.01",
        # the range, not the bearing, next to angle_min
        "reading = self._closest_reading(self.scan_msg)\n"
        "self.out_angle = reading[0] + self.scan_msg.angle_min",
    ],
)
def test_a_bearing_used_as_it_is_is_fine(statements: str) -> None:
    assert _bearings("def execute(self):\n" + textwrap.indent(statements, "    ") + "\n") == []


def test_a_helper_that_does_not_count_from_angle_min_leaves_the_offset_to_the_skill() -> None:
    source = """\
import math


class Skill:
    def _closest_reading(self, scan):
        index = min(range(len(scan.ranges)), key=lambda i: scan.ranges[i])
        return scan.ranges[index], index * scan.angle_increment

    def execute(self):
        scan = self._closest_reading(self.scan_msg)
        self.out_angle = scan[1] + self.scan_msg.angle_min
"""
    assert check_bearings(facts_of(source)) == []


def test_the_fix_gives_the_bearing_the_simulator_measures() -> None:
    # a scan from -pi with its nearest reading straight ahead (beam 180 of 360)
    ranges = [5.0] * 360
    ranges[180] = 1.0
    scan = SimpleNamespace(
        ranges=ranges,
        range_min=0.05,
        range_max=12.0,
        angle_min=-math.pi,
        angle_increment=2 * math.pi / 360,
    )
    execute = """\
    def execute(self):
        scan = self._closest_reading(self.scan_msg)
        self.out_angle = scan[1] - self.scan_msg.angle_min
    """
    [finding] = _bearings(execute)
    assert finding.replacement is not None
    fixed = _source(execute).replace(
        "self.out_angle = scan[1] - self.scan_msg.angle_min", finding.replacement
    )
    for code, expected in ((_source(execute), math.pi), (fixed, 0.0)):
        namespace: dict[str, object] = {}
        exec(compile(code, "<skill>", "exec"), namespace)
        skill = namespace["Skill"]()  # type: ignore[operator]
        skill.scan_msg = scan
        skill.execute()
        assert skill.out_angle == pytest.approx(expected, abs=1e-9)
