"""Finding the number a wait that gave up takes its seconds from, and changing it."""

from __future__ import annotations

import ast

import pytest

from skillwright.validation.timeouts import fixes, rounded_up, timeout_site, with_seconds

HELPERS = """import time


class Skill:
    def _wait_until(self, condition, timeout: float, what: str) -> None:
        deadline = time.monotonic() + timeout
        while not condition():
            if time.monotonic() > deadline:
                raise RuntimeError(f"no {what} within {timeout:g} s")
            time.sleep(0.02)

    def _result_of(self, future, timeout: float, what: str):
        self._wait_until(future.done, timeout, what)
        return future.result()

"""


def line_of(code: str, text: str, nth: int = 0) -> int:
    return [i for i, line in enumerate(code.splitlines(), 1) if text in line][nth]


def test_a_deadline_taken_before_the_loop_is_where_the_seconds_come_from() -> None:
    code = HELPERS + (
        "    def execute(self):\n"
        "        if not self.client.wait_for_server(timeout_sec=5.0):\n"
        "            raise RuntimeError('no server')\n"
        "        deadline = time.monotonic() + 5.0\n"
        "        while not self.done:\n"
        "            if time.monotonic() > deadline:\n"
        "                raise RuntimeError('the navigation was not completed within 5 s')\n"
        "            time.sleep(0.5)\n"
    )
    raised = line_of(code, "not completed within")
    site = timeout_site(code, raised, (), 5.0)
    assert site is not None
    # the server wait's 5.0 is another timeout: it stays
    assert [n[0] for n in site.numbers] == [line_of(code, "deadline = time", 1)]
    changed = with_seconds(code, site, 50.0)
    assert "deadline = time.monotonic() + 50.0" in changed
    assert "not completed within 50 s')" in changed
    assert "wait_for_server(timeout_sec=5.0)" in changed
    assert fixes(code, site, 50.0) == [
        (line_of(code, "deadline = time", 1), 9, "deadline = time.monotonic() + 50.0"),
        (raised, 17, "raise RuntimeError('the navigation was not completed within 50 s')"),
    ]


def test_a_guard_that_holds_the_number_is_changed_whole_with_its_raise() -> None:
    code = HELPERS + (
        "    def execute(self):\n"
        "        start = time.monotonic()\n"
        "        while self.turning:\n"
        "            if time.monotonic() - start > 2:  # the turn's budget\n"
        "                raise RuntimeError('not turned within 2 seconds')\n"
        "            time.sleep(0.05)\n"
    )
    site = timeout_site(code, line_of(code, "not turned"), (), 2.0)
    assert site is not None
    [(line, column, text)] = fixes(code, site, 20.0)
    assert (line, column) == (line_of(code, "if time.monotonic() - start"), 13)
    assert text == (
        "if time.monotonic() - start > 20:  # the turn's budget\n"
        "    raise RuntimeError('not turned within 20 seconds')"
    )


def test_a_helpers_parameter_leads_out_to_the_states_argument_and_not_into_its_lambda() -> None:
    code = HELPERS + (
        "    def execute(self):\n"
        "        self._wait_until(\n"
        "            lambda: abs(self.speed - 0.5) < 0.5,\n"
        "            0.5,\n"
        '            "the velocity",\n'
        "        )\n"
    )
    call = line_of(code, "self._wait_until(", 1)
    site = timeout_site(code, line_of(code, "raise RuntimeError(f"), (call,), 0.5)
    assert site is not None
    assert site.numbers == ((call + 2, 12, 15),)
    assert site.raise_line is None  # the helper's text formats the timeout it is given
    [(line, column, text)] = fixes(code, site, 3.0)
    assert (line, column) == (call, 9)
    assert text.splitlines()[2] == "    3.0,"
    changed = with_seconds(code, site, 3.0)
    assert ast.parse(changed)
    assert "< 0.5," in changed


def test_two_helpers_deep_the_number_is_the_states_argument() -> None:
    code = HELPERS + (
        "    def execute(self):\n"
        "        result = self._result_of(self.future, 30, 'result of the goal')\n"
    )
    outer = line_of(code, "result = self._result_of")
    middle = line_of(code, "self._wait_until(future.done")
    site = timeout_site(code, line_of(code, "raise RuntimeError(f"), (outer, middle), 30.0)
    assert site is not None
    assert (
        with_seconds(code, site, 120.0)
        .splitlines()[outer - 1]
        .endswith("self._result_of(self.future, 120, 'result of the goal')")
    )


def test_a_number_reached_through_an_assigned_name_counts() -> None:
    code = HELPERS + (
        "    def execute(self):\n"
        "        patience = 4.0\n"
        "        until = time.monotonic() + patience\n"
        "        while time.monotonic() < until and not self.done:\n"
        "            time.sleep(0.1)\n"
        "        if time.monotonic() >= until:\n"
        "            raise RuntimeError(f'the goal was not reached within {patience} s')\n"
    )
    site = timeout_site(code, line_of(code, "not reached within"), (), 4.0)
    assert site is not None
    assert [n[0] for n in site.numbers] == [line_of(code, "patience = 4.0")]


@pytest.mark.parametrize(
    ("extra", "found"),
    [
        ("", True),  # the one 3.0 of the state: a spin with a timeout, then a check
        ("        self.speed = 3.0\n", False),  # two of them: which one is not clear
    ],
)
def test_without_a_trail_only_a_number_alone_of_its_value_is_taken(extra: str, found: bool) -> None:
    code = HELPERS + (
        "    def execute(self):\n"
        + extra
        + "        rclpy.spin_until_future_complete(self.node, self.future, timeout_sec=3.0)\n"
        "        if not self.future.done():\n"
        "            raise RuntimeError('no answer within 3 s')\n"
    )
    site = timeout_site(code, line_of(code, "no answer within"), (), 3.0)
    assert (site is not None) is found


def test_no_number_of_that_value_means_no_site() -> None:
    code = HELPERS + (
        "    def execute(self):\n"
        "        if not self.done:\n"
        "            raise RuntimeError(f'not done within {self.in_timeout} s')\n"
    )
    assert timeout_site(code, line_of(code, "not done within"), (), 7.0) is None
    assert timeout_site("def broken(:\n", 1, (), 1.0) is None


@pytest.mark.parametrize(
    ("before", "said", "after"),
    [
        (  # text that is not ASCII before the number keeps its place
            "self.label = '90°'; deadline = time.monotonic() + 2.0",
            "'90° not reached within 2 s'",
            ("self.label = '90°'; deadline = time.monotonic() + 10.0", "within 10 s'"),
        ),
        (  # only the seconds the raise names change in its text
            "deadline = time.monotonic() + 2",
            "'not there within 2 s (0.5 s steps, 12 s at most)'",
            ("deadline = time.monotonic() + 10\n", "within 10 s (0.5 s steps, 12 s at most)'"),
        ),
    ],
    ids=["not ascii", "other numbers"],
)
def test_the_number_and_the_raises_text_change_in_place(
    before: str, said: str, after: tuple[str, str]
) -> None:
    code = HELPERS + (
        "    def execute(self):\n"
        f"        {before}\n"
        "        if time.monotonic() > deadline:\n"
        f"            raise RuntimeError({said})\n"
    )
    site = timeout_site(code, line_of(code, "raise RuntimeError(", 1), (), 2.0)
    assert site is not None
    changed = with_seconds(code, site, 10.0)
    assert all(text in changed for text in after), changed


@pytest.mark.parametrize(
    ("seconds", "rounded"),
    [(0.3, 1.0), (3.0, 3.0), (9.2, 10.0), (10.4, 15.0), (45.3, 50.0), (61.0, 70.0)],
)
def test_seconds_are_rounded_up_to_a_number_an_engineer_would_write(
    seconds: float, rounded: float
) -> None:
    assert rounded_up(seconds) == rounded
