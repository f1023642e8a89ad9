"""The simulation of a result: every oracle's verdict and the base's path and speed.

The table lists every verdict of every scenario and run, passed ones too, with the values
the oracle measured, what it expected (its check, e.g. ``abs(outDistance - inDistance) <=
0.02``) and its tolerance: the numbers an engineer needs to judge a near miss, which the
record holds and the summary line cannot show. The plots are drawn from the trace the
pipeline keeps beside the record (``simulation.trace.json``: the base's ground truth at
20 Hz): the path from above and the speed over time, each run in its own colour, the
resource's limits the run was judged against as lines, as in the PNG plot.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from rich.text import Text
from textual.app import ComposeResult
from textual.containers import VerticalScroll
from textual.widgets import DataTable, Static

from skillwright.pipeline.verdict import Verdict
from skillwright.tui.widgets.plot import Series, braille_plot

__all__ = ["ORACLE_COLUMNS", "SimulationView", "read_trajectories", "verdict_of"]

ORACLE_COLUMNS = ("", "where", "oracle", "measured", "expected", "tolerance", "message")

_RUN_STYLES = {"normal": "dodger_blue1", "stop": "dark_orange"}
_YAW_STYLES = {"normal": "light_sky_blue3", "stop": "light_salmon3"}
_RUN_LABELS = {"normal": "run", "stop": "run stopped during execute"}
_LIMIT_STYLES = ("red", "magenta", "bright_red", "deep_pink2")


def verdict_of(passed: bool | None) -> Verdict:
    """An oracle's verdict: passed, failed, or skipped when it does not apply to the run."""
    if passed is None:
        return Verdict.SKIPPED
    return Verdict.PASSED if passed else Verdict.FAILED


def _value(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def _measured(measured: dict[str, Any]) -> str:
    return ", ".join(f"{key}={_value(value)}" for key, value in measured.items())


Sample = tuple[float, float, float, float, float]
"""(t, x, y, speed, |yaw rate|) of the base at one moment."""


def read_trajectories(trace: Path) -> dict[str, list[Sample]]:
    """The base's samples per run of ``trace`` (a ``simulation.trace.json``), by run name;
    empty when the file is missing or holds no ground truth."""
    try:
        document = json.loads(trace.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    runs: dict[str, list[Sample]] = {}
    for episode in document.get("episodes", []):
        truth = episode.get("ground_truth") or {}
        columns = truth.get("columns", [])
        wanted = ("t", "x", "y", "vx", "vy", "wz")
        if not set(wanted) <= set(columns):
            continue
        at = {name: columns.index(name) for name in wanted}
        runs[str(episode.get("name", f"run {len(runs) + 1}"))] = [
            (
                row[at["t"]],
                row[at["x"]],
                row[at["y"]],
                math.hypot(row[at["vx"]], row[at["vy"]]),
                abs(row[at["wz"]]),
            )
            for row in truth.get("samples", [])
            if all(isinstance(row[i], int | float) for i in at.values())
        ]
    return runs


class SimulationView(VerticalScroll):
    """The oracle table and the plots of one result (:meth:`show`)."""

    def __init__(self, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self.verdicts: list[Any] = []
        """The verdicts in table order."""
        self.trajectories: dict[str, list[Sample]] = {}
        """The base's samples per run of the default scenario."""
        self._limits: list[tuple[str, float]] = []

    def compose(self) -> ComposeResult:
        yield Static("", id="simulation-head", markup=False)
        yield DataTable(id="simulation-oracles", cursor_type="row", zebra_stripes=True)
        yield Static("", id="simulation-oracle", markup=False)
        yield Static("", id="simulation-plot", markup=False)

    def on_mount(self) -> None:
        self.query_one(DataTable).add_columns(*ORACLE_COLUMNS)

    def show(self, simulation: Any, folder: Path) -> None:
        """Shows ``simulation`` (a ``SimulationRecord`` or ``None``) of the result in
        ``folder``."""
        head = self.query_one("#simulation-head", Static)
        table = self.query_one(DataTable)
        table.clear()
        self.verdicts = []
        self.trajectories = {}
        self._limits = []
        self.query_one("#simulation-oracle", Static).update("")
        if simulation is None:
            head.update("This result was not simulated (the simulate stage was turned off).")
            self._plot()
            return
        if simulation.skipped is not None:
            head.update(f"Not simulated: {simulation.skipped}")
            self._plot()
            return
        judged = [v for v in simulation.verdicts if v.passed is not None]
        failed = sum(v.passed is False for v in judged)
        speed = f", {simulation.speed:.0f}x real time" if simulation.speed else ""
        inputs = ", ".join(f"{k}={_value(v)}" for k, v in simulation.inputs.items())
        head.update(
            f"{simulation.where} in the {simulation.world} world ({inputs}): "
            f"{len(judged) - failed}/{len(judged)} verdicts passed{speed}"
        )
        # Failed ones first: they are what the user came for; the rest in the record's order.
        self.verdicts = sorted(simulation.verdicts, key=lambda v: v.passed is not False)
        for verdict in self.verdicts:
            mark = verdict_of(verdict.passed)
            tolerance = "" if verdict.tolerance is None else _value(verdict.tolerance)
            table.add_row(
                Text(mark.mark, style=mark.style),
                Text(simulation.verdict_place(verdict)),
                Text(verdict.oracle, style=mark.style if verdict.passed is False else ""),
                Text(_measured(verdict.measured)),
                Text(verdict.check),
                Text(tolerance),
                Text(verdict.message),
            )
        if simulation.trace:
            self.trajectories = read_trajectories(folder / simulation.trace)
        # The resource's limits the default scenario's normal run was judged against, as in
        # the PNG plot.
        self._limits = [
            (v.oracle, float(v.measured["limit"]))
            for v in simulation.verdicts
            if v.kind == "limit"
            and v.episode == "normal"
            and v.scenario in (None, simulation.scenario)
            and isinstance(v.measured.get("limit"), int | float)
        ]
        self._plot()
        self.show_oracle(0)

    def show_oracle(self, row: int) -> None:
        """The whole verdict of table row ``row`` (the table cuts long cells)."""
        box = self.query_one("#simulation-oracle", Static)
        if not 0 <= row < len(self.verdicts):
            box.update("")
            return
        verdict = self.verdicts[row]
        mark = verdict_of(verdict.passed)
        text = Text()
        text.append(f"{mark.mark} {mark.word}", style=mark.style)
        text.append(f"  {verdict.oracle} ({verdict.kind})\n")
        text.append(f"expected: {verdict.check}\n")
        if verdict.measured:
            text.append(f"measured: {_measured(verdict.measured)}\n")
        if verdict.tolerance is not None:
            text.append(f"tolerance: {_value(verdict.tolerance)}\n")
        when = [f"at {verdict.time:.2f} s"] if verdict.time is not None else []
        when += [f"in {verdict.state}"] if verdict.state else []
        text.append(verdict.message + (f" ({', '.join(when)})" if when else ""))
        box.update(text)

    def on_data_table_row_highlighted(self, event: DataTable.RowHighlighted) -> None:
        event.stop()
        self.show_oracle(event.cursor_row)

    def on_resize(self) -> None:
        self._plot()

    def _plot(self) -> None:
        box = self.query_one("#simulation-plot", Static)
        if not self.trajectories:
            box.update(Text("no trajectory to plot", style="dim") if self.verdicts else "")
            return
        width = max(20, self.size.width - 12)
        runs = self.trajectories.items()
        paths = [
            Series(
                [(x, y) for _t, x, y, _v, _w in samples],
                _RUN_STYLES.get(name, "white"),
                _RUN_LABELS.get(name, name),
            )
            for name, samples in runs
        ]
        speeds = []
        for name, samples in runs:
            label = _RUN_LABELS.get(name, name)
            speeds.append(
                Series(
                    [(t, v) for t, _x, _y, v, _w in samples],
                    _RUN_STYLES.get(name, "white"),
                    f"speed m/s ({label})",
                )
            )
            speeds.append(
                Series(
                    [(t, w) for t, _x, _y, _v, w in samples],
                    _YAW_STYLES.get(name, "grey50"),
                    f"|yaw rate| rad/s ({label})",
                )
            )
        end = max(t for samples in self.trajectories.values() for t, *_ in samples)
        for (oracle, value), style in zip(self._limits, _LIMIT_STYLES, strict=False):
            speeds.append(Series([(0.0, value), (end, value)], style, oracle))
        text = Text("path from above (map frame, m)\n", style="bold")
        text.append_text(
            braille_plot(paths, width, 10, x_label="x [m]", y_label="y [m]", equal_axes=True)
        )
        text.append("\n\nspeed over time\n", style="bold")
        text.append_text(
            braille_plot(speeds, width, 6, x_label="t [s]", y_label="m/s, rad/s", y_floor=0.0)
        )
        box.update(text)
