"""Where skillwright keeps per-user files, following the XDG base directory convention."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["cache_dir"]


def cache_dir() -> Path:
    """The per-user cache folder.

    ``$SKILLWRIGHT_CACHE_DIR``, else ``$XDG_CACHE_HOME/skillwright``, else
    ``~/.cache/skillwright``.

    The folder is not created here; writers create the subfolder they need.
    """
    explicit = os.environ.get("SKILLWRIGHT_CACHE_DIR")
    if explicit:
        return Path(explicit)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "skillwright"
