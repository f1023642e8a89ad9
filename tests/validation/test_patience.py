"""A wait of the skill's own helpers given no time at all."""

from __future__ import annotations

import pytest

from skillwright.validation.patience import check_zero_timeouts
from tests.validation.test_loops import HEAD, skill_facts

HELPERS = """    def _transform(self, target_frame, source_frame, timeout):
        return None

    def _drive(self, seconds):
        return None

"""


def _zero(execute: str) -> list:
    return check_zero_timeouts(skill_facts(HEAD + HELPERS, execute))


def test_a_transform_looked_up_with_no_time_gets_two_seconds() -> None:
    # the MR-1 navigate-to-point of the demo at 3ec2321: the 0.0 was meant as tf's stamp
    [finding] = _zero(
        """
        def execute(self):
            pose = self._transform("map", "base_link", 0.0)
        """
    )
    assert (finding.check, finding.severity) == ("waits", "error")
    assert "gives _transform() a timeout of 0.0 s" in finding.message
    assert finding.replacement == "pose = self._transform('map', 'base_link', 2.0)"


@pytest.mark.parametrize(
    "call",
    [
        "self._wait_until(lambda: self.odom_msg is not None, timeout=0, what='odometry')",
        "self._wait_until(lambda: self.odom_msg is not None, -1.0, 'odometry')",
    ],
)
def test_no_time_by_keyword_or_below_zero_is_found(call: str) -> None:
    [finding] = _zero(f"\n        def execute(self):\n            {call}\n        ")
    assert "2.0" in (finding.replacement or "")


@pytest.mark.parametrize(
    "call",
    [
        "self._transform('map', 'base_link', 2.0)",
        "self._transform('map', 'base_link', self.in_time)",
        "self._drive(0.0)",  # a duration, not a wait's timeout
    ],
)
def test_time_given_or_no_timeout_is_left_alone(call: str) -> None:
    assert _zero(f"\n        def execute(self):\n            {call}\n        ") == []
