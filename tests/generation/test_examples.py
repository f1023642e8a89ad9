"""The few-shot examples are complete, correct by our own checks, and in sync."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.generation.examples import EXAMPLES_DIR, FewShotExample, few_shot_examples
from skillwright.validation.static import check_skill
from tests.conftest import SHIPPED_CAPABILITIES


def test_three_examples_in_prompt_order() -> None:
    assert [e.spec.name for e in few_shot_examples()] == [
        "get_position",
        "set_velocity",
        "navigate_to_point",
    ]


@pytest.mark.parametrize("example", few_shot_examples(), ids=lambda e: e.spec.name)
def test_each_example_passes_every_static_check(example: FewShotExample) -> None:
    report = check_skill(
        example.code, capability=example.capability, spec=example.spec, path=str(example.code_path)
    )
    assert report.findings == []


@pytest.mark.parametrize("copy", sorted((EXAMPLES_DIR / "inputs").iterdir()), ids=lambda p: p.name)
def test_example_inputs_match_the_shipped_capabilities(copy: Path) -> None:
    original = SHIPPED_CAPABILITIES / copy.name
    assert copy.read_bytes() == original.read_bytes(), f"{copy} drifted from {original}"
