"""``skillwright inventory show|describe``: read an inventory, and fill descriptions and verdicts.

Only click is imported at module level (``skillwright --help`` lists this group); pydantic,
rich, the Rust core and any model load inside the commands.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import click

if TYPE_CHECKING:
    from rich.console import Console
    from rich.table import Table

    from skillwright.interfaces.enrich import Engine, EnrichReport
    from skillwright.interfaces.inventory import Interface, Inventory

__all__ = ["inventory"]


@click.group("inventory")
def inventory() -> None:
    """Show a robot's interfaces, and describe and judge them for retrieval.

    INVENTORY is a saved inventory .json or anything `skillwright discover` reads from a
    path: an .mcap file, a rosbag2 folder, a Cap2Skill report .json.
    """


def _effective(interface: Interface) -> tuple[str, bool]:
    """The verdict retrieval acts on (category, whether stored), as retrieval decides it."""
    if interface.relevance is not None:
        return interface.relevance.category, True
    return ("infrastructure" if interface.infrastructure is not None else "control"), False


@inventory.command("show")
@click.argument("source", metavar="INVENTORY", type=click.Path(path_type=Path))
@click.option(
    "--kind", type=click.Choice(["topic", "service", "action"]), help="Only interfaces of a kind."
)
@click.option("--all", "show_all", is_flag=True, help="Include infrastructure interfaces.")
@click.option("--json", "as_json", is_flag=True, help="Print the entries as a JSON array.")
def show(source: Path, kind: str | None, show_all: bool, as_json: bool) -> None:
    """List the interfaces of INVENTORY with their relevance and description.

    Infrastructure (parameters, logging, lifecycle, ...) is left out unless --all, as
    retrieval leaves it out. An interface without a stored description shows the rules
    engine's, which is what retrieval uses for it.
    """
    from skillwright.console import out_console, warn
    from skillwright.interfaces.load import load_inventory, read_warnings

    loaded = load_inventory(source)
    warn(read_warnings(loaded))
    entries = [
        i
        for i in loaded.interfaces
        if (kind is None or i.kind == kind) and (show_all or _effective(i)[0] == "control")
    ]
    if as_json:
        import sys

        sys.stdout.write(json.dumps([i.model_dump(mode="json") for i in entries], indent=2) + "\n")
        return
    console = out_console()
    _print_table(console, _table(entries))
    hidden = sum(
        (kind is None or i.kind == kind) and _effective(i)[0] == "infrastructure"
        for i in loaded.interfaces
    )
    summary = f"{len(entries)} interface(s) of {loaded.resource.name}"
    if hidden and not show_all:
        summary += f"; {hidden} infrastructure hidden (--all shows them)"
    console.print(summary, markup=False, soft_wrap=True)
    if any(not _effective(i)[1] or i.description is None for i in entries):
        console.print(
            "* not stored: the verdict is the discovery flag and the description the rules "
            "engine's, as retrieval uses them; `skillwright inventory describe` stores both",
            markup=False,
            soft_wrap=True,
        )


def _short(text: str, limit: int = 90) -> str:
    return text if len(text) <= limit else text[: limit - 1].rstrip() + "…"


def _table(entries: list[Interface]) -> Table:
    from rich.markup import escape
    from rich.table import Table

    from skillwright.retrieval.documents import describe

    table = Table(show_edge=False, pad_edge=False)
    table.add_column("Name", overflow="fold")
    table.add_column("Kind")
    table.add_column("Type", overflow="fold")
    table.add_column("Relevance")
    table.add_column("Description", overflow="fold")
    table.add_column("By")
    for entry in entries:
        category, stored = _effective(entry)
        description = describe(entry)
        table.add_row(
            escape(entry.name),
            entry.kind,
            escape(entry.type_name),
            category if stored else f"{category}*",
            escape(_short(description.purpose)),
            escape(entry.description.engine) if entry.description is not None else "*",
        )
    return table


def _print_table(console: Console, table: Table) -> None:
    # Piped output is not cut to the terminal's width: names stay whole for grep and diff.
    if console.is_terminal:
        console.print(table)
        return
    from rich.measure import Measurement

    saved = console.width
    console.width = max(
        saved, Measurement.get(console, console.options.update_width(10_000), table).maximum
    )
    try:
        console.print(table)
    finally:
        console.width = saved


def _is_saved_inventory(path: Path) -> bool:
    """Whether ``path`` is a saved inventory document (so it may be rewritten in place)."""
    if not (path.is_file() and path.suffix.lower() == ".json"):
        return False
    try:
        document = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return False
    return isinstance(document, dict) and "resource" in document and "interfaces" in document


@inventory.command("describe")
@click.argument("source", metavar="INVENTORY", type=click.Path(path_type=Path))
@click.option(
    "--engine",
    type=click.Choice(["rules", "llm"]),
    default="rules",
    show_default=True,
    help="rules: deterministic, no model; llm: the local generation model (see models.toml).",
)
@click.option("--model", "model_id", help="Generation model id or alias (llm engine).")
@click.option(
    "--models",
    "models_file",
    type=click.Path(path_type=Path, dir_okay=False),
    help="A models.toml overriding the shipped one (llm engine).",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    help="Write the described inventory here (default: back into a saved inventory .json).",
)
@click.option(
    "--replace-report-descriptions",
    is_flag=True,
    help="Also replace descriptions that came with an imported report.",
)
def describe(
    source: Path,
    engine: str,
    model_id: str | None,
    models_file: Path | None,
    output: Path | None,
    replace_report_descriptions: bool,
) -> None:
    """Fill the description and relevance verdict of every interface of INVENTORY.

    The result is written atomically: back into INVENTORY when it is a saved inventory
    .json, else to -o FILE. The llm engine caches each answer by the interface's content
    and the model, so a re-run only asks about what changed.
    """
    from skillwright.console import err_console, out_console, warn
    from skillwright.errors import InvalidArgumentError
    from skillwright.fileio import write_atomic
    from skillwright.interfaces.load import load_inventory, read_warnings

    if model_id is not None and engine != "llm":
        raise InvalidArgumentError("--model chooses the model of the llm engine; add --engine llm")
    loaded = load_inventory(source)
    warn(read_warnings(loaded))
    target = output
    if target is None:
        if not _is_saved_inventory(source):
            raise InvalidArgumentError(
                f"{source} is not a saved inventory .json, so it cannot be rewritten in "
                "place; give -o FILE for the described inventory"
            )
        target = source
    if engine == "llm":
        report = _run_llm(loaded, model_id, models_file, replace_report_descriptions)
    else:
        from skillwright.interfaces.enrich import RulesEngine

        report = _run(loaded, RulesEngine(), replace_report_descriptions)
    write_atomic(target, report.inventory.model_dump_json(indent=2) + "\n")
    _summarise(report, target, out_console(), err_console())


def _run_llm(
    loaded: Inventory, model_id: str | None, models_file: Path | None, replace: bool
) -> EnrichReport:
    from skillwright.interfaces.enrich import LlmEngine
    from skillwright.llm import load_generator
    from skillwright.llm.config import load_registry

    generator = load_generator(load_registry(models_file), model_id)
    try:
        return _run(loaded, LlmEngine(generator), replace)
    finally:
        generator.close()


def _run(loaded: Inventory, engine: Engine, replace: bool) -> EnrichReport:
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn

    from skillwright.console import err_console
    from skillwright.interfaces.enrich import default_cache, enrich

    with Progress(
        TextColumn("describing ({task.fields[engine]})"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[current]}", markup=False),
        console=err_console(),
        transient=True,
    ) as bar:
        task = bar.add_task(
            "describe", total=len(loaded.interfaces), engine=engine.name, current=""
        )

        def progress(done: int, _total: int, name: str) -> None:
            bar.update(task, completed=done, current=name)

        return enrich(
            loaded,
            engine,
            cache=default_cache(),
            progress=progress,
            replace_source_descriptions=replace,
        )


def _summarise(report: EnrichReport, target: Path, out: Console, err: Console) -> None:
    total = len(report.inventory.interfaces)
    out.print(f"{total} interfaces: {', '.join(report.summary())}", markup=False, soft_wrap=True)
    out.print(
        f"relevance: {report.control} control, {report.infrastructure} infrastructure",
        markup=False,
        soft_wrap=True,
    )
    out.print(f"inventory written to {target}", markup=False, soft_wrap=True)
    for note in report.notes:
        err.print(f"note: {note}", markup=False, soft_wrap=True, style="yellow")
