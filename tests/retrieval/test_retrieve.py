"""Ranking a robot's interfaces for a capability."""

from __future__ import annotations

from collections.abc import Sequence
from functools import cache

import pytest

from skillwright.capability import load_capability
from skillwright.interfaces.inventory import Inventory
from skillwright.interfaces.load import load_inventory
from skillwright.retrieval.retrieve import rank_interfaces
from skillwright.spec import load_spec
from tests.conftest import SHIPPED_CAPABILITIES


@cache
def mr1() -> Inventory:
    return load_inventory(SHIPPED_CAPABILITIES / "recordings" / "mr1")


def ranked(stem: str, **kwargs: object) -> list[str]:
    capability = load_capability(SHIPPED_CAPABILITIES / f"{stem}.ttl").capability
    spec = load_spec(SHIPPED_CAPABILITIES / f"{stem}.spec.yaml")
    return [h.name for h in rank_interfaces(mr1(), capability, spec, **kwargs)]  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("stem", "needed"),
    [
        ("move-forward", {"/cmd_vel", "/odom"}),
        ("set-velocity", {"/cmd_vel", "/odom"}),
        ("get-distance-to-nearest-object", {"/scan"}),
        ("collision-avoidance", {"/scan", "/cmd_vel"}),
        ("navigate-to-point", {"/navigate_to_pose"}),
        ("move-to-point", {"/move_action"}),
    ],
)
def test_lexical_ranking_finds_the_obvious_interfaces(stem: str, needed: set[str]) -> None:
    assert needed <= set(ranked(stem))


def test_k_limits_the_hits_and_scores_descend() -> None:
    capability = load_capability(SHIPPED_CAPABILITIES / "rotate.ttl").capability
    hits = rank_interfaces(mr1(), capability, k=6)
    assert len(hits) == 6
    assert all(h.reason for h in hits)
    assert [h.dense for h in hits] == [None] * 6
    assert rank_interfaces(mr1(), capability, k=0) == []


def test_infrastructure_is_left_out_unless_asked_for() -> None:
    everything = ranked("set-velocity", k=500)
    assert "/rosout" not in everything
    assert "/controller_server/get_parameters" not in everything
    with_infrastructure = ranked("set-velocity", k=500, include_infrastructure=True)
    assert "/rosout" in with_infrastructure


def test_near_duplicates_do_not_crowd_out_other_needs() -> None:
    hits = ranked("set-velocity")
    assert hits.index("/odom") < 3
    assert not {"/cmd_vel", "/cmd_vel_nav"} <= set(hits[:2])


def test_an_embedder_is_mixed_in_when_given() -> None:
    capability = load_capability(SHIPPED_CAPABILITIES / "get-position.ttl").capability

    def fake_embed(texts: Sequence[str]) -> list[list[float]]:
        # a stand-in model that only knows whether a text mentions SLAM's pose topic
        return [
            [1.0, 0.0] if ("/pose " in t or i == 0) else [0.0, 1.0] for i, t in enumerate(texts)
        ]

    hits = rank_interfaces(mr1(), capability, embed=fake_embed)
    assert hits[0].name == "/pose"
    assert hits[0].dense == 1.0
