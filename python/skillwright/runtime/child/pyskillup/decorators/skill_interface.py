"""Stand-in of ``pyskillup.decorators.skill_interface``."""

from enum import Enum


class SkillInterface(Enum):
    """How a skill is offered to its clients."""

    REST = "REST"
    OPC_UA = "OPC_UA"
    MQTT = "MQTT"
