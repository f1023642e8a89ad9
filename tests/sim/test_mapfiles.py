"""Maps saved for a skill: safe names, map_server's files."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from skillwright.sim.grid import GridFrame, OccupancyMap
from skillwright.sim.mapfiles import safe_map_name, save_map


@pytest.mark.parametrize(
    ("url", "name"),
    [
        ("map-20260101", "map-20260101"),
        ("/tmp/run/room.yaml", "room"),
        ("../../etc/passwd", "passwd"),
        ("C:\\maps\\hall.pgm", "hall"),
        ("my map!", "my_map"),
        ("", "map"),
        ("..", "map"),
    ],
)
def test_a_url_becomes_a_safe_file_stem(url: str, name: str) -> None:
    assert safe_map_name(url) == name


def test_a_saved_map_is_a_trinary_pgm_with_its_yaml(tmp_path: Path) -> None:
    grid = OccupancyMap(GridFrame.covering(-1, -1, 3, 3, 0.1))
    angles = np.array([0.0, math.pi / 2])
    grid.integrate(0.0, 0.0, 0.0, angles, np.array([2.0, 1.0]), range_max=12.0)
    record = save_map(grid, "lab", tmp_path, "map")
    pgm, yaml = tmp_path / "lab.pgm", tmp_path / "lab.yaml"
    assert record["files"] == [str(yaml), str(pgm)]
    header, _, pixels = pgm.read_bytes().partition(b"255\n")
    width, height = (int(v) for v in header.split()[1:3])
    assert len(pixels) == width * height
    assert set(pixels) <= {0, 205, 254}
    assert "image: lab.pgm" in yaml.read_text()
    assert "resolution: 0.1" in yaml.read_text()


def test_without_a_folder_nothing_is_written(tmp_path: Path) -> None:
    grid = OccupancyMap(GridFrame.covering(0, 0, 1, 1, 0.1))
    assert save_map(grid, "x", None, "map")["files"] == []
    assert list(tmp_path.iterdir()) == []
