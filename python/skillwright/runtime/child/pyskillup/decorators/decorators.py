"""Stand-in of ``pyskillup.decorators.decorators``.

The decorators record what they mark; the driver reads the marks to find the skill's
parameters, outputs and state methods, and runs the states in pySkillUp's order.
"""

from __future__ import annotations

TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Callable
    from typing import Any, TypeVar

    F = TypeVar("F", bound=Callable[..., Any])


__all__ = [
    "aborting",
    "clearing",
    "completing",
    "execute",
    "holding",
    "resetting",
    "skill",
    "skill_output",
    "skill_parameter",
    "starting",
    "stopping",
    "suspending",
    "unholding",
    "unsuspending",
]

STATES = (
    "starting",
    "execute",
    "completing",
    "holding",
    "unholding",
    "suspending",
    "unsuspending",
    "stopping",
    "aborting",
    "clearing",
    "resetting",
)


def skill(
    skill_interface: Any = None,
    skill_iri: str | None = None,
    module_iri: str | None = None,
    capability_iri: str | None = None,
    description: str | None = None,
    **extra: Any,
) -> Callable[[type], type]:
    """Marks a class as a skill, with its interface and IRIs."""

    def mark(cls: type) -> type:
        if not isinstance(cls, type):
            raise TypeError("@skill decorates a class")
        cls._pyskillup_skill = {  # type: ignore[attr-defined]
            "skill_interface": getattr(skill_interface, "value", skill_interface),
            "skill_iri": skill_iri,
            "module_iri": module_iri,
            "capability_iri": capability_iri,
            "description": description,
            **extra,
        }
        return cls

    return mark


def _variable(
    kind: str, is_required: bool, name: str | None, description: str | None, extra: dict
) -> Callable[[F], F]:
    def mark(function: F) -> F:
        if not callable(function):
            raise TypeError(f"@{kind} decorates a getter method")
        function._pyskillup_variable = {  # type: ignore[attr-defined]
            "kind": kind,
            "name": name or function.__name__,
            "is_required": is_required,
            "description": description,
            **extra,
        }
        return function

    return mark


def skill_parameter(
    is_required: bool = True, name: str | None = None, description: str | None = None, **extra: Any
) -> Callable[[F], F]:
    """Marks the getter of a skill input."""
    return _variable("skill_parameter", is_required, name, description, extra)


def skill_output(
    is_required: bool = True, name: str | None = None, description: str | None = None, **extra: Any
) -> Callable[[F], F]:
    """Marks the getter of a skill output."""
    return _variable("skill_output", is_required, name, description, extra)


def _state(state: str) -> Callable[[F], F]:
    def mark(function: F) -> F:
        if not callable(function):
            raise TypeError(f"@{state} decorates a method")
        function._pyskillup_state = state  # type: ignore[attr-defined]
        return function

    mark.__name__ = state
    mark.__doc__ = f"Marks the method that runs in the PackML state {state}."
    return mark


starting = _state("starting")
execute = _state("execute")
completing = _state("completing")
holding = _state("holding")
unholding = _state("unholding")
suspending = _state("suspending")
unsuspending = _state("unsuspending")
stopping = _state("stopping")
aborting = _state("aborting")
clearing = _state("clearing")
resetting = _state("resetting")
