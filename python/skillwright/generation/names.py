"""Turning capability, spec and ROS 2 names into Python names for generated code."""

from __future__ import annotations

import keyword
import re

__all__ = ["attribute_name", "class_name", "python_import", "snake_case"]


def snake_case(name: str) -> str:
    """``inDistance`` -> ``in_distance``; ``/cmd_vel`` -> ``cmd_vel``; never a keyword."""
    text = re.sub(r"(?<=[a-z0-9])(?=[A-Z])|(?<=[A-Z])(?=[A-Z][a-z])", "_", name)
    text = re.sub(r"[^0-9A-Za-z]+", "_", text).strip("_").lower()
    if not text:
        text = "value"
    if text[0].isdigit():
        text = f"_{text}"
    return f"{text}_" if keyword.iskeyword(text) else text


def class_name(skill_name: str) -> str:
    """``move_forward`` -> ``MoveForwardSkill``."""
    words = re.split(r"[^0-9A-Za-z]+", snake_case(skill_name))
    base = "".join(w[:1].upper() + w[1:] for w in words if w)
    return base if base.endswith("Skill") else f"{base}Skill"


def attribute_name(interface_name: str, suffix: str) -> str:
    """``/cmd_vel`` + ``publisher`` -> ``cmd_vel_publisher``."""
    return f"{snake_case(interface_name)}_{suffix}"


def python_import(type_name: str, kind: str) -> tuple[str, str]:
    """``geometry_msgs/msg/Twist`` -> (``geometry_msgs.msg``, ``Twist``).

    Accepts ``pkg/Type`` too, placing it in the sub-module for ``kind``
    (``msg`` for topics, ``srv`` for services, ``action`` for actions).
    """
    parts = [p for p in type_name.split("/") if p]
    if len(parts) == 3:
        return f"{parts[0]}.{parts[1]}", parts[2]
    if len(parts) == 2:
        sub = {"topic": "msg", "service": "srv", "action": "action"}.get(kind, "msg")
        return f"{parts[0]}.{sub}", parts[1]
    raise ValueError(f"not a ROS 2 type name: {type_name!r} (expected pkg/msg/Type)")
