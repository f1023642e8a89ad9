"""Best-of-N: several candidate skills from one batched first round, judged by behaviour.

A small model decoding greedily writes the same mistake again when it is asked again; a
sampled answer to the same request often does not make it. So the first round may ask
every method for ``count`` answers at once (:func:`candidate_options`: the greedy one, and
sampled ones with their own temperature and seed; a local model decodes them in one batch,
:mod:`skillwright.llm.batch`). Candidate ``k`` is the file of every method's ``k``-th answer
(a helper asked for once serves every candidate). Each distinct file is judged with the
same stages as any other (the static checks, the sandboxed run, the simulation); a file
equal to an earlier one, character for character, is recorded as its duplicate and not
judged again. The winner is the candidate with the fewest errors the static checks find,
then the fewest the run and the simulation find (a file that ran beats one that did not),
then the fewest warnings, then the lowest index (the greedy one first): the same order in
which :mod:`~skillwright.generation.repair` ranks single answers. Repair then starts from
the winner's answers; every candidate and its verdict is kept for the record.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from typing import Protocol

from skillwright.generation.assemble import Assembly
from skillwright.generation.model import Attempt, CandidateVerdict, Skeleton
from skillwright.generation.repair import Judgement, Method, Writer, is_later, judged
from skillwright.llm.base import GenerationOptions

__all__ = ["CandidateWriter", "candidate_options", "choose_candidate", "file_score"]

_UNJUDGED = 10**6


class CandidateWriter(Writer, Protocol):
    """A writer whose first round holds several candidates."""

    def assembled(self, picked: Mapping[str, Attempt | None]) -> tuple[Skeleton, Assembly]:
        """The file of the ``picked`` answers (by method), not judged."""

    def adopt(self, index: int) -> None:
        """Makes candidate ``index``'s answers each method's latest (repair goes on from
        them)."""


def candidate_options(
    count: int,
    *,
    max_tokens: int,
    temperature: float,
    seed: int,
    stop: Sequence[str],
) -> list[GenerationOptions]:
    """The options of ``count`` sequences of one request: the first greedy (the answer a
    single first round gives, so best-of-N never loses it), the others sampled at
    ``temperature`` with seeds ``seed + 1``, ``seed + 2`` ... so that they differ from it and
    from each other, and a rerun gives the same candidates."""
    return [
        GenerationOptions(
            max_tokens=max_tokens,
            temperature=0.0 if index == 0 else temperature,
            seed=seed + index,
            stop=tuple(stop),
        )
        for index in range(count)
    ]


def file_score(judgement: Judgement, unusable: int = 0) -> tuple[int, int, int, int]:
    """Lower is better: the methods whose answer could not be used (the file holds the
    skeleton's placeholder there, whose few findings say nothing of a behaviour nobody
    wrote), then the static checks' errors, then the run's and the simulation's (counted only
    where the file got that far), then warnings."""
    errors = [f for f in judgement.findings if f.severity == "error"]
    static = [f for f in errors if not is_later(f)]
    later = _UNJUDGED if static else len(errors) - len(static)
    warnings = len(judgement.findings) - len(errors)
    return (unusable, len(static), later, warnings)


def _answer_of(method: Method, index: int) -> Attempt | None:
    """Method's answer in candidate ``index``: its ``index``-th sampled answer, else the one
    every candidate shares (a helper asked for once), else the greedy candidate's."""
    own = [a for a in method.attempts if a.candidate == index]
    if own:
        return own[0]
    shared = [a for a in method.attempts if a.candidate is None]
    if shared:
        return shared[0]
    greedy = [a for a in method.attempts if a.candidate == 0]
    return greedy[0] if greedy else None


def _picked(picked: Mapping[str, Attempt | None], method: Method) -> Attempt | None:
    return picked[method.name]


def choose_candidate(
    writer: CandidateWriter, temperatures: Sequence[tuple[float, int]]
) -> tuple[Judgement, list[CandidateVerdict]]:
    """Judges every distinct candidate file (``temperatures``: each candidate's temperature
    and seed, by index), makes the best one's answers the writer's latest and returns its
    judgement with every candidate's verdict."""
    verdicts: list[CandidateVerdict] = []
    by_code: dict[str, int] = {}
    scores: dict[int, tuple[int, int, int, int]] = {}
    last: tuple[int, Judgement] | None = None
    for index, (temperature, seed) in enumerate(temperatures):
        picked = {method.name: _answer_of(method, index) for method in writer.methods()}
        code = writer.assembled(picked)[1].code
        earlier = by_code.get(code)
        if earlier is not None:
            verdicts.append(
                verdicts[earlier].model_copy(
                    update={
                        "index": index,
                        "temperature": temperature,
                        "seed": seed,
                        "duplicate_of": earlier,
                    }
                )
            )
            continue
        by_code[code] = index
        judgement = judged(writer, functools.partial(_picked, picked))
        score = file_score(judgement, sum(a is None or a.code is None for a in picked.values()))
        scores[index] = score
        last = (index, judgement)
        errors = [f for f in judgement.findings if f.severity == "error"]
        verdicts.append(
            CandidateVerdict(
                index=index,
                temperature=temperature,
                seed=seed,
                unusable=score[0],
                errors=score[1],
                behaviour_errors=None if score[2] == _UNJUDGED else score[2],
                warnings=score[3],
                codes=sorted({f.code for f in errors}),
            )
        )
    if last is None:
        raise ValueError("no candidate to choose from")
    winner = min(scores, key=lambda k: (scores[k], k))
    verdicts[winner] = verdicts[winner].model_copy(update={"won": True})
    writer.adopt(winner)
    if last[0] == winner:
        return last[1], verdicts
    # Judging again sets the winner's answers' own scores (a helper shared by every
    # candidate was last scored in another one's file).
    return judged(writer, lambda method: _answer_of(method, winner)), verdicts
