"""Each rule's VALID and INVALID cases, by stage, as edits of skills this project ships.

A case names a base skill (``skill``: a file of ``capabilities/skills`` by stem, or
``move_forward_good``, the validation tests' hand-written skill) and the ``edits`` that turn
it into the case (each ``old`` text must occur exactly once), or gives its whole ``source``.

``static.yaml``
    ``catalog`` is ``small`` (the four interfaces of ``tests/validation/test_static.py``) or
    ``mr1`` (every interface of the shipped MR-1 recording); ``retrieved`` the interfaces
    retrieval chose (default: /cmd_vel and /odom). An INVALID case's ``fixed`` are the edits
    the rule's fixes (safe and unsafe) make to it.
``run.yaml``
    ``inputs``, ``scenario`` (a run scenario, or ``shipped`` for the base skill's own
    ``.scenario.yaml``), ``world`` (``kinematic``, or ``speed-limit``: the test world of
    ``test_registry.py`` that reports a command above ``world_options.limit``) and
    ``stall_seconds`` (how long a silent, idle state may wait; shortened so a case of a
    blocked state ends within seconds); ``capability`` (a shipped model by stem) gives the
    inputs by the capability's names, bound to the skill's parameters.
``simulation.yaml``
    ``scenario`` names one of the base skill's scenarios in ``sim/scenarios``; ``scenarios``
    gives scenarios of its own instead.
"""

from __future__ import annotations

from pathlib import Path

import yaml

from tests.conftest import SHIPPED_CAPABILITIES

HERE = Path(__file__).parent
SKILLS = SHIPPED_CAPABILITIES / "skills"
GOOD = HERE.parent.parent / "validation" / "skills" / "move_forward_good.py"

STAGES = ("static", "run", "simulation")


def load(stage: str) -> dict[str, dict[str, list[dict[str, object]]]]:
    """The cases of ``stage`` by rule code."""
    loaded = yaml.safe_load((HERE / f"{stage}.yaml").read_text(encoding="utf-8"))
    assert isinstance(loaded, dict)
    return loaded


def base_path(case: dict[str, object]) -> Path:
    """The file of the case's base skill."""
    name = str(case["skill"])
    return GOOD if name == "move_forward_good" else SKILLS / f"{name}.py"


def capability_stem(case: dict[str, object]) -> str:
    """The shipped capability the case's skill implements (``move-forward``)."""
    name = str(case.get("skill", ""))
    if name == "move_forward_good":
        return "move-forward"
    if not name:
        raise AssertionError("a case with a whole source names the skill it stands for")
    return name.replace("_", "-")


def edited(text: str, edits: object) -> str:
    """``text`` with ``edits`` (``[{old, new}]``) made, each ``old`` found exactly once."""
    for edit in edits or []:  # type: ignore[attr-defined]
        old, new = edit["old"], edit["new"]
        count = text.count(old)
        assert count == 1, f"the edit's old text occurs {count} times: {old!r}"
        text = text.replace(old, new, 1)
    return text


def source_of(case: dict[str, object]) -> str:
    """The case's skill text."""
    if "source" in case:
        return str(case["source"])
    return edited(base_path(case).read_text(encoding="utf-8"), case.get("edits"))
