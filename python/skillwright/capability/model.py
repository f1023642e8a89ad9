"""The capability document: what a capability model says, in typed form.

The vocabulary follows the ontologies it comes from: VDI 3682 inputs and outputs
(Information or Product), DIN EN 61360 data elements (a type description with unit and
definition, an instance description with data type, value, expression goal and logic
interpretation) and CSS constraints written as OpenMath applications.
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

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
]

Scalar = float | int | bool | str


class _Document(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class DataElement(_Document):
    """One DIN EN 61360 instance description together with its type description."""

    iri: str | None = Field(default=None, description="IRI of the instance description.")
    name: str = Field(description="Readable name of the instance, e.g. outPositionX.")
    data_type: str | None = Field(
        default=None, description="DIN EN 61360 data type, e.g. Real, Integer, Boolean, String."
    )
    unit: str | None = Field(default=None, description="Unit of measure, e.g. m, s, m/s.")
    definition: str | None = Field(default=None, description="Definition of the type, in words.")
    value: Scalar | None = Field(default=None, description="Fixed value, when the model has one.")
    expression_goal: str | None = Field(
        default=None, description="Requirement, Assurance or Actual_Value."
    )
    logic_interpretation: str | None = Field(
        default=None, description="Relation of the value to reality, e.g. '=', '<='."
    )

    def describe(self) -> str:
        """A short phrase such as ``Real [m]`` or ``Real [m/s] <= 0.8 (Requirement)``."""
        text = self.data_type or "untyped"
        if self.unit:
            text += f" [{self.unit}]"
        if self.value is not None:
            text += f" {self.logic_interpretation or '='} {self.value}"
        if self.expression_goal:
            text += f" ({self.expression_goal})"
        return text


class Parameter(_Document):
    """An input or output of the capability (VDI 3682 Information or Product)."""

    iri: str = Field(description="IRI of the input or output individual.")
    name: str = Field(description="Local name of the IRI, e.g. inDistance.")
    direction: Literal["input", "output"] = Field(description="Whether it goes in or comes out.")
    kind: str = Field(description="VDI 3682 class: Information, Product or Energy.")
    comment: str | None = Field(default=None, description="Its rdfs:comment, when it has one.")
    components: list[DataElement] = Field(
        description="Its instance descriptions: one for a scalar, several for e.g. x and y."
    )

    @property
    def element(self) -> DataElement:
        """The first (for scalars the only) component."""
        return self.components[0]

    def describe(self) -> str:
        """Data type and unit, with the component names when there are several."""
        if len(self.components) == 1:
            return self.element.describe()
        return "; ".join(f"{c.name}: {c.describe()}" for c in self.components)


class ResourceProperty(_Document):
    """A property of the resource, with each instance description the model gives it.

    For example the MMO-700's velocity: an actual value and a requirement ``<= 0.8 m/s``.
    """

    iri: str = Field(description="IRI of the data element (or the instance description).")
    name: str = Field(description="Readable name, e.g. velocity.")
    instances: list[DataElement] = Field(description="Its instance descriptions.")

    def limits(self) -> list[str]:
        """Readable requirements such as ``velocity <= 0.8 m/s``."""
        out = []
        for instance in self.instances:
            if instance.value is None or instance.expression_goal != "Requirement":
                continue
            unit = f" {instance.unit}" if instance.unit else ""
            out.append(f"{self.name} {instance.logic_interpretation or '='} {instance.value}{unit}")
        return out


class Resource(_Document):
    """The resource (machine, robot) that provides the capability."""

    iri: str = Field(description="IRI of the resource individual.")
    name: str = Field(description="Local name of the IRI.")
    properties: list[ResourceProperty] = Field(
        default_factory=list, description="Its own properties."
    )


class Expression(_Document):
    """A term of an OpenMath expression: a variable, a literal or an application."""

    kind: Literal["variable", "literal", "application"] = Field(description="Which kind of term.")
    text: str = Field(description="The term written out, e.g. 'outDistance' or '360'.")
    refers_to: str | None = Field(
        default=None, description="IRI of the input, output or property a variable stands for."
    )
    operator: str | None = Field(default=None, description="Operator IRI of an application.")
    arguments: list[Expression] = Field(
        default_factory=list, description="Arguments of an application."
    )


class Constraint(_Document):
    """A capability constraint (``CSS:isRestrictedBy``) as an OpenMath application."""

    iri: str = Field(description="IRI of the constraint individual.")
    name: str = Field(description="Local name of the IRI.")
    relation: str = Field(description="Readable operator, e.g. '=' or '<='.")
    expression: Expression = Field(description="The whole application.")

    @property
    def text(self) -> str:
        """The constraint written out, e.g. ``outDistance = inDistance``."""
        return self.expression.text


class Capability(_Document):
    """A capability with everything the later stages need from its model."""

    iri: str = Field(description="IRI of the capability individual.")
    name: str = Field(description="Local name of the IRI, e.g. moveForward.")
    label: str = Field(description="Readable name, e.g. 'Move forward'.")
    kinds: list[str] = Field(description="Its capability classes, e.g. CaSk:ProvidedCapability.")
    comment: str | None = Field(default=None, description="Its rdfs:comment.")
    inputs: list[Parameter] = Field(
        default_factory=list,
        description="Its inputs: VDI3682:hasInput or a variant (see capability.terms).",
    )
    outputs: list[Parameter] = Field(
        default_factory=list,
        description="Its outputs: VDI3682:hasOutput or a variant (see capability.terms).",
    )
    constraints: list[Constraint] = Field(
        default_factory=list, description="CSS:isRestrictedBy constraints."
    )
    resource: Resource | None = Field(
        default=None, description="The resource that provides it (CSS:providesCapability)."
    )


class CapabilityChoice(_Document):
    """One of the capabilities a file holds, as offered for choosing."""

    iri: str = Field(description="IRI of the capability individual.")
    name: str = Field(description="Local name of the IRI, e.g. moveForward.")
    label: str = Field(description="Its rdfs:label, else a readable form of the name.")


class CapabilityLoad(_Document):
    """The result of reading a capability file: the capability and what to warn about."""

    source: str = Field(description="Path of the file it was read from.")
    capability: Capability = Field(description="The selected capability.")
    others: list[str] = Field(
        default_factory=list, description="IRIs of further capabilities in the same file."
    )
    choices: list[CapabilityChoice] = Field(
        default_factory=list,
        description="Every capability in the file, the selected one included, by IRI.",
    )
    warnings: list[str] = Field(default_factory=list, description="Things the user should know.")
