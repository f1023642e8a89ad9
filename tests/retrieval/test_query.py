"""The retrieval query: facets of evidence with their terms and intent."""

from __future__ import annotations

import pytest

from skillwright.retrieval.query import intent_of


@pytest.mark.parametrize(
    ("sentence", "intent"),
    [
        ("Set the velocity of the robot to zero.", "command"),
        ("Cancel the navigation.", "command"),
        ("Print the current velocity of the robot.", "measure"),
        ("Retrieve the current position of the robot and store it as output.", "measure"),
        ("If the goal is not possible, fire transition abort.", None),
        ("", None),
    ],
)
def test_a_sentence_sends_or_reads_by_its_first_verb(sentence: str, intent: str | None) -> None:
    assert intent_of(sentence) == intent
