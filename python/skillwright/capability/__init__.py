"""Stage 1a: read a capability model (CaSk / CSS / VDI 3682 / DIN EN 61360 / OpenMath).

``load_capability`` turns a Turtle or RDF file into a :class:`Capability` document.
Names are loaded on first use so that ``skillwright --help`` does not import rdflib or
pydantic through this package.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from skillwright.capability.model import (
        Capability,
        CapabilityChoice,
        CapabilityLoad,
        Constraint,
        DataElement,
        Expression,
        Parameter,
        Resource,
        ResourceProperty,
    )
    from skillwright.capability.reader import load_capability

__all__ = [
    "Capability",
    "CapabilityChoice",
    "CapabilityLoad",
    "Constraint",
    "DataElement",
    "Expression",
    "Parameter",
    "Resource",
    "ResourceProperty",
    "load_capability",
]


def __getattr__(name: str) -> Any:
    if name == "load_capability":
        return import_module("skillwright.capability.reader").load_capability
    if name in __all__:
        return getattr(import_module("skillwright.capability.model"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
