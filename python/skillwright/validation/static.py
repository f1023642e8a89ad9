"""Static checks of a skill: what can be known without running it.

The checks follow the paper's evaluation criteria and the failure modes seen when LLMs
wrote these skills (see the project's SKILL-FRAMEWORK notes): syntax; annotation
completeness against the capability and the specification; grounding of every topic,
service, action and message field in the robot's inventory; placeholders; constants
that stand in for a capability input; errors caught and ignored where the specification
says to abort; interfaces retrieved but unused, or used but not retrieved.
"""

from __future__ import annotations

import ast
import builtins
import copy
import io
import re
import tokenize
from collections.abc import Callable, Iterable, Mapping, Sequence
from collections.abc import Set as AbstractSet
from dataclasses import dataclass, field
from keyword import kwlist

from skillwright.capability.model import Capability
from skillwright.rules.api import (
    GOAL_RESULT_WITHOUT_SEND,
    HANDLE_MADE_TWICE,
    TIMER_NEVER_CANCELLED,
    TIMER_NOT_KEPT,
)
from skillwright.rules.capability import (
    CONSTANT_FOR_INPUT,
    INPUT_COPIED_UNUSED,
    INPUT_NEVER_READ,
    INPUT_ONLY_VALIDATED,
    INPUT_OVERWRITTEN,
    OUTPUT_CONSTANT,
    OUTPUT_NEVER_SET,
)
from skillwright.rules.finding import Finding
from skillwright.rules.interfaces import (
    ARGUMENT_TYPE_MISMATCH,
    DURATION_SECONDS_FIELD,
    HEADING_NOT_ANGLE,
    INTERFACE_KIND_MISMATCH,
    INTERFACE_NAME_NOT_LITERAL,
    INTERFACE_NOT_RETRIEVED,
    INTERFACE_RETRIEVED_UNUSED,
    INTERFACE_TYPE_MISMATCH,
    MESSAGE_FIELD_NOT_NUMBER,
    POSITIONAL_MESSAGE_FIELDS,
    UNKNOWN_CONSTANT,
    UNKNOWN_FIELD,
    UNKNOWN_INTERFACE,
    YAW_OF_MESSAGE,
)
from skillwright.rules.registry import Rule
from skillwright.rules.structure import (
    ABORT_SWALLOWED,
    ANNOTATION_AMBIGUOUS,
    ANNOTATION_MATCHES_NOTHING,
    EMPTY_STATE,
    ERROR_SWALLOWED,
    LEFTOVER_MARKER,
    NO_SKILL_CLASS,
    NOT_IMPLEMENTED,
    NOT_ROS2SKILL,
    PARAMETER_UNANNOTATED,
    SKILL_INTERFACE_MISMATCH,
    SKILL_IRI_MISMATCH,
    SKILL_IRI_MISSING,
    STATE_MISSING,
    STATE_NOT_SPECIFIED,
    SYNTAX_ERROR,
)
from skillwright.spec.model import SkillSpec
from skillwright.validation.bearings import check_bearings
from skillwright.validation.equality import check_equality
from skillwright.validation.facts import SkillFacts
from skillwright.validation.first_messages import check_first_messages
from skillwright.validation.frames import check_frames
from skillwright.validation.grace import check_grace
from skillwright.validation.loops import check_waits
from skillwright.validation.model import (
    SEQUENCE_METHODS,
    Catalog,
    CheckReport,
    FieldTree,
)
from skillwright.validation.motion import check_motion
from skillwright.validation.names import check_names
from skillwright.validation.patience import check_zero_timeouts
from skillwright.validation.positions import check_filtered_positions
from skillwright.validation.settle import check_settling
from skillwright.validation.sources import measuring_sources, raw_scans
from skillwright.validation.stale import check_stale_conditions
from skillwright.validation.stops import check_stops
from skillwright.validation.syntax import (
    COMPOUND_STATEMENTS,
    called_name,
    keyword_argument,
    self_attribute,
    string_value,
)
from skillwright.validation.units import check_angle_units
from skillwright.validation.unsent import check_unsent
from skillwright.validation.views import check_views

__all__ = ["check_skill", "local_name"]

_NESTED_TYPES = {"Request", "Response", "Goal", "Result", "Feedback"}
_GENERIC_TOKENS = {"in", "out", "value", "the", "of", "id", "x", "y", "z"}


@dataclass
class _Context:
    findings: list[Finding] = field(default_factory=list)

    def add(
        self,
        rule: Rule,
        node: ast.AST | None,
        message: str,
        replacement: str | None = None,
        *,
        data: dict[str, object] | None = None,
    ) -> None:
        self.findings.append(rule.at(node, message, data=data, replacement=replacement))


def _normalise(name: str) -> str:
    return name if name.startswith("/") else f"/{name}"


# --- annotations -----------------------------------------------------------------


def _check_skill_decorator(facts: SkillFacts) -> list[Finding]:
    """The ``@skill`` decorator names the capability and its resource by their IRIs, has a
    skill IRI and the specification's skill interface, and the class derives from pySkillUp's
    ``ROS2Skill``."""
    ctx = _Context()
    cls, call = facts.skill, facts.decorator
    if cls is None or call is None:
        return ctx.findings
    capability, spec = facts.capability, facts.spec
    expected = {"capability_iri": capability.iri}
    if capability.resource is not None:
        expected["module_iri"] = capability.resource.iri
    for key, value in expected.items():
        given = keyword_argument(call, key)
        text = string_value(given)
        if given is None:
            ctx.add(
                SKILL_IRI_MISMATCH,
                call,
                f"@skill has no {key}; it must be {value!r}",
                data={"key": key, "expected": value, "given": None},
            )
        elif text is not None and text != value:
            ctx.add(
                SKILL_IRI_MISMATCH,
                given,
                f"@skill {key} is {text!r}, expected {value!r}",
                data={"key": key, "expected": value, "given": text},
            )
    if not string_value(keyword_argument(call, "skill_iri")):
        ctx.add(SKILL_IRI_MISSING, call, "@skill needs a skill_iri (a string IRI)")
    interface = keyword_argument(call, "skill_interface")
    wanted = f"SkillInterface.{spec.skill_interface}"
    if interface is None or ast.unparse(interface) != wanted:
        ctx.add(
            SKILL_INTERFACE_MISMATCH,
            interface or call,
            f"@skill skill_interface should be {wanted}, as the specification says",
            data={"expected": wanted},
        )
    if not any(ast.unparse(base).endswith("ROS2Skill") for base in cls.bases):
        ctx.add(
            NOT_ROS2SKILL,
            cls,
            f"class {cls.name} must derive from ROS2Skill",
            data={"class": cls.name},
        )
    return ctx.findings


def _check_parameters(facts: SkillFacts) -> list[Finding]:
    """Each capability input and output has an annotation bound to it (by name, by meaning
    or by --bind, :mod:`skillwright.capability.binding`), and each annotation is bound."""
    ctx = _Context()
    cls, capability, binding = facts.skill, facts.capability, facts.binding
    if cls is None:
        return ctx.findings
    bound = {b.target for b in binding.bound}
    given = {g.annotation.name for g in facts.getters}
    composites = {p.name for p in capability.inputs + capability.outputs if len(p.components) > 1}
    for parameters, decorator, what in (
        (capability.inputs, "skill_parameter", "input"),
        (capability.outputs, "skill_output", "output"),
    ):
        for parameter in parameters:
            names = [c.name for c in parameter.components] if len(parameter.components) > 1 else []
            if parameter.name in bound | given or (names and set(names) <= bound):
                continue
            missing = sorted(set(names) - bound)
            ctx.add(
                PARAMETER_UNANNOTATED,
                cls,
                f"no @{decorator} for the capability's {what} {parameter.name}"
                + (f" (missing: {', '.join(missing)})" if len(names) > 1 else ""),
                data={"decorator": decorator, "parameter": parameter.name, "missing": missing},
            )
    for getter in facts.getters:
        annotation, node = getter.annotation, getter.decorator
        decorator = "skill_parameter" if annotation.direction == "input" else "skill_output"
        candidates = binding.ambiguous.get(annotation.name)
        if candidates:
            ctx.add(
                ANNOTATION_AMBIGUOUS,
                node,
                f"@{decorator} {annotation.name!r} could stand for the capability's "
                f"{' or '.join(candidates)}; name it as the capability does, or say which "
                f"with --bind {annotation.name}=NAME",
                data={"decorator": decorator, "name": annotation.name, "candidates": candidates},
            )
        elif annotation.name in binding.unknown and annotation.name not in composites:
            ctx.add(
                ANNOTATION_MATCHES_NOTHING,
                node,
                f"@{decorator} {annotation.name!r} matches no {annotation.direction} of the "
                "capability, by name or by what its name and description mean",
                data={"decorator": decorator, "name": annotation.name},
            )
    return ctx.findings


def _check_states(facts: SkillFacts) -> list[Finding]:
    """The class has a method for each state the specification describes, and none for a
    state it leaves out but a halting one."""
    ctx = _Context()
    cls, spec, methods = facts.skill, facts.spec, facts.states
    if cls is None:
        return ctx.findings
    for state in spec.states:
        if state not in methods:
            ctx.add(
                STATE_MISSING,
                cls,
                f"no method decorated @{state}: the spec asks for it",
                data={"state": state},
            )
    for state, method in methods.items():
        # A halting state the specification left out is welcome: the skeleton adds one to a
        # skill that can move the robot.
        if state not in spec.states and state not in _HALTING:
            ctx.add(
                STATE_NOT_SPECIFIED,
                method,
                f"@{state} is not in the specification; remove it or add it to the spec",
                data={"state": state},
            )
    return ctx.findings


# --- placeholders ------------------------------------------------------------------


def _body_without_docstring(function: ast.FunctionDef) -> list[ast.stmt]:
    body = list(function.body)
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        body = body[1:]
    return body


def _empty_states(facts: SkillFacts) -> list[tuple[str, ast.FunctionDef]]:
    """The state methods with no behaviour: only ``pass`` or ``...`` after the docstring."""
    if facts.skill is None:
        return []
    return [
        (state, method)
        for state, method in facts.states.items()
        if all(
            isinstance(s, ast.Pass)
            or (
                isinstance(s, ast.Expr)
                and isinstance(s.value, ast.Constant)
                and s.value.value is ...
            )
            for s in _body_without_docstring(method)
        )
    ]


def _unimplemented(facts: SkillFacts) -> list[ast.Raise]:
    """Every ``raise NotImplementedError``: behaviour still to be written."""
    if facts.skill is None:
        return []
    found = []
    for node in facts.walk(facts.tree):
        if isinstance(node, ast.Raise) and node.exc is not None:
            exc = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
            if isinstance(exc, ast.Name) and exc.id == "NotImplementedError":
                found.append(node)
    return found


def _check_placeholders(facts: SkillFacts) -> list[Finding]:
    """States with no behaviour, behaviour still to be written and left-over markers."""
    ctx = _Context()
    if facts.skill is None:
        return ctx.findings
    for state, method in _empty_states(facts):
        ctx.add(
            EMPTY_STATE,
            method,
            f"@{state} has no behaviour (only pass / ...)",
            data={"state": state},
        )
    for node in _unimplemented(facts):
        ctx.add(
            NOT_IMPLEMENTED,
            node,
            "raises NotImplementedError: this behaviour is still to be written",
        )
    try:
        tokens = list(tokenize.generate_tokens(io.StringIO(facts.source).readline))
    except (tokenize.TokenError, SyntaxError):
        return ctx.findings
    for token in tokens:
        if token.type == tokenize.COMMENT and re.search(r"\b(TODO|FIXME|XXX)\b", token.string):
            ctx.findings.append(
                LEFTOVER_MARKER.finding(
                    line=token.start[0],
                    column=token.start[1] + 1,
                    message=f"left-over marker in a comment: {token.string.strip()}",
                    data={"marker": token.string.strip()},
                )
            )
    return ctx.findings


# --- errors swallowed where the specification says to abort -----------------------------

_ABORT = re.compile(r"\babort", re.IGNORECASE)


_HALTING = frozenset({"stopping", "aborting"})
"""States that bring the robot to a halt when a skill ends early."""


def _check_swallowed_errors(facts: SkillFacts) -> list[Finding]:
    """An ``except`` in a state that does not raise again lets the state end as if nothing
    failed (logging or returning included); where the specification says to abort, that hides
    the failure from the operator (pySkillUp aborts the skill when a state raises)."""
    ctx = _Context()
    for state, method in facts.states.items():
        text = facts.spec.states.get(state, "")
        for node in facts.walk(method):
            if not isinstance(node, ast.ExceptHandler):
                continue
            if any(isinstance(n, ast.Raise) for part in node.body for n in ast.walk(part)):
                continue
            caught = ast.unparse(node.type) if node.type is not None else "every exception"
            if _ABORT.search(text):
                ctx.add(
                    ABORT_SWALLOWED,
                    node,
                    f"the specification says @{state} aborts, but this handler catches "
                    f"{caught} and carries on: log it if you like, then raise (a state that "
                    "raises aborts the skill)",
                    data={"state": state, "caught": caught},
                )
            elif state not in _HALTING:
                # A halting state that logs a failed cancellation and goes on halting does
                # right: nothing follows it that the failure could mislead.
                ctx.add(
                    ERROR_SWALLOWED,
                    node,
                    f"this handler catches {caught} in @{state} and carries on; check that "
                    "the skill should go on after it",
                    data={"state": state, "caught": caught},
                )
    return ctx.findings


# --- constants standing in for inputs ------------------------------------------------


def _tokens(name: str) -> set[str]:
    words = re.sub(r"(?<=[a-z0-9])(?=[A-Z])", " ", name).replace("_", " ").lower().split()
    return {w for w in words if w not in _GENERIC_TOKENS and len(w) > 1}


def _target_name(node: ast.expr) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    return None


def _is_number(node: ast.expr | None) -> bool:
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        node = node.operand
    return (
        isinstance(node, ast.Constant)
        and isinstance(node.value, int | float)
        and not isinstance(node.value, bool)
    )


def _bounding_names(
    facts: SkillFacts, matching: Callable[[str], str | None]
) -> set[tuple[str, str]]:
    """(name, input) for each name compared with, or clamped against (``min``, ``max``), a
    value named for the same input that is not a constant itself: ``min(self.in_velocity,
    self.MAX_VELOCITY)`` or ``abs(velocity - self.velocity_cmd.linear.x) <= tolerance`` hold
    the input's value to the number, so the number is a bound or a tolerance, not a stand-in
    for the input."""
    found: set[tuple[str, str]] = set()
    for node in facts.walk(facts.tree):
        is_clamp = (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id in {"min", "max"}
        )
        if not (isinstance(node, ast.Compare) or is_clamp):
            continue
        names = [
            name
            for part in facts.walk(node)
            if isinstance(part, ast.Name | ast.Attribute)
            for name in [_target_name(part)]
            if name is not None
        ]
        variables = {matching(n) for n in names if not n.isupper()} - {None}
        for name in names:
            meant = matching(name)
            if meant is not None and meant in variables and (name.isupper() or "tol" in name):
                found.add((name, meant))
    found |= _guarded_clamps(facts, matching)
    return found


def _names_in(facts: SkillFacts, node: ast.AST) -> list[str]:
    return [
        name
        for part in facts.walk(node)
        if isinstance(part, ast.Name | ast.Attribute)
        for name in [_target_name(part)]
        if name is not None
    ]


def _guarded_clamps(
    facts: SkillFacts, matching: Callable[[str], str | None]
) -> set[tuple[str, str]]:
    """(name, input) for a constant assigned to the input's value under a test of that
    value: ``if abs(self.velocity_cmd.angular.z) > 0.5: self.velocity_cmd.angular.z =
    math.copysign(self.MAX_ANGULAR_VELOCITY, ...)`` saturates the input at the capability's
    limit (a clamp written as an ``if``, the same as ``min``); a stand-in replaces the
    input's value whatever it is, so it is never guarded by a test of it."""
    found: set[tuple[str, str]] = set()
    for node in facts.walk(facts.tree):
        if not isinstance(node, ast.If) or not isinstance(node.test, ast.Compare):
            continue
        tested = {matching(n) for n in _names_in(facts, node.test) if not n.isupper()}
        if not tested - {None}:
            continue
        for statement in node.body:
            if not isinstance(statement, ast.Assign):
                continue
            targets = {
                matching(name) for target in statement.targets for name in _names_in(facts, target)
            }
            for meant in {m for m in tested & targets if m is not None}:
                for name in _names_in(facts, statement.value):
                    if name.isupper() and matching(name) == meant:
                        found.add((name, meant))
    return found


def _resource_limits(capability: Capability) -> list[tuple[set[str], float]]:
    """(name tokens, value) of each numeric requirement of the resource."""
    out: list[tuple[set[str], float]] = []
    if capability.resource is None:
        return out
    for prop in capability.resource.properties:
        for instance in prop.instances:
            if isinstance(instance.value, int | float) and not isinstance(instance.value, bool):
                out.append((_tokens(prop.name), float(instance.value)))
    return out


def _number(node: ast.expr) -> float:
    value = ast.literal_eval(node)
    return float(value)


def _assignments(facts: SkillFacts) -> Iterable[tuple[ast.AST, ast.expr, ast.expr, bool]]:
    """(statement, target, value, inside __init__) for assignments and comparisons."""
    init_nodes: set[int] = set()
    for function in facts.walk(facts.tree):
        if isinstance(function, ast.FunctionDef) and function.name == "__init__":
            init_nodes.update(id(n) for n in facts.walk(function))
    for node in facts.walk(facts.tree):
        in_init = id(node) in init_nodes
        if isinstance(node, ast.Assign):
            for target in node.targets:
                yield node, target, node.value, in_init
        elif isinstance(node, ast.AnnAssign) and node.value is not None:
            yield node, node.target, node.value, in_init
        elif isinstance(node, ast.Compare):
            operands = [node.left, *node.comparators]
            names = [o for o in operands if _target_name(o)]
            numbers = [o for o in operands if _is_number(o)]
            if names and numbers:
                yield node, names[0], numbers[0], in_init


def _spec_numbers(spec: SkillSpec) -> set[float]:
    """Numbers the specification states itself (``slow down for the last 0.1 m``)."""
    texts = [spec.description or "", *spec.states.values()]
    return {float(m) for text in texts for m in re.findall(r"(?<![\w.])\d+(?:\.\d+)?", text)}


def _check_input_constants(facts: SkillFacts) -> list[Finding]:
    """A number written out where the skill should use the value of a capability input: a
    name that means the input given a number that is neither zero, one the specification
    states, the resource's own limit nor a bound the input's value is held to (compared
    with the input's own attribute, clamped against it with ``min``/``max`` or assigned to
    it under a test of its value). A number compared with the input itself is never its
    stand-in: the comparison uses the value the skill was given."""
    ctx = _Context()
    capability, held = facts.capability, facts.input_attributes
    sanctioned = _spec_numbers(facts.spec) | {0.0}
    inputs = [
        (component.name, _tokens(component.name))
        for parameter in capability.inputs
        for component in parameter.components
    ]
    if not inputs:
        return ctx.findings
    own_attributes = {re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", n).lower() for n, _ in inputs}
    outputs = {
        re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", c.name).lower()
        for parameter in capability.outputs
        for c in parameter.components
    }
    limits = _resource_limits(capability)
    qualifiers = {"min", "max", "minimum", "maximum", "limit", "desired", "target", "requested"}

    def matching(name: str) -> str | None:
        words = _tokens(name)
        for input_name, input_words in inputs:
            if input_words and input_words <= words | qualifiers and input_words & words:
                return input_name
        return None

    def meaning(name: str) -> str | None:
        return held.get(name) or matching(name)

    bounding = _bounding_names(facts, meaning)

    for statement, target, value, in_init in _assignments(facts):
        name = _target_name(target)
        if name is None or not _is_number(value):
            continue
        if (in_init and name in own_attributes) or name in outputs:
            continue  # a parameter's storage initialised before it is set, or an output
        if isinstance(statement, ast.Compare) and (name in held or name in own_attributes):
            continue  # the input's own value compared with a number: a bound it is held to
        words = _tokens(name)
        number = _number(value)
        if abs(number) in sanctioned:
            continue  # zero, or a number the specification itself gives
        if any(tokens and tokens <= words and number == limit for tokens, limit in limits):
            continue  # the resource's own limit, taken from the capability model
        input_name = matching(name)
        if input_name is not None and (name, input_name) in bounding:
            continue  # a bound or tolerance the input's own value is held to
        if input_name is not None:
            ctx.add(
                CONSTANT_FOR_INPUT,
                statement,
                f"the number {ast.unparse(value)} stands in for the capability input "
                f"{input_name} (via {name!r}); use the value of its @skill_parameter",
                data={"input": input_name, "name": name, "value": number},
            )
    return ctx.findings


# --- interface grounding ----------------------------------------------------------------


def _check_interface_names(facts: SkillFacts) -> list[Finding]:
    """A handle made for an interface whose name is not a string literal: no check can tell
    which interface it is."""
    return [
        INTERFACE_NAME_NOT_LITERAL.at(
            made.call,
            f"{made.maker}: the interface name is not a string literal, so it cannot be checked",
            data={"call": made.maker},
        )
        for made in facts.made
        if made.interface_kind is not None and made.name is None
    ]


def _check_uses(facts: SkillFacts) -> list[Finding]:
    """Each interface the file uses exists on the robot (in the catalog), as the kind of
    interface and with the type the code uses it as."""
    ctx = _Context()
    catalog = facts.catalog
    if catalog is None:
        return ctx.findings
    for use in facts.interface_uses:
        entry = catalog.entries.get(use.name)
        where = use.call
        if entry is None:
            ctx.add(
                UNKNOWN_INTERFACE,
                where,
                f"{use.kind} {use.name} does not exist on this robot (not in the inventory); "
                "use one of its real interfaces",
                data={"kind": use.kind, "name": use.name},
            )
            continue
        if entry.kind != use.kind:
            ctx.add(
                INTERFACE_KIND_MISMATCH,
                where,
                f"{use.name} is a {entry.kind} on this robot, but the code uses it as a {use.kind}",
                data={"name": use.name, "kind": entry.kind, "used_as": use.kind},
            )
        elif use.type_name is not None and use.type_name != entry.type_name:
            ctx.add(
                INTERFACE_TYPE_MISMATCH,
                where,
                f"{use.name} carries {entry.type_name}, but the code uses {use.type_name}",
                data={"name": use.name, "type": entry.type_name, "used_type": use.type_name},
            )
    return ctx.findings


def _check_retrieved(facts: SkillFacts) -> list[Finding]:
    """The interfaces retrieval chose are the ones the code uses: one retrieved and never
    used, or used and never retrieved, is most likely the wrong one."""
    ctx = _Context()
    if not facts.retrieved:
        return ctx.findings
    used = {u.name for u in facts.interface_uses}
    wanted = {_normalise(n) for n in facts.retrieved}
    for name in sorted(wanted - used):
        ctx.add(
            INTERFACE_RETRIEVED_UNUSED,
            None,
            f"{name} was retrieved but the code never uses it",
            data={"name": name},
        )
    for use in facts.interface_uses:
        if use.name not in wanted:
            ctx.add(
                INTERFACE_NOT_RETRIEVED,
                use.call,
                f"{use.name} is used but was not retrieved for this capability; "
                "check that it is the right interface",
                data={"name": use.name},
            )
    return ctx.findings


def _chain(node: ast.expr) -> tuple[ast.expr, list[str]]:
    """``a.b[0].c`` -> (``a``, ["b", "c"])."""
    parts: list[str] = []
    while True:
        if isinstance(node, ast.Attribute):
            parts.append(node.attr)
            node = node.value
        elif isinstance(node, ast.Subscript):
            node = node.value
        else:
            return node, list(reversed(parts))


_SAME_AS = {
    ("geometry_msgs/msg/TransformStamped", "pose", "position"): ("transform", "translation"),
    ("geometry_msgs/msg/TransformStamped", "pose", "orientation"): ("transform", "rotation"),
}
"""Paths a model takes from a pose into a transform, which carries the same quantities."""
_SAME_AS_FIRST = {
    ("geometry_msgs/msg/TransformStamped", "position"): ("transform", "translation"),
    ("geometry_msgs/msg/TransformStamped", "orientation"): ("transform", "rotation"),
}
"""A pose's own fields asked of a transform (``transform.orientation``): a
TransformStamped's ``transform`` has ``translation`` and ``rotation``, a Pose ``position``
and ``orientation``."""


def _missing_field(
    tree: FieldTree, path: Sequence[str], type_name: str
) -> tuple[str, list[str] | None] | None:
    """The message for the first field of ``path`` the type does not have, and the path
    that exists when it is clear which one was meant (a field one level further down, as
    ``transform.translation`` for ``translation``); ``None`` when the path exists."""
    current: FieldTree | None = tree
    for index, part in enumerate(path):
        if current is None:
            return None  # attribute of a primitive or a list (e.g. .append): not a message field
        if part not in current:
            known = ", ".join(sorted(set(current) - SEQUENCE_METHODS)) or "none"
            where = ".".join(path[:index]) or "the message"
            message = f"{type_name} has no field {part!r} in {where} (fields: {known})"
            fixed = _meant(current, path, index, type_name)
            if fixed is None or not _exists(tree, fixed):
                fixed = _renamed(tree, path if fixed is None else fixed)
            if fixed is not None and _exists(tree, fixed):
                message += f"; it is {'.'.join(fixed)}"
                return message, fixed
            return message, None
        current = current[part]
    return None


def _meant(
    current: dict[str, FieldTree], path: Sequence[str], index: int, type_name: str
) -> list[str] | None:
    head, part = list(path[:index]), path[index]
    same = _SAME_AS.get((type_name, part, path[index + 1] if index + 1 < len(path) else ""))
    if index == 0 and same is not None:
        return [*same, *path[2:]]
    first = _SAME_AS_FIRST.get((type_name, part))
    if index == 0 and first is not None:
        return [*first, *path[1:]]
    holders = [name for name, sub in current.items() if isinstance(sub, dict) and part in sub]
    if len(holders) == 1:
        return [*head, holders[0], *path[index:]]
    return None


_TIME_TYPES = frozenset({"builtin_interfaces/msg/Duration", "builtin_interfaces/msg/Time"})
_RENAMED = {"secs": "sec", "nsecs": "nanosec", "seconds": "sec", "nanoseconds": "nanosec"}
"""ROS 1's time fields (and rclpy Duration's keywords) as builtin_interfaces names them."""
_AXES = {"roll": "x", "pitch": "y", "yaw": "z"}
_AXES |= {f"{angle}_rate": axis for angle, axis in _AXES.items()}
"""A rate or angle about an axis, as a Vector3 (angular velocity, not a quaternion) holds it."""


def _renamed(tree: FieldTree, path: Sequence[str]) -> list[str] | None:
    """``path`` with the parts a message names differently put as it names them (``secs`` is
    ``sec``; ``yaw_rate`` of an angular Vector3 is ``z``), or ``None`` when there is none."""
    out: list[str] = []
    changed = False
    current: FieldTree | None = tree
    for written in path:
        part = written
        if current is None:
            out.append(part)
            continue
        if part not in current:
            vector = {"x", "y", "z"} <= set(current) and "w" not in current
            alias = (
                _RENAMED.get(part)
                or (_AXES.get(part) if vector else None)
                or _plural(part, current)
            )
            if alias is None or alias not in current:
                return None
            part, changed = alias, True
        out.append(part)
        current = current[part]
    return out if changed else None


def _renamed_keywords(
    call: ast.Call, tree: FieldTree, key: str, statement: ast.stmt | None
) -> str | None:
    """``statement`` with every keyword of ``call`` that names no field of the message put
    as the field it means (``position=`` of a JointTrajectoryPoint is ``positions=``);
    ``None`` unless each such keyword has one."""
    fixed = copy.deepcopy(call)
    changed = False
    for keyword in fixed.keywords:
        if keyword.arg is None or keyword.arg in tree:
            continue
        missing = _missing_field(tree, [keyword.arg], key)
        meant = None if missing is None else missing[1]
        if meant is None or len(meant) != 1:
            return None
        keyword.arg, changed = meant[0], True
    if statement is None or not changed:
        return None
    return ast.unparse(statement).replace(ast.unparse(call), ast.unparse(fixed))


def _split_seconds(
    call: ast.Call, keyword: ast.keyword, key: str, statement: ast.stmt | None
) -> tuple[str, str | None] | None:
    """For ``Duration(seconds=x)`` made from the message class (rclpy's Duration takes
    ``seconds``; builtin_interfaces' has integer ``sec`` and ``nanosec``): the message and
    ``statement`` with the call making the message from ``x`` split into both fields."""
    if key not in _TIME_TYPES or keyword.arg != "seconds" or len(call.keywords) != 1:
        return None
    value = keyword.value
    number = _literal_seconds(value)
    if number is not None:
        whole = int(number)
        fields = f"sec={whole}, nanosec={round((number - whole) * 1e9)}"
    else:
        seconds = ast.unparse(value)
        fields = f"sec=int({seconds}), nanosec=int({seconds} % 1 * 1e9)"
    made = f"{ast.unparse(call.func)}({fields})"
    message = (
        f"{key} has no field 'seconds' (fields: nanosec, sec; both integers): it is {made} "
        "(rclpy.duration.Duration is the class that takes seconds)"
    )
    if statement is None:
        return message, None
    return message, ast.unparse(statement).replace(ast.unparse(call), made)


def _literal_seconds(node: ast.expr) -> float | None:
    """The value of a non-negative literal int or float."""
    value = node.value if isinstance(node, ast.Constant) else None
    if isinstance(value, int | float) and not isinstance(value, bool) and value >= 0:
        return float(value)
    return None


def _plural(name: str, fields: dict[str, FieldTree]) -> str | None:
    """The array field ``name`` is the singular of (``position`` of ``positions``)."""
    for plural in (f"{name}s", f"{name[:-1]}ies" if name.endswith("y") else ""):
        if plural in fields:
            return plural
    return None


def _exists(tree: FieldTree, path: Sequence[str]) -> bool:
    current: FieldTree | None = tree
    for part in path:
        if current is None:
            return True
        if part not in current:
            return False
        current = current[part]
    return True


class _FieldVisitor(ast.NodeVisitor):
    """Checks attribute chains on names and self-attributes whose message type is known."""

    def __init__(
        self,
        ctx: _Context,
        catalog: Catalog,
        bound: dict[str, str],
        checked: AbstractSet[str] = frozenset(),
    ) -> None:
        self.ctx = ctx
        self.catalog = catalog
        self.bound = bound  # "name" or "self.attr" -> field-tree key
        self.checked = checked
        """Names holding a result a helper returns only when the goal succeeded."""
        self.statement: ast.stmt | None = None
        self.found: list[tuple[ast.stmt | None, ast.Attribute, str, str | None]] = []
        """(simple statement or guard, chain, message, the chain as it should read)"""
        self.outcome_guards: dict[int, str] = {}
        """Guards on a made-up field of such a result -> what they come to (statements)."""

    def visit(self, node: ast.AST) -> None:
        if isinstance(node, ast.stmt) and not isinstance(node, COMPOUND_STATEMENTS):
            outer, self.statement = self.statement, node
            super().visit(node)
            self.statement = outer
            return
        super().visit(node)

    def visit_If(self, node: ast.If) -> None:
        outer, self.statement = self.statement, node
        self.visit(node.test)
        self.statement = outer
        for statement in [*node.body, *node.orelse]:
            self.visit(statement)

    def _outcome_guard(self, root: ast.expr, chain: ast.Attribute, message: str) -> str:
        """``message``, and the guard's fix when the statement is an ``if`` on a made-up
        field of a result its helper returns only after the goal succeeded (``if not
        result.success: raise ...``): the guard tests what is already known, so it comes to
        its body when it tests the field and to its ``else`` when it tests the negation
        (what a failed goal would have done never runs: the helper raised instead)."""
        guard = self.statement
        if not isinstance(guard, ast.If) or not (
            isinstance(root, ast.Name) and root.id in self.checked
        ):
            return message
        test = guard.test
        if ast.unparse(test) == ast.unparse(chain):
            taken = guard.body
        elif (
            isinstance(test, ast.UnaryOp)
            and isinstance(test.op, ast.Not)
            and ast.unparse(test.operand) == ast.unparse(chain)
        ):
            taken = guard.orelse
        else:
            return message
        self.outcome_guards[id(guard)] = "\n".join(ast.unparse(s) for s in taken)
        return (
            f"{message}; the helper that returned {root.id} raises RuntimeError when the goal "
            "did not succeed, so this test is not needed"
        )

    def report(self) -> None:
        """Adds the findings; each carries its simple statement with every chain in it that
        has a clear fix fixed, when all of them have one; a guard on the outcome of a
        checked result carries what the guard comes to."""
        by_statement: dict[int, list[tuple[ast.Attribute, str | None]]] = {}
        for statement, chain, _, fixed in self.found:
            if statement is not None:
                by_statement.setdefault(id(statement), []).append((chain, fixed))
        for statement, chain, message, _ in self.found:
            fixes = by_statement.get(id(statement), []) if statement is not None else []
            replacement = None
            if statement is not None and id(statement) in self.outcome_guards:
                replacement = self.outcome_guards[id(statement)]
            elif (
                statement is not None
                and not isinstance(statement, ast.If)
                and fixes
                and all(f is not None for _, f in fixes)
            ):
                text = ast.unparse(statement)
                for wrong, right in fixes:
                    text = text.replace(ast.unparse(wrong), str(right))
                replacement = text
            self.ctx.add(
                UNKNOWN_FIELD,
                chain,
                message,
                replacement=replacement,
                data={"field": ast.unparse(chain), "meant": replacement},
            )

    def visit_Attribute(self, node: ast.Attribute) -> None:
        root, path = _chain(node)
        key = None
        if isinstance(root, ast.Call) and _is_transform_lookup(root):
            key = _TRANSFORM_STAMPED
        elif isinstance(root, ast.Name) and root.id in self.bound:
            key = self.bound[root.id]
        elif (
            isinstance(root, ast.Name)
            and root.id == "self"
            and path
            and f"self.{path[0]}" in self.bound
        ):
            key = self.bound[f"self.{path[0]}"]
            path = path[1:]
        held: list[str] = []
        if key is not None and "#" in key:
            key, _, inside = key.partition("#")
            held = inside.split(".")
        if key is not None and path and key in self.catalog.fields:
            tree = self.catalog.fields[key]
            if held and _missing_field(tree, held, key) is not None:
                return  # the part itself is made up: its own statement says so
            missing = _missing_field(tree, [*held, *path], key)
            if missing is not None:
                message, fixed = missing
                if held:
                    head, _, _ = message.partition("; it is ")
                    fixed = fixed[len(held) :] if fixed and fixed[: len(held)] == held else None
                    holder = ast.unparse(node)[: -len(".".join(path)) - 1]
                    message = f"{head}, and {holder} holds its {'.'.join(held)}" + (
                        f"; it is {'.'.join(fixed)}" if fixed else ""
                    )
                right = None
                if fixed is not None and not _has_subscript(node):
                    whole = _chain(node)[1]
                    prefix = whole[: len(whole) - len(path)]
                    right = ".".join([ast.unparse(root), *prefix, *fixed])
                    # the whole expression: "it is transform.translation.x" read as no change
                    # when the variable itself is called transform
                    message = message.replace(f"; it is {'.'.join(fixed)}", f"; it is {right}")
                elif fixed is None:
                    message = self._outcome_guard(root, node, message)
                self.found.append((self.statement, node, message, right))
            return
        self.generic_visit(node)


def _has_subscript(node: ast.expr) -> bool:
    return any(isinstance(n, ast.Subscript) for n in ast.walk(node))


_TRANSFORM_STAMPED = "geometry_msgs/msg/TransformStamped"
_TF_MESSAGE = "tf2_msgs/msg/TFMessage"


def _is_transform_lookup(call: ast.Call) -> bool:
    """``self._transform(...)`` (the skeleton's helper) or ``<buffer>.lookup_transform(...)``:
    both give a TransformStamped."""
    func = call.func
    return isinstance(func, ast.Attribute) and (
        func.attr == "lookup_transform"
        or (func.attr == "_transform" and ast.unparse(func.value) == "self")
    )


def _with_transforms(catalog: Catalog) -> Catalog:
    """The catalog with the fields of a TransformStamped (what a transform lookup gives),
    taken from the transform tree's type when the robot has one."""
    transforms = catalog.fields.get(_TF_MESSAGE, {}).get("transforms")
    if not isinstance(transforms, dict) or _TRANSFORM_STAMPED in catalog.fields:
        return catalog
    return catalog.model_copy(update={"fields": {**catalog.fields, _TRANSFORM_STAMPED: transforms}})


def _returned_messages(facts: SkillFacts) -> dict[str, str]:
    """Methods of the class annotated to return a message (``-> "NavigateToPose.Result"``,
    as the skeleton's result helpers are): method name -> ``pkg/action/Type.Result``."""
    imports = facts.imports
    out: dict[str, str] = {}
    for method in facts.functions:
        if method.returns is None:
            continue
        annotation = method.returns
        if isinstance(annotation, ast.Constant) and isinstance(annotation.value, str):
            text = annotation.value
        else:
            text = ast.unparse(annotation)
        head, _, tail = text.partition(".")
        if head in imports and (not tail or tail in _NESTED_TYPES):
            out[method.name] = imports[head] + (f".{tail}" if tail else "")
    return out


def _checked_results(method: ast.FunctionDef, helpers: AbstractSet[str]) -> set[str]:
    """Local names of ``method`` assigned the return of one of ``helpers``: the skeleton's
    result helpers, which return an action's result only when its goal succeeded."""
    return {
        node.targets[0].id
        for node in ast.walk(method)
        if isinstance(node, ast.Assign)
        and len(node.targets) == 1
        and isinstance(node.targets[0], ast.Name)
        and isinstance(node.value, ast.Call)
        and isinstance(node.value.func, ast.Attribute)
        and ast.unparse(node.value.func.value) == "self"
        and node.value.func.attr in helpers
    }


def _message_bindings(facts: SkillFacts, returns: dict[str, str]) -> dict[str, dict[str, str]]:
    """Per method: which local names / self attributes hold which message type (``returns``:
    the class's methods annotated to return a message, as :func:`_returned_messages` finds).
    A name given a part of a message (``twist = self.odom_msg.twist``) holds
    ``type#path`` (``nav_msgs/msg/Odometry#twist``): an Odometry's ``twist`` is a
    TwistWithCovariance, so ``twist.linear.x`` is missing (it is ``twist.twist.linear.x``).
    The second pass sees the attributes every method stores."""
    callbacks = {m.callback: m.type_name for m in facts.made if m.callback and m.type_name}
    stored: dict[str, str] = {}
    per_method: dict[str, dict[str, str]] = {}
    for _ in range(2):
        per_method = _bindings_pass(facts, callbacks, stored, returns)
    for bound in per_method.values():
        for attribute, key in stored.items():
            bound.setdefault(attribute, key)
    return per_method


def _bindings_pass(
    facts: SkillFacts,
    callbacks: dict[str, str],
    stored: dict[str, str],
    returns: dict[str, str],
) -> dict[str, dict[str, str]]:
    """One pass of :func:`_message_bindings`; adds to ``stored``."""
    imports = facts.imports
    per_method: dict[str, dict[str, str]] = {}
    for method in facts.functions:
        bound: dict[str, str] = {}
        if method.name in callbacks and len(method.args.args) >= 2:
            message_type = callbacks[method.name]
            assert message_type is not None
            bound[method.args.args[1].arg] = message_type
        for node in facts.walk(method):
            if not isinstance(node, ast.Assign) or len(node.targets) != 1:
                continue
            target = node.targets[0]
            value = node.value
            key = None
            if isinstance(value, ast.Call) and _is_transform_lookup(value):
                key = _TRANSFORM_STAMPED
            elif isinstance(value, ast.Call):
                func = ast.unparse(value.func)
                head, _, tail = func.partition(".")
                if head in imports and (not tail or tail in _NESTED_TYPES):
                    key = imports[head] + (f".{tail}" if tail else "")
                elif head == "self" and tail in returns:
                    key = returns[tail]
            elif isinstance(value, ast.Name) and value.id in bound:
                key = bound[value.id]
            elif isinstance(value, ast.Attribute):
                key = _part_of_message(value, bound, stored)
            if key is None:
                continue
            if isinstance(target, ast.Name):
                bound[target.id] = key
            elif isinstance(target, ast.Attribute) and ast.unparse(target.value) == "self":
                stored[f"self.{target.attr}"] = key
        per_method[method.name] = bound
    return per_method


def _part_of_message(
    value: ast.Attribute, bound: dict[str, str], stored: dict[str, str]
) -> str | None:
    """``type#path`` for a part of a message held by a name or attribute
    (``self.odom_msg.twist``), else ``None``."""
    root, path = _chain(value)
    if not isinstance(root, ast.Name):
        return None
    if root.id == "self" and path and f"self.{path[0]}" in stored:
        key, path = stored[f"self.{path[0]}"], path[1:]
    elif root.id in bound:
        key = bound[root.id]
    else:
        return None
    if not path:
        return key
    return f"{key}.{'.'.join(path)}" if "#" in key else f"{key}#{'.'.join(path)}"


def _check_fields(facts: SkillFacts) -> list[Finding]:
    """Messages built, sent and read as the robot's interfaces define them: each field a
    chain of attributes or a keyword names exists, a message handed to a handle is of its
    type, the skeleton's helpers get a quaternion or an angle where they take one, and a
    message's fields are given by keyword and as messages where they are messages."""
    ctx = _Context()
    catalog, imports = facts.catalog, facts.imports
    if facts.skill is None or catalog is None:
        return ctx.findings
    returns = _returned_messages(facts)
    bindings = _message_bindings(facts, returns)
    _check_arguments(ctx, facts, catalog, bindings)
    _check_yaw_arguments(ctx, facts, bindings)
    _check_heading_arguments(ctx, facts, bindings)
    numeric_attributes = _numeric_attributes(facts)
    numeric_attributes |= _numeric_callables(facts, numeric_attributes)
    known = _with_transforms(catalog)
    helpers = {name for name, key in returns.items() if key.endswith(".Result")}
    for method in facts.functions:
        visitor = _FieldVisitor(
            ctx, known, bindings.get(method.name, {}), _checked_results(method, helpers)
        )
        visitor.generic_visit(method)
        visitor.report()
    statement_of = facts.statement_of
    for method in facts.functions:
        numbers = _numeric_names(method, numeric_attributes) | numeric_attributes
        published = {
            id(call.args[0]): ast.unparse(call.func)
            for call in facts.calls(method)
            if isinstance(call.func, ast.Attribute)
            and call.func.attr == "publish"
            and len(call.args) == 1
        }
        for node in facts.calls(method):
            func = ast.unparse(node.func)
            head, _, tail = func.partition(".")
            if head not in imports or (tail and tail not in _NESTED_TYPES):
                continue
            key = imports[head] + (f".{tail}" if tail else "")
            tree = catalog.fields.get(key)
            if tree is None:
                continue
            # Twist(linear=0.0, angular=0.0) means "stand still", and Twist() says it: every
            # field of a new message is zero.
            zero = key.endswith("/Twist") and all(_is_zero(k.value) for k in node.keywords)
            publish = published.get(id(node))
            fix: str | None
            if zero and publish is not None:
                fix = f"{publish}(Twist())"
            else:
                fix = _twist_with_vectors(statement_of.get(id(node)), node, key, numbers)
            if node.args:
                _positional_fields(ctx, node, tree, key, statement_of.get(id(node)))
            renamed = _renamed_keywords(node, tree, key, statement_of.get(id(node)))
            for keyword in node.keywords:
                if keyword.arg is None:
                    continue
                split = _split_seconds(node, keyword, key, statement_of.get(id(node)))
                if split is not None:
                    ctx.add(DURATION_SECONDS_FIELD, keyword, *split, data={"type": key})
                    continue
                missing = _missing_field(tree, [keyword.arg], key)
                if missing is not None:
                    ctx.add(
                        UNKNOWN_FIELD,
                        keyword,
                        missing[0],
                        replacement=renamed,
                        data={
                            "type": key,
                            "field": keyword.arg,
                            "meant": None if missing[1] is None else ".".join(missing[1]),
                        },
                    )
                nested = tree.get(keyword.arg)
                if isinstance(nested, dict) and nested and _is_scalar(keyword.value, numbers):
                    ctx.add(
                        MESSAGE_FIELD_NOT_NUMBER,
                        keyword,
                        f"{key}'s field {keyword.arg!r} is a message (fields "
                        f"{', '.join(sorted(nested))}), not a number: make the message first and "
                        f"set its fields, e.g. msg.{keyword.arg}.{sorted(nested)[0]} = ..."
                        + ("; a zero command is Twist(), every field of it is 0" if zero else ""),
                        replacement=fix,
                        data={"type": key, "field": keyword.arg, "fields": sorted(nested)},
                    )
    return ctx.findings


_ORIENTATIONS = {
    "nav_msgs/msg/Odometry": "pose.pose.orientation",
    "geometry_msgs/msg/PoseWithCovarianceStamped": "pose.pose.orientation",
    "geometry_msgs/msg/PoseStamped": "pose.orientation",
    "geometry_msgs/msg/Pose": "orientation",
    _TRANSFORM_STAMPED: "transform.rotation",
}
"""Where a message keeps its orientation quaternion."""


def _check_yaw_arguments(
    ctx: _Context, facts: SkillFacts, bindings: dict[str, dict[str, str]]
) -> None:
    """The skeleton's ``self._yaw(q)`` handed a whole message (``self._yaw(transform)``): it
    takes the quaternion, which a message has no x, y, z, w of its own for (AttributeError),
    and the fix hands it the message's orientation."""
    for call, bound, statement in _helper_calls(facts, "_yaw", bindings):
        given = facts.helper_argument(call, "q")
        if given is None or len(call.args) + len(call.keywords) != 1:
            continue
        argument = ast.unparse(given)
        key = bound.get(argument)
        path = _ORIENTATIONS.get(key or "")
        if path is None:
            continue
        named = "q=" if call.keywords else ""
        fix = _replaced_once(
            statement, f"self._yaw({named}{argument})", f"self._yaw({named}{argument}.{path})"
        )
        ctx.add(
            YAW_OF_MESSAGE,
            call,
            f"self._yaw() takes an orientation quaternion, and {argument} is a whole "
            f"{key}: its orientation is {argument}.{path}",
            replacement=fix,
            data={"argument": argument, "type": key, "orientation": path},
        )


def _replaced_once(statement: ast.stmt | None, old: str, new: str) -> str | None:
    """The statement with ``old`` replaced by ``new``, as the finding's fix; none where the
    call is not a statement of its own or ``old`` is not there exactly once."""
    if statement is None:
        return None
    text = ast.unparse(statement)
    return text.replace(old, new) if text.count(old) == 1 else None


def _helper_calls(
    facts: SkillFacts, helper: str, bindings: dict[str, dict[str, str]]
) -> Iterable[tuple[ast.Call, dict[str, str], ast.stmt | None]]:
    """Every call of the skeleton's ``self.<helper>(...)`` when the class has that helper,
    with the message types its method binds to names and the statement that holds it."""
    if helper not in facts.methods:
        return
    for method in facts.functions:
        bound = bindings.get(method.name, {})
        for call in facts.calls(method):
            if self_attribute(call.func) == helper:
                yield call, bound, facts.statement_of.get(id(call))


def _check_heading_arguments(
    ctx: _Context, facts: SkillFacts, bindings: dict[str, dict[str, str]]
) -> None:
    """The skeleton's ``self._pose_goal(frame, x, y, yaw)`` handed an orientation for the
    heading (a quaternion, or a whole odometry, pose or transform): it takes the angle in
    radians, which ``math.sin`` of a message raises TypeError on, and the fix hands it
    ``self._yaw()`` of the quaternion."""
    for call, bound, statement in _helper_calls(facts, "_pose_goal", bindings):
        heading = facts.helper_argument(call, "yaw")
        if heading is None:
            continue
        text = ast.unparse(heading)
        path = _ORIENTATIONS.get(bound.get(text) or "")
        if path is not None:
            quaternion = f"{text}.{path}"
        elif text.endswith((".orientation", ".rotation")):
            quaternion = text
        else:
            continue
        fix = _replaced_once(statement, text, f"self._yaw({quaternion})")
        ctx.add(
            HEADING_NOT_ANGLE,
            heading,
            f"self._pose_goal() takes the heading as an angle in radians, and {text} is an "
            f"orientation: self._yaw({quaternion}) is its heading",
            replacement=fix,
            data={"argument": text},
        )


def _positional_fields(
    ctx: _Context, call: ast.Call, tree: FieldTree, key: str, statement: ast.stmt | None
) -> None:
    """A message made with positional arguments (``Vector3(0.0, 0.0, bearing)``): a ROS 2
    message takes its fields as keywords only, and raises
    TypeError. The fix names each argument by the field in its place."""
    names = [n for n in tree if n not in {k.arg for k in call.keywords}]
    fix = None
    if (
        statement is not None
        and len(call.args) <= len(names)
        and not any(isinstance(a, ast.Starred) for a in call.args)
    ):
        fixed = copy.deepcopy(statement)
        for node in ast.walk(fixed):
            if (
                isinstance(node, ast.Call)
                and (node.lineno, node.col_offset) == (call.lineno, call.col_offset)
                and ast.unparse(node.func) == ast.unparse(call.func)
            ):
                given = [
                    ast.keyword(arg=n, value=a) for n, a in zip(names, node.args, strict=False)
                ]
                node.keywords = given + node.keywords
                node.args = []
                fix = ast.unparse(fixed)
                break
    ctx.add(
        POSITIONAL_MESSAGE_FIELDS,
        call,
        f"`{ast.unparse(call)}` gives {key} positional arguments, and a ROS 2 message takes "
        f"its fields as keywords only (it raises TypeError): name them, "
        f"{ast.unparse(call.func)}({', '.join(f'{n}=...' for n in names[: len(call.args)])})",
        replacement=fix,
        data={"type": key, "fields": names},
    )


_TWIST_AXES = {"linear": "x", "angular": "z"}
"""The axis a number given for a whole Twist vector means on a ground robot: forward speed,
yaw rate."""


def _twist_with_vectors(
    statement: ast.stmt | None, call: ast.Call, key: str, numbers: AbstractSet[str]
) -> str | None:
    """``statement`` with ``Twist(linear=v)`` written ``Twist(linear=Vector3(x=v))`` (and
    ``angular`` about z), when every number the call gives a vector is one of those."""
    if statement is None or not key.endswith("/Twist"):
        return None
    scalars = [k for k in call.keywords if k.arg is not None and _is_scalar(k.value, numbers)]
    if not scalars or any(k.arg not in _TWIST_AXES for k in scalars):
        return None
    fixed = copy.deepcopy(statement)
    same = [
        node
        for node in ast.walk(fixed)
        if isinstance(node, ast.Call)
        and (node.lineno, node.col_offset) == (call.lineno, call.col_offset)
        and ast.unparse(node.func) == ast.unparse(call.func)
    ]
    for node in same:
        for keyword in node.keywords:
            if keyword.arg in _TWIST_AXES and _is_scalar(keyword.value, numbers):
                axis = _TWIST_AXES[keyword.arg]
                keyword.value = ast.Call(
                    func=ast.Name(id="Vector3", ctx=ast.Load()),
                    args=[],
                    keywords=[ast.keyword(arg=axis, value=keyword.value)],
                )
    return ast.unparse(ast.fix_missing_locations(fixed))


_TAKES = {"publish": "", "send_goal_async": ".Goal", "call_async": ".Request"}
"""What a handle's method takes, as the suffix of the handle's type."""
_MADE_BY = {
    "publish": "create_publisher",
    "send_goal_async": "ActionClient",
    "call_async": "create_client",
}
"""The call that makes a handle with that method."""


def _argument_type(
    argument: ast.expr, bound: dict[str, str], imports: Mapping[str, str]
) -> str | None:
    if isinstance(argument, ast.Name):
        return bound.get(argument.id)
    if isinstance(argument, ast.Call):
        head, _, tail = ast.unparse(argument.func).partition(".")
        if head in imports and (not tail or tail in _NESTED_TYPES):
            return imports[head] + (f".{tail}" if tail else "")
    return None


def _check_arguments(
    ctx: _Context,
    facts: SkillFacts,
    catalog: Catalog,
    bindings: dict[str, dict[str, str]],
) -> None:
    """A message handed to ``publish``, ``send_goal_async``, ``call_async`` or a skeleton's
    ``_send_<action>_goal`` must be of the type the handle carries (the model sent a
    PoseStamped as a NavigateToPose goal). When the expected message has a field of the
    given type, the finding carries the statement that wraps it in one."""
    imports = facts.imports
    handles = {
        h.target: h.made.type_name
        for h in facts.handles
        if h.made.interface_kind is not None and h.made.type_name is not None
    }
    makers = {h.target: h.made.maker for h in facts.handles}
    classes = {type_name: name for name, type_name in imports.items()}
    statement_of = facts.statement_of
    for method in facts.functions:
        bound = bindings.get(method.name, {})
        for call in facts.calls(method):
            if not isinstance(call.func, ast.Attribute):
                continue
            receiver, attr = ast.unparse(call.func.value), call.func.attr
            expected = None
            if attr in _TAKES and receiver in handles:
                expected = handles[receiver] + _TAKES[attr]
            elif receiver == "self" and attr.startswith("_send_") and attr.endswith("_goal"):
                client = f"self.{attr.removeprefix('_send_').removesuffix('_goal')}_client"
                expected = handles[client] + ".Goal" if client in handles else None
            if expected is None or not call.args:
                continue
            given = _argument_type(call.args[0], bound, imports)
            if given is None or given == expected:
                continue
            message = f"{ast.unparse(call.func)} takes a {expected}, not a {given}"
            made = _wrapping(catalog, classes, expected, given, call.args[0])
            replacement = None
            statement = statement_of.get(id(call))
            text = ast.unparse(statement) if statement is not None else ""
            fitting = [
                h
                for h, type_name in handles.items()
                if attr in _TAKES
                and type_name + _TAKES[attr] == given
                and makers.get(h) == _MADE_BY[attr]
            ]
            if made is not None:
                message += f": put it in one, {made}"
                if text.count(ast.unparse(call.args[0])) == 1:
                    replacement = text.replace(ast.unparse(call.args[0]), made)
            elif len(fitting) == 1:
                # the message is right and the handle wrong: a Twist published on a handle of
                # another type (an arm's Float64MultiArray controller beside the base's cmd_vel)
                message += f"; {fitting[0]} takes a {given}: {attr} it there"
                if text.count(f"{receiver}.{attr}(") == 1:
                    replacement = text.replace(f"{receiver}.{attr}(", f"{fitting[0]}.{attr}(")
            ctx.add(
                ARGUMENT_TYPE_MISMATCH,
                call.args[0],
                message,
                replacement=replacement,
                data={"call": ast.unparse(call.func), "expected": expected, "given": given},
            )


def _wrapping(
    catalog: Catalog, classes: dict[str, str], expected: str, given: str, argument: ast.expr
) -> str | None:
    """``NavigateToPose.Goal(pose=goal_pose)``: the expected message made around the given
    one, when exactly one of its fields has the given one's type."""
    holder = _field_holding(catalog, expected, given)
    base, _, nested = expected.partition(".")
    owner = classes.get(base)
    if holder is None or owner is None:
        return None
    cls = f"{owner}.{nested}" if nested else owner
    return f"{cls}({holder}={ast.unparse(argument)})"


def _field_holding(catalog: Catalog, container: str, content: str) -> str | None:
    """The one top-level field of ``container`` whose type has ``content``'s fields."""
    tree, wanted = catalog.fields.get(container), catalog.fields.get(content)
    if not tree or not wanted:
        return None
    holders = [name for name, sub in tree.items() if sub == wanted]
    return holders[0] if len(holders) == 1 else None


def _check_constants(facts: SkillFacts) -> list[Finding]:
    """``Twist.YAW_RATE``: an upper-case attribute of a message class whose definition is
    known must be one of its constants."""
    ctx = _Context()
    cls, catalog, imports = facts.skill, facts.catalog, facts.imports
    if cls is None or catalog is None:
        return ctx.findings
    own = [
        f"self.{target.id}"
        for statement in cls.body
        if isinstance(statement, ast.Assign)
        for target in statement.targets
        if isinstance(target, ast.Name) and target.id.isupper()
    ]
    mine = f"; the skill's own: {', '.join(own)}" if own else ""
    statement_of = facts.statement_of
    for node in facts.nodes:
        if not (
            isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.value.id in imports
            and node.attr.isupper()
        ):
            continue
        type_name = imports[node.value.id]
        known = catalog.constants.get(type_name)
        if known is None or node.attr in known:
            continue
        listed = ", ".join(known) or "none"
        ctx.add(
            UNKNOWN_CONSTANT,
            node,
            f"{type_name} has no constant {node.attr!r} (its constants: {listed}){mine}",
            replacement=_with_own_constant(node, own, statement_of.get(id(node))),
            data={"type": type_name, "constant": node.attr, "constants": known},
        )
    return ctx.findings


_QUANTITY_WORDS = {"yaw": "angular", "turn": "angular", "rate": "velocity", "speed": "velocity"}
"""Words a model names a quantity with, as the skill's limit constants name it."""


def _with_own_constant(
    node: ast.Attribute, own: Sequence[str], statement: ast.stmt | None
) -> str | None:
    """``statement`` with the made-up message constant ``node`` replaced by the one constant
    of the skill that names the same quantity (``Twist.YAW_RATE`` is the skill's
    ``ANGULAR_VELOCITY_MAX``); ``None`` unless exactly one does."""
    wanted = {_QUANTITY_WORDS.get(word, word) for word in _tokens(node.attr)}
    matches = [name for name in own if wanted and wanted <= _tokens(name.removeprefix("self."))]
    if statement is None or len(matches) != 1:
        return None
    return ast.unparse(statement).replace(ast.unparse(node), matches[0])


def _is_zero(node: ast.expr) -> bool:
    return isinstance(node, ast.Constant) and node.value == 0 and not isinstance(node.value, bool)


_NUMERIC_CALLS = {"min", "max", "abs", "float", "int", "round", "sum", "len"}


def _numeric_names(function: ast.FunctionDef, known: AbstractSet[str] = frozenset()) -> set[str]:
    """Local names the function assigns numbers to (``speed = min(a, b)``), in order;
    ``known`` are the attributes and methods of the class known to hold or give one."""
    names: set[str] = set()
    for node in ast.walk(function):
        if isinstance(node, ast.Assign) and len(node.targets) == 1:
            target = node.targets[0]
            if isinstance(target, ast.Name) and _is_scalar(node.value, names | known):
                names.add(target.id)
    return names


_NUMERIC_ANNOTATIONS = frozenset({"float", "int"})


def _numeric_callables(facts: SkillFacts, attributes: AbstractSet[str]) -> set[str]:
    """``self.<name>()`` for the methods of the class that return a number (annotated so, or
    every value they return is one) and the lambdas it keeps on itself that do
    (``self._clipped_speed = lambda speed: min(...)``, then
    ``Twist(linear=self._clipped_speed(v))``, a number where a Vector3 goes)."""
    out: set[str] = set()
    methods = facts.functions
    for method in methods:
        annotation = ast.unparse(method.returns) if method.returns is not None else None
        values = [
            n.value for n in ast.walk(method) if isinstance(n, ast.Return) and n.value is not None
        ]
        numbers = _numeric_names(method, attributes) | attributes
        if annotation in _NUMERIC_ANNOTATIONS or (
            annotation is None and values and all(_is_scalar(v, numbers) for v in values)
        ):
            out.add(f"self.{method.name}()")
    for method in methods:
        for node in ast.walk(method):
            if (
                isinstance(node, ast.Assign)
                and isinstance(node.value, ast.Lambda)
                and _is_scalar(node.value.body, attributes)
            ):
                out |= {
                    f"{ast.unparse(t)}()"
                    for t in node.targets
                    if ast.unparse(t).startswith("self.")
                }
    return out


def _numeric_attributes(facts: SkillFacts) -> set[str]:
    """``self.<name>`` for the class's upper-case constants and the attributes ``__init__``
    gives a number (the skill's inputs and outputs): what holds a number, not a message."""
    cls = facts.skill
    if cls is None:
        return set()
    out = {
        f"self.{target.id}"
        for statement in cls.body
        if isinstance(statement, ast.Assign) and _is_scalar(statement.value)
        for target in statement.targets
        if isinstance(target, ast.Name) and target.id.isupper()
    }
    for method in facts.functions:
        if method.name == "__init__":
            for node in facts.walk(method):
                if isinstance(node, ast.Assign) and _is_number(node.value):
                    targets = node.targets
                elif isinstance(node, ast.AnnAssign) and _is_number(node.value):
                    targets = [node.target]
                else:
                    continue
                out |= {ast.unparse(t) for t in targets if ast.unparse(t).startswith("self.")}
    return out


def _is_scalar(node: ast.expr, numbers: AbstractSet[str] = frozenset()) -> bool:
    """A number or string: a literal, arithmetic, a numeric builtin or math function, or a
    local name known to hold one (``numbers``); what cannot be a message."""
    if isinstance(node, ast.Constant):
        return node.value is not None
    if isinstance(node, ast.Name):
        return node.id in numbers
    if isinstance(node, ast.Attribute):
        return ast.unparse(node) in numbers
    if isinstance(node, ast.UnaryOp):
        return _is_scalar(node.operand, numbers)
    if isinstance(node, ast.BinOp):
        return _is_scalar(node.left, numbers) or _is_scalar(node.right, numbers)
    if isinstance(node, ast.Call):
        func = node.func
        if isinstance(func, ast.Name):
            return func.id in _NUMERIC_CALLS
        return isinstance(func, ast.Attribute) and (
            ast.unparse(func.value) == "math" or f"{ast.unparse(func)}()" in numbers
        )
    return False


def _check_input_writes(facts: SkillFacts) -> list[Finding]:
    """Inputs are set by the client; a state that overwrites one changes the request. Where
    it can, the fix keeps the method's arithmetic on a local copy of the input."""
    ctx = _Context()
    attributes = {
        re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", c.name).lower(): c.name
        for parameter in facts.capability.inputs
        for c in parameter.components
    }
    for method in facts.functions:
        if method.name == "__init__":
            continue
        written: dict[str, ast.stmt] = {}
        for node in facts.walk(method):
            if not isinstance(node, ast.Assign | ast.AugAssign | ast.AnnAssign):
                continue
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                if (
                    isinstance(target, ast.Attribute)
                    and ast.unparse(target.value) == "self"
                    and target.attr in attributes
                ):
                    written.setdefault(target.attr, node)
        for attr, node in written.items():
            message = (
                f"self.{attr} holds the capability input {attributes[attr]}, which the client "
                "sets; do not overwrite it, keep a derived value in a local variable"
            )
            copied = _local_copy(method, attr)
            if copied is None:
                ctx.add(
                    INPUT_OVERWRITTEN,
                    node,
                    message,
                    data={"input": attributes[attr], "attribute": attr, "local": None},
                )
                continue
            local, statements = copied
            for statement, replacement in statements:
                ctx.add(
                    INPUT_OVERWRITTEN,
                    statement,
                    f"{message}; {method.name} works on the local copy {local} instead",
                    replacement=replacement,
                    data={"input": attributes[attr], "attribute": attr, "local": local},
                )
    return ctx.findings


def _parameter_detail(capability: Capability, name: str, annotation: str | None) -> str:
    """What the capability says of its parameter (or component) ``name``, as the task card
    puts it: the getter's type and the unit (``float, m``), then the constraints that name it
    (``abs(outDistance - inDistance) <= 0.02``)."""
    for parameter in [*capability.inputs, *capability.outputs]:
        component = next((c for c in parameter.components if c.name == name), None)
        if parameter.name != name and component is None:
            continue
        unit = (component or parameter.element).unit
        names = {name, parameter.name}
        named = [
            c.text
            for c in capability.constraints
            if any(re.search(rf"\b{re.escape(n)}\b", c.text) for n in names)
        ]
        kind = ", ".join(filter(None, [annotation, unit]))
        return "; ".join(filter(None, [kind, *named]))
    return ""


def _check_parameter_use(facts: SkillFacts) -> list[Finding]:
    """An input no method reads, or an output no method sets, once every state is written:
    the skill ignores what it is asked, or reports what ``__init__`` put there. Each is
    given at its getter, as the run gives it (generation asks ``execute`` for the fix), with
    what the capability says the parameter is, so that the fix knows what to use or store.
    The attribute is the one the getter returns, as pySkillUp reads it
    (:attr:`~skillwright.validation.facts.Getter.path`); a getter that returns a part of an
    object (``self.goal.x``) is left alone: what it reads and writes are the object's
    fields."""
    ctx = _Context()
    capability, binding = facts.capability, facts.binding
    if facts.skill is None or _empty_states(facts) or _unimplemented(facts):
        return ctx.findings  # not every state is written yet
    getters: dict[str, tuple[str, str, str, ast.AST, str, str]] = {}
    for getter in facts.getters:
        path = getter.path
        if path is None or "." in path:
            continue
        method, name = getter.method, getter.annotation.name
        kind = "skill_parameter" if getter.annotation.direction == "input" else "skill_output"
        annotation = ast.unparse(method.returns) if method.returns is not None else None
        meant = binding.target_of(name) or name
        detail = _parameter_detail(capability, meant, annotation)
        getters[method.name] = (kind, name, path, getter.decorator, detail, meant)
    uses = _attribute_uses(facts, {*getters, "__init__"})
    reads, idle, checked = uses.reads, uses.idle, uses.checked
    for method_name, (kind, _, attr, _, _, _) in getters.items():
        if kind == "skill_parameter" and method_name in reads:
            # A method that calls the input's own getter (self.get_distance_x()) reads what
            # it returns: the getter is plain Python, pySkillUp only adds the annotation.
            reads.add(attr)
    for kind, name, attr, where, detail, meant in getters.values():
        about = f" ({detail})" if detail else ""
        if kind == "skill_parameter" and attr not in reads and attr in idle:
            method_name, local = idle[attr]
            ctx.add(
                INPUT_COPIED_UNUSED,
                where,
                f"input {name} is never used: {method_name} copies self.{attr} into {local} "
                f"and nothing reads {local}, so the skill ignores the value it is given; use "
                f"{local}{about} where the skill needs it",
                data={"input": name, "attribute": attr, "method": method_name, "local": local},
            )
        elif kind == "skill_parameter" and attr not in reads and attr in checked:
            ctx.add(
                INPUT_ONLY_VALIDATED,
                where,
                f"input {name} is never used: {checked[attr]} only tests self.{attr} to refuse "
                "a bad value, and nothing the skill does depends on it; use "
                f"self.{attr}{about} where the skill needs it",
                data={"input": name, "attribute": attr, "method": checked[attr]},
            )
        elif kind == "skill_parameter" and attr not in reads:
            ctx.add(
                INPUT_NEVER_READ,
                where,
                f"input {name} is never read: no method uses self.{attr}, so the skill "
                "ignores the value it is given (a hard-coded value in its place?); use "
                f"self.{attr}{about} where the skill needs it",
                data={"input": name, "attribute": attr},
            )
        elif kind == "skill_output" and attr not in uses.writes:
            ctx.add(
                OUTPUT_NEVER_SET,
                where,
                f"output {name} is never set: no method assigns self.{attr}, so the getter "
                f"returns what __init__ put there; store the value it reports{about} in "
                f"self.{attr} before execute ends{_sources(facts, meant)}",
                data={"output": name, "attribute": attr, "scans": _scans(facts, meant)},
            )
        elif (
            kind == "skill_output"
            and _measured(capability, meant)
            and _only_constants(uses.stored.get(attr, []))
        ):
            values = ", ".join(dict.fromkeys(ast.unparse(v) for v in uses.stored[attr] if v))
            _literal_output(ctx, facts, (meant, attr, values), where, about)
    return ctx.findings


@dataclass
class _AttributeUses:
    """How the methods of a skill use its ``self`` attributes."""

    reads: set[str] = field(default_factory=set)
    writes: set[str] = field(default_factory=set)
    idle: dict[str, tuple[str, str]] = field(default_factory=dict)
    """attribute -> (method, local) for a copy (``local = self.attr``) nothing then reads."""
    stored: dict[str, list[ast.expr | None]] = field(default_factory=dict)
    """attribute -> each value a state or helper stores in it (``None``: not a plain store);
    resetting, which clears the outputs, is left out."""
    checked: dict[str, str] = field(default_factory=dict)
    """attribute -> the method whose test refuses a bad value of it (``if ...: raise``), by
    itself or through a local copy."""


def _attribute_uses(facts: SkillFacts, skipped: AbstractSet[str]) -> _AttributeUses:
    """How the methods of the class but the ``skipped`` ones use its attributes."""
    uses = _AttributeUses()
    for method in facts.functions:
        if method.name in skipped:
            continue
        if method.name != "resetting":
            for attr, value in _self_stores(method):
                uses.stored.setdefault(attr, []).append(value)
        guards = _refusals(method)
        copies = _idle_copies(method, guards)
        refused = {
            n.id
            for n in ast.walk(method)
            if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load) and id(n) in guards
        }
        for inner in ast.walk(method):
            if not (
                isinstance(inner, ast.Attribute)
                and isinstance(inner.value, ast.Name)
                and inner.value.id == "self"
            ):
                continue
            if isinstance(inner.ctx, ast.Store):
                uses.writes.add(inner.attr)
            elif id(inner) in guards or copies.get(id(inner), "") in refused:
                uses.checked.setdefault(inner.attr, method.name)
            elif id(inner) in copies:
                uses.idle.setdefault(inner.attr, (method.name, copies[id(inner)]))
            else:
                uses.reads.add(inner.attr)
    return uses


def _literal_output(
    ctx: _Context,
    facts: SkillFacts,
    output: tuple[str, str, str],
    where: ast.AST,
    about: str,
) -> None:
    """The finding for an output only ever set to the literal ``values``: at the store, with
    the local to store instead, when the method worked one out; else at the getter."""
    name, attr, values = output
    message = (
        f"output {name} is only ever set to {values}: no method assigns self.{attr} "
        f"a measured value, so the skill reports a fixed number whatever happened; "
    )
    worked_out = _worked_out_local(facts, attr)
    if worked_out is not None:
        store, method_name, local = worked_out
        ctx.add(
            OUTPUT_CONSTANT,
            store,
            message + f"{method_name} works out {local} and then stores "
            f"{ast.unparse(store.value)} in its place; store {local}",
            replacement=f"self.{attr} = {local}",
            data={
                "output": name,
                "attribute": attr,
                "values": values,
                "scans": _scans(facts, name),
            },
        )
    elif (reading := _helper_reading(facts, name, attr)) is not None:
        store, method_name, value = reading
        ctx.add(
            OUTPUT_CONSTANT,
            store,
            message + f"{method_name} finds the nearest reading with _closest_reading() and "
            f"then stores {ast.unparse(store.value)} in its place; store {value}",
            replacement=f"self.{attr} = {value}",
            data={
                "output": name,
                "attribute": attr,
                "values": values,
                "scans": _scans(facts, name),
            },
        )
    else:
        ctx.add(
            OUTPUT_CONSTANT,
            where,
            message + f"store what it measures{about} in self.{attr} before execute "
            f"ends{_sources(facts, name)}",
            data={
                "output": name,
                "attribute": attr,
                "values": values,
                "scans": _scans(facts, name),
            },
        )


_DEGREES = frozenset({"°", "deg", "degree", "degrees"})
_RADIANS = frozenset({"rad", "radian", "radians"})


def _helper_reading(facts: SkillFacts, name: str, attr: str) -> tuple[ast.Assign, str, str] | None:
    """A store of a literal in ``self.<attr>`` in a method that calls the skeleton's
    ``self._closest_reading(scan)``, for an output in metres or in an angle unit: the
    store, the method and the element of the helper's answer that the output reports (its
    bearing in the output's unit, or its distance): the helper gives both, and a literal
    reports the same number whatever the scan showed."""
    unit = next((p.element.unit for p in facts.capability.outputs if p.name == name), None)
    unit = (unit or "").strip().lower()
    if unit == "m":
        element = "[0]"
    elif unit in _DEGREES | _RADIANS:
        element = "[1]"
    else:
        return None
    for method in facts.functions:
        if method.name in {"__init__", "resetting"}:
            continue
        scans = {
            ast.unparse(node.args[0])
            for node in facts.calls(method)
            if self_attribute(node.func) == "_closest_reading" and len(node.args) == 1
        }
        stores = [
            node
            for node in facts.walk(method)
            if isinstance(node, ast.Assign)
            and len(node.targets) == 1
            and self_attribute(node.targets[0]) == attr
            and _is_number(node.value)
        ]
        if len(scans) == 1 and stores:
            value = f"self._closest_reading({scans.pop()}){element}"
            if unit in _DEGREES:
                value = f"math.degrees({value})"
            return stores[-1], method.name, value
    return None


def _worked_out_local(facts: SkillFacts, attr: str) -> tuple[ast.Assign, str, str] | None:
    """A store of a literal in ``self.<attr>`` that follows, in the same method, a local of
    the output's name (``out_obstacle_degree``, else ``obstacle_degree``) given a computed
    value, not a copy of an input: the store, the method and the local. The value worked out
    is what the output should report; the literal reports a fixed number."""
    names = {attr, attr.removeprefix("out_")}
    for method in facts.functions:
        if method.name in {"__init__", "resetting"}:
            continue
        computed: dict[str, int] = {}
        store: tuple[ast.Assign, str] | None = None
        for node in sorted(
            (n for n in facts.walk(method) if isinstance(n, ast.Assign) and len(n.targets) == 1),
            key=lambda n: n.lineno,
        ):
            target = node.targets[0]
            if isinstance(target, ast.Name) and target.id in names:
                copied = self_attribute(node.value)
                if not _is_number(node.value) and not (copied or "").startswith("in_"):
                    computed.setdefault(target.id, node.lineno)
            elif self_attribute(target) == attr and _is_number(node.value) and computed:
                store = (node, attr if attr in computed else next(iter(computed)))
        if store is not None:
            return store[0], method.name, store[1]
    return None


def _sources(facts: SkillFacts, name: str) -> str:
    """Where the skill can read what output ``name`` measures, as the end of a message."""
    unit = _measured_unit(facts.capability, name)
    found = measuring_sources(facts, unit) if unit is not None else []
    return f"; the skill can read it from {' or '.join(found)}" if found else ""


def _measured_unit(capability: Capability, name: str) -> str | None:
    """The unit of output ``name`` when the capability measures it."""
    unit = next(
        (p.element.unit for p in capability.outputs if p.name == name and p.element.unit), None
    )
    return unit if unit is not None and _measured(capability, name) else None


def _scans(facts: SkillFacts, name: str) -> list[str]:
    """The scans the finding of output ``name`` tells the skill to read raw."""
    unit = _measured_unit(facts.capability, name)
    return raw_scans(facts, unit) if unit is not None else []


def _self_stores(method: ast.FunctionDef) -> list[tuple[str, ast.expr | None]]:
    """Each ``self.<attr>`` the method stores into, with the value of a plain assignment
    (``None`` for ``+=``, a loop or ``with`` target, an unpacking)."""
    out: list[tuple[str, ast.expr | None]] = []
    for node in ast.walk(method):
        value: ast.expr | None = None
        if isinstance(node, ast.Assign):
            targets, value = list(node.targets), node.value
        elif isinstance(node, ast.AnnAssign):
            targets, value = [node.target], node.value
        elif isinstance(node, ast.AugAssign | ast.For):
            targets = [node.target]
        elif isinstance(node, ast.With):
            targets = [i.optional_vars for i in node.items if i.optional_vars is not None]
        else:
            continue
        for target in targets:
            direct = self_attribute(target)
            if direct is not None:
                out.append((direct, value))
                continue
            out += [(a, None) for n in ast.walk(target) if (a := self_attribute(n)) is not None]
    return out


def _measured(capability: Capability, name: str) -> bool:
    """Whether output ``name`` is a quantity the skill measures: it has a unit, and the
    model asserts no value for it (``outLinearVelocity = 0.0``, Assurance)."""
    for parameter in capability.outputs:
        if parameter.name == name and len(parameter.components) == 1:
            element = parameter.element
            return bool(element.unit) and element.value is None
    return False


def _only_constants(values: list[ast.expr | None]) -> bool:
    """Whether there are stores and every one is a number written out (``0.0``, ``-1``)."""

    def constant(value: ast.expr | None) -> bool:
        return _is_number(value) or (isinstance(value, ast.Constant) and value.value is None)

    return bool(values) and all(constant(v) for v in values)


def _refusals(method: ast.FunctionDef) -> set[int]:
    """``id`` of every node of the refusals in ``method``: an ``if`` without ``else`` whose
    body only raises (after logging, perhaps), test and body. An input read only there is
    checked, not used (a non-positive minimum distance refused in starting, and then a stop
    at a distance taken from somewhere else)."""
    out: set[int] = set()
    for node in ast.walk(method):
        if (
            isinstance(node, ast.If)
            and not node.orelse
            and isinstance(node.body[-1], ast.Raise)
            and all(isinstance(s, ast.Raise | ast.Expr) for s in node.body)
        ):
            out |= {id(n) for n in ast.walk(node)}
    return out


def _idle_copies(method: ast.FunctionDef, refusals: AbstractSet[int]) -> dict[int, str]:
    """``id`` of the ``self.<attr>`` of each ``local = self.<attr>`` in ``method`` whose local
    nothing in the method reads but the ``refusals`` (node ids) -> the local. ``local =
    local`` reads nothing (``min_obstacle_distance = min_obstacle_distance`` after a copy of
    the input that only a refusal reads)."""
    no_ops = {
        id(node.value)
        for node in ast.walk(method)
        if isinstance(node, ast.Assign)
        and isinstance(node.value, ast.Name)
        and all(isinstance(t, ast.Name) and t.id == node.value.id for t in node.targets)
    }
    loaded = {
        n.id
        for n in ast.walk(method)
        if isinstance(n, ast.Name)
        and isinstance(n.ctx, ast.Load)
        and id(n) not in no_ops
        and id(n) not in refusals
    }
    return {
        id(node.value): target.id
        for node in ast.walk(method)
        if isinstance(node, ast.Assign)
        and len(node.targets) == 1
        and isinstance(target := node.targets[0], ast.Name)
        and target.id not in loaded
        and isinstance(node.value, ast.Attribute)
        and isinstance(node.value.value, ast.Name)
        and node.value.value.id == "self"
    }


def local_name(attr: str, taken: AbstractSet[str]) -> str:
    """The local variable that holds a copy of ``self.<attr>``: ``velocity`` for
    ``in_velocity``, numbered when ``taken`` (or a keyword, builtin or module) has it."""
    base = attr.removeprefix("in_") if attr.startswith("in_") else f"{attr}_value"
    local = base
    number = 2
    while local in taken or local in _KEYWORDS_AND_BUILTINS:
        local, number = f"{base}{number}", number + 1
    return local


class _InputToLocal(ast.NodeTransformer):
    """Replaces ``self.<attr>`` (read or written) by the local name ``local``."""

    def __init__(self, attr: str, local: str) -> None:
        self.attr = attr
        self.local = local

    def visit_Attribute(self, node: ast.Attribute) -> ast.AST:
        if node.attr == self.attr and isinstance(node.value, ast.Name) and node.value.id == "self":
            return ast.Name(id=self.local, ctx=node.ctx)
        return self.generic_visit(node)


def _local_copy(
    method: ast.FunctionDef, attr: str
) -> tuple[str, list[tuple[ast.stmt, str]]] | None:
    """The local name and, per statement of ``method``'s body that uses ``self.<attr>``, the
    statement on a local copy instead (the first one preceded by the copy); ``None`` when a
    statement that uses it is not a plain one, an ``if`` or a ``while``, which a fix may not
    replace whole."""

    def uses(statement: ast.stmt) -> bool:
        return any(
            isinstance(n, ast.Attribute)
            and n.attr == attr
            and isinstance(n.value, ast.Name)
            and n.value.id == "self"
            for n in ast.walk(statement)
        )

    using = [statement for statement in method.body if uses(statement)]
    replaceable = ast.Assign | ast.AugAssign | ast.AnnAssign | ast.Expr | ast.If | ast.While
    if not using or not all(isinstance(statement, replaceable) for statement in using):
        return None
    taken = {n.id for n in ast.walk(method) if isinstance(n, ast.Name)} | {
        a.arg for a in ast.walk(method) if isinstance(a, ast.arg)
    }
    local = local_name(attr, taken)
    fixed = []
    for index, statement in enumerate(using):
        text = ast.unparse(_InputToLocal(attr, local).visit(copy.deepcopy(statement)))
        if index == 0:
            text = f"{local} = self.{attr}\n{text}"
        fixed.append((statement, text))
    return local, fixed


_KEYWORDS_AND_BUILTINS = frozenset({*kwlist, *dir(builtins), "self", "math", "time"})
"""Names a local copy may not take."""


def _check_goal_results(facts: SkillFacts) -> list[Finding]:
    """A goal's result waited for (the skeleton's ``self._X_result(...)``) in a class that
    never sends that goal (``self._X_goal(...)`` is never called): the wait can only fail."""
    ctx = _Context()
    methods = facts.methods
    calls = [
        (node, node.func.attr)
        for node in facts.nodes
        if isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and isinstance(node.func.value, ast.Name)
        and node.func.value.id == "self"
    ]
    called = {name for _, name in calls}
    for call, name in calls:
        stem = name.removeprefix("_").removesuffix("_result")
        send = f"_send_{stem}_goal"
        if not name.endswith("_result") or send not in methods or send in called:
            continue
        ctx.add(
            GOAL_RESULT_WITHOUT_SEND,
            call,
            f"self.{name}(...) waits for the result of a goal nothing sends: send it first "
            f"with self.{send}(goal, timeout), and then wait for its result",
            data={"helper": name, "send": send},
        )
    return ctx.findings


_MAKES_HANDLE = frozenset(
    {
        "create_publisher",
        "create_subscription",
        "create_client",
        "ActionClient",
        "TransformListener",
    }
)


def _check_handles(facts: SkillFacts) -> list[Finding]:
    """A handle made in one state and made again in another: the second one leaks the first
    (a subscription then delivers every message twice)."""
    ctx = _Context()
    makes = {id(m.call) for m in facts.made if m.maker in _MAKES_HANDLE}
    made: dict[str, str] = {}
    for method in facts.functions:
        for node in facts.walk(method):
            if not (isinstance(node, ast.Assign) and id(node.value) in makes):
                continue
            for target in node.targets:
                if not (isinstance(target, ast.Attribute) and ast.unparse(target.value) == "self"):
                    continue
                first = made.setdefault(target.attr, method.name)
                if first != method.name:
                    ctx.add(
                        HANDLE_MADE_TWICE,
                        node,
                        f"self.{target.attr} is made in {first} already; use that handle here "
                        "(making it again leaks the first one, and a second subscription "
                        "delivers every message twice)",
                        replacement="" if len(node.targets) == 1 else None,
                        data={"attribute": target.attr, "first": first},
                    )
    return ctx.findings


def _check_timers(facts: SkillFacts) -> list[Finding]:
    """A timer fires until it is cancelled: one kept only in a local variable (or not kept)
    goes on firing after its state ended, with handles resetting released; one kept on the
    skill must be cancelled somewhere."""
    ctx = _Context()
    cancelled = _cancelled(facts.nodes)
    for method in facts.functions:
        for statement in facts.walk(method):
            if not isinstance(statement, ast.Assign | ast.Expr):
                continue
            call = statement.value
            if not (isinstance(call, ast.Call) and called_name(call) == "create_timer"):
                continue
            targets = statement.targets if isinstance(statement, ast.Assign) else []
            kept = [ast.unparse(t) for t in targets if ast.unparse(t).startswith("self.")]
            if kept:
                if kept[0] not in cancelled:
                    ctx.add(
                        TIMER_NEVER_CANCELLED,
                        statement,
                        f"{kept[0]} is never cancelled: the timer fires until it is, also after "
                        f"the skill stopped; cancel it ({kept[0]}.cancel()) when it is no "
                        "longer needed, in stopping and in resetting",
                        data={"timer": kept[0]},
                    )
                continue
            local = {ast.unparse(t) for t in targets}
            if local & _cancelled(facts.walk(method)):
                continue  # a timer for a while of this method, cancelled in it
            attribute = f"self.{_timer_name(call)}"
            reads = any(
                isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load) and n.id in local
                for n in ast.walk(method)
            )
            ctx.add(
                TIMER_NOT_KEPT,
                statement,
                "the timer is not kept on the skill, so nothing cancels it: it fires until the "
                "node ends, also after the skill stopped and released the handles it uses; "
                f"keep it as {attribute} and cancel it ({attribute}.cancel()) when it is no "
                "longer needed, in stopping and in resetting",
                replacement=None if reads else f"{attribute} = {ast.unparse(call)}",
                data={"attribute": attribute},
            )
    return ctx.findings


def _cancelled(nodes: Iterable[ast.AST]) -> set[str]:
    """What ``nodes`` cancel or destroy as a timer (``x.cancel()``, ``destroy_timer(x)``), as
    source."""
    return {
        ast.unparse(call.func.value) if call.func.attr == "cancel" else ast.unparse(call.args[0])
        for call in nodes
        if isinstance(call, ast.Call)
        and isinstance(call.func, ast.Attribute)
        and (call.func.attr == "cancel" or (call.func.attr == "destroy_timer" and call.args))
    }


def _timer_name(call: ast.Call) -> str:
    """``timer`` attribute name for a ``create_timer(period, self._hold)`` call:
    ``hold_timer``."""
    callback = call.args[1] if len(call.args) > 1 else None
    if isinstance(callback, ast.Attribute):
        return f"{callback.attr.strip('_')}_timer"
    return "timer"


def _check_skill_class(facts: SkillFacts) -> list[Finding]:
    """The file has a class decorated with ``@skill(...)``: pySkillUp runs nothing else."""
    if facts.skill is not None:
        return []
    return [NO_SKILL_CLASS.at(None, "no class decorated with @skill(...)")]


STATIC_CHECKS: tuple[Callable[[SkillFacts], list[Finding]], ...] = (
    _check_interface_names,
    _check_input_constants,
    _check_skill_class,
    _check_skill_decorator,
    _check_parameters,
    _check_states,
    _check_placeholders,
    _check_swallowed_errors,
    _check_input_writes,
    _check_parameter_use,
    _check_handles,
    _check_goal_results,
    _check_timers,
    check_names,
    check_waits,
    check_stale_conditions,
    check_stops,
    check_filtered_positions,
    check_angle_units,
    check_unsent,
    check_first_messages,
    check_settling,
    check_views,
    check_equality,
    check_motion,
    check_zero_timeouts,
    check_bearings,
    check_frames,
    check_grace,
    _check_fields,
    _check_constants,
    _check_uses,
    _check_retrieved,
)
"""Every static check, in the order its findings are gathered: each takes the file's facts
and says what it finds (the class's checks find nothing in a file without a skill class)."""


def check_skill(
    source: str,
    *,
    capability: Capability,
    spec: SkillSpec,
    catalog: Catalog | None = None,
    retrieved: Sequence[str] = (),
    path: str = "skill.py",
    bindings: Mapping[str, str] | None = None,
) -> CheckReport:
    """Runs every static check on the skill ``source``: parses it once, works out its facts
    (:class:`~skillwright.validation.facts.SkillFacts`) and hands them to each of
    :data:`STATIC_CHECKS` in one pass.

    The skill's parameters and outputs are bound to the capability's inputs and outputs by
    name, by meaning or as ``bindings`` (the skill's name -> the capability's) say.

    ``catalog`` enables the grounding checks; ``retrieved`` names the interfaces
    retrieval chose, for the used-versus-retrieved check.
    """
    try:
        facts = SkillFacts.build(
            source,
            capability=capability,
            spec=spec,
            catalog=catalog,
            retrieved=retrieved,
            path=path,
            bindings=bindings,
        )
    except SyntaxError as error:
        finding = SYNTAX_ERROR.finding(
            line=error.lineno or 0,
            column=error.offset or 0,
            message=f"syntax error: {error.msg}",
            data={"detail": error.msg},
        )
        return CheckReport(path=path, findings=[finding])
    findings = [finding for check in STATIC_CHECKS for finding in check(facts)]
    findings.sort(key=lambda f: (f.line, f.column, f.check))
    used = sorted({u.name for u in facts.interface_uses})
    return CheckReport(path=path, findings=findings, used_interfaces=used)
