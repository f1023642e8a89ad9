"""The trace and the findings of one episode, as the host observes them.

Entries are plain JSON-serialisable dicts with the virtual time ``t``, a ``kind`` and
what happened; long arrays in messages are shortened so that a trace stays readable and
bounded (at most :data:`MAX_ENTRIES` entries; the rest are counted, not kept).
"""

from __future__ import annotations

import math
from typing import Any, Final

from skillwright.rules.finding import Finding, Severity
from skillwright.rules.registry import Rule

__all__ = ["MAX_ENTRIES", "Recorder", "abbreviate"]

MAX_ENTRIES: Final = 20_000
_MAX_ITEMS: Final = 16
_MAX_TEXT: Final = 2_000


def abbreviate(value: Any, depth: int = 0) -> Any:
    """``value`` with long lists and strings cut, non-finite floats as strings."""
    if isinstance(value, dict):
        if depth > 12:
            return "{...}"
        return {str(k): abbreviate(v, depth + 1) for k, v in value.items()}
    if isinstance(value, list):
        shown = [abbreviate(v, depth + 1) for v in value[:_MAX_ITEMS]]
        if len(value) > _MAX_ITEMS:
            shown.append(f"... {len(value)} items")
        return shown
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    if isinstance(value, str) and len(value) > _MAX_TEXT:
        return value[:_MAX_TEXT] + f"... ({len(value)} characters)"
    return value


class Recorder:
    """Collects trace entries and findings; knows the current state and skill line."""

    def __init__(self) -> None:
        self.entries: list[dict[str, Any]] = []
        self.dropped = 0
        self.findings: list[Finding] = []
        self.now = 0.0
        self.state: str | None = None
        self.line = 0
        """The skill line of the most recent call into the runtime."""

    def record(self, kind: str, **data: Any) -> None:
        """Adds a trace entry at the current virtual time."""
        if len(self.entries) >= MAX_ENTRIES:
            self.dropped += 1
            return
        entry: dict[str, Any] = {"t": round(self.now, 6), "kind": kind}
        if self.state is not None:
            entry["state"] = self.state
        entry.update({k: abbreviate(v) for k, v in data.items()})
        self.entries.append(entry)

    def finding(
        self,
        rule: Rule,
        message: str,
        *,
        line: int | None = None,
        severity: Severity | None = None,
        stack: tuple[int, ...] = (),
        data: dict[str, object] | None = None,
    ) -> None:
        """Adds a finding of ``rule`` (once: the same rule, line and message are kept once);
        ``stack`` holds the lines of the calls that led to ``line``, outermost first."""
        finding = rule.finding(
            line=self.line if line is None else max(0, int(line)),
            message=message,
            severity=severity,
            stack=stack,
            data=data,
        )
        if finding not in self.findings:
            self.findings.append(finding)
