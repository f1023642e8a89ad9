"""Grids over the floor: the occupancy map built from the lidar, and path planning.

The map is what a SLAM node would publish if its pose estimate were perfect: every scan is
traced into a grid from the true pose of the lidar (free cells along each beam, an occupied
cell where it ends). Beams without a return are left out, as slam_toolbox does by default.
Planning runs A* over a grid of the world's obstacles grown by the robot's radius and then
cuts corners wherever the straight line stays free.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = ["GridFrame", "OccupancyMap", "plan_path"]

UNKNOWN, FREE, OCCUPIED = -1, 0, 100


@dataclass(frozen=True)
class GridFrame:
    """Cells of ``resolution`` metres, ``width`` x ``height``, cell (0, 0) at ``origin``."""

    origin_x: float
    origin_y: float
    resolution: float
    width: int
    height: int

    @classmethod
    def covering(
        cls, x_min: float, y_min: float, x_max: float, y_max: float, resolution: float
    ) -> GridFrame:
        """The smallest grid of ``resolution`` that covers the rectangle."""
        width = max(1, math.ceil((x_max - x_min) / resolution))
        height = max(1, math.ceil((y_max - y_min) / resolution))
        return cls(x_min, y_min, resolution, width, height)

    def cell(self, x: float, y: float) -> tuple[int, int]:
        """Column and row of the cell holding ``(x, y)`` (may lie outside the grid)."""
        return (
            math.floor((x - self.origin_x) / self.resolution),
            math.floor((y - self.origin_y) / self.resolution),
        )

    def centre(self, column: int, row: int) -> tuple[float, float]:
        """The point at the middle of a cell."""
        return (
            self.origin_x + (column + 0.5) * self.resolution,
            self.origin_y + (row + 0.5) * self.resolution,
        )

    def inside(self, column: int, row: int) -> bool:
        """Whether the cell is part of the grid."""
        return 0 <= column < self.width and 0 <= row < self.height


class OccupancyMap:
    """Hit and pass counts per cell, from scans traced at known poses."""

    def __init__(
        self, frame: GridFrame, reference: tuple[float, float, float] = (0.0, 0.0, 0.0)
    ) -> None:
        import numpy as np

        self.frame = frame
        self.hits = np.zeros((frame.height, frame.width), dtype=np.int32)
        self.passes = np.zeros((frame.height, frame.width), dtype=np.int32)
        self.scans = 0
        self.reference = reference
        """A pose (x, y, heading) whose axes :attr:`extent` is measured along."""
        self._bounds = [math.inf, -math.inf, math.inf, -math.inf]

    def integrate(
        self,
        x: float,
        y: float,
        yaw: float,
        angles: NDArray[np.float64],
        ranges: NDArray[np.float64],
        range_max: float,
    ) -> None:
        """Trace one scan taken at ``(x, y, yaw)``; ``ranges`` without a return are ``inf``."""
        import numpy as np

        frame = self.frame
        valid = np.isfinite(ranges) & (ranges <= range_max)
        if not valid.any():
            return
        bearings = angles[valid] + yaw
        lengths = ranges[valid]
        step = frame.resolution / 2.0
        samples = np.arange(0.0, float(lengths.max()), step)
        # Points along each beam up to just short of its end: those cells are free.
        along = samples[None, :] < (lengths[:, None] - step)
        px = x + samples[None, :] * np.cos(bearings)[:, None]
        py = y + samples[None, :] * np.sin(bearings)[:, None]
        self._count(self.passes, px[along], py[along])
        self._count(self.hits, x + lengths * np.cos(bearings), y + lengths * np.sin(bearings))
        self.scans += 1

    def _count(
        self, target: NDArray[np.int32], px: NDArray[np.float64], py: NDArray[np.float64]
    ) -> None:
        """Count each cell the points fall in once (repeated indices add one, not several)."""
        import numpy as np

        frame = self.frame
        columns = np.floor((px - frame.origin_x) / frame.resolution).astype(np.int64)
        rows = np.floor((py - frame.origin_y) / frame.resolution).astype(np.int64)
        keep = (columns >= 0) & (columns < frame.width) & (rows >= 0) & (rows < frame.height)
        columns, rows = columns[keep], rows[keep]
        target.ravel()[rows * frame.width + columns] += 1
        if columns.size:
            # Known cells never become unknown again, so the extent only grows.
            rx, ry, heading = self.reference
            cx = frame.origin_x + (columns + 0.5) * frame.resolution - rx
            cy = frame.origin_y + (rows + 0.5) * frame.resolution - ry
            along = cx * math.cos(heading) + cy * math.sin(heading)
            across = -cx * math.sin(heading) + cy * math.cos(heading)
            bounds = self._bounds
            bounds[0] = min(bounds[0], float(along.min()))
            bounds[1] = max(bounds[1], float(along.max()))
            bounds[2] = min(bounds[2], float(across.min()))
            bounds[3] = max(bounds[3], float(across.max()))

    @property
    def extent(self) -> tuple[float, float]:
        """Extent of the known cells along and across the reference heading [m]."""
        lo_along, hi_along, lo_across, hi_across = self._bounds
        if lo_along > hi_along:
            return (0.0, 0.0)
        res = self.frame.resolution
        return (hi_along - lo_along + res, hi_across - lo_across + res)

    def states(self) -> NDArray[np.int8]:
        """Per cell: ``-1`` unknown, ``0`` free, ``100`` occupied (rows from the bottom)."""
        import numpy as np

        states = np.full(self.hits.shape, UNKNOWN, dtype=np.int8)
        seen = (self.hits + self.passes) > 0
        occupied = seen & (self.hits * 3 >= self.passes)
        states[seen] = FREE
        states[occupied] = OCCUPIED
        return states

    def cropped(self) -> tuple[GridFrame, NDArray[np.int8]]:
        """The bounding box of the known cells, as published (SLAM grows its map that way)."""
        import numpy as np

        states = self.states()
        rows, columns = np.nonzero(states != UNKNOWN)
        if rows.size == 0:
            frame = GridFrame(self.frame.origin_x, self.frame.origin_y, self.frame.resolution, 1, 1)
            return frame, np.full((1, 1), UNKNOWN, dtype=np.int8)
        r0, r1 = int(rows.min()), int(rows.max()) + 1
        c0, c1 = int(columns.min()), int(columns.max()) + 1
        res = self.frame.resolution
        frame = GridFrame(
            self.frame.origin_x + c0 * res, self.frame.origin_y + r0 * res, res, c1 - c0, r1 - r0
        )
        return frame, states[r0:r1, c0:c1]


def _line_free(blocked: NDArray[np.bool_], a: tuple[int, int], b: tuple[int, int]) -> bool:
    """Whether the straight line between two cell centres crosses only free cells."""
    steps = max(abs(b[0] - a[0]), abs(b[1] - a[1])) * 5 + 1
    for k in range(steps + 1):
        t = k / steps
        column = math.floor(a[0] + 0.5 + (b[0] - a[0]) * t)
        row = math.floor(a[1] + 0.5 + (b[1] - a[1]) * t)
        if blocked[row, column]:
            return False
    return True


def plan_path(
    blocked: NDArray[np.bool_],
    frame: GridFrame,
    start: tuple[float, float],
    goal: tuple[float, float],
) -> list[tuple[float, float]] | None:
    """Waypoints from ``start`` to ``goal`` through free cells, or ``None`` when the goal is
    blocked, outside the grid or unreachable. ``blocked[row, column]`` marks cells the
    robot's centre must not enter (obstacles already grown by its radius).
    """
    s = frame.cell(*start)
    g = frame.cell(*goal)
    if not frame.inside(*g) or blocked[g[1], g[0]] or not frame.inside(*s):
        return None
    if blocked[s[1], s[0]]:
        # The robot may start touching the grown obstacles; plan from where it is anyway.
        blocked = blocked.copy()
        blocked[s[1], s[0]] = False
    moves = [(dx, dy, math.hypot(dx, dy)) for dx in (-1, 0, 1) for dy in (-1, 0, 1) if dx or dy]
    best: dict[tuple[int, int], float] = {s: 0.0}
    parent: dict[tuple[int, int], tuple[int, int]] = {}
    queue: list[tuple[float, float, tuple[int, int]]] = [(0.0, 0.0, s)]
    while queue:
        _, cost, cell = heapq.heappop(queue)
        if cell == g:
            break
        if cost > best.get(cell, math.inf):
            continue
        for dx, dy, length in moves:
            nxt = (cell[0] + dx, cell[1] + dy)
            if not frame.inside(*nxt) or blocked[nxt[1], nxt[0]]:
                continue
            if dx and dy and (blocked[cell[1], nxt[0]] or blocked[nxt[1], cell[0]]):
                continue  # no squeezing diagonally between two blocked cells
            new = cost + length
            if new < best.get(nxt, math.inf):
                best[nxt] = new
                parent[nxt] = cell
                h = math.hypot(g[0] - nxt[0], g[1] - nxt[1])
                heapq.heappush(queue, (new + h, new, nxt))
    if g not in best:
        return None
    cells = [g]
    while cells[-1] != s:
        cells.append(parent[cells[-1]])
    cells.reverse()
    # Keep a cell only where the straight line from the last kept one would hit something.
    kept = [cells[0]]
    for index in range(1, len(cells)):
        if not _line_free(blocked, kept[-1], cells[index]):
            kept.append(cells[index - 1])
    kept.append(g)
    points = [frame.centre(*c) for c in kept[1:-1]]
    return [start, *points, goal]
