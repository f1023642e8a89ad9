"""``skillwright spec ...``: check skill specifications."""

from __future__ import annotations

from pathlib import Path

import click

__all__ = ["spec"]


@click.group()
def spec() -> None:
    """Check skill specifications (behaviour per PackML state)."""


@spec.command("check")
@click.argument("file", type=click.Path(path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print the checked specification as JSON.")
def check(file: Path, as_json: bool) -> None:
    """Check the skill specification in FILE (.json or .yaml) and summarise it."""
    from skillwright.console import out_console, print_model_json
    from skillwright.spec.loader import load_spec

    skill_spec = load_spec(file)
    if as_json:
        print_model_json(skill_spec)
        return
    from rich.table import Table

    table = Table(
        title=f"{skill_spec.name} ({skill_spec.skill_interface}) — {skill_spec.description}",
        title_justify="left",
    )
    table.add_column("state", style="bold")
    table.add_column("behaviour", overflow="fold")
    for state, action in skill_spec.states.items():
        table.add_row(state, action)
    console = out_console()
    console.print(table)
    console.print(f"{file}: valid, {len(skill_spec.states)} states")
