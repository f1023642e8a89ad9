"""Every scanner of a split view a skill subscribes to must be read."""

from __future__ import annotations

import textwrap

from skillwright.rules.finding import Finding
from skillwright.validation.views import check_views
from tests.validation.test_facts import facts_of

HEADER = """\
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan


class Skill:
    def starting(self):
        self.scan_subscription = self.node.create_subscription(
            LaserScan, "/scan", self._on_scan, 10
        )
        self.scan2_subscription = self.node.create_subscription(
            LaserScan, "/scan2", self._on_scan2, 10
        )
        self.odom_subscription = self.node.create_subscription(
            Odometry, "/odom", self._on_odom, 10
        )
        self._wait_until(lambda: self.scan_msg is not None, 2.0, "scan_msg")
        self._wait_until(lambda: self.scan2_msg is not None, 2.0, "scan2_msg")

    def _on_scan(self, msg: LaserScan) -> None:
        self.scan_msg = msg

    def _on_scan2(self, msg: LaserScan) -> None:
        self.scan2_msg = msg

    def _on_odom(self, msg: Odometry) -> None:
        self.odom_msg = msg
"""


def _views(execute: str) -> list[Finding]:
    source = HEADER + textwrap.indent(textwrap.dedent(execute), "    ")
    return check_views(facts_of(source))


def test_a_skill_that_measures_with_one_scanner_of_two_is_told_to_read_the_other() -> None:
    # cap2skill get-distance-to-nearest-object after retrieval gave it /scan and /scan2
    [finding] = _views(
        """
        def execute(self):
            if self.scan2_msg is None:
                raise RuntimeError("no scan")
            distance, bearing = self._closest_reading(self.scan_msg)
            self.out_distance = distance
        """
    )
    assert finding.check == "views"
    assert finding.severity == "error"
    # where /scan is read: the other scanner's reading belongs beside it
    assert (finding.line, finding.column) == (32, 51)
    assert finding.message.startswith(
        "/scan2 and /scan are two scanners of one split view, each seeing a side the other "
        "does not, but only /scan is read here and nothing reads self.scan2_msg"
    )
    assert finding.message.endswith(
        "wait for self.scan2_msg too and use the nearer of the two closest readings"
    )
    assert finding.replacement is None  # no helper in this class to hand both scans to


HELPER = """
def _closest_reading(self, *scans):
    return min((r, 0.0) for scan in scans for r in scan.ranges)
"""


def test_the_helpers_call_with_one_scanner_gets_the_other_added_after_its_wait() -> None:
    [finding] = _views(
        HELPER
        + """
def execute(self):
    distance, bearing = self._closest_reading(self.scan_msg)
    self.out_distance = distance
"""
    )
    assert "pass it to the same call, self._closest_reading(self.scan_msg, self.scan2_msg)" in (
        finding.message
    )
    assert finding.replacement == (
        'self._wait_until(lambda: self.scan2_msg is not None, 2.0, "scan2_msg")\n'
        "distance, bearing = self._closest_reading(self.scan_msg, self.scan2_msg)"
    )


def test_a_statement_that_calls_the_helper_twice_gets_no_fix() -> None:
    [finding] = _views(
        HELPER
        + """
def execute(self):
    self.out_distance = self._closest_reading(self.scan_msg)[0] + self._closest_reading(
        self.scan_msg
    )[1]
"""
    )
    assert finding.replacement is None


def test_reading_both_scanners_is_fine() -> None:
    both = """
def execute(self):
    near = min(self._closest_reading(self.scan_msg), self._closest_reading(self.scan2_msg))
    self.out_distance = near[0]
"""
    assert _views(HELPER + both) == []


def test_an_unread_stream_that_is_no_part_of_a_read_ones_view_is_left_to_other_checks() -> None:
    # the odometry is read by nobody, and neither scanner is read: nothing here measures one
    # side of a view only
    assert _views("def execute(self):\n    self.out_distance = 1.0\n") == []
