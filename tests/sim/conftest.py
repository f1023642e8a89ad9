"""Fixtures of the simulation tests: the MR-1's capabilities and inventory."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.capability.model import Capability
from skillwright.interfaces.inventory import Inventory
from tests.conftest import SHIPPED_CAPABILITIES

RECORDING = SHIPPED_CAPABILITIES / "recordings" / "mr1"


@pytest.fixture(scope="session")
def mr1_capabilities() -> dict[str, Capability]:
    """The nine shipped MR-1 capabilities by file stem (``move-forward``)."""
    from skillwright.capability.reader import load_capability

    return {
        path.stem: load_capability(path).capability
        for path in sorted(SHIPPED_CAPABILITIES.glob("*.ttl"))
    }


@pytest.fixture(scope="session")
def mr1_inventory() -> Inventory:
    """The inventory of the shipped MR-1 recording."""
    from skillwright.interfaces.load import discover_path

    return discover_path(RECORDING)


@pytest.fixture(scope="session")
def recording() -> Path:
    """The shipped MR-1 recording (a rosbag2 folder)."""
    return RECORDING
