"""The skill specification document."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field

__all__ = ["PACKML_STATES", "SKILL_INTERFACES", "SkillSpec"]

PACKML_STATES: tuple[str, ...] = (
    "starting",
    "execute",
    "completing",
    "holding",
    "unholding",
    "suspending",
    "unsuspending",
    "stopping",
    "aborting",
    "clearing",
    "resetting",
)
"""The PackML acting states a skill can implement, in the order a run meets them."""

SKILL_INTERFACES: tuple[str, ...] = ("REST", "OPC_UA", "MQTT")
"""Skill interface types of the pySkillUp framework family (names of ``SkillInterface``)."""


class SkillSpec(BaseModel):
    """What a skill should do: its name, interface and behaviour per PackML acting state.

    Build one with :func:`skillwright.spec.parse_spec` or :func:`skillwright.spec.load_spec`,
    which check every rule and say which field or state is wrong.
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str = Field(description="Skill name, a valid Python identifier, e.g. move_forward.")
    description: str = Field(description="One or two sentences on what the skill does.")
    skill_interface: str = Field(description="REST, OPC_UA or MQTT.")
    states: dict[str, str] = Field(
        description="Behaviour text per PackML acting state, in PackML order; execute is required."
    )

    def to_reference(self) -> dict[str, Any]:
        """The reference project's JSON shape: ``{"skill": {..., "states": [{name, action}]}}``."""
        return {
            "skill": {
                "name": self.name,
                "description": self.description,
                "skill_interface": self.skill_interface,
                "states": [{"name": n, "action": a} for n, a in self.states.items()],
            }
        }
