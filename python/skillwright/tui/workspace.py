"""The workspace: a folder holding capabilities, specifications, inventories and results.

The layout is a convention, not a requirement; everything is found by name:

- ``*.ttl`` (also ``*.owl``, ``*.rdf``) capability models, in any subfolder;
- ``*.spec.yaml``, ``*.spec.yml``, ``*.spec.json`` skill specifications;
- ``*.inventory.json`` saved inventories, ``*.mcap`` recordings and rosbag2 folders
  (a folder with ``metadata.yaml``) anywhere, conventionally under ``recordings/``;
- ``generated/<skill>-<YYYYmmdd-HHMMSS>/`` generation results, each with ``record.json``;
- ``.skillwright/session.json`` the TUI's saved session.

The shipped ``capabilities/`` folder is a workspace as it is. Nothing here imports more
than the standard library, so the TUI can list a workspace before its first paint.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator
from dataclasses import dataclass
from datetime import datetime
from pathlib import Path

__all__ = ["CAPABILITY_SUFFIXES", "SPEC_SUFFIXES", "Workspace", "resolve_workspace"]

CAPABILITY_SUFFIXES = (".ttl", ".owl", ".rdf")
"""File suffixes listed as capability models."""

SPEC_SUFFIXES = (".spec.yaml", ".spec.yml", ".spec.json")
"""File name endings listed as skill specifications."""

INVENTORY_SUFFIX = ".inventory.json"
"""File name ending of saved inventories."""

STATE_DIR = ".skillwright"
GENERATED_DIR = "generated"
ONTOLOGY_DIR = "ontologies"
"""Local copies of ontologies the capability models import, read with every model (the
TUI's ``--ontology``); not listed as capabilities."""
ONTOLOGY_SUFFIXES = (".ttl", ".owl", ".rdf", ".xml", ".jsonld", ".nt", ".n3")

# Folders that never hold inputs: our own state and results, tool caches, virtualenvs.
_SKIPPED_DIRS = {
    STATE_DIR,
    GENERATED_DIR,
    ONTOLOGY_DIR,
    "__pycache__",
    "node_modules",
    ".git",
    ".venv",
}
# A workspace is browsed on start-up; a deep tree (a user pointing at $HOME) must not stall it.
_MAX_DEPTH = 6


def resolve_workspace(explicit: Path | None, cwd: Path) -> Path:
    """The workspace: ``explicit`` if given, else ``cwd/capabilities`` if present, else cwd."""
    if explicit is not None:
        return explicit.expanduser().resolve()
    shipped = cwd / "capabilities"
    return (shipped if shipped.is_dir() else cwd).resolve()


_STAMP = re.compile(r"-(\d{8}-\d{6})(?:-(\d+))?$")


def _result_order(folder: Path) -> tuple[str, int, str]:
    """Sort key of a result folder: its time stamp, then its same-second counter."""
    match = _STAMP.search(folder.name)
    if match is None:
        return ("", 0, folder.name)
    return (match.group(1), int(match.group(2) or 1), folder.name)


def _is_bag_folder(folder: Path) -> bool:
    return (folder / "metadata.yaml").is_file()


@dataclass(frozen=True)
class Workspace:
    """One workspace folder and where things live inside it."""

    root: Path

    @property
    def state_dir(self) -> Path:
        """Where the TUI keeps its session (``.skillwright/``)."""
        return self.root / STATE_DIR

    @property
    def session_path(self) -> Path:
        """The saved session."""
        return self.state_dir / "session.json"

    @property
    def generated_dir(self) -> Path:
        """Where generation results go."""
        return self.root / GENERATED_DIR

    def _walk(self) -> Iterator[tuple[Path, list[str], list[str]]]:
        base_depth = len(self.root.parts)
        for top, dirs, files in os.walk(self.root):
            folder = Path(top)
            dirs[:] = sorted(d for d in dirs if d not in _SKIPPED_DIRS and not d.startswith("."))
            if len(folder.parts) - base_depth >= _MAX_DEPTH:
                dirs[:] = []
            yield folder, dirs, sorted(files)

    @property
    def ontology_dir(self) -> Path:
        """Where local copies of imported ontologies go (``ontologies/``)."""
        return self.root / ONTOLOGY_DIR

    def ontologies(self) -> tuple[Path, ...]:
        """The ontology files of :attr:`ontology_dir`, sorted (none when it is missing)."""
        if not self.ontology_dir.is_dir():
            return ()
        return tuple(
            sorted(
                p
                for p in self.ontology_dir.iterdir()
                if p.is_file() and p.name.lower().endswith(ONTOLOGY_SUFFIXES)
            )
        )

    def ontology_hint(self) -> str:
        """How a TUI user gives a local copy of an ontology, as messages say it."""
        return (
            f"a file in the workspace's {ONTOLOGY_DIR}/ folder, which the TUI reads with every "
            "model"
        )

    def capabilities(self) -> list[Path]:
        """Capability model files, sorted by path."""
        return [
            folder / name
            for folder, _dirs, files in self._walk()
            for name in files
            if name.lower().endswith(CAPABILITY_SUFFIXES)
        ]

    def specs(self) -> list[Path]:
        """Skill specification files, sorted by path."""
        return [
            folder / name
            for folder, _dirs, files in self._walk()
            for name in files
            if name.lower().endswith(SPEC_SUFFIXES)
        ]

    def spec_for(self, capability: Path) -> Path | None:
        """The specification written for ``capability``: same name, ``.spec.*`` suffix."""
        stem = capability.name.rsplit(".", 1)[0]
        for suffix in SPEC_SUFFIXES:
            candidate = capability.with_name(stem + suffix)
            if candidate.is_file():
                return candidate
        return None

    def interface_sources(self) -> list[Path]:
        """Saved inventories, ``.mcap`` files and rosbag2 folders, sorted by path.

        Files inside a rosbag2 folder are not listed on their own: the folder is the source.
        """
        found: list[Path] = []
        for folder, dirs, files in self._walk():
            if folder != self.root and _is_bag_folder(folder):
                found.append(folder)
                dirs[:] = []
                continue
            for name in files:
                lower = name.lower()
                if lower.endswith((INVENTORY_SUFFIX, ".mcap")):
                    found.append(folder / name)
        return sorted(found)

    def results(self) -> list[Path]:
        """Result folders that hold a ``record.json``, newest first (by folder name)."""
        if not self.generated_dir.is_dir():
            return []
        folders = [p for p in self.generated_dir.iterdir() if (p / "record.json").is_file()]
        return sorted(folders, key=_result_order, reverse=True)

    def new_result_dir(self, skill_name: str, now: datetime | None = None) -> Path:
        """``generated/<skill>-<YYYYmmdd-HHMMSS>``; a suffix keeps two runs in one second apart."""
        stamp = (now or datetime.now()).strftime("%Y%m%d-%H%M%S")
        candidate = self.generated_dir / f"{skill_name}-{stamp}"
        counter = 2
        while candidate.exists():
            candidate = self.generated_dir / f"{skill_name}-{stamp}-{counter}"
            counter += 1
        return candidate

    def relative(self, path: Path) -> str:
        """``path`` relative to the workspace when it is inside it, else absolute."""
        try:
            return path.resolve().relative_to(self.root.resolve()).as_posix()
        except ValueError:
            return str(path.resolve())

    def absolute(self, stored: str) -> Path:
        """The inverse of :meth:`relative`."""
        path = Path(stored).expanduser()
        return path if path.is_absolute() else self.root / path
