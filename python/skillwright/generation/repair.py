"""Stage 7, repair: what the checks found goes back to the model, a bounded number of rounds,
and each method's best answer by its findings makes the final skill.

The writer (:mod:`~skillwright.generation.author`) asks for every method once; from then on
this module decides, round by round, what happens to each method whose latest answer failed
or has errors on its lines (:class:`Judgement` says which findings are a method's):

1. Where the checks carry the right statement for every flagged one (a rule's fix: the wait
   for a first message, a zero command, a loop with a sleep), it is put in place of the
   flagged statement without asking the model: an attempt that costs no model time, recorded
   with each fix's rule and safety (:func:`_apply_replacements`).
2. Else the method is asked for again within ``attempts`` answers per method: its request
   once more with every problem found so far (:func:`_problems`, which reads each finding's
   rule code and data, never its message text), the answer prefilled with the latest
   answer's statements before its first error (:func:`_resume_point`), or with a start that
   reads the inputs it ignored or sets the output it never set. ``run_repairs`` more rounds
   follow when only the run's or the simulation's findings are left.
3. Every answer is scored by its findings (:func:`_score`); the best per method wins, and
   every attempt is kept for the record.

Repair lives in :mod:`skillwright.generation` rather than in a package of its own: what it
reads and changes are the writer's documents (an :class:`~skillwright.generation.model.Attempt`,
the assembled file, the method's prefill) and the writer drives it, so a package beside
``generation`` would import it and be imported by it. Here the direction is one way: the
author imports this module, which reaches the writer only through :class:`Writer`.
"""

from __future__ import annotations

import ast
import textwrap
from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass
from typing import Literal, Protocol

from skillwright.generation.assemble import Assembly, method_spans, parse_method
from skillwright.generation.model import AppliedFix, Attempt, Skeleton
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
from skillwright.validation.static import local_name

__all__ = ["Judgement", "Method", "Writer", "is_later", "judged", "repair_skill"]

_MAX_PROBLEMS = 6
"""Problems told per answer, and of the problems found so far, the latest told in a repair's
request."""
_MAX_FIX_ROUNDS = 3
"""Rounds of the checks' own fixes per skill (they cost no model time, but a fix may meet a
new finding that suggests the old statement back)."""


class Method(Protocol):
    """One method the model writes (a state or a helper), as the repair sees it."""

    @property
    def name(self) -> str:
        """The method's name."""

    @property
    def kind(self) -> Literal["state", "helper"]:
        """A PackML state or a helper a state calls."""

    @property
    def prefill(self) -> str:
        """The start its first answer was given (the ``def`` line, the skeleton's prologue):
        where a repair begins when it cannot continue an earlier answer."""

    @property
    def attempts(self) -> list[Attempt]:
        """Its answers so far, in order; a fix of the checks is appended here."""

    @property
    def problems(self) -> list[str]:
        """Every problem found in its answers so far, in order."""


_Pick = Callable[[Method], Attempt | None]
"""Which of a method's answers goes into the file."""


class Writer(Protocol):
    """What the repair needs of the stage that writes the methods."""

    def methods(self) -> Sequence[Method]:
        """The methods asked for so far, in the order they were."""

    @property
    def offered(self) -> Collection[str]:
        """The helpers the full skeleton offers the behaviour."""

    def judge(self, picked: Mapping[str, Attempt | None]) -> Judgement:
        """The file assembled from the ``picked`` answer of each method (by name), with what
        the checks found in it."""

    def ask_again(
        self, name: str, problems: Sequence[str], prefill: str, codes: Sequence[str] = ()
    ) -> Attempt:
        """The model's next answer for method ``name``: its request with ``problems``, the
        answer starting with ``prefill``; ``codes`` are the rules of the findings it is asked
        to fix."""

    def write_helpers(self) -> None:
        """Asks for helpers the answers call but nobody has written."""

    def record_fix(self, name: str, attempt: Attempt) -> None:
        """Logs and announces the checks' own fix of method ``name`` (already appended)."""


@dataclass
class Judgement:
    """A file assembled from one answer per method, and what the checks found in it."""

    skeleton: Skeleton
    """The skeleton the file is built on (only the interfaces and helpers it uses)."""
    assembly: Assembly
    findings: list[Finding]
    """The findings of the static checks and of whatever later stages the caller added."""
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


def repair_skill(
    writer: Writer, *, attempts: int, run_repairs: int, initial: Judgement | None = None
) -> Judgement:
    """Repairs ``writer``'s methods (see the module docstring) and returns the judgement of
    the final file, made of each method's best answer, whose attempts are marked chosen;
    ``initial`` is the judgement of the latest answers when the caller has made it already
    (best-of-N judged its winner)."""
    judgement = initial if initial is not None else judged(writer, _latest)
    rounds = fixes = later = 0
    # The checks' own fixes cost no model time, so they also follow the last repairs.
    while _failing(writer, judgement):
        fixable = _fixes(writer, judgement) if fixes < _MAX_FIX_ROUNDS else []
        if fixable:
            fixes += 1
            for method, code, told, applied in fixable:
                _fix(writer, method, code, told, applied)
        elif rounds < attempts - 1:
            rounds += 1
            _repair_failing(writer, judgement)
        elif later < run_repairs and _only_later_stages(judgement):
            later += 1
            _repair_failing(writer, judgement)
        else:
            break
        judgement = judged(writer, _latest)
    # The final file takes each method's best answer (fewest errors, then warnings), chosen
    # once: judging the final file counts again and may move a score, not the choice.
    choices = {method.name: _best(method) or _latest(method) for method in writer.methods()}
    judgement = judged(writer, lambda method: choices[method.name])
    for method in writer.methods():
        kept = judgement.mine(method.name) is not None
        for attempt in method.attempts:
            attempt.chosen = kept and attempt is choices[method.name] and attempt.code is not None
    return judgement


def judged(writer: Writer, pick: _Pick) -> Judgement:
    """The writer's judgement of the file of the picked answers, each answer scored by the
    findings on its lines."""
    picked = {method.name: pick(method) for method in writer.methods()}
    judgement = writer.judge(picked)
    # The run and the simulation follow only a file without static errors: in any other,
    # an answer's behaviour is not known, which is not the same as none found.
    measured = not any(f.severity == "error" and not is_later(f) for f in judgement.findings)
    for method in writer.methods():
        attempt = picked[method.name]
        mine = judgement.mine(method.name)
        if attempt is None or attempt.code is None or mine is None:
            continue
        errors = [f for f in mine if f.severity == "error"]
        attempt.errors = len(errors)
        attempt.warnings = len(mine) - attempt.errors
        attempt.behaviour_errors = sum(is_later(f) for f in errors) if measured else None
    return judgement


def _failing(
    writer: Writer, judgement: Judgement
) -> list[tuple[Method, list[tuple[str, str]], str]]:
    """Methods whose latest answer failed or has errors, with what to tell the model and
    the start its repair continues from."""
    lines = judgement.assembly.code.splitlines()
    out = []
    for method in writer.methods():
        last = method.attempts[-1]
        mine = judgement.mine(method.name)
        if last.code is None:
            out.append((method, _problems(last, [], lines), method.prefill))
        elif last.errors and mine is not None:
            errors = [f for f in mine if f.severity == "error"]
            unset = [a for f in errors if (a := _unset_output(f)) is not None]
            unread = [a for f in errors if (a := _unread_input(f)) is not None]
            others = [f for f in errors if _unset_output(f) is None and _unread_input(f) is None]
            if others:
                first = min(others, key=lambda f: f.line)
                start = _resume_point(method, last.code, judgement, first)
            elif unread:
                start = _inputs_resume(method, unread)
            else:
                start = _output_resume(method, last.code, unset[0])
            out.append((method, _problems(last, mine, lines, writer.offered), start))
    return out


def _fixes(
    writer: Writer, judgement: Judgement
) -> list[tuple[Method, str, list[tuple[str, str]], list[Finding]]]:
    """Methods with errors that come with the statement to put in their place, with the
    latest answer so fixed, what it was told (the errors left are the repair's) and the
    findings whose fixes went in."""
    lines = judgement.assembly.code.splitlines()
    out = []
    for method in writer.methods():
        last = method.attempts[-1]
        mine = judgement.mine(method.name)
        if last.code is None or not last.errors or mine is None:
            continue
        errors = [f for f in mine if f.severity == "error"]
        fixed = _apply_replacements(method, last.code, judgement, errors)
        if fixed is not None:
            code, applied = fixed
            told = _problems(last, mine, lines, writer.offered)
            out.append((method, code, told, applied))
    return out


def _fix(
    writer: Writer,
    method: Method,
    code: str,
    told: list[tuple[str, str]],
    applied: Sequence[Finding] = (),
) -> None:
    """Records ``code`` (the latest answer with the checks' fixes ``applied``) as the
    method's next attempt."""
    problems = [text for _, text in told]
    attempt = Attempt(
        target=method.name,
        kind=method.kind,
        number=len(method.attempts) + 1,
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
            AppliedFix(code=f.code, safety=f.fix_safety or "unsafe", line=f.line) for f in applied
        ],
    )
    method.attempts.append(attempt)
    # What the checks fixed is still worth avoiding when the model writes it again.
    method.problems.extend([p for p in problems if p not in method.problems])
    writer.record_fix(method.name, attempt)


def _repair_failing(writer: Writer, judgement: Judgement) -> None:
    """Asks again for every method that failed, then for helpers the repairs call."""
    for method, told, prefill in _failing(writer, judgement):
        _repair(writer, method, told, prefill)
    writer.write_helpers()  # a repair may call a helper nobody has written yet


def _repair(writer: Writer, method: Method, told: list[tuple[str, str]], prefill: str) -> None:
    # A repair branches off where the method was first asked for: the same request with
    # everything found so far, continuing the latest answer up to its first error.
    problems = [text for _, text in told]
    method.problems.extend([p for p in problems if p not in method.problems])
    codes = [c for c, _ in told if c]
    attempt = writer.ask_again(method.name, method.problems[-_MAX_PROBLEMS:], prefill, codes)
    attempt.problems = problems
    attempt.problem_codes = codes


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


def _resume_point(method: Method, code: str, judgement: Judgement, error: Finding) -> str:
    """``code`` (an answer of ``method``) up to the statement that holds the ``error`` (in
    its body, or nested in a loop or branch of it), followed by the statement the check
    suggests instead when there is one and the flagged statement is a plain one (or a loop)
    that it can take the place of; the method's own prefill when the statement cannot be
    told."""
    found = _statements_at(judgement, method.name, error.line, error.column)
    parsed = parse_method(code)
    if found is None or parsed is None:
        return method.prefill
    top, inner = found
    key = ast.unparse(top)
    mine = next((s for s in parsed.body if ast.unparse(s) == key), None)
    if mine is None:
        return method.prefill
    lines = code.splitlines(keepends=True)
    cut = mine.lineno + inner.lineno - top.lineno
    kept = "".join(lines[: cut - 1])
    if len(kept) < len(method.prefill):
        kept = method.prefill
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


def _inputs_resume(method: Method, attributes: Sequence[str]) -> str:
    """The method's start with a local copy of each input it ignored, for the model to go on
    from. Each input is a skill parameter the capability declares (``VDI3682:hasInput``), so
    the behaviour must act on it; a model told only that it is ignored tends to write the
    method the same way again, while it uses a variable it is handed. A copy that nothing
    then reads is still an input never used (the checks say so)."""
    taken: set[str] = set()
    lines = []
    for attribute in dict.fromkeys(attributes):
        local = local_name(attribute, taken)
        taken.add(local)
        lines.append(f"        {local} = self.{attribute}\n")
    return method.prefill + "".join(lines)


def _output_resume(method: Method, code: str, attribute: str) -> str:
    """``code`` whole (but a ``return`` that ends it), then the start of the statement that
    sets the output ``attribute``: each output is a skill output the capability declares
    (``VDI3682:hasOutput``), which the skill must set; a model told only that it is never
    set tends to write the same method again, while it completes an assignment it is
    handed."""
    parsed = parse_method(code)
    if parsed is None:
        return method.prefill
    lines = code.splitlines(keepends=True)
    last = parsed.body[-1]
    end = last.lineno - 1 if isinstance(last, ast.Return) else last.end_lineno or last.lineno
    kept = "".join(lines[:end])
    if not kept.endswith("\n"):
        kept += "\n"
    first = lines[parsed.body[0].lineno - 1]
    return f"{kept}{first[: len(first) - len(first.lstrip())]}self.{attribute} = "


def _indented(replacement: str, line: str) -> str:
    """``replacement`` (statements; empty for none) indented as ``line`` is."""
    if not replacement:
        return ""
    return textwrap.indent(replacement, line[: len(line) - len(line.lstrip())]) + "\n"


def _apply_replacements(
    method: Method, code: str, judgement: Judgement, errors: Sequence[Finding]
) -> tuple[str, list[Finding]] | None:
    """``code`` (the answer of ``method`` in the judged file) with each flagged statement
    whose finding suggests one replaced by it, and the findings whose fixes went in; ``None``
    unless at least one applies and the result is a different method that parses. The errors
    without a suggestion stay for the model, which then repairs a method with fewer of them.
    Of two suggestions for one statement (or for a statement and one inside it) only the
    first applies: the other was made for the statement as it was, and the next round's
    checks make it again for the statement as it is (a loop that needs a sleep and holds a
    local named ``time``: the loop with the sleep is the old loop's text, so putting it in
    after the local's rename would undo the rename, and the loop would compare a float with
    the module ``time``)."""
    parsed = parse_method(code)
    if parsed is None or not errors:
        return None
    lines = code.splitlines(keepends=True)
    spans: dict[tuple[int, int], str] = {}
    applied: list[Finding] = []
    for error in errors:
        found = _statements_at(judgement, method.name, error.line, error.column)
        if error.replacement is None or found is None or not _replaceable(found[1]):
            continue
        top, inner = found
        mine = next((s for s in parsed.body if ast.unparse(s) == ast.unparse(top)), None)
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
    judgement: Judgement, name: str, line: int, column: int
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


def _only_later_stages(judgement: Judgement) -> bool:
    """Whether the file passed the static checks and only the run or simulation found
    errors."""
    errors = [f for f in judgement.findings if f.severity == "error"]
    return bool(errors) and all(is_later(f) for f in errors)


def _score(attempt: Attempt) -> tuple[int, int, int, int]:
    """Lower is better: unusable answers last, then errors the static checks find (an answer
    that passed them got further), then the run's and simulation's errors (an answer whose
    file did not get that far after one that did), then warnings."""
    if attempt.code is None or attempt.errors is None:
        return (1, 10**6, 10**6, 10**6)
    later = attempt.behaviour_errors
    if later is None:
        # Not run: another method's static error stopped the file. Zero run errors then
        # says nothing, so the answer ranks behind one whose run was judged (else an answer
        # would beat one with simulation findings only because a helper it calls failed the
        # static checks and nothing ran).
        return (0, attempt.errors, 10**6, attempt.warnings or 0)
    return (0, attempt.errors - later, later, attempt.warnings or 0)


def is_later(finding: Finding) -> bool:
    """Whether ``finding`` comes from running the skill (the run, the simulation) rather
    than from reading it."""
    rule = rule_of(finding)
    return rule is not None and rule.stage != "static"


def _execute_owns(finding: Finding) -> bool:
    """Whether ``finding``, outside any written method (at an input's or output's getter:
    an input never read, an output never set), is ``execute``'s to fix."""
    rule = rule_of(finding)
    return is_later(finding) or (rule is not None and rule.group in ("inputs", "outputs"))


def _latest(method: Method) -> Attempt | None:
    return method.attempts[-1] if method.attempts else None


def _best(method: Method) -> Attempt | None:
    """The answer with the best score; of equals the latest, which was told more of what was
    wrong (its count may include findings another method's answer caused), or of a best-of-N
    first round the winner's, which the writer put last."""
    order = {id(a): position for position, a in enumerate(method.attempts)}
    judged = [a for a in method.attempts if a.code is not None and a.errors is not None]
    return min(judged, key=lambda a: (_score(a), -order[id(a)])) if judged else None
