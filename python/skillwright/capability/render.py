"""A readable summary of a capability for the terminal."""

from __future__ import annotations

from typing import TYPE_CHECKING

from skillwright.capability.model import CapabilityLoad, Parameter

if TYPE_CHECKING:
    from rich.console import RenderableType

__all__ = ["render_capability"]


def _parameter_rows(parameters: list[Parameter]) -> list[tuple[str, str, str, str, str]]:
    rows = []
    for parameter in parameters:
        for component in parameter.components:
            name = parameter.name if len(parameter.components) == 1 else component.name
            value = ""
            if component.value is not None:
                value = f"{component.logic_interpretation or '='} {component.value}"
            rows.append(
                (
                    name,
                    component.data_type or "?",
                    component.unit or "",
                    " ".join(x for x in (component.expression_goal or "", value) if x),
                    component.definition or "",
                )
            )
    return rows


def render_capability(load: CapabilityLoad) -> RenderableType:
    """Inputs, outputs, constraints and resource limits of the capability, as rich tables."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    capability = load.capability
    parts: list[RenderableType] = [
        Text.assemble((capability.label, "bold"), f"  <{capability.iri}>"),
        Text(f"{', '.join(capability.kinds)} — from {load.source}", style="dim"),
    ]
    if capability.comment:
        parts.append(Text(capability.comment))
    for title, parameters in (("Inputs", capability.inputs), ("Outputs", capability.outputs)):
        table = Table(title=title, title_justify="left", expand=False)
        for column in ("name", "type", "unit", "goal / value", "definition"):
            table.add_column(column, overflow="fold")
        for row in _parameter_rows(parameters):
            table.add_row(*row)
        if not parameters:
            table.add_row("(none)", "", "", "", "")
        parts.append(table)
    if capability.constraints:
        parts.append(Text("Constraints", style="bold"))
        parts.extend(Text(f"  {c.name}: {c.text}") for c in capability.constraints)
    resource = capability.resource
    if resource is not None:
        parts.append(Text.assemble(("Resource ", "bold"), f"{resource.name}  <{resource.iri}>"))
        limits = [limit for prop in resource.properties for limit in prop.limits()]
        parts.extend(Text(f"  limit: {limit}") for limit in limits)
        others = [p.name for p in resource.properties if not p.limits()]
        if others:
            parts.append(Text(f"  properties: {', '.join(others)}", style="dim"))
    if load.others:
        parts.append(Text(f"Also in this file: {', '.join(load.others)}", style="dim"))
    return Group(*parts)
