"""The trajectory plot of a scenario (PNG, matplotlib's Agg backend, no display needed).

Left: the world from above — obstacles, the base's path in each run, its footprint at the
end, contacts, navigation goals. Right: speed and yaw rate over time with the resource's
limits and the states that ran, so a limit exceeded or a base that never stops shows at once.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

from skillwright.fileio import write_atomic

if TYPE_CHECKING:
    from skillwright.sim.report import ScenarioReport
    from skillwright.sim.scenario import Scenario
    from skillwright.sim.world import MujocoWorld

__all__ = ["plot_scenario"]

_COLOURS = {"normal": "#1f6fb4", "stop": "#e07b00"}


def plot_scenario(
    path: Path, scenario: Scenario, report: ScenarioReport, worlds: list[MujocoWorld]
) -> None:
    """Draw ``scenario``'s runs (one world per run, in the report's order) into ``path``."""
    import io

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle, Polygon

    figure = Figure(figsize=(12, 5.2), dpi=100)
    FigureCanvasAgg(figure)
    plan, speeds = figure.subplots(1, 2, gridspec_kw={"width_ratios": [1.15, 1]})
    world = worlds[0]
    for kind, cx, cy, sx, sy, yaw in world.obstacle_outlines():
        if kind == "box":
            plan.add_patch(Polygon(_rectangle(cx, cy, sx, sy, yaw), closed=True, color="#9aa0a6"))
        else:
            plan.add_patch(Circle((cx, cy), sx, color="#9aa0a6"))
    xs_all: list[float] = []
    ys_all: list[float] = []
    half_length, half_width = world.footprint()
    for episode, run_world in zip(report.episodes, worlds, strict=False):
        truth = run_world.truth
        colour = _COLOURS.get(episode.episode, "black")
        xs = [s.x for s in truth.samples]
        ys = [s.y for s in truth.samples]
        xs_all += xs
        ys_all += ys
        label = "run" if episode.episode == "normal" else "run stopped during execute"
        plan.plot(xs, ys, color=colour, linewidth=1.6, label=label)
        end = truth.samples[-1]
        plan.add_patch(
            Polygon(
                _rectangle(end.x, end.y, half_length, half_width, end.yaw),
                closed=True,
                fill=False,
                edgecolor=colour,
                linewidth=1.0,
            )
        )
        for contact in truth.contacts:
            plan.plot(contact.x, contact.y, "x", color="#c5221f", markersize=10, mew=2)
        for goal in truth.goals:
            target = goal.get("target_xy")
            if target:
                plan.plot(*target, "*", color=colour, markersize=12)
        times = [s.t for s in truth.samples]
        speeds.plot(times, [s.speed for s in truth.samples], color=colour, label=f"speed ({label})")
        speeds.plot(
            times,
            [abs(s.wz) for s in truth.samples],
            color=colour,
            linestyle=":",
            label=f"|yaw rate| ({label})",
        )
    sx, sy, syaw = world.config.start
    plan.annotate(
        "",
        xy=(sx + 0.5 * math.cos(syaw), sy + 0.5 * math.sin(syaw)),
        xytext=(sx, sy),
        arrowprops={"arrowstyle": "->", "color": "black"},
    )
    if xs_all:
        margin = 1.0
        x0, x1 = min(xs_all) - margin, max(xs_all) + margin
        y0, y1 = min(ys_all) - margin, max(ys_all) + margin
        for _kind, cx, cy, hx, hy, _yaw in world.obstacle_outlines():
            reach = math.hypot(hx, hy)
            if x0 - 3 < cx < x1 + 3 and y0 - 3 < cy < y1 + 3:
                x0, x1 = min(x0, cx - reach), max(x1, cx + reach)
                y0, y1 = min(y0, cy - reach), max(y1, cy + reach)
        plan.set_xlim(x0, x1)
        plan.set_ylim(y0, y1)
    plan.set_aspect("equal")
    plan.set_xlabel("x [m] (map)")
    plan.set_ylabel("y [m] (map)")
    plan.grid(True, alpha=0.3)
    plan.legend(loc="best", fontsize=8)
    limits = [
        (v.check, float(v.measured["limit"]))
        for e in report.episodes[:1]
        for v in e.verdicts
        if v.kind == "limit" and "limit" in v.measured
    ]
    for check, value in limits:
        speeds.axhline(value, color="#c5221f", linestyle="--", linewidth=1)
        speeds.annotate(check, (0, value), fontsize=7, color="#c5221f", va="bottom")
    for episode in report.episodes[:1]:
        for verdict in episode.verdicts:
            if verdict.passed is False and verdict.time is not None:
                speeds.axvline(verdict.time, color="#c5221f", alpha=0.4)
    speeds.set_xlabel("virtual time [s]")
    speeds.set_ylabel("m/s, rad/s")
    speeds.grid(True, alpha=0.3)
    speeds.legend(loc="upper right", fontsize=7)
    failed = sum(1 for e in report.episodes for v in e.verdicts if v.passed is False)
    verdict = "passed" if failed == 0 else f"{failed} oracle(s) failed"
    figure.suptitle(f"{scenario.name} in {scenario.world}: {verdict}", fontsize=11)
    figure.tight_layout()
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png")
    write_atomic(path, buffer.getvalue())


def _rectangle(cx: float, cy: float, hx: float, hy: float, yaw: float) -> list[tuple[float, float]]:
    c, s = math.cos(yaw), math.sin(yaw)
    corners = [(hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy)]
    return [(cx + c * x - s * y, cy + s * x + c * y) for x, y in corners]
