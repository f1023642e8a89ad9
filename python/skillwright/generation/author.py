"""Stage 5's model half: a model writes a skill one method at a time.

1. The skeleton (structure, annotations, handles, helpers) comes first; the model gets a
   task card and writes each specified state in turn (:mod:`~skillwright.generation.conversation`),
   each answer prefilled with the method's start and ended at the method's end, under a
   per-method token budget and a :class:`~skillwright.generation.guard.RepetitionGuard`.
2. Helper methods the states call but nobody wrote are asked for next (and again after each
   round of repairs).
3. The methods go into the skeleton, rebuilt with only the interfaces and helpers the
   behaviour uses (:mod:`~skillwright.generation.assemble`), and the result is validated (the
   static checks, and whatever later stages the caller adds: run, simulation).

What the checks find then goes back to the model, a bounded number of rounds, and each
method's best answer makes the final file: that is stage 7, repair
(:mod:`~skillwright.generation.repair`), which drives this module's writer (:class:`_Skill`)
through :class:`~skillwright.generation.repair.Writer`. The writer keeps how an answer is
asked for: a repair's request is the method's first request with the problems listed, the
answer prefilled with where the repair goes on, decoded greedily the first time (sampled at
once after an answer that looped or ran out of tokens) and sampled with a fixed seed after.
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
    parse_method,
    usage,
)
from skillwright.generation.candidates import candidate_options, choose_candidate
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
    Attempt,
    AttemptFinish,
    CandidateVerdict,
    InterfaceRef,
    Skeleton,
)
from skillwright.generation.repair import Judgement, repair_skill
from skillwright.llm.base import GenerationOptions, TextGenerator
from skillwright.llm.batch import BatchAnswer, generate_each
from skillwright.rules.finding import Finding
from skillwright.spec.model import SkillSpec
from skillwright.validation.syntax import self_attribute

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


@dataclass(frozen=True)
class AuthorSettings:
    """How hard to try."""

    attempts: int = 3
    """Answers per method at most: the first, then repairs."""
    run_repairs: int = 1
    """Repairs beyond ``attempts`` once the static checks pass and only the run's or the
    simulation's findings are left: those come last, often after the static repairs used the
    attempts up, and only running tells some errors (a wait for an action's result shorter
    than the goal takes, a timer callback that raises), so without these rounds they would
    never be told to the model."""
    max_tokens: int = 768
    """Tokens per answer of ``execute`` at most (a method, not a file)."""
    short_max_tokens: int = 320
    """Tokens per answer of every other state and of a helper at most (never more than
    ``max_tokens``). The other PackML states and the helpers each do one thing (create or
    release handles, publish a zero command, wait for one result, return one field): a few
    statements, so an answer that runs longer is repeating itself rather than adding
    behaviour, and the tokens are better spent on a repair."""

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
    candidates: int = 1
    """Candidate skills of the first round (best-of-N,
    :mod:`~skillwright.generation.candidates`): every state is asked for this many answers
    in one batch, the greedy one and sampled ones, and repair starts from the candidate file
    the judge ranks best. 1: the greedy answer alone."""
    candidate_temperature: float = 0.7
    """Temperature of the sampled candidates (the greedy one is candidate 0)."""


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
    candidates: list[CandidateVerdict] = field(default_factory=list)
    """Every candidate of a best-of-N first round and its verdict (empty: one first
    answer)."""


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
    first_round: int = 1
    """Answers of its first round (more than one: best-of-N candidates)."""


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
        # they fixed; a best-of-N first round counts as one answer, its winner's.
        answers = [a for a in target.attempts if a.finish != "fixed"]
        greedy = not answers or (
            len(answers) == target.first_round and answers[-1].finish not in _DEAD_ENDS
        )
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
        answer = BatchAnswer(
            text="".join(parts),
            finish_reason=stream.finish_reason,
            prompt_tokens=stream.prompt_tokens,
            reused_tokens=stream.reused_tokens,
            completion_tokens=stream.completion_tokens or stream.completion_chunks,
            seconds=round(time.perf_counter() - started, 3),
            prefix_cache=stream.prefix_cache,
        )
        return self._attempt(target, ask, prefill, options, answer, guard if looped else None)

    def answer_many(
        self, conversation: Conversation, target: _Target, ask: str, prefill: str, count: int
    ) -> list[Attempt]:
        """Asks the model for ``count`` answers of the target's first request at once (a
        best-of-N first round, see :func:`~skillwright.generation.candidates.candidate_options`),
        each with its own repetition guard; only the greedy answer's text is streamed to
        the caller, the others are announced when they end."""
        self.check_cancel()
        budget = self.settings.budget(target.kind, target.name)
        options = candidate_options(
            count,
            max_tokens=budget,
            temperature=self.settings.candidate_temperature,
            seed=self.settings.seed,
            stop=STOP,
        )
        first = len(target.attempts) + 1
        for index in range(count):
            self.emit(AttemptStarted(target.name, target.kind, first + index, budget))
        prompt = conversation.prompt(ask, prefill, upto=target.turn_index)
        guards = [RepetitionGuard() for _ in options]
        looped: set[int] = set()

        def on_chunk(index: int, chunk: str) -> bool:
            if index == 0:
                self.emit(chunk)
            if guards[index].feed(chunk):
                looped.add(index)
                return True
            return False

        answers = generate_each(
            self.generator, prompt, options, on_chunk=on_chunk, cancel=self.cancel
        )
        self.check_cancel()
        target.first_round = count
        return [
            self._attempt(
                target,
                ask,
                prefill,
                option,
                answer,
                guards[index] if index in looped else None,
                candidate=index,
            )
            for index, (option, answer) in enumerate(zip(options, answers, strict=True))
        ]

    def _attempt(
        self,
        target: _Target,
        ask: str,
        prefill: str,
        options: GenerationOptions,
        answer: BatchAnswer,
        looped: RepetitionGuard | None,
        candidate: int | None = None,
    ) -> Attempt:
        """The answer judged as a method, recorded as the target's next attempt."""
        number = len(target.attempts) + 1
        response = answer.text
        reason = None if answer.finish_reason == "stopped" else answer.finish_reason
        finish, note, code = self._judge(target, prefill + response, reason, looped)
        attempt = Attempt(
            target=target.name,
            kind=target.kind,
            number=number,
            temperature=options.temperature or 0.0,
            seed=options.seed or 0,
            finish=finish,
            note=note,
            code=code,
            response=response,
            prompt_tokens=answer.prompt_tokens,
            reused_tokens=answer.reused_tokens,
            completion_tokens=answer.completion_tokens,
            seconds=answer.seconds,
            prefix_cache=answer.prefix_cache,
            kept_lines=prefill.count("\n") - target.prefill.count("\n"),
            candidate=candidate,
        )
        target.attempts.append(attempt)
        label = f"attempt {number}" + (f", candidate {candidate}" if candidate is not None else "")
        self.log.append(
            f"===== user =====\n{ask}\n\n===== assistant ({label}) =====\n"
            f"```python\n{prefill}{response}"
        )
        self.emit(AttemptFinished(attempt))
        return attempt

    def _judge(
        self,
        target: _Target,
        text: str,
        reason: str | None,
        looped: RepetitionGuard | None,
    ) -> tuple[AttemptFinish, str | None, str | None]:
        if looped is not None:
            return "repetition", f"the answer repeated {looped.reason} and was stopped", None
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
    try:
        ast.parse(textwrap.dedent(text))
    except SyntaxError as error:
        lines = textwrap.dedent(text).splitlines()
        where = (
            lines[error.lineno - 1].strip() if error.lineno and error.lineno <= len(lines) else ""
        )
        return f"the answer is not valid Python ({error.msg} at `{where}`)"
    return f"the answer holds more than the one method {name}"


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

    def write_states(self, spec: SkillSpec, candidates: int = 1) -> None:
        """Asks for every specified state in turn; with ``candidates`` above 1, that many
        answers of each at once, the greedy one of each earlier state standing in the
        conversation (:meth:`adopt` puts the winner's there)."""
        for state, text in spec.states.items():
            prefill = _state_prefill(state, self.full)
            turn = len(self.conversation.turns)
            target = _Target(state, "state", state_ask(state, text), prefill, turn)
            if candidates <= 1:
                self.first_answer(target)
                continue
            self.targets[state] = target
            greedy = self.author.answer_many(
                self.conversation, target, target.ask, target.prefill, candidates
            )[0]
            self.conversation.turns.append(
                Turn(target.ask, greedy.code or target.prefill + greedy.response)
            )

    def adopt(self, index: int) -> None:
        """Makes candidate ``index``'s answer each state's latest (repair goes on from it)
        and the one the conversation shows."""
        for target in self.targets.values():
            own = [a for a in target.attempts if a.candidate == index]
            if not own:
                continue
            target.attempts.remove(own[0])
            target.attempts.append(own[0])
            if target.kind == "state":
                self.conversation.turns[target.turn_index] = Turn(
                    target.ask, own[0].code or target.prefill + own[0].response
                )

    def _written_sets(self) -> list[dict[str, str]]:
        """The method code of each file the latest round can make: the latest answers, or
        in a best-of-N first round each candidate's."""
        rounds = max((t.first_round for t in self.targets.values()), default=1)
        fresh = all(len(t.attempts) <= t.first_round for t in self.targets.values())
        if rounds <= 1 or not fresh:
            return [{t.name: c for t in self.targets.values() if (c := t.attempts[-1].code)}]
        sets = []
        for index in range(rounds):
            written: dict[str, str] = {}
            for target in self.targets.values():
                own = [a for a in target.attempts if a.candidate in (index, None)]
                if own and own[0].code:
                    written[target.name] = own[0].code
            sets.append(written)
        return sets

    def write_helpers(self) -> None:
        """Asks for helpers the methods call but nobody wrote (helpers may need helpers); in
        a best-of-N first round, those any candidate calls, each asked for once."""
        for _ in range(2):
            known = _class_methods(self.full) | set(self.targets)
            # A call copied from a worked example (its stopping's self._cancel_dock_robot_goal)
            # is not asked for: the examples are of an invented robot, so their helpers drive
            # interfaces this skill does not have. The checks flag the call instead, naming
            # the helpers this skill has.
            known |= example_helpers() - _class_methods(self.full)
            missing: list[_Missing] = []
            for written in self._written_sets():
                found = _missing_helpers(written, known, _assigned_attributes(written))
                missing += [m for m in found if m.name not in {n.name for n in missing}]
            missing = missing[:_MAX_HELPERS]
            if not missing:
                return
            for item in missing:
                ask = helper_ask(item.name, item.caller, item.call, callback=item.callback)
                turn = len(self.conversation.turns)
                prefill = f"    def {item.name}(self"
                target = _Target(item.name, "helper", ask, prefill, turn, item.caller)
                self.first_answer(target)

    def methods(self) -> list[_Target]:
        """The methods asked for so far, in the order they were."""
        return list(self.targets.values())

    @property
    def offered(self) -> list[str]:
        """The helpers the full skeleton offers the behaviour."""
        return self.full.helpers

    def judge(self, picked: Mapping[str, Attempt | None]) -> Judgement:
        """Assembles the ``picked`` answers (by method) and validates the file."""
        skeleton, assembly = self.assembled(picked)
        return Judgement(
            skeleton, assembly, self.validate(assembly.code, skeleton), frozenset(self.targets)
        )

    def assembled(self, picked: Mapping[str, Attempt | None]) -> tuple[Skeleton, Assembly]:
        """The file of the ``picked`` answers (by method), on the skeleton of what they use."""
        states: dict[str, str] = {}
        helpers: dict[str, str] = {}
        for target in self.targets.values():
            attempt = picked[target.name]
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
        return skeleton, assembly

    def ask_again(
        self, name: str, problems: Sequence[str], prefill: str, codes: Sequence[str] = ()
    ) -> Attempt:
        """The model's next answer for ``name``: its request with the ``problems``, the answer
        starting with ``prefill``, after the turns before the method's first request;
        ``codes`` are the rules of the findings it is asked to fix."""
        target = self.targets[name]
        return self.author.answer(
            self.conversation, target, repair_ask(target.ask, problems), prefill, codes
        )

    def record_fix(self, name: str, attempt: Attempt) -> None:
        """Logs the checks' own fix of ``name`` and announces it."""
        self.author.log.append(
            f"===== checks' fix of {name} (attempt {attempt.number}) =====\n"
            f"```python\n{attempt.code}```"
        )
        self.author.emit(AttemptFinished(attempt))


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
    skill.write_states(spec, settings.candidates)
    skill.write_helpers()
    initial: Judgement | None = None
    verdicts: list[CandidateVerdict] = []
    if settings.candidates > 1:
        temperatures = [
            (0.0 if index == 0 else settings.candidate_temperature, settings.seed + index)
            for index in range(settings.candidates)
        ]
        initial, verdicts = choose_candidate(skill, temperatures)
    judgement = repair_skill(
        skill, attempts=settings.attempts, run_repairs=settings.run_repairs, initial=initial
    )
    return Authored(
        code=judgement.assembly.code,
        findings=judgement.findings,
        attempts=[a for t in skill.methods() for a in t.attempts],
        assembly=judgement.assembly,
        skeleton=judgement.skeleton,
        card=skill.conversation.card,
        transcript=_transcript(skill.conversation, author.log),
        notes=_notes(skill.full, judgement.skeleton),
        candidates=verdicts,
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
