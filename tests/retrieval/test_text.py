"""Words for retrieval: names split the way an engineer reads them."""

from __future__ import annotations

import pytest

from skillwright.capability import load_capability
from skillwright.retrieval.lexical import BM25
from skillwright.retrieval.query import build_query
from skillwright.retrieval.text import split_words, stem, tokens, weighted_tokens
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
        ("speed", "speed"),
        ("string", "string"),
        ("published", "publish"),
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


def test_expansions_weigh_less_than_the_words_written_out() -> None:
    weights = dict(weighted_tokens("/odom"))
    assert weights["odom"] == 1.0
    assert weights["odometry"] == 0.5
    assert weights["position"] == 0.25


def test_query_texts_drop_framework_chatter_and_read_verbs_as_intent() -> None:
    terms = [
        t
        for t, _ in weighted_tokens("Prepare the system to print the current velocity", query=True)
    ]
    assert terms == ["measure", "velocity"]
    stop = [t for t, _ in weighted_tokens("Set the velocity to zero", query=True)]
    assert stop[:2] == ["command", "velocity"]
    assert "stop" in stop
    # interface documents keep every word
    assert "print" in tokens("Prepare the system to print the current velocity")


def test_the_query_has_a_facet_per_parameter_type_and_per_state_sentence() -> None:
    capability = load_capability(SHIPPED_CAPABILITIES / "move-forward.ttl").capability
    spec = load_spec(SHIPPED_CAPABILITIES / "move-forward.spec.yaml")
    query = build_query(capability, spec)
    keys = [f.key for f in query.facets]
    assert keys[0] == "capability"
    assert query.facets[0].text.startswith("Move forward.")
    # inDistance and outDistance share a type description: one facet
    [distance] = [f for f in query.facets if f.key == "parameter:distance"]
    assert distance.label == "inDistance/outDistance"
    assert "distance in m" in distance.text
    sentences = [f for f in query.facets if f.key.startswith("state:execute")]
    assert len(sentences) > 1
    assert " ".join(f.text for f in sentences) == " ".join(spec.states["execute"].split())
    assert sum(f.weight for f in sentences) > query.facets[0].weight
    assert query.terms["velocity"] > query.terms.get("odometry", 0) > 0


def test_without_a_spec_the_query_has_no_state_facets() -> None:
    capability = load_capability(SHIPPED_CAPABILITIES / "move-forward.ttl").capability
    query = build_query(capability)
    assert not [f for f in query.facets if f.key.startswith("state:")]
    assert query.text.startswith("Move forward.")
