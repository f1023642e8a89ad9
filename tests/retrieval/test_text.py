"""Words for retrieval: names split the way an engineer reads them."""

from __future__ import annotations

import pytest

from skillwright.capability import load_capability
from skillwright.retrieval.lexical import BM25
from skillwright.retrieval.query import build_query
from skillwright.retrieval.text import split_words, stem, tokens
from skillwright.spec import load_spec
from tests.conftest import SHIPPED_CAPABILITIES


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("/cmd_vel", ["cmd", "vel"]),
        ("inLinearVelocity", ["in", "linear", "velocity"]),
        (
            "geometry_msgs/msg/PoseWithCovarianceStamped",
            ["geometry", "msgs", "msg", "pose", "with", "covariance", "stamped"],
        ),
        ("HTTPServer2Go", ["http", "server2", "go"]),
    ],
)
def test_split_words(text: str, words: list[str]) -> None:
    assert split_words(text) == words


@pytest.mark.parametrize(
    ("word", "stemmed"),
    [
        ("velocities", "velocity"),
        ("planning", "plan"),
        ("mapping", "map"),
        ("rolled", "roll"),
        ("pass", "pass"),
        ("maps", "map"),
        ("is", "is"),
    ],
)
def test_stem(word: str, stemmed: str) -> None:
    assert stem(word) == stemmed


def test_abbreviations_meet_their_long_forms() -> None:
    assert set(tokens("/cmd_vel")) >= {"command", "velocity"}
    assert set(tokens("/odom")) >= {"odometry", "position"}
    assert "msg" not in tokens("nav_msgs/msg/Odometry")


def test_bm25_prefers_the_document_with_rarer_matching_terms() -> None:
    docs = [{"velocity": 1.0, "command": 1.0}, {"velocity": 1.0, "odometry": 1.0}, {"map": 1.0}]
    scores = BM25(docs).scores({"command": 1.0, "velocity": 1.0})
    assert scores[0] > scores[1] > scores[2] == 0.0


def test_bm25_on_no_documents_scores_nothing() -> None:
    assert BM25([]).scores({"x": 1.0}) == []


def test_query_uses_names_units_and_the_spec() -> None:
    capability = load_capability(SHIPPED_CAPABILITIES / "move-forward.ttl").capability
    spec = load_spec(SHIPPED_CAPABILITIES / "move-forward.spec.yaml")
    query = build_query(capability, spec)
    assert query.terms["velocity"] > query.terms.get("odometry", 0) > 0
    assert "distance" in query.terms
    assert query.text.startswith("Move forward.")
    assert "velocity in m/s" in query.text
    assert spec.states["execute"] in query.text
    without_spec = build_query(capability)
    assert (
        "odometry" not in without_spec.terms
        or without_spec.terms["odometry"] < query.terms["odometry"]
    )
