"""Which rules apply: ``--select`` / ``--ignore`` on the command line, and a project's own.

A project keeps its choice in the ``pyproject.toml`` nearest above the skill file (or the
folder a command runs in), the way ruff reads its settings::

    [tool.skillwright]
    select = ["ALL"]          # codes (SW301), blocks (SW3), groups (names), rule names
    ignore = ["SW113", "interfaces"]

The command line's selection replaces the project's ``select``; its ``ignore`` adds to the
project's. A finding of a rule that is not selected, or ignored, is left out of what the
command reports and of what generation repairs.
"""

from __future__ import annotations

import tomllib
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from skillwright.errors import ConfigError, InvalidArgumentError
from skillwright.rules.finding import Finding
from skillwright.rules.registry import UnknownRuleError, resolve

__all__ = ["Selection", "project_selection"]


@dataclass(frozen=True)
class Selection:
    """The rules a command reports; every rule unless told otherwise."""

    selected: frozenset[str] | None = None
    """Codes that apply (``None``: all)."""
    ignored: frozenset[str] = field(default_factory=frozenset)
    source: str | None = None
    """Where the project's part came from (its pyproject.toml), for messages."""

    def keeps(self, finding: Finding) -> bool:
        """Whether ``finding`` is reported (a finding without a code always is)."""
        if not finding.code:
            return True
        if finding.code in self.ignored:
            return False
        return self.selected is None or finding.code in self.selected

    def filter(self, findings: Iterable[Finding]) -> list[Finding]:
        """The findings this selection reports, in their order."""
        return [f for f in findings if self.keeps(f)]

    def narrowed(self, select: Sequence[str], ignore: Sequence[str]) -> Selection:
        """This selection with the command line's ``--select`` and ``--ignore`` applied."""
        selected = self.selected
        if select:
            selected = frozenset(_codes(select, "--select"))
        ignored = self.ignored | frozenset(_codes(ignore, "--ignore"))
        return Selection(selected, ignored, self.source)


def _split(values: Iterable[str]) -> list[str]:
    return [part for value in values for part in value.replace(",", " ").split() if part]


def _codes(values: Sequence[str], where: str) -> set[str]:
    try:
        return resolve(_split(values))
    except UnknownRuleError as error:
        raise InvalidArgumentError(
            f"{where} {error.args[0]}: no rule has that code, block, group or name; "
            "`skillwright rules` lists them"
        ) from None


def project_selection(start: Path) -> Selection:
    """The selection of the project ``start`` (a file or folder) lies in: the
    ``[tool.skillwright]`` table of the nearest ``pyproject.toml`` above it, if it has one."""
    folder = start if start.is_dir() else start.parent
    for candidate in [folder.resolve(), *folder.resolve().parents]:
        path = candidate / "pyproject.toml"
        if not path.is_file():
            continue
        try:
            table = tomllib.loads(path.read_text(encoding="utf-8")).get("tool", {})
        except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as error:
            raise ConfigError(f"{path}: cannot be read as TOML ({error})") from None
        own = table.get("skillwright") if isinstance(table, dict) else None
        if not isinstance(own, dict):
            return Selection()
        return _from_table(own, path)
    return Selection()


def _from_table(table: dict[str, object], path: Path) -> Selection:
    values: dict[str, list[str]] = {}
    for key in ("select", "ignore"):
        value = table.get(key, [])
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise ConfigError(f"{path}: [tool.skillwright] {key} must be a list of strings")
        values[key] = [str(v) for v in value]
    unknown = sorted(set(table) - {"select", "ignore"})
    if unknown:
        raise ConfigError(
            f"{path}: [tool.skillwright] has no setting {unknown[0]!r} (it takes select, ignore)"
        )
    try:
        selected = frozenset(resolve(values["select"])) if values["select"] else None
        ignored = frozenset(resolve(values["ignore"]))
    except UnknownRuleError as error:
        raise ConfigError(
            f"{path}: [tool.skillwright] names {error.args[0]!r}, which no rule has; "
            "`skillwright rules` lists them"
        ) from None
    return Selection(selected, ignored, str(path))
