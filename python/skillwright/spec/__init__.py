"""Stage 1b: the skill specification — what the skill does in each PackML acting state.

Names are loaded on first use so that ``skillwright --help`` does not import pydantic.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from skillwright.spec.loader import load_spec, parse_spec
    from skillwright.spec.model import PACKML_STATES, SKILL_INTERFACES, SkillSpec

__all__ = ["PACKML_STATES", "SKILL_INTERFACES", "SkillSpec", "load_spec", "parse_spec"]


def __getattr__(name: str) -> Any:
    if name in {"load_spec", "parse_spec"}:
        return getattr(import_module("skillwright.spec.loader"), name)
    if name in __all__:
        return getattr(import_module("skillwright.spec.model"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
