"""The behaviour mutants stay applicable to the shipped skills (the catch rate is measured by
``bench/behaviour_catch_rate.py``; ``test_validate.py`` runs mutants of a test skill)."""

from __future__ import annotations

import ast

import pytest

from tests.sim.mutants import KINDS, MUTANTS, BehaviourMutant


@pytest.mark.parametrize("mutant", MUTANTS, ids=lambda m: m.id)
def test_every_mutant_applies_and_still_parses(mutant: BehaviourMutant) -> None:
    source = mutant.source()
    ast.parse(source)
    assert mutant.kind in KINDS
    assert mutant.capability.is_file()


def test_every_kind_of_mistake_is_planted_and_ids_are_unique() -> None:
    assert {m.kind for m in MUTANTS} == set(KINDS)
    assert len({m.id for m in MUTANTS}) == len(MUTANTS)


def test_a_mutant_is_caught_by_one_of_its_oracles_or_their_family() -> None:
    mutant = MUTANTS[0]
    assert mutant.caught_by({"truth:distanceCovered", "contact"})
    assert not mutant.caught_by({"contact"})
