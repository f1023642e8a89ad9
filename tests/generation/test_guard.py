"""The repetition guard ends answers that loop and lets real code through."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from skillwright.generation.guard import RepetitionGuard
from tests.conftest import SHIPPED_CAPABILITIES

EXAMPLES = SHIPPED_CAPABILITIES / "skills"


def _feed(text: str, chunk: int = 5) -> tuple[bool, int]:
    guard = RepetitionGuard()
    for start in range(0, len(text), chunk):
        if guard.feed(text[start : start + chunk]):
            return True, start
    return False, len(text)


@pytest.mark.parametrize(
    "text",
    [
        "        self.cmd_vel_publisher.publish(Twist())\n" * 6,
        "        x = 1\n        self.node.get_logger().info('again')\n        time.sleep(0.1)\n"
        * 4,
        "        value = " + "self.odom_msg.pose + " * 30,
        # MR-1 mapping's completing state: five lines of one f-string twice, then the
        # 320-token budget ran out before a third copy could show the loop
        "        self.node.get_logger().info(\n"
        + "".join(
            f'            f"map {name}: {{self.map_msg.info.{name}}}, "\n'
            for name in ("width", "height", "resolution", "origin", "map_load_time")
        )
        * 2
        + '            f"map width: "\n',
    ],
    ids=["one line", "a block of lines", "one long line", "a long block twice"],
)
def test_a_loop_is_found_before_the_text_ends(text: str) -> None:
    looped, at = _feed(text)
    assert looped
    assert at < len(text)


def _methods(source: str) -> list[str]:
    """Each function of a skill as its own text: the guard watches one method's answer."""
    lines = source.splitlines(keepends=True)
    return [
        "".join(lines[node.lineno - 1 : node.end_lineno])
        for node in ast.walk(ast.parse(source))
        if isinstance(node, ast.FunctionDef)
    ]


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.py")), ids=lambda p: p.stem)
def test_real_skill_code_is_not_mistaken_for_a_loop(path: Path) -> None:
    methods = _methods(path.read_text(encoding="utf-8"))
    assert methods
    for method in methods:
        looped, _ = _feed(method)
        assert not looped, method


def test_the_guard_says_what_was_repeated() -> None:
    guard = RepetitionGuard()
    for _ in range(5):
        guard.feed("        self.stop_the_robot_now()\n")
    assert guard.reason is not None
    assert "self.stop_the_robot_now()" in guard.reason


def test_short_lines_may_repeat() -> None:
    text = "".join(f"        else:\n            x{i} = {i}\n        )\n" for i in range(8))
    assert not _feed(text)[0]


def test_a_line_repeated_under_different_conditions_is_not_a_loop() -> None:
    text = "".join(
        f"        if self.reading_{i} < self.limit:\n            self._stop_base()\n"
        for i in range(6)
    )
    assert not _feed(text)[0]


def test_a_line_repeated_after_the_same_line_is_a_loop() -> None:
    text = "        if blocked:\n            self._stop_base()\n" * 5
    assert _feed(text)[0]


def test_a_short_block_twice_is_not_a_loop() -> None:
    # Real code stops the base and says so under two conditions in a row.
    text = (
        "        if self.scan_msg.ranges[0] < 0.3:\n"
        "            self._stop_base()\n"
        "            raise RuntimeError('blocked')\n"
    ) * 2
    assert not _feed(text)[0]


def test_a_long_block_of_short_lines_twice_is_not_a_loop() -> None:
    text = "        try:\n            x()\n        except E:\n            y()\n" * 2
    assert not _feed(text)[0]
