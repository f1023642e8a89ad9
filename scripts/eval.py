"""`make eval`: the default local model writes all 18 evaluation skills; a table of how it went.

The pairs are the nine MR-1 capabilities shipped in ``capabilities/`` against the shipped MR-1
recording, and the paper's nine (``../shared/data/cap2skill``) against the paper robot's raw
interface report. Each runs through the same pipeline as ``skillwright generate`` (default
retrieval, the default model, repairs from the findings of the checks, the sandboxed run and the
MuJoCo simulation); the results go to ``eval-out/``
(one folder per skill with its record, and ``summary.json``) and a table is printed:
per skill the verdict of the checks, answers and repairs, errors by rule, tokens and seconds,
then the totals the targets are judged by, and per rule (its code) how often the model was
told of it, how often it is left in the final skills, how often the checks fixed it without
the model and how many of those fixes the final skills kept.

    python scripts/eval.py [--only NAME ...] [--attempts N] [--out DIR] [--model ID]

This is slow by nature (a 1.5B model on the CPU); it is not part of ``make test``.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from collections import Counter
from dataclasses import asdict, dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared" / "data" / "cap2skill"


@dataclass
class Pair:
    """One capability/specification pair and the robot's interfaces."""

    robot: str
    name: str
    capability: Path
    spec: Path
    interfaces: Path


@dataclass
class Row:
    """How one skill went."""

    robot: str
    name: str
    passed: bool = False
    errors: int = 0
    warnings: int = 0
    kinds: dict[str, int] = field(default_factory=dict)
    """Errors of the final skill's static checks, by rule code."""
    told: dict[str, int] = field(default_factory=dict)
    """Findings the model was told of over all its repairs, by rule code."""
    final: dict[str, int] = field(default_factory=dict)
    """Errors left in the final skill (checks, run and simulation), by rule code."""
    fixed: dict[str, int] = field(default_factory=dict)
    """Fixes the checks put in themselves, by rule code."""
    kept: dict[str, int] = field(default_factory=dict)
    """Of those, the ones in answers the final skill holds."""
    answers: int = 0
    repairs: int = 0
    fixes: int = 0
    tokens: int = 0
    seconds: float = 0.0
    generation_seconds: float = 0.0
    hit_limit: int = 0
    looped: int = 0
    ran: str = "-"
    """The run stage: pass, fail, or - when it did not run (the checks failed)."""
    behaved: str = "-"
    """The simulation: oracles passed/applied, or - when it did not run."""
    failure: str | None = None


def pairs(only: set[str]) -> list[Pair]:
    found = []
    recording = ROOT / "capabilities" / "recordings" / "mr1"
    for ttl in sorted((ROOT / "capabilities").glob("*.ttl")):
        spec = ttl.with_name(ttl.stem + ".spec.yaml")
        found.append(Pair("mr1", ttl.stem, ttl, spec, recording))
    report = SHARED / "interface-reports" / "ros2_system_report.json"
    if SHARED.is_dir():
        for ttl in sorted((SHARED / "capability-models").glob("*.ttl")):
            spec = SHARED / "skill-specs" / (ttl.stem.replace("-", "_") + ".json")
            found.append(Pair("cap2skill", ttl.stem, ttl, spec, report))
    else:
        print(f"note: {SHARED} not found; only the MR-1 pairs run", file=sys.stderr)
    if only:
        found = [p for p in found if p.name in only or f"{p.robot}/{p.name}" in only]
    return found


def run(pair: Pair, out: Path, attempts: int, model: str | None) -> Row:
    from skillwright.errors import SkillwrightError
    from skillwright.pipeline import GenerationRequest, run_generation
    from skillwright.pipeline.events import AttemptFinished, Event

    row = Row(pair.robot, pair.name)

    def on_event(event: Event) -> None:
        if isinstance(event, AttemptFinished):
            attempt = event.attempt
            print(
                f"    {attempt.target} #{attempt.number}: {attempt.finish}, "
                f"{attempt.completion_tokens or 0} tokens, {attempt.seconds:.1f} s",
                file=sys.stderr,
                flush=True,
            )

    request = GenerationRequest(
        capability=pair.capability,
        spec=pair.spec,
        interfaces=pair.interfaces,
        out_dir=out / pair.robot / pair.name,
        model=model,
        attempts=attempts,
    )
    started = time.perf_counter()
    try:
        outcome = run_generation(request, on_event=on_event)
    except SkillwrightError as error:
        row.failure = str(error)
        row.seconds = round(time.perf_counter() - started, 1)
        return row
    row.seconds = round(time.perf_counter() - started, 1)
    record = outcome.record
    row.passed = record.checks.passed
    row.errors = record.checks.errors
    row.warnings = record.checks.warnings
    row.kinds = dict(Counter(f.code for f in record.checks.findings if f.severity == "error"))
    final = [f for f in record.checks.findings if f.severity == "error"]
    for stage in (record.run, record.simulation):
        if stage is not None:
            final += [f for f in stage.findings if f.severity == "error"]
    row.final = dict(Counter(f.code for f in final))
    row.generation_seconds = record.timings.get("generation", 0.0)
    if record.model is not None:
        answers = [a for a in record.model.attempts if a.finish != "fixed"]
        row.answers = len(answers)
        row.repairs = sum(a.number > 1 for a in answers)
        row.fixes = len(record.model.attempts) - len(answers)
        row.tokens = record.model.completion_tokens or 0
        row.hit_limit = sum(a.finish == "length" for a in record.model.attempts)
        row.looped = sum(a.finish == "repetition" for a in record.model.attempts)
        row.told = dict(Counter(c for a in record.model.attempts for c in a.problem_codes))
        row.fixed = dict(Counter(f.code for a in record.model.attempts for f in a.fixes))
        row.kept = dict(
            Counter(f.code for a in record.model.attempts if a.chosen for f in a.fixes)
        )
    else:
        row.failure = "no model: the skeleton was written"
    if record.run is not None and record.run.skipped is None:
        row.ran = "pass" if record.run.passed else "fail"
    simulation = record.simulation
    if simulation is not None and simulation.skipped is None:
        judged = [v for v in simulation.verdicts if v.passed is not None]
        row.behaved = f"{sum(bool(v.passed) for v in judged)}/{len(judged)}"
        if not simulation.passed:
            row.behaved += " fail"
    return row


def table(rows: list[Row]) -> str:
    head = (
        f"{'robot':<10} {'skill':<32} {'checks':<7} {'errors by rule':<28} {'run':<5} "
        f"{'sim':<9} {'answers':>7} {'repairs':>7} {'fixes':>5} {'tokens':>6} {'seconds':>8}"
    )
    lines = [head, "-" * len(head)]
    for row in rows:
        kinds = ", ".join(f"{k} {n}" for k, n in sorted(row.kinds.items())) or "-"
        verdict = "pass" if row.passed else ("ERROR" if row.failure else "fail")
        lines.append(
            f"{row.robot:<10} {row.name:<32} {verdict:<7} {kinds:<28} {row.ran:<5} "
            f"{row.behaved:<9} {row.answers:>7} {row.repairs:>7} {row.fixes:>5} {row.tokens:>6} "
            f"{row.seconds:>8.1f}"
        )
        if row.failure:
            lines.append(f"{'':<10} {row.failure}")
    passed = sum(r.passed for r in rows)
    seconds = [r.seconds for r in rows if not r.failure]
    lines += [
        "-" * len(head),
        f"passed every static check: {passed} of {len(rows)}; ran clean: "
        f"{sum(r.ran == 'pass' for r in rows)}; behaved in the simulation: "
        f"{sum(r.behaved != '-' and not r.behaved.endswith('fail') for r in rows)}",
        f"answers cut at the token limit: {sum(r.hit_limit for r in rows)}; "
        f"stopped as loops: {sum(r.looped for r in rows)}",
        f"repairs: {sum(r.repairs for r in rows)} of {sum(r.answers for r in rows)} answers; "
        f"fixed by the checks without the model: {sum(r.fixes for r in rows)}",
        f"seconds per skill: median {statistics.median(seconds):.1f}, "
        f"max {max(seconds):.1f}, total {sum(seconds):.1f}"
        if seconds
        else "seconds per skill: -",
    ]
    return "\n".join([*lines, "", *rule_table(rows)])


def rule_table(rows: list[Row]) -> list[str]:
    """Per rule: told to the model, left in the final skills, fixed by the checks, kept."""
    from skillwright.rules.registry import RULES, all_rules

    all_rules()
    totals: dict[str, list[int]] = {}
    for row in rows:
        for index, counts in enumerate((row.told, row.final, row.fixed, row.kept)):
            for code, count in counts.items():
                totals.setdefault(code, [0, 0, 0, 0])[index] += count
    head = f"{'rule':<6} {'name':<34} {'told':>5} {'left':>5} {'fixed':>6} {'kept':>5}"
    lines = [head, "-" * len(head)]
    for code in sorted(totals):
        told, left, fixed, kept = totals[code]
        name = RULES[code].name if code in RULES else "(no code)"
        lines.append(f"{code or '-':<6} {name:<34} {told:>5} {left:>5} {fixed:>6} {kept:>5}")
    return lines


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", action="append", default=[], help="a skill (repeatable)")
    parser.add_argument("--attempts", type=int, default=3, help="answers per method")
    parser.add_argument("--out", type=Path, default=ROOT / "eval-out", help="results folder")
    parser.add_argument("--model", default=None, help="models.toml id (default model)")
    args = parser.parse_args()
    chosen = pairs(set(args.only))
    if not chosen:
        print("error: no pair matches --only", file=sys.stderr)
        return 2
    rows = []
    for index, pair in enumerate(chosen, start=1):
        print(f"[{index}/{len(chosen)}] {pair.robot}/{pair.name}", file=sys.stderr, flush=True)
        rows.append(run(pair, args.out, args.attempts, args.model))
        print(
            f"    -> {'pass' if rows[-1].passed else 'fail'} in {rows[-1].seconds:.1f} s",
            file=sys.stderr,
            flush=True,
        )
    args.out.mkdir(parents=True, exist_ok=True)
    summary = args.out / "summary.json"
    summary.write_text(json.dumps([asdict(r) for r in rows], indent=2) + "\n", encoding="utf-8")
    print(table(rows))
    print(f"results: {args.out} (summary.json, one folder per skill)")
    return 0 if all(not r.failure for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
