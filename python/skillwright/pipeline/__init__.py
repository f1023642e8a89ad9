"""The generation engine the headless commands and the TUI share.

Names are loaded on first use, so importing the package costs nothing.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from skillwright.pipeline.record import GenerationRecord
    from skillwright.pipeline.run import (
        GenerationRequest,
        Outcome,
        RetrievalResult,
        retrieve,
        run_generation,
    )

__all__ = [
    "GenerationRecord",
    "GenerationRequest",
    "Outcome",
    "RetrievalResult",
    "retrieve",
    "run_generation",
]


def __getattr__(name: str) -> Any:
    if name == "GenerationRecord":
        return import_module("skillwright.pipeline.record").GenerationRecord
    if name in __all__:
        return getattr(import_module("skillwright.pipeline.run"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
