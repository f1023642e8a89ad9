"""The trajectory plot of a scenario (PNG, matplotlib's Agg backend, no display needed).

Left: the world from above — obstacles, the base's path in each run, its footprint at the
end, contacts, navigation goals. Right: speed and yaw rate over time with the resource's
limits and the moments oracles failed, so a limit exceeded or a base that never stops shows
at once.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

from skillwright.fileio import write_atomic

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from skillwright.sim.report import ScenarioReport
    from skillwright.sim.scenario import Scenario
    from skillwright.sim.world import MujocoWorld

__all__ = ["plot_scenario"]

_COLOURS = {"normal": "#1f6fb4", "stop": "#e07b00"}
_OBSTACLE = "#9aa0a6"
_FAILURE = "#c5221f"


def _rectangle(cx: float, cy: float, hx: float, hy: float, yaw: float) -> list[tuple[float, float]]:
    c, s = math.cos(yaw), math.sin(yaw)
    corners = [(hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy)]
    return [(cx + c * x - s * y, cy + s * x + c * y) for x, y in corners]


def _label(episode: str) -> str:
    return "run" if episode == "normal" else "run stopped during execute"


def _draw_plan(axes: Axes, report: ScenarioReport, worlds: list[MujocoWorld]) -> None:
    from matplotlib.patches import Circle, Polygon

    world = worlds[0]
    outlines = world.obstacle_outlines()
    for kind, cx, cy, sx, sy, yaw in outlines:
        if kind == "box":
            axes.add_patch(Polygon(_rectangle(cx, cy, sx, sy, yaw), closed=True, color=_OBSTACLE))
        else:
            axes.add_patch(Circle((cx, cy), sx, color=_OBSTACLE))
    half_length, half_width = world.footprint()
    xs: list[float] = []
    ys: list[float] = []
    for episode, run_world in zip(report.episodes, worlds, strict=False):
        truth = run_world.truth
        colour = _COLOURS.get(episode.episode, "black")
        xs += [s.x for s in truth.samples]
        ys += [s.y for s in truth.samples]
        axes.plot(
            [s.x for s in truth.samples],
            [s.y for s in truth.samples],
            color=colour,
            linewidth=1.6,
            label=_label(episode.episode),
        )
        end = truth.samples[-1]
        footprint = _rectangle(end.x, end.y, half_length, half_width, end.yaw)
        axes.add_patch(Polygon(footprint, closed=True, fill=False, edgecolor=colour))
        for contact in truth.contacts:
            axes.plot(contact.x, contact.y, "x", color=_FAILURE, markersize=10, mew=2)
        for goal in truth.goals:
            if goal.get("target_xy"):
                axes.plot(*goal["target_xy"], "*", color=colour, markersize=12)
    sx, sy, syaw = world.config.start
    tip = (sx + 0.5 * math.cos(syaw), sy + 0.5 * math.sin(syaw))
    axes.annotate("", xy=tip, xytext=(sx, sy), arrowprops={"arrowstyle": "->"})
    if xs:
        # The paths with a metre around them, and every obstacle close to that area.
        x0, x1, y0, y1 = min(xs) - 1.0, max(xs) + 1.0, min(ys) - 1.0, max(ys) + 1.0
        for _kind, cx, cy, hx, hy, _yaw in outlines:
            reach = math.hypot(hx, hy)
            if x0 - 3 < cx < x1 + 3 and y0 - 3 < cy < y1 + 3:
                x0, x1 = min(x0, cx - reach), max(x1, cx + reach)
                y0, y1 = min(y0, cy - reach), max(y1, cy + reach)
        axes.set_xlim(x0, x1)
        axes.set_ylim(y0, y1)
    axes.set_aspect("equal")
    axes.set_xlabel("x [m] (map)")
    axes.set_ylabel("y [m] (map)")
    axes.grid(True, alpha=0.3)
    axes.legend(loc="best", fontsize=8)


def _draw_speeds(axes: Axes, report: ScenarioReport, worlds: list[MujocoWorld]) -> None:
    for episode, run_world in zip(report.episodes, worlds, strict=False):
        samples = run_world.truth.samples
        colour = _COLOURS.get(episode.episode, "black")
        times = [s.t for s in samples]
        label = _label(episode.episode)
        axes.plot(times, [s.speed for s in samples], color=colour, label=f"speed ({label})")
        axes.plot(
            times,
            [abs(s.wz) for s in samples],
            color=colour,
            linestyle=":",
            label=f"|yaw rate| ({label})",
        )
    for episode in report.episodes[:1]:
        for verdict in episode.verdicts:
            if verdict.kind == "limit" and "limit" in verdict.measured:
                value = float(verdict.measured["limit"])
                axes.axhline(value, color=_FAILURE, linestyle="--", linewidth=1)
                axes.annotate(verdict.check, (0, value), fontsize=7, color=_FAILURE, va="bottom")
            if verdict.passed is False and verdict.time is not None:
                axes.axvline(verdict.time, color=_FAILURE, alpha=0.4)
    axes.set_xlabel("virtual time [s]")
    axes.set_ylabel("m/s, rad/s")
    axes.grid(True, alpha=0.3)
    axes.legend(loc="upper right", fontsize=7)


def plot_scenario(
    path: Path, scenario: Scenario, report: ScenarioReport, worlds: list[MujocoWorld]
) -> None:
    """Draw ``scenario``'s runs (one world per run, in the report's order) into ``path``."""
    import io

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(12, 5.2), dpi=100)
    FigureCanvasAgg(figure)
    plan, speeds = figure.subplots(1, 2, gridspec_kw={"width_ratios": [1.15, 1]})
    _draw_plan(plan, report, worlds)
    _draw_speeds(speeds, report, worlds)
    failed = sum(1 for e in report.episodes for v in e.verdicts if v.passed is False)
    verdict = "passed" if failed == 0 else f"{failed} oracle(s) failed"
    figure.suptitle(f"{scenario.name} in {scenario.world}: {verdict}", fontsize=11)
    figure.tight_layout()
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png")
    write_atomic(path, buffer.getvalue())
