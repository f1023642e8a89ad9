"""The comparison a wait tests, watched on every pass, and what its values say."""

from __future__ import annotations

import math
import sys
import textwrap
import types
from typing import Any

import pytest

from skillwright.validation.watch import LOGGER, Watch, diagnose, samples, watch_at, watched


def code(body: str) -> str:
    return textwrap.dedent(body).lstrip("\n")


def line_of(source: str, text: str) -> int:
    return next(n for n, line in enumerate(source.splitlines(), start=1) if text in line)


TURN = code(
    """
    import math
    import time


    class Skill:
        def execute(self):
            remaining = self.target - self.heading()
            deadline = time.monotonic() + 5.0
            while abs(remaining) > 0.01 and time.monotonic() < deadline:
                self.turn(remaining)
                time.sleep(0.05)
                remaining = self.target - self.heading()
    """
)


def test_the_condition_of_the_loop_around_the_wait_is_watched() -> None:
    watch = watch_at(TURN, line_of(TURN, "time.sleep"))

    assert watch == Watch(
        line=line_of(TURN, "while abs"),
        start=TURN.splitlines()[line_of(TURN, "while abs") - 1].index("abs"),
        end=TURN.splitlines()[line_of(TURN, "while abs") - 1].index(" and"),
        left="remaining",
        operator="gt",
        right="0.01",
        ends_when=False,
        absolute="left",
    )
    assert watch.text == "abs(remaining) > 0.01"  # the clock's half of the `and` is the limit


def test_an_if_that_breaks_out_of_an_endless_loop_is_the_condition() -> None:
    source = code(
        """
        class Skill:
            def execute(self):
                while True:
                    error = self.target - self.position()
                    if math.fabs(error) <= self.TOLERANCE:
                        break
                    time.sleep(0.05)
        """
    )
    watch = watch_at(source, line_of(source, "time.sleep"))

    assert watch is not None
    assert (watch.left, watch.operator, watch.right) == ("error", "le", "self.TOLERANCE")
    assert watch.ends_when is True
    assert watch.absolute == "left"


def test_a_helper_that_waits_on_a_callable_watches_the_lambda_it_was_given() -> None:
    source = code(
        """
        class Skill:
            def _wait_until(self, condition, timeout, what):
                deadline = time.monotonic() + timeout
                while not condition():
                    if time.monotonic() > deadline:
                        raise RuntimeError(f"no {what} within {timeout:g} s")
                    time.sleep(0.02)

            def execute(self):
                self._wait_until(lambda: self.odom.x - self.start >= 1.0, 5.0, "metre")
        """
    )
    raised = line_of(source, "raise RuntimeError")

    assert watch_at(source, raised) is None  # without the call, `condition` is unknown
    watch = watch_at(source, raised, (line_of(source, "self._wait_until(lambda"),))

    assert watch is not None
    assert watch.text == "self.odom.x - self.start >= 1.0"
    assert watch.ends_when is True
    assert watch.line == line_of(source, "self._wait_until(lambda")


@pytest.mark.parametrize(
    "loop",
    [
        "while time.monotonic() < deadline:",  # only a clock: nothing of the robot to watch
        "while self.busy:",
        "while a < b < c:",
        "while (self.position()\n           < 1.0):",  # spread over two lines
    ],
)
def test_a_wait_on_something_else_is_not_watched(loop: str) -> None:
    source = (
        "class Skill:\n    def execute(self):\n        deadline = 0\n"
        f"        {loop}\n            time.sleep(0.05)\n"
    )
    assert watch_at(source, line_of(source, "time.sleep")) is None


def test_the_watched_skill_keeps_its_lines_and_what_it_computes(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    watch = watch_at(TURN, line_of(TURN, "time.sleep"))
    assert watch is not None

    text = watched(TURN, watch)

    old_lines, new_lines = TURN.splitlines(), text.splitlines()
    changed = [n for n, (a, b) in enumerate(zip(old_lines, new_lines, strict=False), 1) if a != b]
    assert changed == [watch.line]
    assert '_skillwright_compare(remaining, "gt", 0.01, "left") and' in new_lines[watch.line - 1]
    logged: list[str] = []
    logging = types.ModuleType("rclpy.logging")
    logging.get_logger = lambda name: types.SimpleNamespace(  # type: ignore[attr-defined]
        info=lambda text: logged.append(f"{name}: {text}")
    )
    rclpy = types.ModuleType("rclpy")
    rclpy.logging = logging  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "rclpy", rclpy)
    monkeypatch.setitem(sys.modules, "rclpy.logging", logging)
    namespace: dict[str, Any] = {}
    exec(compile(text, "skill.py", "exec"), namespace)
    compare = namespace["_skillwright_compare"]

    assert compare(-0.5, "gt", 0.01, "left") is True
    assert compare(0.005, "gt", 0.01, "left") is False
    assert compare(0.5, "le", -0.2, "right") is False
    assert compare("a", "lt", "b", "") is True  # not numbers: compared, not logged
    assert logged == [f"{LOGGER}: -0.5 0.01", f"{LOGGER}: 0.005 0.01", f"{LOGGER}: 0.5 -0.2"]


def test_samples_are_the_watch_logs_of_the_state() -> None:
    events = [
        {"t": 0.1, "kind": "log", "state": "execute", "name": LOGGER, "text": "2.0 0.01"},
        {"t": 0.1, "kind": "log", "state": "execute", "name": "skill", "text": "1.0 2.0"},
        {"t": 0.2, "kind": "publish", "state": "execute"},
        {"t": 0.3, "kind": "log", "state": "completing", "name": LOGGER, "text": "1.0 0.01"},
        {"t": 0.4, "kind": "log", "state": "execute", "name": LOGGER, "text": "-0.5 0.01"},
    ]
    assert samples(events, "execute") == [(0.1, 2.0, 0.01), (0.4, -0.5, 0.01)]


ABS_ABOVE = Watch(1, 0, 1, "remaining", "gt", "0.01", ends_when=False, absolute="left")
"""``while abs(remaining) > 0.01:``"""


def passes(
    values: list[float], right: float = 0.01, dt: float = 0.05
) -> list[tuple[float, float, float]]:
    return [(round(i * dt, 3), v, right) for i, v in enumerate(values)]


def test_a_value_that_never_changes_is_said_not_to_follow_the_robot() -> None:
    said = diagnose(ABS_ABOVE, passes([2.0] * 40), moving=True)
    assert said is not None
    assert said.startswith("`remaining` was 2 on every one of its 40 passes (0.0 to 1.9 s)")
    assert "read the robot's state again on every pass" in said
    assert diagnose(ABS_ABOVE, passes([2.0] * 40), moving=False) is None  # nothing to follow


def test_a_turn_that_steps_over_its_band_is_said_to_step_over_its_goal() -> None:
    # 0.04 rad a pass towards 0, never within 0.01: past zero, on round to -pi, wrapped to
    # +pi (a jump, not a crossing), and past zero again
    values = [2.0 - 0.04 * i - 0.015 for i in range(50)]
    onwards = (values[-1] - 0.04 * i for i in range(1, 240))
    values += [v + 2 * math.pi if v < -math.pi else v for v in onwards]
    said = diagnose(ABS_ABOVE, passes(values), moving=True)

    assert said is not None
    assert said.startswith("`remaining` went past zero 2 times (first at 2.5 s) without ever")
    assert "changed by up to 0.04 from one reading to the next, more than the 0.02 wide" in said
    assert "end the wait once the goal is passed (`remaining` changed sign)" in said


def test_a_heading_read_from_a_slower_topic_still_shows_its_crossings() -> None:
    # the MR-1's map pose at 5 Hz, watched at 20 Hz: three passes in four see no change
    readings = [0.35 - 0.1 * (i // 4) for i in range(40)]
    said = diagnose(ABS_ABOVE, passes(readings), moving=True)
    assert said is not None
    assert said.startswith("`remaining` went past zero once (first at 0.8 s)")
    assert "changed by up to 0.1 from one reading to the next" in said


def test_a_swing_about_the_goal_is_a_crossing_on_every_pass() -> None:
    said = diagnose(ABS_ABOVE, passes([0.43, -0.43] * 20, right=0.05), moving=True)
    assert said is not None
    assert said.startswith("`remaining` went past zero 39 times (first at 0.1 s)")


def test_a_distance_that_came_close_and_grew_again_went_past_its_goal() -> None:
    distance = Watch(1, 0, 1, "math.hypot(dx, dy)", "gt", "0.05", ends_when=False)
    said = diagnose(
        distance, passes([1.0, 0.7, 0.4, 0.12, 0.2, 0.5, 0.8], 0.05, dt=0.5), moving=True
    )
    assert said == (
        "`math.hypot(dx, dy) > 0.05` came within 0.07 of holding at 1.5 s and then moved "
        "away from it again, so the robot went past its goal between two checks: also end "
        "the wait once the goal is passed, or slow down close to it"
    )


def test_a_value_that_moves_away_from_the_start_is_told_to_check_the_sign() -> None:
    covered = Watch(1, 0, 1, "x - start", "lt", "1.0", ends_when=False)  # while x - start < 1
    said = diagnose(covered, passes([0.0, -0.02, -0.1, -0.3, -0.6], right=1.0), moving=True)
    assert said == (
        "`x - start < 1.0` moved further from holding from the first pass on (`x - start` "
        "went from 0 to -0.6): check the direction (the sign) of what the skill commands"
    )


@pytest.mark.parametrize(
    "values",
    [
        [1.0, 0.8, 0.6, 0.4, 0.2],  # on its way: the wait was too short, not wrong
        [1.0, 0.5, 0.0, -0.5],  # it held at some pass
        [1.0, 0.5],  # too few passes to tell
        [1.0, math.nan, 0.5],
    ],
)
def test_values_that_say_nothing_clear_give_no_diagnosis(values: list[float]) -> None:
    plain = Watch(1, 0, 1, "remaining", "gt", "0.01", ends_when=False)
    assert diagnose(plain, passes(values), moving=True) is None
