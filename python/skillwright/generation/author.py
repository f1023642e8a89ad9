"""A model writes a skill one method at a time, and repairs what the checks find.

1. The skeleton (structure, annotations, handles, helpers) comes first; the model gets a
   task card and writes each specified state in turn (:mod:`~skillwright.generation.conversation`),
   each answer prefilled with the method's start and ended at the method's end, under a
   per-method token budget and a :class:`~skillwright.generation.guard.RepetitionGuard`.
2. Helper methods the states call but nobody wrote are asked for next (and again after each
   round of repairs).
3. The methods go into the skeleton, rebuilt with only the interfaces and helpers the
   behaviour uses (:mod:`~skillwright.generation.assemble`), and the result is validated (the
   static checks, and whatever later stages the caller adds: run, simulation).
4. Where the checks know the right statement for every error of a method (the wait for a
   first message, a zero command, a loop with a sleep), it is put in place of the flagged
   one without asking the model: an attempt that costs no model time.
5. Every method with an error — a finding on its lines, or an answer that failed outright —
   is asked for again within ``attempts`` per method: its request once more with every
   problem found so far, the answer prefilled with the latest answer's statements before its
   first error (so the model continues where it went wrong, without the wrong lines to copy).
   The second answer is greedy (sampled when the first looped or ran out of tokens), later
   ones sampled with a fixed seed. The best answer per method by its findings wins; every
   attempt is kept for the record.
"""

from __future__ import annotations

import ast
import re
import textwrap
import threading
import time
from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal

from skillwright.capability.model import Capability
from skillwright.errors import GenerationCancelledError
from skillwright.generation.assemble import (
    Assembly,
    assemble,
    message_classes,
    method_spans,
    parse_method,
    usage,
)
from skillwright.generation.card import CardInterface, task_card
from skillwright.generation.conversation import (
    STOP,
    Conversation,
    Turn,
    example_helpers,
    helper_ask,
    repair_ask,
    state_ask,
)
from skillwright.generation.guard import RepetitionGuard
from skillwright.generation.model import (
    AppliedFix,
    Attempt,
    AttemptFinish,
    InterfaceRef,
    Skeleton,
)
from skillwright.llm.base import GenerationOptions, TextGenerator
from skillwright.rules.capability import (
    INPUT_COPIED_UNUSED,
    INPUT_NEVER_READ,
    INPUT_ONLY_VALIDATED,
    OUTPUT_CONSTANT,
    OUTPUT_NEVER_SET,
)
from skillwright.rules.finding import Finding
from skillwright.rules.interfaces import ARGUMENT_TYPE_MISMATCH
from skillwright.rules.registry import rule_of
from skillwright.spec.model import SkillSpec
from skillwright.validation.names import self_attribute
from skillwright.validation.static import local_name

__all__ = [
    "AttemptFinished",
    "AttemptStarted",
    "AuthorSettings",
    "Authored",
    "SkeletonBuilder",
    "Validator",
    "author_skill",
]

Validator = Callable[[str, Skeleton], list[Finding]]
"""Findings for a whole skill file built on a skeleton (the static checks, a run, a
simulation)."""
SkeletonBuilder = Callable[[Sequence[InterfaceRef], Collection[str] | None], Skeleton]
"""Builds the skeleton for these interfaces and helpers (``None``: every helper offered)."""

_MAX_HELPERS = 4
_MAX_FIX_ROUNDS = 3
"""Rounds of the checks' own fixes per skill (they cost no model time, but a fix may meet a
new finding that suggests the old statement back)."""
_MAX_PROBLEMS = 6


@dataclass(frozen=True)
class AuthorSettings:
    """How hard to try."""

    attempts: int = 3
    """Answers per method at most: the first, then repairs."""
    run_repairs: int = 1
    """Repairs beyond ``attempts`` once the static checks pass and only the run's or the
    simulation's findings are left: those come last, often after the static repairs used the
    attempts up (the demo's navigate-to-point got no repair for its 5-s result wait)."""
    max_tokens: int = 768
    """Tokens per answer of ``execute`` at most (a method, not a file)."""
    short_max_tokens: int = 320
    """Tokens per answer of every other state and of a helper at most (never more than
    ``max_tokens``). In the evaluation, no such answer without errors took more than 190
    tokens; the longer ones (up to 594) rambled and were rejected anyway."""

    @property
    def short_budget(self) -> int:
        """The token budget of an answer for any method but ``execute``."""
        return min(self.short_max_tokens, self.max_tokens)

    def budget(self, kind: str, name: str) -> int:
        """The token budget of an answer for the method ``name`` of ``kind``."""
        if kind == "state" and name == "execute":
            return self.max_tokens
        return self.short_budget

    repair_temperature: float = 0.6
    """Temperature of the sampled repairs (the third attempt on)."""
    seed: int = 42
    """Base seed of sampled repairs (plus the attempt number)."""


@dataclass(frozen=True)
class AttemptStarted:
    """The model starts an answer of at most ``max_tokens`` tokens; a repair names the rules
    of the findings it is asked to fix (``problem_codes``), so a UI can say why it runs."""

    target: str
    kind: str
    number: int
    max_tokens: int | None = None
    problem_codes: tuple[str, ...] = ()


@dataclass(frozen=True)
class AttemptFinished:
    """An answer ended (before the checks judged it)."""

    attempt: Attempt


@dataclass
class Authored:
    """The written skill and how it was made."""

    code: str
    findings: list[Finding]
    attempts: list[Attempt]
    assembly: Assembly
    skeleton: Skeleton
    """The skeleton the final file is built on (only the interfaces and helpers used)."""
    card: str
    transcript: str
    """Every request and answer, in order (for ``prompt.txt``)."""
    notes: list[str] = field(default_factory=list)


@dataclass
class _Target:
    name: str
    kind: Literal["state", "helper"]
    ask: str
    prefill: str
    turn_index: int
    caller: str | None = None
    attempts: list[Attempt] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    """Every problem found in its answers so far, in order."""


def _state_prefill(state: str, skeleton: Skeleton) -> str:
    head = f"    @{state}\n    def {state}(self) -> None:\n"
    prologue = skeleton.prologues.get(state)
    return head + (prologue + "\n" if prologue else "")


class _Author:
    def __init__(
        self,
        generator: TextGenerator,
        settings: AuthorSettings,
        on_event: Callable[[object], None] | None,
        cancel: threading.Event | None,
    ) -> None:
        self.generator = generator
        self.settings = settings
        self.on_event = on_event
        self.cancel = cancel
        self.log: list[str] = []

    def emit(self, event: object) -> None:
        if self.on_event is not None:
            self.on_event(event)

    def check_cancel(self) -> None:
        if self.cancel is not None and self.cancel.is_set():
            raise GenerationCancelledError("generation cancelled; nothing was written")

    def answer(
        self,
        conversation: Conversation,
        target: _Target,
        ask: str,
        prefill: str,
        codes: Sequence[str] = (),
    ) -> Attempt:
        """Asks the model for one method after the turns before the target's, its answer
        starting with ``prefill``, and judges what comes back; ``codes`` are the rules of
        the findings a repair is asked to fix."""
        self.check_cancel()
        number = len(target.attempts) + 1
        # Greedy decoding gives the first answer, and the first repair of an answer that was
        # written out; an answer that looped or ran too long would only come back the same
        # way, so its repair samples at once. Fixes the checks made count as the answer
        # they fixed.
        answers = [a for a in target.attempts if a.finish != "fixed"]
        greedy = not answers or (len(answers) == 1 and answers[0].finish not in _DEAD_ENDS)
        temperature = 0.0 if greedy else self.settings.repair_temperature
        seed = self.settings.seed + number
        budget = self.settings.budget(target.kind, target.name)
        self.emit(AttemptStarted(target.name, target.kind, number, budget, tuple(codes)))
        prompt = conversation.prompt(ask, prefill, upto=target.turn_index)
        options = GenerationOptions(
            max_tokens=budget,
            temperature=temperature,
            seed=seed,
            stop=STOP,
        )
        started = time.perf_counter()
        stream = self.generator.stream(prompt, options, cancel=self.cancel)
        guard = RepetitionGuard()
        parts: list[str] = []
        looped = False
        for chunk in stream:
            parts.append(chunk)
            self.emit(chunk)
            if guard.feed(chunk):
                looped = True
                stream.close()
                break
        self.check_cancel()
        response = "".join(parts)
        finish, note, code = self._judge(
            target, prefill + response, stream.finish_reason, guard, looped
        )
        attempt = Attempt(
            target=target.name,
            kind=target.kind,
            number=number,
            temperature=temperature,
            seed=seed,
            finish=finish,
            note=note,
            code=code,
            response=response,
            prompt_tokens=stream.prompt_tokens,
            reused_tokens=stream.reused_tokens,
            completion_tokens=stream.completion_tokens or stream.completion_chunks,
            seconds=round(time.perf_counter() - started, 3),
            prefix_cache=stream.prefix_cache,
            kept_lines=prefill.count("\n") - target.prefill.count("\n"),
        )
        target.attempts.append(attempt)
        self.log.append(
            f"===== user =====\n{ask}\n\n===== assistant (attempt {number}) =====\n"
            f"```python\n{prefill}{response}"
        )
        self.emit(AttemptFinished(attempt))
        return attempt

    def _judge(
        self,
        target: _Target,
        text: str,
        reason: str | None,
        guard: RepetitionGuard,
        looped: bool,
    ) -> tuple[AttemptFinish, str | None, str | None]:
        if looped:
            return "repetition", f"the answer repeated {guard.reason} and was stopped", None
        if reason == "length":
            return (
                "length",
                f"the answer was cut off at {self.settings.budget(target.kind, target.name)} "
                "tokens; write a shorter "
                "method",
                None,
            )
        # The closing fence right after the prefilled lines (the method was complete with
        # them) is not preceded by a newline of the answer, so the stop strings miss it.
        fence_at = text.find("\n```")
        if fence_at >= 0:
            text = text[: fence_at + 1]
        method = parse_method(text)
        if method is None:
            return "unparsable", _syntax_note(text, target.name), None
        if method.name != target.name:
            return "unparsable", f"the answer defines {method.name}, not {target.name}", None
        return "stop", None, text.rstrip() + "\n"


_DEAD_ENDS = ("repetition", "length")
"""Finishes after which the same greedy prompt would end the same way."""


def _syntax_note(text: str, name: str) -> str:
    import textwrap

    try:
        ast.parse(textwrap.dedent(text))
    except SyntaxError as error:
        lines = textwrap.dedent(text).splitlines()
        where = (
            lines[error.lineno - 1].strip() if error.lineno and error.lineno <= len(lines) else ""
        )
        return f"the answer is not valid Python ({error.msg} at `{where}`)"
    return f"the answer holds more than the one method {name}"


_CALL = re.compile(r"self\.(_?[A-Za-z]\w*)\(")


_TAKES_CALLBACK = frozenset(
    {"create_timer", "create_subscription", "create_service", "add_done_callback"}
)
"""rclpy calls whose positional arguments include a callback."""


@dataclass(frozen=True)
class _Missing:
    name: str
    caller: str
    call: str
    """The call that uses it, as source."""
    callback: bool
    """Handed over as an argument (a timer's or subscription's callback), not called."""


def _missing_helpers(
    methods: dict[str, str], known: set[str], attributes: set[str]
) -> list[_Missing]:
    """Methods nobody wrote that the behaviour calls (``self.name(...)``) or hands over as a
    callback (``create_timer(0.05, self.name)``)."""
    found: dict[str, _Missing] = {}
    for caller, text in methods.items():
        method = parse_method(text)
        if method is None:
            continue
        for node in ast.walk(method):
            if not isinstance(node, ast.Call):
                continue
            uses = [(self_attribute(node.func), False)]
            if isinstance(node.func, ast.Attribute) and node.func.attr in _TAKES_CALLBACK:
                uses += [(self_attribute(arg), True) for arg in node.args]
            uses += [
                (self_attribute(keyword.value), True)
                for keyword in node.keywords
                if keyword.arg in {"callback", "target"}
            ]
            for name, callback in uses:
                if (
                    name is None
                    or name in known
                    or name in attributes
                    or name in found
                    or name == "node"
                ):
                    continue
                found[name] = _Missing(name, caller, ast.unparse(node), callback)
    return list(found.values())[:_MAX_HELPERS]


def _assigned_attributes(methods: dict[str, str]) -> set[str]:
    names: set[str] = set()
    for text in methods.values():
        method = parse_method(text)
        if method is None:
            continue
        for node in ast.walk(method):
            if isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
                names.add(node.attr)
    return names


def _class_methods(skeleton: Skeleton) -> set[str]:
    tree = ast.parse(skeleton.code)
    return {
        n.name
        for cls in tree.body
        if isinstance(cls, ast.ClassDef)
        for n in cls.body
        if isinstance(n, ast.FunctionDef)
    }


def _problems(
    attempt: Attempt,
    findings: Sequence[Finding],
    code_lines: Sequence[str],
    offered: Collection[str] = (),
) -> list[tuple[str, str]]:
    """What to tell the model about its last answer, as (rule code, text): why it gave no
    code (no code), or the errors in the code it gave (also when the checks wrote that code:
    their note says what they fixed, not what is still wrong)."""
    if attempt.code is None and attempt.note is not None:
        return [("", attempt.note)]
    out = []
    for finding in findings:
        if finding.severity != "error":
            continue
        source = code_lines[finding.line - 1].strip() if 0 < finding.line <= len(code_lines) else ""
        message = finding.message + _helper_hint(finding, offered)
        out.append((finding.code, f"`{source}`: {message}" if source else message))
    return out[:_MAX_PROBLEMS]


_NAVIGATION_GOAL = "nav2_msgs/action/NavigateToPose.Goal"
_OUTPUT_RULES = frozenset({OUTPUT_NEVER_SET.code, OUTPUT_CONSTANT.code})
_UNUSED_INPUT_RULES = frozenset(
    {INPUT_NEVER_READ.code, INPUT_COPIED_UNUSED.code, INPUT_ONLY_VALIDATED.code}
)


def _helper_hint(finding: Finding, offered: Collection[str]) -> str:
    """The skeleton helper that gives what a finding says was done by hand: the nearest
    reading and its bearing from a scan, a navigation goal from a point and a heading (the
    file the checks saw holds only the helpers already called, so the finding cannot name
    the others)."""
    if (
        finding.code == ARGUMENT_TYPE_MISMATCH.code
        and finding.data.get("expected") == _NAVIGATION_GOAL
        and "_pose_goal" in offered
    ):
        return "; self._pose_goal(frame, x, y, yaw) returns one for a point and a heading"
    scans = finding.data.get("scans") if finding.code in _OUTPUT_RULES else None
    if not scans or "_closest_reading" not in offered:
        return ""
    return (
        f"; self._closest_reading(self.{scans[0]}) returns (distance, bearing) of the "
        "nearest valid reading"
    )


def _resume_point(target: _Target, code: str, judgement: _Judgement, error: Finding) -> str:
    """``code`` (an answer of ``target``) up to the statement that holds the ``error`` (in
    its body, or nested in a loop or branch of it), followed by the statement the check
    suggests instead when there is one and the flagged statement is a plain one (or a loop)
    that it can take the place of; the target's own prefill when the statement cannot be
    told."""
    found = _statements_at(judgement, target.name, error.line, error.column)
    method = parse_method(code)
    if found is None or method is None:
        return target.prefill
    top, inner = found
    key = ast.unparse(top)
    mine = next((s for s in method.body if ast.unparse(s) == key), None)
    if mine is None:
        return target.prefill
    lines = code.splitlines(keepends=True)
    cut = mine.lineno + inner.lineno - top.lineno
    kept = "".join(lines[: cut - 1])
    if len(kept) < len(target.prefill):
        kept = target.prefill
    elif error.replacement is not None and _replaceable(inner):
        kept += _indented(error.replacement, lines[cut - 1])
    return kept


def _unset_output(finding: Finding) -> str | None:
    """The attribute of the output that ``finding`` says no method sets (with a measured
    value), if it says so."""
    return str(finding.data["attribute"]) if finding.code in _OUTPUT_RULES else None


def _unread_input(finding: Finding) -> str | None:
    """The attribute of the input that ``finding`` says the skill ignores, if it says so."""
    return str(finding.data["attribute"]) if finding.code in _UNUSED_INPUT_RULES else None


def _inputs_resume(target: _Target, attributes: Sequence[str]) -> str:
    """The method's start with a local copy of each input it ignored, for the model to go on
    from: cap2skill collision-avoidance wrote an execute that ignored its four inputs three
    times over after being told so, and a small model uses the variables it is handed. A
    copy that nothing then reads is still an input never used (the checks say so)."""
    taken: set[str] = set()
    lines = []
    for attribute in dict.fromkeys(attributes):
        local = local_name(attribute, taken)
        taken.add(local)
        lines.append(f"        {local} = self.{attribute}\n")
    return target.prefill + "".join(lines)


def _output_resume(target: _Target, code: str, attribute: str) -> str:
    """``code`` whole (but a ``return`` that ends it), then the start of the statement that
    sets the output ``attribute``: a small model told three times that an output is never
    set wrote the same method again, and completes an assignment it is handed."""
    method = parse_method(code)
    if method is None:
        return target.prefill
    lines = code.splitlines(keepends=True)
    last = method.body[-1]
    end = last.lineno - 1 if isinstance(last, ast.Return) else last.end_lineno or last.lineno
    kept = "".join(lines[:end])
    if not kept.endswith("\n"):
        kept += "\n"
    first = lines[method.body[0].lineno - 1]
    return f"{kept}{first[: len(first) - len(first.lstrip())]}self.{attribute} = "


def _indented(replacement: str, line: str) -> str:
    """``replacement`` (statements; empty for none) indented as ``line`` is."""
    if not replacement:
        return ""
    return textwrap.indent(replacement, line[: len(line) - len(line.lstrip())]) + "\n"


def _apply_replacements(
    target: _Target, code: str, judgement: _Judgement, errors: Sequence[Finding]
) -> tuple[str, list[Finding]] | None:
    """``code`` (the answer of ``target`` in the judged file) with each flagged statement
    whose finding suggests one replaced by it, and the findings whose fixes went in; ``None``
    unless at least one applies and the result is a different method that parses. The errors
    without a suggestion stay for the model, which then repairs a method with fewer of them.
    Of two suggestions for one statement (or for a statement and one inside it) only the
    first applies: the other was
    made for the statement as it was, and the next round's checks make it again for the
    statement as it is (cap2skill collision avoidance's loop needed a sleep and a local
    renamed; keeping the sleep's loop dropped the rename, and the skill compared a float with
    the module ``time``)."""
    method = parse_method(code)
    if method is None or not errors:
        return None
    lines = code.splitlines(keepends=True)
    spans: dict[tuple[int, int], str] = {}
    applied: list[Finding] = []
    for error in errors:
        found = _statements_at(judgement, target.name, error.line, error.column)
        if error.replacement is None or found is None or not _replaceable(found[1]):
            continue
        top, inner = found
        mine = next((s for s in method.body if ast.unparse(s) == ast.unparse(top)), None)
        if mine is None:
            continue
        first = mine.lineno + inner.lineno - top.lineno
        last = mine.lineno + (inner.end_lineno or inner.lineno) - top.lineno
        if not any(first <= end and start <= last for start, end in spans):
            spans[(first, last)] = error.replacement
            applied.append(error)
    for first, last in sorted(spans, reverse=True):
        lines[first - 1 : last] = [_indented(spans[(first, last)], lines[first - 1])]
    fixed = "".join(lines)
    return (fixed, applied) if fixed != code and parse_method(fixed) is not None else None


def _replaceable(statement: ast.stmt) -> bool:
    """Whether a check's suggested statements may take the place of ``statement`` whole: a
    plain statement (a ``raise`` whose text names a timeout the run changed, a helper's
    ``return`` of a field that is one level deeper), a loop, or an ``if`` (a guard on
    something that does not exist, which the suggestion replaces by what it comes to)."""
    return isinstance(
        statement,
        ast.Assign
        | ast.AugAssign
        | ast.AnnAssign
        | ast.Expr
        | ast.While
        | ast.If
        | ast.Raise
        | ast.Return,
    )


def _statements_at(
    judgement: _Judgement, name: str, line: int, column: int
) -> tuple[ast.stmt, ast.stmt] | None:
    """(statement of the method's body, innermost statement in it) holding the position
    ``line``:``column`` (1-based column; 0 for anywhere on the line) of the judged file."""
    tree = ast.parse(judgement.assembly.code)
    for cls in tree.body:
        if isinstance(cls, ast.ClassDef) and cls.name == judgement.skeleton.class_name:
            for member in cls.body:
                if isinstance(member, ast.FunctionDef) and member.name == name:
                    holding = [s for s in member.body if _holds(s, line, column)]
                    if not holding:
                        return None
                    inner = [s for s in ast.walk(holding[0]) if isinstance(s, ast.stmt)]
                    return holding[0], [s for s in inner if _holds(s, line, column)][-1]
    return None


def _holds(statement: ast.stmt, line: int, column: int) -> bool:
    start = (statement.lineno, statement.col_offset + 1 if column else 0)
    end = (statement.end_lineno or statement.lineno, statement.end_col_offset or 10**6)
    return start <= (line, column) <= end


def _called(states: Mapping[str, str], helpers: Mapping[str, str]) -> dict[str, str]:
    """The ``helpers`` (name -> code) the ``states`` call or hand over as callbacks, directly
    or through each other: a helper written for an answer that was not kept is dead code,
    and its errors are not the file's."""
    reached: dict[str, str] = {}
    pending = list(states.values())
    while pending:
        for name in re.findall(r"self\.(\w+)", pending.pop()):  # a call, or a callback
            if name in helpers and name not in reached:
                reached[name] = helpers[name]
                pending.append(helpers[name])
    return {name: code for name, code in helpers.items() if name in reached}


def _only_later_stages(judgement: _Judgement) -> bool:
    """Whether the file passed the static checks and only the run or simulation found
    errors."""
    errors = [f for f in judgement.findings if f.severity == "error"]
    return bool(errors) and all(_later(f) for f in errors)


def _score(attempt: Attempt) -> tuple[int, int, int, int]:
    """Lower is better: unusable answers last, then errors the static checks find (an answer
    that passed them got further), then the run's and simulation's errors (an answer whose
    file did not get that far after one that did), then warnings."""
    if attempt.code is None or attempt.errors is None:
        return (1, 10**6, 10**6, 10**6)
    later = attempt.behaviour_errors
    if later is None:
        # Not run: another method's static error stopped the file. Zero run errors then
        # says nothing, so the answer ranks behind one whose run was judged (cap2skill
        # collision-avoidance's final execute "beat" one with four simulation findings only
        # because a helper it called failed the checks and nothing ran).
        return (0, attempt.errors, 10**6, attempt.warnings or 0)
    return (0, attempt.errors - later, later, attempt.warnings or 0)


def _later(finding: Finding) -> bool:
    """Whether ``finding`` comes from running the skill (the run, the simulation) rather
    than from reading it."""
    rule = rule_of(finding)
    return rule is not None and rule.stage != "static"


def _execute_owns(finding: Finding) -> bool:
    """Whether ``finding``, outside any written method (at an input's or output's getter:
    an input never read, an output never set), is ``execute``'s to fix."""
    rule = rule_of(finding)
    return _later(finding) or (rule is not None and rule.group in ("inputs", "outputs"))


_Pick = Callable[[_Target], Attempt | None]


def _latest(target: _Target) -> Attempt | None:
    return target.attempts[-1] if target.attempts else None


def _best(target: _Target) -> Attempt | None:
    """The answer with the best score; of equals the latest, which was told more of what was
    wrong (its count may include findings another method's answer caused)."""
    judged = [a for a in target.attempts if a.code is not None and a.errors is not None]
    return min(judged, key=lambda a: (_score(a), -a.number)) if judged else None


@dataclass
class _Judgement:
    skeleton: Skeleton
    assembly: Assembly
    findings: list[Finding]
    written: frozenset[str] = frozenset()
    """The methods the model writes (states and helpers)."""

    def mine(self, name: str) -> list[Finding] | None:
        """The findings on method ``name``'s lines, or ``None`` if the file has no such method.

        A run's finding in a helper of the skeleton (``_result_of`` timing out) belongs to the
        written method whose call led there, and is given at the line of that call: the
        helper is not the model's to change, the call (its timeout, its goal) is. A run's
        finding, or an input's or output's, in no written method or helper (an input never
        read, at its getter) belongs to ``execute``, given at its first line.
        """
        spans = method_spans(self.assembly.code, self.skeleton.class_name)
        if name not in spans:
            return None
        first, last = spans[name]
        found = [f for f in self.findings if first <= f.line <= last]
        owned = set(self.skeleton.helpers)
        if name == "execute":
            found += [
                f.model_copy(update={"line": first, "column": 0})
                for f in self.findings
                if _execute_owns(f)
                and f.severity == "error"
                and not f.stack
                and _method_at(spans, f.line) not in self.written | owned
            ]
        for finding in self.findings:
            if not finding.stack or _method_at(spans, finding.line) not in owned:
                continue
            for line in reversed(finding.stack):
                caller = _method_at(spans, line)
                if caller is not None and caller not in owned:
                    if caller == name:
                        found.append(finding.model_copy(update={"line": line, "column": 0}))
                    break
        return found


def _method_at(spans: Mapping[str, tuple[int, int]], line: int) -> str | None:
    """The method whose lines hold ``line``."""
    return next((name for name, (first, last) in spans.items() if first <= line <= last), None)


class _Skill:
    """One skill being written: its conversation, its methods and their answers."""

    def __init__(
        self,
        author: _Author,
        build_skeleton: SkeletonBuilder,
        capability: Capability,
        interfaces: Sequence[CardInterface],
        validate: Validator,
    ) -> None:
        self.author = author
        self.build_skeleton = build_skeleton
        self.validate = validate
        self.full = build_skeleton([item.ref for item in interfaces], None)
        self.conversation = Conversation(task_card(capability, self.full, interfaces))
        self.targets: dict[str, _Target] = {}
        self.classes = message_classes(item.interface for item in interfaces)
        self.model_name = f"the local model {author.generator.model_id}"

    def first_answer(self, target: _Target) -> None:
        self.targets[target.name] = target
        attempt = self.author.answer(self.conversation, target, target.ask, target.prefill)
        self.conversation.turns.append(
            Turn(target.ask, attempt.code or target.prefill + attempt.response)
        )

    def write_states(self, spec: SkillSpec) -> None:
        for state, text in spec.states.items():
            prefill = _state_prefill(state, self.full)
            turn = len(self.conversation.turns)
            self.first_answer(_Target(state, "state", state_ask(state, text), prefill, turn))

    def write_helpers(self) -> None:
        """Asks for helpers the methods call but nobody wrote (helpers may need helpers)."""
        for _ in range(2):
            written = {t.name: code for t in self.targets.values() if (code := t.attempts[-1].code)}
            known = _class_methods(self.full) | set(self.targets)
            # A call copied from a worked example (its stopping's self._cancel_dock_robot_goal)
            # is not asked for: written, it drives an interface this skill does not have
            # (cap2skill navigate-to-point, three answers). The checks flag the call instead.
            known |= example_helpers() - _class_methods(self.full)
            missing = _missing_helpers(written, known, _assigned_attributes(written))
            if not missing:
                return
            for item in missing:
                ask = helper_ask(item.name, item.caller, item.call, callback=item.callback)
                turn = len(self.conversation.turns)
                prefill = f"    def {item.name}(self"
                target = _Target(item.name, "helper", ask, prefill, turn, item.caller)
                self.first_answer(target)

    def judge(self, pick: _Pick) -> _Judgement:
        """Assembles the picked answers, validates the file and scores each answer."""
        states: dict[str, str] = {}
        helpers: dict[str, str] = {}
        for target in self.targets.values():
            attempt = pick(target)
            if attempt is not None and attempt.code is not None:
                (states if target.kind == "state" else helpers)[target.name] = attempt.code
        helpers = _called(states, helpers)
        used = usage(self.full, {**states, **helpers})
        skeleton = self.build_skeleton(used.interfaces, used.helpers)
        assembly = assemble(
            skeleton,
            states,
            helpers,
            prefilled=[self.full.prologues.get("starting", "")],
            author=self.model_name,
            classes=self.classes,
        )
        judgement = _Judgement(
            skeleton, assembly, self.validate(assembly.code, skeleton), frozenset(self.targets)
        )
        # The run and the simulation follow only a file without static errors: in any other,
        # an answer's behaviour is not known, which is not the same as none found.
        measured = not any(f.severity == "error" and not _later(f) for f in judgement.findings)
        for target in self.targets.values():
            attempt = pick(target)
            mine = judgement.mine(target.name)
            if attempt is None or attempt.code is None or mine is None:
                continue
            errors = [f for f in mine if f.severity == "error"]
            attempt.errors = len(errors)
            attempt.warnings = len(mine) - attempt.errors
            attempt.behaviour_errors = sum(_later(f) for f in errors) if measured else None
        return judgement

    def failing(self, judgement: _Judgement) -> list[tuple[_Target, list[tuple[str, str]], str]]:
        """Methods whose latest answer failed or has errors, with what to tell the model and
        the start its repair continues from."""
        lines = judgement.assembly.code.splitlines()
        out = []
        for target in self.targets.values():
            last = target.attempts[-1]
            mine = judgement.mine(target.name)
            if last.code is None:
                out.append((target, _problems(last, [], lines), target.prefill))
            elif last.errors and mine is not None:
                errors = [f for f in mine if f.severity == "error"]
                unset = [a for f in errors if (a := _unset_output(f)) is not None]
                unread = [a for f in errors if (a := _unread_input(f)) is not None]
                others = [
                    f for f in errors if _unset_output(f) is None and _unread_input(f) is None
                ]
                if others:
                    first = min(others, key=lambda f: f.line)
                    start = _resume_point(target, last.code, judgement, first)
                elif unread:
                    start = _inputs_resume(target, unread)
                else:
                    start = _output_resume(target, last.code, unset[0])
                out.append((target, _problems(last, mine, lines, self.full.helpers), start))
        return out

    def fixes(
        self, judgement: _Judgement
    ) -> list[tuple[_Target, str, list[tuple[str, str]], list[Finding]]]:
        """Methods with errors that come with the statement to put in their place, with the
        latest answer so fixed, what it was told (the errors left are the repair's) and the
        findings whose fixes went in."""
        lines = judgement.assembly.code.splitlines()
        out = []
        for target in self.targets.values():
            last = target.attempts[-1]
            mine = judgement.mine(target.name)
            if last.code is None or not last.errors or mine is None:
                continue
            errors = [f for f in mine if f.severity == "error"]
            fixed = _apply_replacements(target, last.code, judgement, errors)
            if fixed is not None:
                code, applied = fixed
                told = _problems(last, mine, lines, self.full.helpers)
                out.append((target, code, told, applied))
        return out

    def fix(
        self,
        target: _Target,
        code: str,
        told: list[tuple[str, str]],
        applied: Sequence[Finding] = (),
    ) -> None:
        problems = [text for _, text in told]
        attempt = Attempt(
            target=target.name,
            kind=target.kind,
            number=len(target.attempts) + 1,
            temperature=0.0,
            seed=0,
            finish="fixed",
            note="the statements the checks suggested, put in place of the flagged ones",
            code=code,
            response="",
            seconds=0.0,
            problems=problems,
            problem_codes=[c for c, _ in told if c],
            fixes=[
                AppliedFix(code=f.code, safety=f.fix_safety or "unsafe", line=f.line)
                for f in applied
            ],
        )
        target.attempts.append(attempt)
        # What the checks fixed is still worth avoiding when the model writes it again.
        target.problems += [p for p in problems if p not in target.problems]
        self.author.log.append(
            f"===== checks' fix of {target.name} (attempt {attempt.number}) =====\n"
            f"```python\n{code}```"
        )
        self.author.emit(AttemptFinished(attempt))

    def repair_failing(self, judgement: _Judgement) -> None:
        """Asks again for every method that failed, then for helpers the repairs call."""
        for target, told, prefill in self.failing(judgement):
            self.repair(target, told, prefill)
        self.write_helpers()  # a repair may call a helper nobody has written yet

    def repair(self, target: _Target, told: list[tuple[str, str]], prefill: str) -> None:
        # A repair branches off where the method was first asked for: the same request with
        # everything found so far, continuing the latest answer up to its first error.
        problems = [text for _, text in told]
        target.problems += [p for p in problems if p not in target.problems]
        ask = repair_ask(target.ask, target.problems[-_MAX_PROBLEMS:])
        codes = [c for c, _ in told if c]
        attempt = self.author.answer(self.conversation, target, ask, prefill, codes)
        attempt.problems = problems
        attempt.problem_codes = codes


def author_skill(
    generator: TextGenerator,
    build_skeleton: SkeletonBuilder,
    capability: Capability,
    spec: SkillSpec,
    interfaces: Sequence[CardInterface],
    validate: Validator,
    *,
    settings: AuthorSettings | None = None,
    on_event: Callable[[object], None] | None = None,
    cancel: threading.Event | None = None,
) -> Authored:
    """Has ``generator`` write the behaviour of the skill (see the module docstring)."""
    settings = settings or AuthorSettings()
    author = _Author(generator, settings, on_event, cancel)
    skill = _Skill(author, build_skeleton, capability, interfaces, validate)
    skill.write_states(spec)
    skill.write_helpers()
    judgement = skill.judge(_latest)
    rounds = fixes = later = 0
    # The checks' own fixes cost no model time, so they also follow the last repairs.
    while skill.failing(judgement):
        fixable = skill.fixes(judgement) if fixes < _MAX_FIX_ROUNDS else []
        if fixable:
            fixes += 1
            for target, code, told, applied in fixable:
                skill.fix(target, code, told, applied)
        elif rounds < settings.attempts - 1:
            rounds += 1
            skill.repair_failing(judgement)
        elif later < settings.run_repairs and _only_later_stages(judgement):
            later += 1
            skill.repair_failing(judgement)
        else:
            break
        judgement = skill.judge(_latest)
    # The final file takes each method's best answer (fewest errors, then warnings), chosen
    # once: judging the final file counts again and may move a score, not the choice.
    choices = {name: _best(t) or _latest(t) for name, t in skill.targets.items()}
    judgement = skill.judge(lambda t: choices[t.name])
    for target in skill.targets.values():
        kept = judgement.mine(target.name) is not None
        for attempt in target.attempts:
            attempt.chosen = kept and attempt is choices[target.name] and attempt.code is not None
    return Authored(
        code=judgement.assembly.code,
        findings=judgement.findings,
        attempts=[a for t in skill.targets.values() for a in t.attempts],
        assembly=judgement.assembly,
        skeleton=judgement.skeleton,
        card=skill.conversation.card,
        transcript=_transcript(skill.conversation, author.log),
        notes=_notes(skill.full, judgement.skeleton),
    )


def _notes(full: Skeleton, final: Skeleton) -> list[str]:
    kept = {i.name for i in final.interfaces}
    unused = [i.name for i in full.interfaces if i.name not in kept]
    if not unused:
        return []
    return [
        f"retrieved but not used by the behaviour, so left out of the skill: {', '.join(unused)}"
    ]


def _transcript(conversation: Conversation, log: Sequence[str]) -> str:
    prefix = conversation.prompt("", "").messages[: conversation.prompt("", "").prefix_messages]
    head = [f"===== {m.role} (cached prefix) =====\n{m.content}" for m in prefix]
    return "\n\n".join([*head, f"===== task card =====\n{conversation.card}", *log]) + "\n"
