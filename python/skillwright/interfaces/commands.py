"""``skillwright discover``: the interfaces of a recording, a report or the live ROS 2 graph.

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

    from skillwright.interfaces.inventory import Endpoints, Inventory, Source, SourceFile
    from skillwright.interfaces.sources.bag import ReadMode

__all__ = ["discover", "render_summary"]


@click.command()
@click.argument("source", required=False, type=click.Path(path_type=Path))
@click.option(
    "--live",
    is_flag=True,
    help="Discover the running ROS 2 graph instead (needs ROS 2 sourced in this shell).",
)
@click.option(
    "--timeout",
    type=click.FloatRange(min=0, min_open=True),
    default=10.0,
    show_default=True,
    help="--live: seconds to wait for two consecutive snapshots of the graph to agree.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON only.")
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    help="Write the result (JSON) to this file.",
)
@click.option(
    "--format",
    "output_format",
    type=click.Choice(["inventory", "report"]),
    default="inventory",
    show_default=True,
    help="What -o and --json write: a skillwright inventory, or the reference tool's "
    "(LLMCap2Skill) report JSON.",
)
@click.option(
    "--read",
    "mode",
    type=click.Choice(["auto", "scan", "full"]),
    default="auto",
    show_default=True,
    help="Recordings only. auto: summary section when complete, else scan; scan: ignore "
    "the summary; full: also decompress every chunk.",
)
@click.option(
    "--name",
    "--resource",
    "resource_name",
    help="Resource name (default: the recording's or report's name).",
)
def discover(
    source: Path | None,
    live: bool,
    timeout: float,
    as_json: bool,
    output: Path | None,
    output_format: str,
    mode: str,
    resource_name: str | None,
) -> None:
    """Discover the ROS 2 topics, services and actions in SOURCE, or on the live graph.

    SOURCE is an .mcap file, a rosbag2 folder (metadata.yaml plus split .mcap files), or
    a report of the reference tool (JSON, told apart by content). With --live, a
    short-lived node lists the running graph until two snapshots agree. Prints a summary
    in the spirit of `ros2 bag info`; the inventory, with every interface's full message
    definition, goes to -o FILE and/or stdout with --json (--format report writes the
    reference tool's report instead).
    """
    from skillwright.errors import InvalidArgumentError

    if live == (source is not None):
        raise InvalidArgumentError(
            "give either a SOURCE (.mcap file, rosbag2 folder, report .json) or --live, not both"
            if live
            else "give a SOURCE (.mcap file, rosbag2 folder, report "
            ".json) or --live for the running ROS 2 graph"
        )
    if source is None:
        from skillwright.console import err_console
        from skillwright.interfaces.sources.live import LiveSource

        err_console().print(
            f"discovering the live ROS 2 graph (up to {timeout:g} s) ...", soft_wrap=True
        )
        inventory = LiveSource(timeout=timeout, resource_name=resource_name).discover()
    else:
        from skillwright.interfaces.load import discover_path

        inventory = discover_path(source, cast("ReadMode", mode), resource_name)
    _emit(inventory, as_json=as_json, output=output, output_format=output_format)


def _emit(inventory: Inventory, *, as_json: bool, output: Path | None, output_format: str) -> None:
    """Writes and prints a discovered inventory as the options ask."""
    import sys

    from skillwright.console import err_console, out_console
    from skillwright.fileio import write_atomic

    notes: list[str] = []
    if output_format == "report":
        from skillwright.interfaces.sources.report import report_text

        text, notes = report_text(inventory)
        text += "\n"
    else:
        text = inventory.model_dump_json(indent=2) + "\n"
    if output is not None:
        write_atomic(output, text)
    if as_json:
        sys.stdout.write(text)
    else:
        render_summary(inventory, out_console())
    _warn_partial(inventory, err_console(), notes)
    if output is not None and not as_json:
        what = "report" if output_format == "report" else "inventory"
        out_console().print(f"{what} written to {output}", soft_wrap=True)


def _time(ns: int | None) -> str:
    if ns is None:
        return "-"
    from datetime import UTC, datetime

    return datetime.fromtimestamp(ns / 1e9, tz=UTC).isoformat(timespec="milliseconds")


def _chunks(files: list[SourceFile]) -> str:
    count = sum(f.chunk_count for f in files)
    kinds = sorted({c or "none" for f in files for c in f.compressions})
    return f"{count} ({', '.join(kinds)})" if kinds else str(count)


def _endpoints(endpoints: Endpoints | None) -> str:
    if endpoints is None:
        return "-"
    if endpoints.servers is not None or endpoints.clients is not None:
        return f"{endpoints.servers or 0} srv / {endpoints.clients or 0} cli"
    return f"{endpoints.publishers or 0} pub / {endpoints.subscribers or 0} sub"


def _render_recording_source(source: Source, console: Console) -> None:
    """Source lines of a recording, like ``ros2 bag info``."""
    from rich.markup import escape

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


def _render_other_source(source: Source, console: Console) -> None:
    """Source lines of a report or the live graph: no files, durations or chunks."""
    from rich.markup import escape

    kinds = {"report": "report", "ros2_live": "live ROS 2 graph"}
    lines = [("Source", f"{escape(source.location)} ({kinds.get(source.kind, source.kind)})")]
    if source.captured_at:
        lines.append(("Captured", escape(source.captured_at)))
    if source.ros_distro:
        lines.append(("ROS distro", escape(source.ros_distro)))
    for label, value in lines:
        console.print(f"[bold]{label + ':':<12}[/bold]{value}", soft_wrap=True)


def render_summary(inventory: Inventory, console: Console) -> None:
    """Prints duration, counts and a table of the interfaces, like ``ros2 bag info``."""
    from rich.markup import escape
    from rich.table import Table

    for source in inventory.sources:
        if source.kind in ("mcap", "rosbag2"):
            _render_recording_source(source, console)
        else:
            _render_other_source(source, console)
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
    # Recordings have messages and rates, a live graph has endpoints, a report neither.
    recorded = any(source.kind in ("mcap", "rosbag2") for source in inventory.sources)
    live = any(entry.endpoints is not None for entry in inventory.interfaces)
    if recorded:
        table.add_column("Messages", justify="right")
        table.add_column("Rate (Hz)", justify="right")
    if live:
        table.add_column("Endpoints")
    table.add_column("Infrastructure")
    approximate = False
    for entry in inventory.interfaces:
        traffic = entry.traffic
        rate = "-"
        if traffic is not None and traffic.rate_hz is not None:
            rate = f"{traffic.rate_hz:.2f}" if traffic.times_exact else f"~{traffic.rate_hz:.2f}"
            approximate = approximate or not traffic.times_exact
        columns = []
        if recorded:
            columns += [str(traffic.message_count) if traffic is not None else "-", rate]
        if live:
            columns.append(_endpoints(entry.endpoints))
        table.add_row(
            entry.kind,
            escape(entry.name),
            escape(entry.type_name or "?"),
            *columns,
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


def _warn_partial(inventory: Inventory, console: Console, notes: list[str]) -> None:
    from rich.markup import escape

    from skillwright.interfaces.load import read_warnings
    from skillwright.interfaces.sources.live import NOT_SETTLED

    def say(label: str, text: str) -> None:
        console.print(f"[yellow]{label}:[/yellow] {escape(text)}", soft_wrap=True)

    for warning in read_warnings(inventory):
        say("warning", warning)
    for source in inventory.sources:
        for note in source.notes:
            say("warning" if note.startswith(NOT_SETTLED) else "note", note)
    for note in notes:
        say("note", note)
