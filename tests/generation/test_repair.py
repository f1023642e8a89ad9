"""Stage 7, repair: what the model is told of its answers' findings, the checks' own fixes,
the bounded rounds and the choice of each method's best answer.

The loop is driven here through a small writer of its own (a class of plain methods, a
finding per marked line), so what is pinned is the repair's part alone; the writer of
:mod:`skillwright.generation.author` drives it in ``test_author.py``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal

from skillwright.generation.assemble import Assembly
from skillwright.generation.model import Attempt, Skeleton
from skillwright.generation.repair import Judgement, _helper_hint, repair_skill
from skillwright.rules.api import UNDEFINED_NAME
from skillwright.rules.behaviour import MIXED_ANGLE_UNITS
from skillwright.rules.capability import OUTPUT_CONSTANT
from skillwright.rules.finding import Finding
from skillwright.rules.interfaces import ARGUMENT_TYPE_MISMATCH
from skillwright.rules.run import RUN_EXCEPTION


@dataclass
class _Method:
    name: str
    kind: Literal["state", "helper"] = "state"
    prefill: str = ""
    attempts: list[Attempt] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)


def _answer(name: str, number: int, body: str) -> Attempt:
    code = f"    def {name}(self):\n{body}"
    return Attempt(
        target=name,
        kind="state",
        number=number,
        temperature=0.0,
        seed=0,
        finish="stop",
        code=code,
        response=body,
        seconds=0.0,
    )


def _findings(code: str) -> list[Finding]:
    """An undefined name at each ``bad()`` (with ``good()`` as its fix where the line says
    ``fixable``), a run's exception at each ``crash()``."""
    out = []
    for line, text in enumerate(code.splitlines(), start=1):
        if "bad()" in text:
            fix = "good()" if "fixable" in text else None
            data = {"name": "bad"}
            out.append(
                UNDEFINED_NAME.finding(line=line, message="bad is not defined", data=data)
                if fix is None
                else UNDEFINED_NAME.finding(
                    line=line, message="bad is not defined", data=data, replacement=fix
                )
            )
        if "crash()" in text:
            out.append(RUN_EXCEPTION.finding(line=line, message="crash raised"))
    return out


class _Writer:
    """Methods of a class ``C``; ``answers`` are the model's next answers per method."""

    def __init__(self, first: Mapping[str, str], answers: Mapping[str, Sequence[str]]) -> None:
        self.targets = [_Method(name) for name in first]
        for target in self.targets:
            target.prefill = f"    def {target.name}(self):\n"
            target.attempts.append(_answer(target.name, 1, first[target.name]))
        self.answers = {name: list(texts) for name, texts in answers.items()}
        self.asked: list[tuple[str, list[str], str]] = []
        self.codes: list[list[str]] = []
        self.fixed: list[str] = []
        self.helpers_asked = 0

    def methods(self) -> list[_Method]:
        return self.targets

    @property
    def offered(self) -> list[str]:
        return []

    def judge(self, picked: Mapping[str, Attempt | None]) -> Judgement:
        code = "class C:\n" + "".join(
            a.code for a in picked.values() if a is not None and a.code is not None
        )
        skeleton = Skeleton(
            code="class C:\n    pass\n",
            class_name="C",
            skill_iri="urn:c",
            parameters=[],
            interfaces=[],
            unimplemented=[],
        )
        assembly = Assembly(code=code, written=(), missing=(), added=())
        return Judgement(skeleton, assembly, _findings(code), frozenset(picked))

    def ask_again(
        self, name: str, problems: Sequence[str], prefill: str, codes: Sequence[str] = ()
    ) -> Attempt:
        self.asked.append((name, list(problems), prefill))
        self.codes.append(list(codes))
        target = next(t for t in self.targets if t.name == name)
        body = self.answers[name].pop(0)
        attempt = _answer(name, len(target.attempts) + 1, body)
        target.attempts.append(attempt)
        return attempt

    def write_helpers(self) -> None:
        self.helpers_asked += 1

    def record_fix(self, name: str, attempt: Attempt) -> None:
        self.fixed.append(name)


def test_a_method_without_errors_is_not_asked_again_and_its_answer_is_chosen() -> None:
    writer = _Writer({"execute": "        good()\n"}, {})
    judgement = repair_skill(writer, attempts=3, run_repairs=1)
    assert writer.asked == []
    assert writer.fixed == []
    (attempt,) = writer.targets[0].attempts
    assert (attempt.chosen, attempt.errors, attempt.warnings) == (True, 0, 0)
    assert judgement.findings == []


def test_a_method_with_an_error_is_asked_again_from_the_statement_before_it() -> None:
    writer = _Writer(
        {"execute": "        good()\n        bad()\n"},
        {"execute": ["        good()\n        other()\n"]},
    )
    repair_skill(writer, attempts=3, run_repairs=1)
    ((name, problems, prefill),) = writer.asked
    assert name == "execute"
    assert problems == ["`bad()`: bad is not defined"]
    assert prefill == "    def execute(self):\n        good()\n"
    first, second = writer.targets[0].attempts
    assert (first.errors, second.errors) == (1, 0)
    assert second.chosen
    assert not first.chosen
    assert second.problems == problems
    assert second.problem_codes == [UNDEFINED_NAME.code]
    assert writer.helpers_asked == 1


def test_the_checks_fix_goes_in_without_the_model_and_records_the_rule() -> None:
    writer = _Writer({"execute": "        bad()  # fixable\n"}, {})
    repair_skill(writer, attempts=3, run_repairs=1)
    assert writer.asked == []
    assert writer.fixed == ["execute"]
    _, fixed = writer.targets[0].attempts
    assert fixed.finish == "fixed"
    assert fixed.code == "    def execute(self):\n        good()\n"
    assert [(f.code, f.safety, f.line) for f in fixed.fixes] == [(UNDEFINED_NAME.code, "unsafe", 3)]
    assert fixed.chosen
    assert fixed.errors == 0
    assert writer.targets[0].problems == ["`bad()  # fixable`: bad is not defined"]


def test_answers_are_bounded_and_the_best_one_is_chosen() -> None:
    writer = _Writer(
        {"execute": "        bad()\n        bad()  # again\n"},
        {"execute": ["        bad()\n", "        bad()\n        bad()\n        bad()\n"]},
    )
    repair_skill(writer, attempts=3, run_repairs=1)
    assert len(writer.asked) == 2  # attempts - 1 repairs; static errors get no run repair
    errors = [a.errors for a in writer.targets[0].attempts]
    assert errors == [2, 1, 3]
    assert [a.chosen for a in writer.targets[0].attempts] == [False, True, False]
    # every problem found so far is told again, in the order found
    assert writer.asked[1][1] == [
        "`bad()`: bad is not defined",
        "`bad()  # again`: bad is not defined",
    ]
    # each repair is asked with the rules of what it must fix, for a UI to say why it runs
    assert writer.codes[0] == ["SW311", "SW311"]


def test_only_a_runs_errors_left_get_their_own_repair_beyond_the_attempts() -> None:
    writer = _Writer(
        {"execute": "        crash()\n"},
        {"execute": ["        crash()\n", "        good()\n"]},
    )
    repair_skill(writer, attempts=2, run_repairs=1)
    assert len(writer.asked) == 2
    last = writer.targets[0].attempts[-1]
    assert (last.errors, last.behaviour_errors, last.chosen) == (0, 0, True)


def test_an_answer_only_the_run_faults_ranks_ahead_of_one_the_static_checks_stop() -> None:
    writer = _Writer(
        {"execute": "        crash()\n"},
        {"execute": ["        bad()\n"]},
    )
    repair_skill(writer, attempts=2, run_repairs=0)
    first, second = writer.targets[0].attempts
    # the second file did not pass the static checks, so its run is not known
    assert (first.behaviour_errors, second.behaviour_errors) == (1, None)
    assert first.chosen
    assert not second.chosen


def test_of_equally_good_answers_the_latest_is_chosen() -> None:
    writer = _Writer({"execute": "        bad()\n"}, {"execute": ["        bad()\n"]})
    repair_skill(writer, attempts=2, run_repairs=1)
    assert [(a.errors, a.chosen) for a in writer.targets[0].attempts] == [(1, False), (1, True)]


def test_an_output_finding_that_says_to_read_a_scan_by_hand_names_the_helper() -> None:
    finding = OUTPUT_CONSTANT.finding(
        line=1,
        message="output outObstacleAngle is only ever set to 0.0: ...; the skill can read it "
        "from self.scan_msg.angle_min + i * self.scan_msg.angle_increment (the direction of "
        "range i, in radians)",
        data={
            "output": "outObstacleAngle",
            "attribute": "out_obstacle_angle",
            "scans": ["scan_msg"],
        },
    )
    assert _helper_hint(finding, ["_wait_until", "_closest_reading"]) == (
        "; self._closest_reading(self.scan_msg) returns (distance, bearing) of the nearest "
        "valid reading"
    )
    assert _helper_hint(finding, ["_wait_until"]) == ""
    other = finding.model_copy(update={"code": MIXED_ANGLE_UNITS.code, "check": "units"})
    assert _helper_hint(other, ["_closest_reading"]) == ""


def test_a_navigation_goal_of_the_wrong_type_is_told_the_goal_helper() -> None:
    finding = ARGUMENT_TYPE_MISMATCH.finding(
        line=1,
        message="self._send_navigate_to_pose_goal takes a nav2_msgs/action/NavigateToPose.Goal, "
        "not a geometry_msgs/msg/Pose",
        data={
            "call": "self._send_navigate_to_pose_goal",
            "expected": "nav2_msgs/action/NavigateToPose.Goal",
            "given": "geometry_msgs/msg/Pose",
        },
    )
    assert _helper_hint(finding, ["_pose_goal", "_result_of"]) == (
        "; self._pose_goal(frame, x, y, yaw) returns one for a point and a heading"
    )
    assert _helper_hint(finding, ["_result_of"]) == ""
    other = finding.model_copy(
        update={
            "message": "self.pub.publish takes a geometry_msgs/msg/Twist, not a Pose",
            "data": {"expected": "geometry_msgs/msg/Twist", "given": "geometry_msgs/msg/Pose"},
        }
    )
    assert _helper_hint(other, ["_pose_goal"]) == ""
