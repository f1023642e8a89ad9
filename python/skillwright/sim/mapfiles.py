"""Maps saved through the simulated map-saver services, in map_server's format.

The skill names a map (``map_url``, or slam_toolbox's ``name``); the trusted host writes it,
never where the untrusted skill points: only the name's last part is kept, made safe, and
the files (a PGM image and its YAML description) go into the run's own folder.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING, Any

from skillwright.fileio import write_atomic

if TYPE_CHECKING:
    from skillwright.sim.grid import OccupancyMap

__all__ = ["safe_map_name", "save_map"]


def safe_map_name(url: str) -> str:
    """The file stem a map url becomes: last path part, no suffix, only ``[A-Za-z0-9._-]``."""
    stem = re.split(r"[\\/]", url.strip())[-1]
    stem = re.sub(r"\.(ya?ml|pgm|png)$", "", stem, flags=re.IGNORECASE)
    stem = re.sub(r"[^A-Za-z0-9._-]", "_", stem).strip("._")
    return stem or "map"


def save_map(grid: OccupancyMap, url: str, folder: Path | None, frame: str) -> dict[str, Any]:
    """Write ``grid`` as ``<name>.pgm`` and ``<name>.yaml`` in ``folder`` (when given) and
    say what was saved."""
    import numpy as np

    grid_frame, states = grid.cropped()
    name = safe_map_name(url)
    record: dict[str, Any] = {
        "url": url,
        "name": name,
        "width": grid_frame.width,
        "height": grid_frame.height,
        "resolution": grid_frame.resolution,
        "files": [],
    }
    if folder is None:
        return record
    # map_server's trinary image: occupied black, free white, unknown grey; top row first.
    image = np.full(states.shape, 205, dtype=np.uint8)
    image[states == 0] = 254
    image[states == 100] = 0
    image = image[::-1]
    header = f"P5\n{grid_frame.width} {grid_frame.height}\n255\n".encode("ascii")
    pgm = folder / f"{name}.pgm"
    yaml_path = folder / f"{name}.yaml"
    write_atomic(pgm, header + image.tobytes())
    write_atomic(
        yaml_path,
        f"image: {pgm.name}\nmode: trinary\nresolution: {grid_frame.resolution}\n"
        f"origin: [{grid_frame.origin_x}, {grid_frame.origin_y}, 0.0]\n"
        f"negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.25\n# frame: {frame}\n",
    )
    record["files"] = [str(yaml_path), str(pgm)]
    return record
