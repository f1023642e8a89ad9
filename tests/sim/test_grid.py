"""The lidar map and path planning over grids."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from skillwright.sim.grid import FREE, OCCUPIED, UNKNOWN, GridFrame, OccupancyMap, plan_path


def _wall_scan(distance: float, count: int = 360) -> tuple[np.ndarray, np.ndarray]:
    """A scan from the origin of a wall at x = distance (returns only ahead)."""
    angles = -math.pi + np.arange(count) * 2 * math.pi / count
    ranges = np.full(count, np.inf)
    ahead = np.cos(angles) > 0.2
    ranges[ahead] = distance / np.cos(angles[ahead])
    return angles, ranges


def test_a_scan_marks_free_cells_along_beams_and_occupied_cells_where_they_end() -> None:
    grid = OccupancyMap(GridFrame.covering(-1, -5, 5, 5, 0.05))
    grid.integrate(0.0, 0.0, 0.0, *_wall_scan(2.0), range_max=12.0)
    states = grid.states()
    frame = grid.frame
    column, row = frame.cell(1.0, 0.0)
    assert states[row, column] == FREE
    column, row = frame.cell(2.01, 0.0)
    assert states[row, column] == OCCUPIED
    column, row = frame.cell(-0.5, 0.0)
    assert states[row, column] == UNKNOWN


def test_the_extent_and_the_published_crop_cover_the_known_cells() -> None:
    grid = OccupancyMap(GridFrame.covering(-1, -5, 5, 5, 0.05))
    grid.integrate(0.0, 0.0, 0.0, *_wall_scan(2.0), range_max=12.0)
    along, across = grid.extent
    frame, states = grid.cropped()
    assert along == pytest.approx(frame.width * frame.resolution, abs=0.051)
    assert across == pytest.approx(frame.height * frame.resolution, abs=0.051)
    assert 2.0 <= along <= 2.2
    assert (states != UNKNOWN).any()


def test_an_empty_map_has_no_extent() -> None:
    grid = OccupancyMap(GridFrame.covering(0, 0, 1, 1, 0.1))
    grid.integrate(0.5, 0.5, 0.0, np.array([0.0]), np.array([np.inf]), range_max=12.0)
    assert grid.extent == (0.0, 0.0)
    assert grid.cropped()[1].shape == (1, 1)


def _blocked_with_wall(frame: GridFrame) -> np.ndarray:
    blocked = np.zeros((frame.height, frame.width), dtype=bool)
    for row in range(frame.height):
        _x, y = frame.centre(0, row)
        if y < 3.0:
            column, _ = frame.cell(2.0, y)
            blocked[row, column - 2 : column + 3] = True
    return blocked


def test_a_path_goes_around_an_obstacle_and_never_through_blocked_cells() -> None:
    frame = GridFrame.covering(0, 0, 4, 4, 0.1)
    blocked = _blocked_with_wall(frame)
    path = plan_path(blocked, frame, (0.5, 0.5), (3.5, 0.5))
    assert path is not None
    assert path[0] == (0.5, 0.5)
    assert path[-1] == (3.5, 0.5)
    assert max(y for _, y in path) > 3.0
    for (x0, y0), (x1, y1) in itertools.pairwise(path):
        for t in np.linspace(0, 1, 50):
            column, row = frame.cell(x0 + (x1 - x0) * t, y0 + (y1 - y0) * t)
            assert not blocked[row, column]


@pytest.mark.parametrize("goal", [(2.0, 0.5), (9.0, 9.0)])
def test_no_path_to_a_goal_inside_an_obstacle_or_outside_the_grid(
    goal: tuple[float, float],
) -> None:
    frame = GridFrame.covering(0, 0, 4, 4, 0.1)
    assert plan_path(_blocked_with_wall(frame), frame, (0.5, 0.5), goal) is None
