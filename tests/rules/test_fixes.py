"""Putting fixes in: safe ones by default, unsafe ones only when asked, never a broken file."""

from __future__ import annotations

from skillwright.rules.finding import Finding
from skillwright.rules.fixes import apply_fixes, fixable
from skillwright.rules.registry import get

SOURCE = "def f(self):\n    x = self.a\n    y = self.b\n    return x + y\n"


def _at(code: str, line: int, replacement: str) -> Finding:
    return get(code).finding(line=line, column=5, message="m", replacement=replacement)


def test_safe_fixes_go_in_and_unsafe_ones_only_when_asked() -> None:
    safe = _at("SW205", 2, "x = self.aa")  # unknown-field: safe
    unsafe = _at("SW407", 3, "y = self.bb")  # zero-timeout: unsafe
    assert fixable(safe, unsafe=False)
    assert not fixable(unsafe, unsafe=False)
    fixed, applied = apply_fixes(SOURCE, [safe, unsafe])
    assert applied == [safe]
    assert fixed == SOURCE.replace("self.a\n", "self.aa\n")
    fixed, applied = apply_fixes(SOURCE, [safe, unsafe], unsafe=True)
    assert applied == [safe, unsafe]
    assert "self.aa" in fixed
    assert "self.bb" in fixed


def test_a_fix_that_would_not_parse_changes_nothing() -> None:
    broken = _at("SW205", 2, "x = (")
    assert apply_fixes(SOURCE, [broken]) == (SOURCE, [])


def test_an_empty_replacement_of_a_block_s_only_statement_leaves_pass() -> None:
    source = "def f(self):\n    if self.a:\n        self.b = 1\n"
    fixed, applied = apply_fixes(source, [_at("SW205", 3, "")], unsafe=True)
    assert applied
    assert fixed == "def f(self):\n    if self.a:\n        pass\n"


def test_two_fixes_of_one_statement_put_in_only_the_first() -> None:
    first, second = _at("SW205", 2, "x = self.aa"), _at("SW208", 2, "x = self.ab")
    fixed, applied = apply_fixes(SOURCE, [first, second])
    assert applied == [first]
    assert "self.aa" in fixed
