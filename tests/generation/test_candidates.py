"""Best-of-N: candidate skills of one first round, judged, the best repaired."""

from __future__ import annotations

from skillwright.generation.author import Authored, AuthorSettings, author_skill
from skillwright.generation.candidates import candidate_options
from skillwright.generation.model import Skeleton
from skillwright.rules.finding import Finding
from skillwright.rules.run import RUN_EXCEPTION
from tests.fixtures.scripted import MethodScript
from tests.generation.test_author import EXECUTE, GOOD, _Case

# An execute that logs through an attribute rclpy nodes do not have: a static error.
FORGETS_OUTPUT = EXECUTE.replace(
    "        self._stop_base()\n", '        self._stop_base()\n        self.logger.info("done")\n'
)


def _write(
    case: _Case,
    model: MethodScript,
    candidates: int,
    validate: object = None,
    attempts: int = 3,
) -> Authored:
    return author_skill(
        model,
        case.skeleton,
        case.load.capability,
        case.spec,
        case.items,
        validate or case.validate,  # type: ignore[arg-type]
        settings=AuthorSettings(attempts=attempts, max_tokens=400, candidates=candidates),
    )


def test_the_first_candidate_is_greedy_and_the_others_sample_with_their_own_seeds() -> None:
    options = candidate_options(4, max_tokens=99, temperature=0.7, seed=42, stop=("x",))
    assert [o.temperature for o in options] == [0.0, 0.7, 0.7, 0.7]
    assert [o.seed for o in options] == [42, 43, 44, 45]
    assert all(o.max_tokens == 99 and o.stop == ("x",) for o in options)


def test_every_state_is_asked_for_each_candidate_with_that_candidates_options() -> None:
    case = _Case()
    model = MethodScript(dict(GOOD))
    _write(case, model, 3)
    assert model.asked[:3] == ["starting"] * 3
    assert [o.temperature for o in model.options[:3]] == [0.0, 0.7, 0.7]
    assert len({o.seed for o in model.options[:3]}) == 3
    assert [a for a in model.asked if a == "execute"] == ["execute"] * 3


def test_the_candidate_the_checks_rank_best_wins_and_repair_starts_from_it() -> None:
    case = _Case()
    model = MethodScript({**GOOD, "execute": [FORGETS_OUTPUT, EXECUTE, FORGETS_OUTPUT]})
    authored = _write(case, model, 3)
    assert not [f for f in authored.findings if f.severity == "error"], authored.findings
    assert [v.won for v in authored.candidates] == [False, True, False]
    assert authored.candidates[0].errors
    assert authored.candidates[1].errors == 0
    assert authored.candidates[2].duplicate_of == 0
    # The winner passed: no repair was asked for.
    assert model.asked.count("execute") == 3
    chosen = [a for a in authored.attempts if a.target == "execute" and a.chosen]
    assert [a.candidate for a in chosen] == [1]
    assert "self.logger" not in authored.code


def test_a_file_equal_to_an_earlier_candidate_is_judged_once() -> None:
    case = _Case()
    judged: list[str] = []

    def validate(code: str, skeleton: Skeleton) -> list[Finding]:
        judged.append(code)
        return case.validate(code, skeleton)

    authored = _write(case, MethodScript(dict(GOOD)), 4, validate)
    assert [v.duplicate_of for v in authored.candidates] == [None, 0, 0, 0]
    assert [v.won for v in authored.candidates] == [True, False, False, False]
    # The greedy file, not again for its duplicates nor when repair starts from it; then the
    # final file, as without candidates.
    assert len(judged) == 2


def test_of_equal_candidates_the_greedy_one_wins() -> None:
    case = _Case()
    other = EXECUTE.replace("travelled = 0.0\n", "travelled = 0.0  # from the start\n")
    authored = _write(case, MethodScript({**GOOD, "execute": [EXECUTE, other]}), 2)
    assert [v.won for v in authored.candidates] == [True, False]
    assert authored.candidates[1].duplicate_of is None


def test_a_candidate_whose_run_fails_loses_to_one_that_ran_clean() -> None:
    case = _Case()
    raising = EXECUTE.replace(
        "        self._stop_base()\n", "        self._stop_base()\n        x = 1\n"
    )

    def validate(code: str, skeleton: Skeleton) -> list[Finding]:
        found = case.validate(code, skeleton)
        if "x = 1" in code:
            line = code.splitlines().index("        x = 1") + 1
            found.append(RUN_EXCEPTION.finding(line=line, message="the run raised"))
        return found

    model = MethodScript({**GOOD, "execute": [raising, EXECUTE]})
    authored = _write(case, model, 2, validate, attempts=1)
    first, second = authored.candidates
    assert first.errors == 0
    assert first.behaviour_errors == 1
    assert RUN_EXCEPTION.code in first.codes
    assert second.won
    assert second.behaviour_errors == 0
    assert "x = 1" not in authored.code


def test_one_candidate_is_todays_single_greedy_answer() -> None:
    case = _Case()
    model = MethodScript(dict(GOOD))
    authored = _write(case, model, 1)
    assert authored.candidates == []
    assert all(a.candidate is None for a in authored.attempts)
    assert model.asked == ["starting", "execute", "completing", "stopping", "resetting"]


def test_a_candidate_with_a_method_nobody_could_use_loses_to_one_that_wrote_it() -> None:
    # The skeleton's placeholder has fewer findings than a written execute with an error:
    # a candidate must not win by leaving its behaviour out.
    case = _Case()
    unusable = "        speed = (\n```"
    model = MethodScript({**GOOD, "execute": [FORGETS_OUTPUT, unusable]})
    authored = _write(case, model, 2, attempts=1)
    written, missing = authored.candidates
    assert missing.unusable == 1
    assert written.unusable == 0
    assert written.won
