"""The conversation in which a model writes a skill, one method per turn.

Layout (chat turns): the state guide as the system turn, then the few-shot examples (each a
task card and a run of requests and answers) — together the fixed prefix that is evaluated
once per model and restored from the prefix cache — then the skill's own card with the
first request, and one further request per state, helper or repair. Every answer is
prefilled with the method's decorator and signature (and the skeleton's first lines of the
state), so the model only continues a method body and stops when the method ends.

A conversation only grows at its end while the states are written, so the model's context
keeps everything before the new request: each turn costs the model its request and its
answer, not the card again. A repair branches off before the answer it repairs: the same
request with the problems found, the answer prefilled with the earlier answer's lines before
its first error.
"""

from __future__ import annotations

import re
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import yaml

from skillwright.generation.skeleton import helper_summaries
from skillwright.llm.base import ChatMessage, Prompt

__all__ = [
    "EXAMPLES_PATH",
    "GUIDE_PATH",
    "PROMPT_VERSION",
    "STOP",
    "Conversation",
    "Turn",
    "example_helpers",
    "fence",
    "helper_ask",
    "prefix_messages",
    "repair_ask",
    "state_ask",
]

PROMPT_VERSION = 3
"""Bumped when the conversation's layout changes (recorded with every generation); 1 was the
whole-file prompt."""

GUIDE_PATH = Path(__file__).with_name("state_guide.md")
"""The system turn: how to write one method of a skill."""
EXAMPLES_PATH = Path(__file__).with_name("examples") / "states.yaml"
"""The few-shot examples (an invented robot, capabilities nobody evaluates)."""

STOP = ("\n```", "\n    @", "\n    def ", "\nclass ", "\n@", "\ndef ")
"""Text that ends a method: the closing fence, or the next class member or top-level code."""

MEMBER_INDENT = "    "


def fence(method: str) -> str:
    """A method (class-member indentation) as the fenced answer the examples show."""
    return f"```python\n{method.rstrip()}\n```"


@dataclass(frozen=True)
class Turn:
    """A request and the answer given to it."""

    ask: str
    answer: str
    """The method as written (class-member indentation), without the fence."""


@cache
def prefix_messages() -> tuple[ChatMessage, ...]:
    """The fixed prefix: the guide and the few-shot examples as chat turns."""
    guide = GUIDE_PATH.read_text(encoding="utf-8").strip()
    document = yaml.safe_load(EXAMPLES_PATH.read_text(encoding="utf-8"))
    messages = [ChatMessage("system", guide)]
    for example in document["examples"]:
        for index, turn in enumerate(example["turns"]):
            ask = turn["ask"].strip()
            if index == 0:
                ask = f"{example['card'].strip()}\n\n{ask}"
            answer = textwrap.indent(turn["answer"].rstrip(), MEMBER_INDENT)
            messages += [ChatMessage("user", ask), ChatMessage("assistant", fence(answer))]
    return tuple(messages)


@cache
def example_helpers() -> frozenset[str]:
    """The helpers the few-shot examples' cards offer for their invented robots' interfaces
    (``_send_dock_robot_goal`` and the like; not the generic ones any skill may get)."""
    document = yaml.safe_load(EXAMPLES_PATH.read_text(encoding="utf-8"))
    offered = {
        name
        for example in document["examples"]
        for line in example["card"].splitlines()
        if line.lstrip().startswith("Helpers:")
        for name in re.findall(r"self\.(_\w+)\(", line)
    }
    return frozenset(offered - set(helper_summaries([])))


def state_ask(state: str, text: str) -> str:
    """The request for a state: its name and what the specification says it does."""
    return f"Write `{state}`: {' '.join(text.split())}"


def helper_ask(name: str, caller: str, call: str, *, callback: bool = False) -> str:
    """The request for a helper method the behaviour calls (or hands over as a callback, in
    ``call``) but nobody has written."""
    if callback:
        return f"Write the helper `{name}` that `{caller}` hands over as a callback in `{call}`."
    return f"Write the helper `{name}` that `{caller}` calls as `{call}`."


def repair_ask(ask: str, problems: Sequence[str]) -> str:
    """The method's request again, with what the checks found in earlier answers to it.

    The earlier answers themselves are not shown: a small model shown its own answer copies
    it, mistakes and all, even when sampled; the repair's prefill gives it the statements
    of the latest answer worth keeping instead (:mod:`~skillwright.generation.repair`)."""
    listed = "\n".join(f"- {problem}" for problem in problems)
    return f"{ask}\nEarlier answers to this had these problems; avoid them:\n{listed}"


@dataclass
class Conversation:
    """One skill's turns after the fixed prefix; the first request carries the card."""

    card: str
    turns: list[Turn] = field(default_factory=list)

    def prompt(
        self,
        ask: str,
        answer_prefix: str,
        *,
        upto: int | None = None,
    ) -> Prompt:
        """The prompt for a new request after the first ``upto`` turns (default: all), with
        the answer prefilled by ``answer_prefix`` (the fence is added here)."""
        history = self.turns if upto is None else self.turns[:upto]
        prefix = prefix_messages()
        messages = list(prefix)
        for index, turn in enumerate([*history, Turn(ask, "")]):
            text = f"{self.card}\n\n{turn.ask}" if index == 0 else turn.ask
            messages.append(ChatMessage("user", text))
            if index < len(history):
                messages.append(ChatMessage("assistant", fence(turn.answer)))
        return Prompt(
            tuple(messages),
            prefix_messages=len(prefix),
            answer_prefix=f"```python\n{answer_prefix}",
        )
