"""Which topic is a base's velocity command."""

from __future__ import annotations

import pytest

from skillwright.interfaces.roles import command_topic


@pytest.mark.parametrize(
    ("names", "chosen"),
    [
        (["/cmd_vel_nav", "/cmd_vel"], "/cmd_vel"),
        (["/panther/cmd_vel", "/panther/cmd_vel_nav"], "/panther/cmd_vel"),
        (["/stretch/cmd_vel", "/robot/cmd_vel"], "/robot/cmd_vel"),  # equals: the shorter
        (["/controller/cmd_vel_raw", "/cmd_vel_nav"], "/controller/cmd_vel_raw"),
        (["/base/twist_cmd"], "/base/twist_cmd"),
        (["/cmd_vel_nav"], "/cmd_vel_nav"),  # only Nav2's: still the one there is
        (["/turtle1/velocity", "/key_twist"], None),
        ([], None),
    ],
)
def test_the_command_is_the_twist_named_like_one_cmd_vel_first(
    names: list[str], chosen: str | None
) -> None:
    assert command_topic(names) == chosen
