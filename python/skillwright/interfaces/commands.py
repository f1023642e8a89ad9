"""``skillwright discover``: the interfaces recorded in an MCAP file or rosbag2 folder.

Only click is imported at module level; the Rust core, pydantic and rich load inside
the command.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, cast

import click

from skillwright.console import human_size

if TYPE_CHECKING:
    from rich.console import Console

    from skillwright.interfaces.inventory import Inventory, SourceFile
    from skillwright.interfaces.sources.bag import ReadMode

__all__ = ["discover", "render_summary"]


@click.command()
@click.argument("path", type=click.Path(path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print the inventory as JSON only.")
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    help="Write the inventory (JSON) to this file.",
)
@click.option(
    "--read",
    "mode",
    type=click.Choice(["auto", "scan", "full"]),
    default="auto",
    show_default=True,
    help="auto: summary section when complete, else scan; scan: ignore the summary; "
    "full: also decompress every chunk.",
)
@click.option("--name", "resource_name", help="Resource name (default: the recording's name).")
def discover(
    path: Path, as_json: bool, output: Path | None, mode: str, resource_name: str | None
) -> None:
    """Discover the ROS 2 topics, services and actions recorded in PATH.

    PATH is an .mcap file or a rosbag2 folder (metadata.yaml plus split .mcap files).
    Prints a summary in the spirit of `ros2 bag info`; the inventory, with every
    interface's full message definition, goes to -o FILE and/or stdout with --json.
    """
    from skillwright.console import err_console, out_console, print_model_json
    from skillwright.fileio import write_atomic
    from skillwright.interfaces.sources.bag import discover_bag

    inventory = discover_bag(path, cast("ReadMode", mode), resource_name)
    if output is not None:
        write_atomic(output, inventory.model_dump_json(indent=2) + "\n")
    if as_json:
        print_model_json(inventory)
        _warn_partial(inventory, err_console())
        return
    render_summary(inventory, out_console())
    _warn_partial(inventory, err_console())
    if output is not None:
        out_console().print(f"inventory written to {output}", soft_wrap=True)


def _time(ns: int | None) -> str:
    if ns is None:
        return "-"
    from datetime import UTC, datetime

    return datetime.fromtimestamp(ns / 1e9, tz=UTC).isoformat(timespec="milliseconds")


def _chunks(files: list[SourceFile]) -> str:
    count = sum(f.chunk_count for f in files)
    kinds = sorted({c or "none" for f in files for c in f.compressions})
    return f"{count} ({', '.join(kinds)})" if kinds else str(count)


def render_summary(inventory: Inventory, console: Console) -> None:
    """Prints duration, counts and a table of the interfaces, like ``ros2 bag info``."""
    from rich.markup import escape
    from rich.table import Table

    for source in inventory.sources:
        total_size = sum(f.size_bytes for f in source.files)
        methods = sorted({f.read_method for f in source.files})
        duration = source.duration_ns
        lines = [
            ("Recording", f"{escape(source.location)} ({source.kind})"),
            (
                "Files",
                f"{len(source.files)}, {human_size(total_size)}, read by {', '.join(methods)}",
            ),
            ("Duration", f"{duration / 1e9:.3f} s" if duration is not None else "-"),
            ("Start", _time(source.start_time_ns)),
            ("End", _time(source.end_time_ns)),
            ("Messages", str(source.message_count or 0)),
            ("Chunks", _chunks(source.files)),
        ]
        if source.ros_distro:
            lines.append(("ROS distro", source.ros_distro))
        for label, value in lines:
            console.print(f"[bold]{label + ':':<12}[/bold]{value}", soft_wrap=True)
    counts = {
        kind: sum(i.kind == kind for i in inventory.interfaces)
        for kind in ("topic", "service", "action")
    }
    console.print(
        f"[bold]{'Interfaces:':<12}[/bold]{counts['topic']} topics, {counts['service']} "
        f"services, {counts['action']} actions",
        soft_wrap=True,
    )
    table = Table(show_edge=False, pad_edge=False)
    table.add_column("Kind")
    table.add_column("Name", overflow="fold")
    table.add_column("Type", overflow="fold")
    table.add_column("Messages", justify="right")
    table.add_column("Rate (Hz)", justify="right")
    table.add_column("Infrastructure")
    approximate = False
    for entry in inventory.interfaces:
        traffic = entry.traffic
        rate = "-"
        if traffic is not None and traffic.rate_hz is not None:
            rate = f"{traffic.rate_hz:.2f}" if traffic.times_exact else f"~{traffic.rate_hz:.2f}"
            approximate = approximate or not traffic.times_exact
        table.add_row(
            entry.kind,
            escape(entry.name),
            escape(entry.type_name or "?"),
            str(traffic.message_count) if traffic is not None else "-",
            rate,
            entry.infrastructure.rule if entry.infrastructure is not None else "",
        )
    # Piped output is not cut to 80 columns: type names stay whole for grep and diff.
    if console.is_terminal:
        console.print(table)
    else:
        from rich.measure import Measurement

        saved = console.width
        console.width = max(
            saved, Measurement.get(console, console.options.update_width(10_000), table).maximum
        )
        try:
            console.print(table)
        finally:
            console.width = saved
    if approximate:
        console.print(
            "~ rate over chunk time bounds from the summary section; --read scan gives "
            "exact first/last times",
            soft_wrap=True,
        )
    noted = [(entry.name, note) for entry in inventory.interfaces for note in entry.notes]
    if noted:
        console.print("[bold]Notes:[/bold]")
        for name, note in noted:
            console.print(f"  {name}: {note}", markup=False, soft_wrap=True)


def _warn_partial(inventory: Inventory, console: Console) -> None:
    from rich.markup import escape

    def say(label: str, text: str) -> None:
        console.print(f"[yellow]{label}:[/yellow] {escape(text)}", soft_wrap=True)

    for source in inventory.sources:
        for file in source.files:
            if file.read_method == "unreadable" and file.stopped_at is not None:
                say("warning", f"skipped {file.stopped_at.message}")
            elif file.stopped_at is not None:
                say(
                    "warning",
                    f"{file.path}: read only up to byte {file.stopped_at.offset}: "
                    f"{file.stopped_at.message}",
                )
            for damage in file.damaged:
                say("warning", f"{file.path}: byte {damage.offset}: {damage.message}")
        for note in source.notes:
            say("note", note)
