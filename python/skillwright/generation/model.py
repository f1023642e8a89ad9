"""Documents of the generation stage."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

__all__ = ["InterfaceRef", "Skeleton", "SkeletonParameter"]

InterfaceKind = Literal["topic", "service", "action"]


class InterfaceRef(BaseModel):
    """A robot interface the skill will use, as far as code generation needs it."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str = Field(description="Full ROS 2 name, e.g. /cmd_vel.")
    kind: InterfaceKind = Field(description="topic, service or action.")
    type_name: str = Field(description="ROS 2 type, e.g. geometry_msgs/msg/Twist.")
    role: Literal["publish", "subscribe", "call"] = Field(
        description="publish / subscribe for topics; call for services and actions."
    )


class SkeletonParameter(BaseModel):
    """One ``@skill_parameter`` or ``@skill_output`` of the skeleton."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str = Field(description="Name in the annotation: the capability's name for it.")
    attribute: str = Field(description="Attribute of the skill object holding the value.")
    python_type: str = Field(description="Python type of the value: float, int, bool or str.")
    direction: Literal["input", "output"] = Field(description="Parameter or output.")
    description: str = Field(description="Description in the annotation.")


class Skeleton(BaseModel):
    """The deterministic part of a skill: structure, annotations and interface handles."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    code: str = Field(description="The Python source.")
    class_name: str = Field(description="Name of the skill class.")
    skill_iri: str = Field(description="The minted skill IRI.")
    parameters: list[SkeletonParameter] = Field(description="Parameters and outputs.")
    interfaces: list[InterfaceRef] = Field(description="Interfaces with handles in the code.")
    unimplemented: list[str] = Field(
        description="States whose behaviour the skeleton leaves to be written."
    )
    notes: list[str] = Field(default_factory=list, description="Decisions the user should know.")
