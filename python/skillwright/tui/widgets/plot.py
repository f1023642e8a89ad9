"""Line plots drawn in the terminal with Unicode braille characters.

Each character cell holds a 2 x 4 grid of dots (U+2800 to U+28FF), so a plot of ``width``
columns and ``height`` rows has ``2 * width`` by ``4 * height`` points: enough to see a
path from above or a speed profile in a side column. Series keep their own colour; a cell
that two series share takes the later one's. Only Rich is used, no plotting library, so the
plot costs nothing at start-up and looks the same in every terminal with a Unicode font.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

from rich.text import Text

__all__ = ["Series", "braille_plot"]

# The bit of each dot in a braille cell, by (column, row) within the cell.
_DOTS = ((0x01, 0x02, 0x04, 0x40), (0x08, 0x10, 0x20, 0x80))


@dataclass(frozen=True)
class Series:
    """One line: points in data coordinates, its colour and its name in the legend."""

    points: Sequence[tuple[float, float]]
    style: str
    label: str


def _span(values: Sequence[float], equal_to: float | None = None) -> tuple[float, float]:
    low, high = min(values), max(values)
    if equal_to is not None and high - low < equal_to:
        middle = (low + high) / 2
        low, high = middle - equal_to / 2, middle + equal_to / 2
    if high - low < 1e-9:
        low, high = low - 0.5, high + 0.5
    return low, high


def _number(value: float) -> str:
    return f"{value:.2f}" if abs(value) < 100 else f"{value:.0f}"


def braille_plot(
    series: Sequence[Series],
    width: int,
    height: int,
    *,
    x_label: str,
    y_label: str,
    equal_axes: bool = False,
    y_floor: float | None = None,
) -> Text:
    """``series`` drawn into ``width`` x ``height`` cells, with the ranges of both axes and a
    legend underneath.

    ``equal_axes`` gives x and y the same scale (a path seen from above keeps its shape; a
    cell is about twice as high as wide, as are its dot rows and columns together);
    ``y_floor`` puts the lower end of y there (speeds start at 0).
    """
    points = [p for s in series for p in s.points if math.isfinite(p[0]) and math.isfinite(p[1])]
    if not points or width < 4 or height < 2:
        return Text("(nothing to plot)", style="dim")
    dots_x, dots_y = 2 * width, 4 * height
    x_low, x_high = _span([p[0] for p in points])
    y_values = [p[1] for p in points] + ([y_floor] if y_floor is not None else [])
    y_low, y_high = _span(y_values)
    if equal_axes:
        # One dot step in x covers as much as one in y: a cell is 2 dots wide, 4 high and
        # about twice as high as wide, so a dot is about as wide as it is high.
        per_dot = max((x_high - x_low) / (dots_x - 1), (y_high - y_low) / (dots_y - 1))
        x_mid, y_mid = (x_low + x_high) / 2, (y_low + y_high) / 2
        x_low, x_high = x_mid - per_dot * (dots_x - 1) / 2, x_mid + per_dot * (dots_x - 1) / 2
        y_low, y_high = y_mid - per_dot * (dots_y - 1) / 2, y_mid + per_dot * (dots_y - 1) / 2
    cells = [[0] * width for _ in range(height)]
    styles: list[list[str | None]] = [[None] * width for _ in range(height)]

    def dot(x: float, y: float, style: str) -> None:
        column = round((x - x_low) / (x_high - x_low) * (dots_x - 1))
        row = round((y_high - y) / (y_high - y_low) * (dots_y - 1))
        if 0 <= column < dots_x and 0 <= row < dots_y:
            cells[row // 4][column // 2] |= _DOTS[column % 2][row % 4]
            styles[row // 4][column // 2] = style

    for each in series:
        finite = [p for p in each.points if math.isfinite(p[0]) and math.isfinite(p[1])]
        for (x0, y0), (x1, y1) in itertools.pairwise(finite):
            # Enough steps that consecutive dots touch: the line has no gaps.
            steps = max(
                1,
                round(abs(x1 - x0) / (x_high - x_low) * dots_x),
                round(abs(y1 - y0) / (y_high - y_low) * dots_y),
            )
            for i in range(steps + 1):
                dot(x0 + (x1 - x0) * i / steps, y0 + (y1 - y0) * i / steps, each.style)
        if len(finite) == 1:
            dot(*finite[0], each.style)

    text = Text(no_wrap=True, overflow="crop")
    top, bottom = _number(y_high), _number(y_low)
    gutter = max(len(top), len(bottom))
    for row in range(height):
        label = top if row == 0 else bottom if row == height - 1 else ""
        text.append(f"{label:>{gutter}} │", style="dim")
        for column in range(width):
            bits = cells[row][column]
            text.append(chr(0x2800 + bits), style=styles[row][column] or "")
        text.append("\n")
    left, right = _number(x_low), _number(x_high)
    axis = f"{left}{x_label:^{max(0, width - len(left) - len(right))}}{right}"
    text.append(" " * gutter + " └" + axis + "\n", style="dim")
    # The legend, wrapped to the plot's width: one entry is never split.
    line = len(y_label) + 2
    text.append(" " * gutter + f"  {y_label}  ", style="dim")
    for each in series:
        entry = f"━ {each.label}  "
        if line + len(entry) > width + 2 and line > 0:
            text.append("\n" + " " * (gutter + 2))
            line = 0
        text.append("━ ", style=each.style)
        text.append(f"{each.label}  ")
        line += len(entry)
    return text
