"""Where the simulation's data lives: the MJCF robot, the worlds and the default scenarios.

They are kept in the repository's ``sim/`` folder (data, not code). ``$SKILLWRIGHT_SIM_DIR``
points elsewhere, e.g. at a copy next to an installed skillwright.
"""

from __future__ import annotations

import os
from pathlib import Path

from skillwright.errors import InputFileNotFoundError

__all__ = ["WORLD_NAMES", "resolve_world", "scenario_files", "sim_dir"]

WORLD_NAMES = ("open_floor", "corridor", "walled_room")
"""The worlds shipped in ``sim/worlds``."""


def sim_dir() -> Path:
    """The folder with ``mr1.xml``, ``worlds/`` and ``scenarios/``.

    ``$SKILLWRIGHT_SIM_DIR`` if set, else ``sim/`` of the source tree this package runs from.
    """
    explicit = os.environ.get("SKILLWRIGHT_SIM_DIR")
    folder = Path(explicit) if explicit else Path(__file__).resolve().parents[3] / "sim"
    if not (folder / "worlds").is_dir():
        raise InputFileNotFoundError(
            f"the simulation data folder {folder} has no worlds/ folder; set "
            "SKILLWRIGHT_SIM_DIR to the sim/ folder of the skillwright sources"
        )
    return folder


def resolve_world(name: str, relative_to: Path | None = None) -> Path:
    """The MJCF file of a world: a shipped world's name (``corridor``) or a path to an
    ``.xml`` file (relative to ``relative_to``, e.g. the scenario file's folder)."""
    if name in WORLD_NAMES:
        return sim_dir() / "worlds" / f"{name}.xml"
    path = Path(name)
    if not path.is_absolute() and relative_to is not None:
        path = relative_to / path
    if path.suffix.lower() != ".xml" or not path.is_file():
        raise InputFileNotFoundError(
            f"world {name!r}: not one of the shipped worlds ({', '.join(WORLD_NAMES)}) and no "
            f"MJCF file at {path}"
        )
    return path


def scenario_files() -> list[Path]:
    """The default scenario files shipped in ``sim/scenarios``, sorted by name."""
    folder = sim_dir() / "scenarios"
    return sorted(folder.glob("*.yaml")) if folder.is_dir() else []
