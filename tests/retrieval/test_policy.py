"""Which ranked interfaces the skill is given: pins, weak hits set aside, the stop command."""

from __future__ import annotations

from functools import cache

import pytest

from skillwright.interfaces.inventory import Inventory
from skillwright.interfaces.load import load_inventory
from skillwright.retrieval.policy import (
    Given,
    given_interfaces,
    set_aside_weak,
    stop_request,
    with_pins,
    with_stop_command,
)
from skillwright.retrieval.retrieve import Hit
from skillwright.spec.model import SkillSpec
from tests.conftest import SHIPPED_CAPABILITIES


@cache
def _inventory() -> Inventory:
    return load_inventory(SHIPPED_CAPABILITIES / "recordings" / "mr1")


def _hit(name: str, type_name: str, score: float) -> Hit:
    return Hit(
        name=name,
        kind="topic",
        type_name=type_name,
        score=score,
        dense=None,
        lexical=score,
        reason=f"ranked {name}",
    )


def _spec(**states: str) -> SkillSpec:
    return SkillSpec(
        name="s", description="d", skill_interface="REST", states={"execute": "Go.", **states}
    )


ODOM = _hit("/odom", "nav_msgs/msg/Odometry", 0.5)
SCAN = _hit("/scan", "sensor_msgs/msg/LaserScan", 0.3)
CMD_VEL = _hit("/cmd_vel", "geometry_msgs/msg/Twist", 0.01)


def test_pins_ranking_did_not_return_follow_the_ranked_hits_once_in_the_order_pinned() -> None:
    given = with_pins([ODOM, SCAN], _inventory(), ["/cmd_vel", "/scan", "/tf", "/cmd_vel"])
    assert [(g.name, g.pinned, g.hit is not None) for g in given] == [
        ("/odom", False, True),
        ("/scan", True, True),
        ("/cmd_vel", True, False),
        ("/tf", True, False),
    ]
    cmd_vel = given[2]
    assert (cmd_vel.kind, cmd_vel.type_name, cmd_vel.score) == (
        "topic",
        "geometry_msgs/msg/Twist",
        None,
    )
    assert cmd_vel.reason == "pinned by the user"
    assert given[0].reason == "ranked /odom"


@pytest.mark.parametrize(
    ("share", "aside"),
    [(0.1, ["/cmd_vel"]), (0.0, []), (0.7, ["/scan", "/cmd_vel"])],
)
def test_hits_under_the_share_of_the_best_score_are_set_aside(
    share: float, aside: list[str]
) -> None:
    given = set_aside_weak(with_pins([ODOM, SCAN, CMD_VEL], _inventory(), []), share)
    assert [g.name for g in given] == ["/odom", "/scan", "/cmd_vel"]
    assert [g.name for g in given if g.set_aside] == aside


def test_a_pinned_hit_or_a_pin_without_a_score_is_never_set_aside() -> None:
    given = set_aside_weak(with_pins([ODOM, CMD_VEL], _inventory(), ["/cmd_vel", "/tf"]), 0.5)
    assert [(g.name, g.set_aside) for g in given] == [
        ("/odom", False),
        ("/cmd_vel", False),
        ("/tf", False),
    ]


def test_the_set_aside_compares_the_scores_as_recorded() -> None:
    # 0.099996 is recorded as 0.1, which is not under 0.1 of a best score of 1.0
    close = _hit("/scan", "sensor_msgs/msg/LaserScan", 0.099996)
    given = set_aside_weak(with_pins([_hit("/odom", "x/msg/Y", 1.0), close], _inventory(), []), 0.1)
    assert given[1].score == 0.1
    assert not given[1].set_aside


@pytest.mark.parametrize(
    ("sentence", "asks"),
    [
        ("Set the velocity of the robot to zero in all directions.", True),
        ("Publish a zero velocity command so the base stops.", True),
        ("Stop the base and log where it stood.", True),
        ("Cancel the arm's trajectory and stop the manipulator.", False),
        ("Log the velocity the base reached.", False),
    ],
)
def test_a_velocity_command_set_aside_comes_back_when_a_state_stops_the_base(
    sentence: str, asks: bool
) -> None:
    given = [
        Given("/odom", "topic", "nav_msgs/msg/Odometry", ODOM, "r"),
        Given("/cmd_vel", "topic", "geometry_msgs/msg/Twist", CMD_VEL, "r", set_aside=True),
    ]
    kept = with_stop_command(given, _inventory(), _spec(stopping=sentence))
    assert len(kept) == 2
    assert kept[1].set_aside is not asks
    assert ("added: stopping asks to stop the base" in kept[1].reason) is asks
    assert kept[1].reason.startswith("r")


def test_the_stop_request_names_the_state_and_its_sentence() -> None:
    spec = _spec(stopping="Cancel the goal. Then publish a zero velocity command; log it.")
    assert stop_request(spec) == ("stopping", "Then publish a zero velocity command;")
    assert stop_request(_spec(stopping="Cancel the goal.")) is None


def test_the_velocity_command_is_added_when_ranking_did_not_return_it() -> None:
    spec = _spec(stopping="Publish a zero velocity command so the base stops.")
    kept = with_stop_command(with_pins([ODOM, SCAN], _inventory(), []), _inventory(), spec)
    assert [g.name for g in kept] == ["/odom", "/scan", "/cmd_vel"]
    added = kept[-1]
    assert (added.type_name, added.hit, added.score, added.pinned, added.set_aside) == (
        "geometry_msgs/msg/Twist",
        None,
        None,
        False,
        False,
    )
    assert added.reason == (
        "added: stopping asks to stop the base ('Publish a zero velocity command so the base "
        "stops.'), by its velocity command"
    )


def test_no_velocity_command_is_added_when_dropped_or_one_is_given() -> None:
    spec = _spec(stopping="Stop the base.")
    hits = with_pins([ODOM, SCAN], _inventory(), [])
    assert with_stop_command(hits, _inventory(), spec, dropped={"/cmd_vel"}) == hits
    twist = _hit("/cmd_vel_nav", "geometry_msgs/msg/Twist", 0.2)
    given = with_pins([ODOM, twist], _inventory(), [])
    assert with_stop_command(given, _inventory(), spec) == given


def test_given_interfaces_pins_then_sets_aside_then_adds_the_stop_command() -> None:
    spec = _spec(stopping="Stop the base.")
    given = given_interfaces(
        [ODOM, SCAN, CMD_VEL], _inventory(), spec, pinned=["/tf"], min_share=0.1
    )
    assert [(g.name, g.pinned, g.set_aside) for g in given] == [
        ("/odom", False, False),
        ("/scan", False, False),
        ("/cmd_vel", False, False),
        ("/tf", True, False),
    ]
    assert given[2].reason.startswith("ranked /cmd_vel; added: stopping asks to stop the base")
