"""Fixtures of the runtime tests: the MR-1's inventory and quick run settings."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.interfaces.inventory import Inventory
from skillwright.runtime.sandbox import MARKER_VARIABLE
from skillwright.runtime.scenario import Deadlines, RunScenario
from tests.conftest import SHIPPED_CAPABILITIES

MR1_RECORDING = SHIPPED_CAPABILITIES / "recordings" / "mr1"
SKILLS = SHIPPED_CAPABILITIES / "skills"


@pytest.fixture(scope="session")
def mr1_inventory() -> Inventory:
    """The inventory of the shipped MR-1 recording (read once per test session)."""
    from skillwright.interfaces.load import load_inventory

    return load_inventory(MR1_RECORDING)


def quick(**changes: object) -> RunScenario:
    """A scenario with short deadlines, so a skill that hangs is caught in a second."""
    settings: dict[str, object] = {
        "deadlines": Deadlines(state=10.0, busy=1.0, run=30.0),
        "stop_run": "never",
        "settle": 0.2,
    }
    settings.update(changes)
    return RunScenario.model_validate(settings)


def skill_path(name: str) -> Path:
    """A shipped MR-1 skill."""
    return SKILLS / f"{name}.py"


def processes_with(marker: str) -> list[int]:
    """Processes whose environment carries the sandbox marker ``marker``."""
    found = []
    needle = f"{MARKER_VARIABLE}={marker}".encode()
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            environment = (entry / "environ").read_bytes()
        except OSError:
            continue
        if needle in environment.split(b"\0"):
            found.append(int(entry.name))
    return found
