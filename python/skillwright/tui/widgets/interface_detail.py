"""How one interface of an inventory is shown: its facts and its expanded message definitions."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rich.console import RenderableType

    from skillwright.interfaces.inventory import Interface, MessageField

__all__ = ["mark_of", "relevance_of", "render_interface"]


def relevance_of(interface: Interface) -> str:
    """The relevance column: the enrichment verdict, else the infrastructure rule, else blank."""
    if interface.relevance is not None:
        verdict = "relevant" if interface.relevance.relevant else "not relevant"
        return f"{interface.relevance.category}, {verdict}"
    if interface.infrastructure is not None:
        return "infrastructure"
    return ""


def mark_of(name: str, pinned: tuple[str, ...], dropped: tuple[str, ...]) -> str:
    """``pin``, ``drop`` or blank for the mark column."""
    if name in pinned:
        return "pin"
    if name in dropped:
        return "drop"
    return ""


def _field_lines(fields: list[MessageField], depth: int, out: list[str]) -> None:
    for field in fields:
        note = "" if field.resolved else "  (definition not in the source)"
        full = "" if field.builtin or field.base_type in field.type else f"  ({field.base_type})"
        out.append(f"{'  ' * depth}{field.name}: {field.type}{full}{note}")
        if field.fields:
            _field_lines(field.fields, depth + 1, out)


def render_interface(interface: Interface) -> RenderableType:
    """Name, kind and type; flags, relevance, description, traffic; each definition expanded."""
    from rich.console import Group
    from rich.text import Text

    parts: list[RenderableType] = [
        Text.assemble((interface.name, "bold"), f"  {interface.kind}  {interface.type_name}")
    ]
    if interface.infrastructure is not None:
        flag = interface.infrastructure
        parts.append(Text(f"infrastructure ({flag.rule}): {flag.reason}", style="yellow"))
    if interface.relevance is not None:
        relevance = interface.relevance
        engine = f" [{relevance.engine}]" if relevance.engine else ""
        parts.append(Text(f"relevance: {relevance_of(interface)}: {relevance.reason}{engine}"))
    if interface.description is not None:
        parts.append(Text(f"{interface.description.text()} [{interface.description.engine}]"))
    else:
        parts.append(Text("no description yet (Ctrl+E describes the inventory)", style="dim"))
    if interface.traffic is not None:
        rate = interface.traffic.rate_hz
        parts.append(
            Text(
                f"{interface.traffic.message_count} messages recorded"
                + (f", {rate:.1f} Hz" if rate is not None else ""),
                style="dim",
            )
        )
    for note in interface.notes:
        parts.append(Text(f"note: {note}", style="dim"))
    for role, definition in interface.definitions.items():
        origin = "" if definition.origin == "source" else " (standard definition, filled in)"
        parts.append(Text(f"\n{role}: {definition.type_name}{origin}", style="bold"))
        if definition.fields is not None:
            lines: list[str] = []
            for constant in definition.constants:
                lines.append(f"{constant.type} {constant.name}={constant.value}")
            _field_lines(definition.fields, 0, lines)
            parts.append(Text("\n".join(lines) or "(no fields)"))
        else:
            parts.append(Text(definition.raw))
        for note in definition.notes:
            parts.append(Text(f"note: {note}", style="dim"))
    return Group(*parts)
