"""Writing a skill specification from the form, in the format its file name asks for.

``.json`` files get the reference project's shape (``{"skill": {..., "states": [...]}}``),
``.yaml``/``.yml`` the short hand-written form; both are what
:func:`skillwright.spec.load_spec` reads. The file is read back with ``load_spec`` before
this returns, so a saved specification always loads.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

from skillwright.errors import InvalidArgumentError
from skillwright.fileio import write_atomic

if TYPE_CHECKING:
    from skillwright.spec.model import SkillSpec

__all__ = ["spec_text", "write_spec"]


def spec_text(spec: SkillSpec, path: Path) -> str:
    """The file content for ``spec`` at ``path`` (format by suffix)."""
    suffix = path.suffix.lower()
    if suffix == ".json":
        return json.dumps(spec.to_reference(), indent=2, ensure_ascii=False) + "\n"
    if suffix in {".yaml", ".yml"}:
        import yaml

        document = {
            "name": spec.name,
            "description": spec.description,
            "skill_interface": spec.skill_interface,
            "states": dict(spec.states),
        }
        return yaml.safe_dump(document, sort_keys=False, allow_unicode=True, width=96)
    raise InvalidArgumentError(
        f"{path}: save a specification as .json, .yaml or .yml (the suffix picks the format)"
    )


def write_spec(spec: SkillSpec, path: Path) -> SkillSpec:
    """Writes ``spec`` to ``path`` atomically and returns it as read back from the file."""
    from skillwright.spec.loader import load_spec

    write_atomic(path, spec_text(spec, path))
    return load_spec(path)
