"""The rules: each a unit with a stable code, its stage, severity, fix safety and documentation.

A rule is declared once, beside the code that applies it (``Rule(...)`` at module level
registers it), and every finding is made through its rule (:meth:`Rule.finding`,
:meth:`Rule.at`), so a finding always carries a registered code. Codes are stable: a
rule that goes keeps its code retired, a new rule takes a new one. The blocks:

======  =====================================================================
SW1xx   pySkillUp structure: the @skill class, its parameters, outputs, states
SW2xx   the robot's interfaces: names, kinds, types, fields, constants
SW3xx   the rclpy, tf2 and skeleton-helper API: attributes, calls, arguments
SW4xx   behaviour: waits, loops, stops, motion, units, frames, timeouts
SW5xx   the capability: its inputs and outputs, in the code
SW6xx   the run in the sandbox against the simulated graph
SW7xx   the simulation in MuJoCo: the oracles' verdicts
======  =====================================================================

Each rule's documentation says what it checks, why it matters on a real robot (from the
ROS 2, rclpy, tf2 or pySkillUp API, or the capability model), an example and what its fix
does; ``skillwright check --explain CODE`` prints it.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

from skillwright.rules.finding import Finding, FixSafety, Severity, Stage

__all__ = ["RULES", "Rule", "UnknownRuleError", "all_rules", "get", "resolve", "rule_of"]

_CODE = re.compile(r"^SW[1-7]\d\d$")
_NAME = re.compile(r"^[a-z][a-z0-9]*(-[a-z0-9]+)*$")

RULES: dict[str, Rule] = {}
"""Every rule, by code (filled as the modules that declare rules are imported; see
:func:`all_rules`)."""

_DECLARING_MODULES = (
    "skillwright.rules.structure",
    "skillwright.rules.interfaces",
    "skillwright.rules.api",
    "skillwright.rules.behaviour",
    "skillwright.rules.capability",
    "skillwright.rules.run",
    "skillwright.rules.simulation",
)
"""The modules that declare the rules, a block each."""


class UnknownRuleError(KeyError):
    """A code or name no rule has."""


@dataclass(frozen=True)
class Rule:
    """One rule: what it checks, at which stage, and its documentation."""

    code: str
    name: str
    group: str
    """The group its findings show (``Finding.check``), shared by related rules."""
    stage: Stage
    severity: Severity
    summary: str
    """What it checks, in one sentence."""
    why: str
    """Why it matters on a real robot, from the API or the capability model."""
    example: str
    """A short example of code it flags."""
    fix: str | None = None
    """What its fix does, for a rule that has one."""
    safety: FixSafety | None = None
    """How safe its fix is; ``None`` for a rule without one."""
    data: tuple[str, ...] = ()
    """The keys of its findings' ``data``."""
    grounds: tuple[str, ...] = field(default=())
    """Where the rule's truth comes from: ``rclpy``, ``tf2``, ``pySkillUp``, ``ROS 2``, ``the
    capability``, ``the robot``, ``the simulation``."""

    def __post_init__(self) -> None:
        if not _CODE.match(self.code):
            raise ValueError(f"rule code {self.code!r} is not SW1xx..SW7xx")
        if not _NAME.match(self.name):
            raise ValueError(f"rule name {self.name!r} is not kebab-case")
        if (self.fix is None) != (self.safety is None):
            raise ValueError(f"rule {self.code}: a fix needs a safety level and the other way")
        taken = RULES.get(self.code)
        if taken is not None and taken != self:
            raise ValueError(f"rule code {self.code} is taken by {taken.name}")
        if any(r.name == self.name and r.code != self.code for r in RULES.values()):
            raise ValueError(f"rule name {self.name} is taken")
        RULES[self.code] = self

    def finding(
        self,
        *,
        line: int,
        message: str,
        column: int = 0,
        data: Mapping[str, Any] | None = None,
        replacement: str | None = None,
        severity: Severity | None = None,
        stack: tuple[int, ...] = (),
    ) -> Finding:
        """A finding of this rule; ``replacement`` is its fix (for a rule that has one)."""
        if replacement is not None and self.safety is None:
            raise ValueError(f"rule {self.code} has no fix, yet a finding carries one")
        undeclared = set(data or {}) - set(self.data)
        if undeclared:
            raise ValueError(f"rule {self.code}: data {sorted(undeclared)} is not declared")
        return Finding(
            code=self.code,
            check=self.group,
            severity=severity or self.severity,
            line=line,
            column=column,
            message=message,
            data=dict(data or {}),
            replacement=replacement,
            fix_safety=self.safety if replacement is not None else None,
            stack=stack,
        )

    def at(
        self,
        node: ast.AST | None,
        message: str,
        *,
        data: Mapping[str, Any] | None = None,
        replacement: str | None = None,
        severity: Severity | None = None,
    ) -> Finding:
        """A finding at ``node``'s line and column (the whole file without one)."""
        line = getattr(node, "lineno", 0) if node is not None else 0
        column = getattr(node, "col_offset", -1) + 1 if node is not None else 0
        return self.finding(
            line=line,
            column=column,
            message=message,
            data=data,
            replacement=replacement,
            severity=severity,
        )

    def explain(self) -> str:
        """The rule's documentation as text."""
        head = f"{self.code} {self.name} ({self.stage}, {self.severity}; group {self.group})"
        parts = [head, "", "What it checks", self.summary, "", "Why it matters", self.why]
        parts += ["", "Example", self.example]
        if self.fix is not None:
            parts += ["", f"Fix ({self.safety})", self.fix]
        if self.data:
            parts += ["", "Finding data", ", ".join(self.data)]
        if self.grounds:
            parts += ["", "Grounded in", ", ".join(self.grounds)]
        return "\n".join(parts)


def all_rules() -> list[Rule]:
    """Every rule, by code."""
    import importlib

    for module in _DECLARING_MODULES:
        importlib.import_module(module)
    return [RULES[code] for code in sorted(RULES)]


def get(code: str) -> Rule:
    """The rule with ``code`` (or name)."""
    all_rules()
    found = RULES.get(code.upper()) or next((r for r in RULES.values() if r.name == code), None)
    if found is None:
        raise UnknownRuleError(code)
    return found


def rule_of(finding: Finding) -> Rule | None:
    """The rule that made ``finding`` (``None`` for one read from an old record)."""
    all_rules()
    return RULES.get(finding.code)


def resolve(selectors: Iterator[str] | list[str] | tuple[str, ...]) -> set[str]:
    """The codes ``selectors`` name: a code (``SW301``), a block (``SW3``), a group
    (``names``), a name (``made-up-attribute``) or ``ALL``. Raises :class:`UnknownRuleError`
    for a selector that names none."""
    rules = all_rules()
    codes: set[str] = set()
    for selector in selectors:
        wanted = selector.strip()
        upper = wanted.upper()
        matched = {
            r.code
            for r in rules
            if upper == "ALL"
            or (upper.startswith("SW") and r.code.startswith(upper))
            or wanted in (r.group, r.name)
        }
        if not matched:
            raise UnknownRuleError(selector)
        codes |= matched
    return codes
