"""Fixtures the validation tests share."""

from __future__ import annotations

import pytest

from skillwright.capability import Capability, load_capability
from skillwright.spec import SkillSpec, load_spec
from tests.conftest import SHIPPED_CAPABILITIES


@pytest.fixture(scope="module")
def move_forward() -> tuple[Capability, SkillSpec]:
    """The shipped move-forward capability and its specification (the good skill's)."""
    capability = load_capability(SHIPPED_CAPABILITIES / "move-forward.ttl").capability
    return capability, load_spec(SHIPPED_CAPABILITIES / "move-forward.spec.yaml")
