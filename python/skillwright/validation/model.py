"""What a check needs to know about the robot's interfaces, and a file's report."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from skillwright.rules.finding import Finding

__all__ = ["SEQUENCE_METHODS", "Catalog", "CatalogEntry", "CheckReport", "FieldTree"]

FieldTree = dict[str, Any]
"""Field name -> the field tree of its type, or ``None`` for a primitive; an array maps to
the tree of its element, with the list's methods. (Recursive; typed loosely because pydantic
and mypy disagree on recursive aliases under Python 3.11.)"""

SEQUENCE_METHODS = frozenset(
    ("append", "extend", "insert", "pop", "clear", "index", "count", "remove", "sort", "copy")
)
"""Methods of the Python list an array field of messages is; its tree lists them beside the
element's fields (``goal.trajectory.points.append(point)``)."""


class CatalogEntry(BaseModel):
    """One interface of the robot: enough to check code that uses it."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str = Field(description="Full ROS 2 name, e.g. /cmd_vel.")
    kind: Literal["topic", "service", "action"] = Field(description="topic, service or action.")
    type_name: str = Field(description="ROS 2 type, e.g. geometry_msgs/msg/Twist.")


class Catalog(BaseModel):
    """The interfaces a skill may use and the field trees of their types.

    ``fields`` is keyed by message type; services add ``<type>.Request`` and
    ``<type>.Response``, actions ``<type>.Goal``, ``<type>.Result`` and ``<type>.Feedback``.
    """

    model_config = ConfigDict(extra="forbid")

    entries: dict[str, CatalogEntry] = Field(default_factory=dict, description="By name.")
    fields: dict[str, FieldTree] = Field(default_factory=dict, description="By type name.")
    constants: dict[str, list[str]] = Field(
        default_factory=dict,
        description="Constant names by type name, for the types whose definition is known.",
    )


class CheckReport(BaseModel):
    """All findings for one skill file."""

    model_config = ConfigDict(extra="forbid")

    path: str = Field(description="The checked file.")
    findings: list[Finding] = Field(default_factory=list, description="Sorted by line.")
    used_interfaces: list[str] = Field(
        default_factory=list, description="Interface names the code creates handles for."
    )

    @property
    def passed(self) -> bool:
        """True when no finding is an error."""
        return not any(f.severity == "error" for f in self.findings)
