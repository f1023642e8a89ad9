"""Terminal output shared by the commands: rich consoles, created on first use."""

from __future__ import annotations

from collections.abc import Iterable
from functools import cache
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pydantic import BaseModel
    from rich.console import Console

__all__ = ["err_console", "human_size", "out_console", "print_model_json", "warn"]


@cache
def out_console() -> Console:
    """The console for results (stdout)."""
    from rich.console import Console

    # No emoji codes: "skill.py:100:9" would otherwise print a "100" emoji.
    return Console(highlight=False, soft_wrap=False, emoji=False)


@cache
def err_console() -> Console:
    """The console for progress and warnings (stderr)."""
    from rich.console import Console

    return Console(stderr=True, highlight=False, emoji=False)


def warn(warnings: Iterable[str]) -> None:
    """Prints each warning on stderr as ``warning: ...``, its text taken literally."""
    for warning in warnings:
        err_console().print(f"warning: {warning}", markup=False, soft_wrap=True)


def print_model_json(model: BaseModel) -> None:
    """Writes a document as indented JSON on stdout, unstyled so it can be piped."""
    import sys

    sys.stdout.write(model.model_dump_json(indent=2) + "\n")


def human_size(size: int) -> str:
    """``372409`` -> ``363.7 KiB`` (binary units)."""
    value = float(size)
    for unit in ("B", "KiB", "MiB", "GiB"):
        if value < 1024:
            return f"{value:.0f} {unit}" if unit == "B" else f"{value:.1f} {unit}"
        value /= 1024
    return f"{value:.1f} TiB"
