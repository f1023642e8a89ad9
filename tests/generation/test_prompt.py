"""The prompt carries guide, examples, capability, spec, definitions and skeleton, and fits."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from skillwright.errors import ContextOverflowError
from skillwright.generation.examples import few_shot_examples
from skillwright.generation.model import Skeleton
from skillwright.generation.prompt import (
    PromptBuild,
    build_prompt,
    capability_text,
    fit_prompt,
    interface_text,
    spec_text,
)
from skillwright.generation.skeleton import build_skeleton
from skillwright.interfaces.inventory import Interface, Inventory
from skillwright.interfaces.load import load_inventory
from skillwright.llm.base import Prompt
from tests.conftest import SHIPPED_CAPABILITIES
from tests.generation.test_skeleton import CMD_VEL, ODOM, shipped


@pytest.fixture(scope="module")
def mr1() -> Inventory:
    return load_inventory(SHIPPED_CAPABILITIES / "recordings" / "mr1")


@pytest.fixture(scope="module")
def chosen(mr1: Inventory) -> list[tuple[Interface, str]]:
    return [(mr1.interface("/cmd_vel"), "publish"), (mr1.interface("/odom"), "subscribe")]


@pytest.fixture(scope="module")
def skeleton() -> Skeleton:
    capability, spec = shipped("move-forward")
    return build_skeleton(capability, spec, [CMD_VEL, ODOM])


def characters(prompt: Prompt) -> int:
    return sum(len(m.content) for m in prompt.messages)


def fit(
    chosen: list[tuple[Interface, str]],
    skeleton: Skeleton,
    *,
    context_length: int,
    answer_tokens: int = 100,
    examples: int = 3,
    count_tokens: Callable[[Prompt], int | None] = characters,
    model_id: str = "m",
) -> PromptBuild:
    capability, spec = shipped("move-forward")
    return fit_prompt(
        capability,
        spec,
        chosen,
        skeleton,
        few_shot_examples()[:examples],
        count_tokens=count_tokens,
        context_length=context_length,
        answer_tokens=answer_tokens,
        model_id=model_id,
    )


def test_the_capability_text_has_inputs_with_units_constraints_and_limits() -> None:
    capability, _ = shipped("move-forward")
    text = capability_text(capability)
    assert capability.iri in text
    assert "[m/s]" in text
    assert "Inputs:" in text
    assert "Outputs:" in text
    assert "limit: linearVelocity <= 0.8 m/s" in text


def test_the_spec_text_lists_every_state_in_packml_order() -> None:
    _, spec = shipped("move-forward")
    lines = spec_text(spec).splitlines()
    states = [line.split(":")[0].removeprefix("- ") for line in lines if line.startswith("- ")]
    assert states == list(spec.states)


def test_interface_text_gives_the_full_definition_and_how_the_skill_uses_it(
    mr1: Inventory,
) -> None:
    text = interface_text(mr1.interface("/odom"), "subscribe")
    assert text.startswith("### /odom (topic nav_msgs/msg/Odometry; the skill subscribes to it)")
    assert "geometry_msgs/PoseWithCovariance pose" in text


def test_the_examples_and_the_guide_form_the_cached_prefix_and_the_task_comes_last(
    chosen: list[tuple[Interface, str]], skeleton: Skeleton
) -> None:
    capability, spec = shipped("move-forward")
    examples = few_shot_examples()
    prompt = build_prompt(capability, spec, chosen, skeleton, examples)
    assert prompt.prefix_messages == 1 + 2 * len(examples)
    assert prompt.messages[0].role == "system"
    assert "pySkillUp" in prompt.messages[0].content
    assert [m.role for m in prompt.messages[1:-1]] == ["user", "assistant"] * len(examples)
    assert prompt.messages[2].content.startswith("```python\n")
    task = prompt.messages[-1].content
    assert capability_text(capability) in task
    assert spec_text(spec) in task
    assert skeleton.code in task
    assert "/cmd_vel (topic geometry_msgs/msg/Twist; the skill publishes to it)" in task


def test_the_example_turns_list_the_interfaces_their_code_uses(
    chosen: list[tuple[Interface, str]], skeleton: Skeleton
) -> None:
    capability, spec = shipped("move-forward")
    prompt = build_prompt(capability, spec, chosen, skeleton, few_shot_examples())
    navigate = prompt.messages[5].content
    assert "/navigate_to_pose (action NavigateToPose)" in navigate


def test_a_prompt_that_fits_is_not_shortened(
    chosen: list[tuple[Interface, str]], skeleton: Skeleton
) -> None:
    build = fit(chosen, skeleton, context_length=10**6)
    assert build.shortened == ()
    assert build.definition_style == "raw"
    assert build.examples == 3


def test_definitions_are_shortened_before_examples_go_and_the_task_is_never_cut(
    chosen: list[tuple[Interface, str]], skeleton: Skeleton
) -> None:
    capability, spec = shipped("move-forward")
    examples = few_shot_examples()
    full = characters(build_prompt(capability, spec, chosen, skeleton, examples))
    build = fit(chosen, skeleton, context_length=full + 100 - 1)
    assert build.definition_style == "uncommented"
    assert build.shortened == ("definitions without comments",)
    assert build.tokens is not None
    assert build.tokens < full

    small = fit(chosen, skeleton, context_length=full // 2)
    assert small.examples < 3
    assert small.definition_style == "fields2"
    task = small.prompt.messages[-1].content
    assert skeleton.code in task
    assert capability_text(capability) in task
    assert spec_text(spec) in task


def test_a_task_that_cannot_fit_is_refused_with_what_to_change(
    chosen: list[tuple[Interface, str]], skeleton: Skeleton
) -> None:
    with pytest.raises(ContextOverflowError) as caught:
        fit(chosen, skeleton, context_length=1000, answer_tokens=500, model_id="small-model")
    message = str(caught.value)
    assert "'small-model'" in message
    assert "context_length" in message
    assert "1000" in message


def test_backends_that_cannot_count_get_a_cautious_estimate(
    chosen: list[tuple[Interface, str]], skeleton: Skeleton
) -> None:
    build = fit(chosen, skeleton, context_length=10**6, count_tokens=lambda _prompt: None)
    assert build.tokens is not None
    assert build.tokens > characters(build.prompt) // 4


def test_the_transcript_marks_the_cached_prefix(
    chosen: list[tuple[Interface, str]], skeleton: Skeleton
) -> None:
    build = fit(chosen, skeleton, context_length=10**6, answer_tokens=1, examples=1)
    text = build.text()
    assert text.startswith("===== system (cached prefix) =====\n")
    assert text.count("(cached prefix)") == 3
    assert "===== user =====\nTask." in text
