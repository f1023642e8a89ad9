"""The prompt a local model gets to write a skill's behaviour, fitted to its context.

Layout (chat turns): a system turn with the framework guide, then the three shipped
few-shot examples as user/assistant pairs — together the fixed prefix the llama.cpp
backend evaluates once and restores afterwards — and finally the task: the capability, the
skill specification, the retrieved interfaces with their definitions, and the skeleton to
complete.

When the whole prompt does not fit (prompt + answer budget > context), it is shortened in
steps that keep what the model needs most: definitions lose their comments, then become
field lists, then shallower field lists; then the later few-shot examples go. The
capability, the specification and the skeleton are never cut: if they alone do not fit,
the user gets a :class:`~skillwright.errors.ContextOverflowError` saying what to change.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from skillwright.capability.model import Capability, Parameter
from skillwright.errors import ContextOverflowError
from skillwright.generation.examples import FewShotExample
from skillwright.generation.model import Skeleton
from skillwright.interfaces.inventory import Interface, MessageField
from skillwright.llm.base import ChatMessage, Prompt
from skillwright.spec.model import SkillSpec

__all__ = [
    "GUIDE_PATH",
    "PROMPT_VERSION",
    "PromptBuild",
    "build_prompt",
    "capability_text",
    "fit_prompt",
    "interface_text",
    "spec_text",
]

PROMPT_VERSION = 1
"""Bumped when the prompt's layout changes (recorded with every generation)."""

GUIDE_PATH = Path(__file__).with_name("guide.md")
"""The framework guide the system turn carries."""

_USES = {"publish": "publishes to it", "subscribe": "subscribes to it", "call": "calls it"}
_ROLE_ORDER = ("message", "request", "response", "goal", "result", "feedback")
DefinitionStyle = Literal["raw", "uncommented", "fields3", "fields2"]
"""How interface definitions are shown: as recorded, without comments, or as field lists."""

# Definition styles from fullest to shortest, with what each gives up.
_SHORTENINGS: tuple[tuple[DefinitionStyle, str], ...] = (
    ("uncommented", "definitions without comments"),
    ("fields3", "definitions as field lists (3 levels)"),
    ("fields2", "definitions as field lists (2 levels)"),
)


def _value(component_value: object, interpretation: str | None) -> str:
    if component_value is None:
        return ""
    return f", value {interpretation or '='} {component_value}"


def _parameter_lines(parameters: Sequence[Parameter]) -> list[str]:
    lines = []
    for parameter in parameters:
        for component in parameter.components:
            name = parameter.name if len(parameter.components) == 1 else component.name
            unit = f" [{component.unit}]" if component.unit else ""
            kind = component.data_type or "untyped"
            definition = f": {component.definition}" if component.definition else ""
            value = _value(component.value, component.logic_interpretation)
            lines.append(f"- {name} ({kind}{unit}{value}){definition}")
    return lines or ["- (none)"]


def capability_text(capability: Capability) -> str:
    """The capability as plain text: IRI, purpose, inputs, outputs, constraints, resource."""
    lines = [f"Capability {capability.label} <{capability.iri}>"]
    if capability.comment:
        lines.append(capability.comment)
    lines += ["Inputs:", *_parameter_lines(capability.inputs)]
    lines += ["Outputs:", *_parameter_lines(capability.outputs)]
    if capability.constraints:
        lines.append("Constraints:")
        lines += [f"- {c.name}: {c.text}" for c in capability.constraints]
    resource = capability.resource
    if resource is not None:
        lines.append(f"Resource: {resource.name} <{resource.iri}>")
        lines += [f"- limit: {limit}" for p in resource.properties for limit in p.limits()]
    return "\n".join(lines)


def spec_text(spec: SkillSpec) -> str:
    """The skill specification as plain text, states in PackML order."""
    lines = [f"Skill {spec.name} (interface {spec.skill_interface})"]
    if spec.description:
        lines.append(spec.description)
    lines += [f"- {state}: {' '.join(text.split())}" for state, text in spec.states.items()]
    return "\n".join(lines)


def _uncommented(raw: str) -> str:
    out = []
    for line in raw.splitlines():
        code = re.sub(r"\s+#.*$", "", line) if not line.lstrip().startswith("#") else ""
        if code.strip():
            out.append(code.rstrip())
    return "\n".join(out)


def _field_lines(fields: Sequence[MessageField], depth: int, indent: str = "") -> list[str]:
    lines = []
    for field in fields:
        lines.append(f"{indent}{field.type} {field.name}")
        if depth > 1 and field.fields:
            lines += _field_lines(field.fields, depth - 1, indent + "  ")
    return lines


def _definition_text(interface: Interface, role: str, style: DefinitionStyle) -> str:
    definition = interface.definitions[role]
    if style in ("fields3", "fields2") and definition.fields is not None:
        return "\n".join(_field_lines(definition.fields, 3 if style == "fields3" else 2))
    if style == "raw":
        return definition.raw.strip()
    return _uncommented(definition.raw)


def interface_text(interface: Interface, role: str, style: DefinitionStyle = "raw") -> str:
    """One retrieved interface for the prompt: name, kind, type, how the skill uses it, and
    its definitions in the given style."""
    use = _USES.get(role, role)
    lines = [f"### {interface.name} ({interface.kind} {interface.type_name}; the skill {use})"]
    if interface.description is not None:
        lines.append(interface.description.purpose)
    known = [r for r in _ROLE_ORDER if r in interface.definitions]
    for definition_role in known:
        lines += [f"{definition_role}:", "```", _definition_text(interface, definition_role, style)]
        lines.append("```")
    if not known:
        lines.append("(definition unknown: use only what the type name makes certain)")
    return "\n".join(lines)


def _example_turns(example: FewShotExample) -> tuple[ChatMessage, ChatMessage]:
    listed = "\n".join(f"- {handle}" for handle in _handles_in(example.code) or ["(see the code)"])
    user = "\n\n".join(
        [
            "Example task.",
            capability_text(example.capability),
            spec_text(example.spec),
            f"Interfaces:\n{listed}",
        ]
    )
    return ChatMessage("user", user), ChatMessage("assistant", f"```python\n{example.code}```")


_HANDLE = re.compile(
    r"create_(publisher|subscription|client)\(\s*(\w+)\s*,\s*\"([^\"]+)\"|ActionClient\(\s*self\.node\s*,\s*(\w+)\s*,\s*\"([^\"]+)\""
)


def _handles_in(code: str) -> list[str]:
    out = []
    for match in _HANDLE.finditer(code):
        if match.group(1):
            kind = {"publisher": "topic", "subscription": "topic", "client": "service"}
            out.append(f"{match.group(3)} ({kind[match.group(1)]} {match.group(2)})")
        else:
            out.append(f"{match.group(5)} (action {match.group(4)})")
    return list(dict.fromkeys(out))


@dataclass(frozen=True)
class PromptBuild:
    """A prompt and how it was made to fit."""

    prompt: Prompt
    definition_style: DefinitionStyle
    examples: int
    """How many few-shot examples it carries."""
    tokens: int | None
    """Prompt tokens, when the model could count them."""
    shortened: tuple[str, ...]
    """What was shortened to make it fit, in plain words (empty when nothing was)."""

    def text(self) -> str:
        """The prompt as the human-readable transcript written to ``prompt.txt``."""
        blocks = []
        for index, message in enumerate(self.prompt.messages):
            cached = " (cached prefix)" if index < self.prompt.prefix_messages else ""
            blocks.append(f"===== {message.role}{cached} =====\n{message.content}")
        return "\n\n".join(blocks) + "\n"


def build_prompt(
    capability: Capability,
    spec: SkillSpec,
    interfaces: Sequence[tuple[Interface, str]],
    skeleton: Skeleton,
    examples: Sequence[FewShotExample],
    *,
    definition_style: DefinitionStyle = "raw",
) -> Prompt:
    """The chat prompt; ``interfaces`` pairs each retrieved interface with the skill's role
    for it (``publish``, ``subscribe`` or ``call``)."""
    guide = GUIDE_PATH.read_text(encoding="utf-8")
    prefix: list[ChatMessage] = []
    for example in examples:
        prefix.extend(_example_turns(example))
    listed = "\n\n".join(interface_text(i, role, definition_style) for i, role in interfaces)
    task = "\n\n".join(
        [
            "Task. Write the skill for this capability and specification, in Python for "
            "ROS 2 (rclpy) with the pySkillUp conventions.",
            capability_text(capability),
            spec_text(spec),
            "Interfaces of the resource to use (exact names, types and fields):\n\n"
            + (listed or "(none were retrieved)"),
            "Complete this skeleton. Keep its decorators, IRIs, getters and handles; replace "
            "every `raise NotImplementedError(...)` with the behaviour its docstring states:\n"
            f"```python\n{skeleton.code}```",
        ]
    )
    return Prompt.chat(task, system=guide.strip(), prefix=prefix)


def fit_prompt(
    capability: Capability,
    spec: SkillSpec,
    interfaces: Sequence[tuple[Interface, str]],
    skeleton: Skeleton,
    examples: Sequence[FewShotExample],
    *,
    count_tokens: Callable[[Prompt], int | None],
    context_length: int,
    answer_tokens: int,
    model_id: str,
) -> PromptBuild:
    """The fullest prompt that leaves ``answer_tokens`` of the context for the answer."""
    budget = context_length - answer_tokens
    shortened: list[str] = []
    total = len(examples)
    attempts: list[tuple[DefinitionStyle, int, str]] = [("raw", total, "")]
    attempts += [(style, total, label) for style, label in _SHORTENINGS]
    attempts += [
        ("fields2", n, f"{total - n} of {total} few-shot examples left out")
        for n in range(total - 1, -1, -1)
    ]
    tokens: int | None = None
    for style, count, label in attempts:
        if label:
            shortened.append(label)
        prompt = build_prompt(
            capability, spec, interfaces, skeleton, examples[:count], definition_style=style
        )
        tokens = count_tokens(prompt)
        if tokens is None:
            tokens = _estimate_tokens(prompt)
        if tokens <= budget:
            return PromptBuild(prompt, style, count, tokens, tuple(shortened))
    raise ContextOverflowError(
        f"model {model_id!r}: the prompt needs {tokens} tokens even with definitions shortened "
        f"and no examples, plus {answer_tokens} for the answer, but the context holds "
        f"{context_length}; raise `context_length` of {model_id!r} in models.toml, lower its "
        "`max_tokens`, or retrieve fewer interfaces (-k)"
    )


def _estimate_tokens(prompt: Prompt) -> int:
    """A cautious token estimate for backends that cannot count (about 3 characters each)."""
    return sum(len(m.content) for m in prompt.messages) // 3 + 8 * len(prompt.messages)
