"""The robot's pose must be asked of tf with the world frame as the target."""

from __future__ import annotations

import textwrap

import pytest

from skillwright.rules.finding import Finding
from skillwright.validation.frames import check_frames
from tests.validation.test_facts import facts_of


def _frames(execute: str) -> tuple[str, list[Finding]]:
    source = "class Skill:\n" + textwrap.indent(textwrap.dedent(execute), "    ")
    return source, check_frames(facts_of(source))


def test_the_evaluations_reversed_lookup_is_an_error_with_the_frames_swapped() -> None:
    # cap2skill get-position of the evaluation at 48572ae
    source, [finding] = _frames(
        """\
        def execute(self):
            self.out_position_x = self._transform("base_link", "map", 2.0).transform.translation.x
        """
    )
    assert finding.check == "frames"
    assert source.splitlines()[finding.line - 1].strip().startswith("self.out_position_x =")
    assert "self._transform('map', 'base_link', ...) for the robot's pose in map" in (
        finding.message
    )
    assert finding.replacement == (
        "self.out_position_x = self._transform('map', 'base_link', 2.0).transform.translation.x"
    )


def test_a_local_given_the_reversed_lookup_is_flagged_once_where_tf_is_asked() -> None:
    source, [finding] = _frames(
        """\
        def execute(self):
            pose = self._transform("base_footprint", "odom", 2.0)
            self.out_position_x = pose.transform.translation.x
            self.out_position_y = pose.transform.translation.y
        """
    )
    assert source.splitlines()[finding.line - 1].strip().startswith("pose = self._transform(")
    assert finding.replacement == "pose = self._transform('odom', 'base_footprint', 2.0)"


def test_frames_given_by_keyword_are_read_and_swapped_by_the_helpers_parameter_names() -> None:
    _, [finding] = _frames(
        """\
        def execute(self):
            pose = self._transform(source_frame="map", target_frame="base_link", timeout=2.0)
            self.out_position_x = pose.transform.translation.x
        """
    )
    assert finding.replacement == (
        "pose = self._transform(source_frame='base_link', target_frame='map', timeout=2.0)"
    )


@pytest.mark.parametrize(
    "execute",
    [
        # the robot's pose, asked the right way round
        'def execute(self):\n    t = self._transform("map", "base_link", 2.0)\n'
        "    self.out_position_x = t.transform.translation.x\n",
        # the reversed transform used for a goal in the robot's frame, not stored as a pose
        'def execute(self):\n    t = self._transform("base_link", "map", 2.0)\n'
        "    self.goal_x = t.transform.translation.x + self.in_x\n",
        # frames the check does not know (a sensor's)
        'def execute(self):\n    t = self._transform("laser_link", "map", 2.0)\n'
        "    self.out_position_x = t.transform.translation.x\n",
    ],
)
def test_a_pose_asked_the_right_way_or_not_stored_as_one_is_fine(execute: str) -> None:
    assert _frames(execute)[1] == []
