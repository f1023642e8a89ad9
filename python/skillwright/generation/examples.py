"""The few-shot examples shipped with the package (see ``examples/README.md``)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from pathlib import Path

from skillwright.capability.model import Capability
from skillwright.spec.model import SkillSpec

__all__ = ["EXAMPLES_DIR", "FewShotExample", "few_shot_examples"]

EXAMPLES_DIR = Path(__file__).with_name("examples")

# (skill file stem, capability / spec file stem); in the order the prompt shows them.
_EXAMPLES = (
    ("get_position", "get-position"),
    ("set_velocity", "set-velocity"),
    ("navigate_to_point", "navigate-to-point"),
)


@dataclass(frozen=True)
class FewShotExample:
    """A capability, its skill specification and the skill written for them."""

    capability: Capability
    spec: SkillSpec
    code: str
    code_path: Path


@cache
def few_shot_examples() -> tuple[FewShotExample, ...]:
    """Loads the shipped examples (once per process)."""
    from skillwright.capability.reader import load_capability
    from skillwright.spec.loader import load_spec

    out = []
    for skill_stem, input_stem in _EXAMPLES:
        code_path = EXAMPLES_DIR / "skills" / f"{skill_stem}.py"
        out.append(
            FewShotExample(
                capability=load_capability(
                    EXAMPLES_DIR / "inputs" / f"{input_stem}.ttl"
                ).capability,
                spec=load_spec(EXAMPLES_DIR / "inputs" / f"{input_stem}.spec.yaml"),
                code=code_path.read_text(encoding="utf-8"),
                code_path=code_path,
            )
        )
    return tuple(out)
