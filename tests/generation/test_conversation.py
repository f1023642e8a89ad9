"""The conversation a skill is written in: fixed prefix, task card, one turn per method."""

from __future__ import annotations

import ast
import textwrap

import yaml

from skillwright.generation.conversation import (
    EXAMPLES_PATH,
    Conversation,
    Turn,
    fence,
    helper_ask,
    prefix_messages,
    repair_ask,
    state_ask,
)
from skillwright.generation.model import InterfaceRef
from skillwright.generation.skeleton import helper_summaries

CARD_LINES = (
    "Skill ",
    "Inputs (set before starting): ",
    "Outputs: ",
    "Interfaces (handles made in starting, released in resetting):",
    "Helpers: ",
)


def test_the_prefix_is_the_guide_then_the_examples_as_turns() -> None:
    messages = prefix_messages()
    assert messages[0].role == "system"
    assert "Answer with exactly the method asked for" in messages[0].content
    roles = [m.role for m in messages[1:]]
    assert roles == ["user", "assistant"] * (len(roles) // 2)
    assert messages[1].content.startswith("Skill DriveArcSkill: capability driveArc of agv7.")


def test_every_example_answer_is_one_method_of_valid_python() -> None:
    for message in prefix_messages()[2::2]:
        assert message.content.startswith("```python\n    ")
        assert message.content.endswith("\n```")
        code = textwrap.dedent(message.content[len("```python\n") : -len("\n```")])
        tree = ast.parse(code)
        assert len(tree.body) == 1
        assert isinstance(tree.body[0], ast.FunctionDef)


def test_example_cards_are_written_as_the_card_builder_writes_them() -> None:
    document = yaml.safe_load(EXAMPLES_PATH.read_text(encoding="utf-8"))
    for example in document["examples"]:
        lines = example["card"].splitlines()
        for start in CARD_LINES:
            assert any(line.startswith(start) for line in lines), (start, lines[0])
        handles = [line for line in lines if line.startswith("- ")]
        assert handles
        assert all(line.startswith("- self.") for line in handles)


def test_example_action_helpers_read_as_the_card_builder_writes_them() -> None:
    # The example teaches what the real card says.
    document = yaml.safe_load(EXAMPLES_PATH.read_text(encoding="utf-8"))
    cards = "\n".join(example["card"] for example in document["examples"])
    dock = InterfaceRef(
        name="/dock_robot",
        kind="action",
        type_name="opennav_docking_msgs/action/DockRobot",
        role="call",
    )
    for name, summary in helper_summaries([dock]).items():
        if "dock_robot" in name or name in {"_yaw", "_stop_base", "_wait_until"}:
            assert summary in cards, name


def test_examples_are_of_capabilities_nobody_evaluates() -> None:
    document = yaml.safe_load(EXAMPLES_PATH.read_text(encoding="utf-8"))
    names = {
        example["card"].split(": capability ")[1].split(" ")[0] for example in document["examples"]
    }
    evaluated = {
        "collisionAvoidance",
        "getDistanceToNearestObject",
        "getPosition",
        "mapping",
        "moveForward",
        "moveToPoint",
        "navigateToPoint",
        "rotate",
        "setVelocity",
    }
    assert names
    assert not names & evaluated


def test_the_first_request_carries_the_card_and_later_ones_do_not() -> None:
    conversation = Conversation("Skill XSkill: capability x of r.")
    conversation.turns.append(
        Turn(
            state_ask("starting", "Wait."),
            "    @starting\n    def starting(self) -> None:\n        pass",
        )
    )
    prompt = conversation.prompt(state_ask("execute", "Go  \n now."), "    @execute\n")
    own = prompt.messages[prompt.prefix_messages :]
    assert own[0].content == "Skill XSkill: capability x of r.\n\nWrite `starting`: Wait."
    assert own[1].content == fence("    @starting\n    def starting(self) -> None:\n        pass")
    assert own[2].content == "Write `execute`: Go now."
    assert prompt.answer_prefix == "```python\n    @execute\n"


def test_a_repair_is_asked_where_its_method_was_first_asked_for() -> None:
    conversation = Conversation("card")
    for name in ("starting", "execute", "stopping"):
        conversation.turns.append(Turn(state_ask(name, "x"), f"    def {name}(self): ..."))
    ask = repair_ask(state_ask("execute", "Go."), ["a", "b"])
    prompt = conversation.prompt(ask, "    def execute", upto=1)
    own = [m.content for m in prompt.messages[prompt.prefix_messages :]]
    assert len(own) == 3
    assert own[-1] == (
        "Write `execute`: Go.\nEarlier answers to this had these problems; avoid them:\n- a\n- b"
    )
    assert not any("stopping" in text for text in own)


def test_requests_read_as_sentences() -> None:
    assert helper_ask("_yaw", "execute", "self._yaw()") == (
        "Write the helper `_yaw` that `execute` calls as `self._yaw()`."
    )
