"""`make eval`: the default local model writes the evaluation's skills; a table of how it went.

Two splits. The **development split** is the nine MR-1 capabilities shipped in
``capabilities/`` against the shipped MR-1 recording and the paper's nine
(``../shared/data/cap2skill``) against the paper robot's raw interface report: the pairs the
pipeline has been made against. The **test split** is ``eval/test/`` (its README): sixteen
pairs written for this purpose and never tuned on, each with its own scenario file, which is
given to the pipeline. Each pair runs through the same pipeline as ``skillwright generate``
(default retrieval, the default model, repairs from the findings of the checks, the sandboxed
run and the MuJoCo simulation); the results go to ``eval-out/<split>/<robot>/<name>/`` (the
record of each skill) and ``eval-out/summary.json`` (the totals per split, then every skill),
and a table is printed: per skill the verdict of the checks, answers and repairs, errors by
rule, tokens and seconds; then, for each split on its own, the totals the targets are judged
by (passed the static checks, ran clean, behaved in every scenario, median seconds); and per
rule (its code) how often the model was told of it, how often it is left in the final skills,
how often the checks fixed it without the model and how many of those fixes the final skills
kept.

Each pair is written in every mode asked for with ``--candidates`` (repeatable; default 1 and
4): 1 is pass@1, the greedy first answer and its repairs; N is best-of-N, N candidate skills
of the first round sampled in one batch and judged by every stage, repair starting from the
best (:mod:`skillwright.generation.candidates`). The modes' totals print side by side, each
with its wall time, and for best-of-N how often the greedy candidate was not the winner.
Results of mode N go to ``eval-out/n<N>/<split>/<robot>/<name>/``.

    python scripts/eval.py [--split dev|test|all] [--only NAME ...] [--attempts N] [--out DIR]
                           [--model ID] [--candidates N ...]

``--only`` takes a pair's name (``strafe``), ``robot/name`` or ``split/robot/name``. This is
slow by nature (a 1.5B model on the CPU); it is not part of ``make test``.
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
TEST_SPLIT = ROOT / "eval" / "test"
RECORDING = ROOT / "capabilities" / "recordings" / "mr1"
SPLITS = ("dev", "test")


@dataclass
class Pair:
    """One capability/specification pair, the robot's interfaces and the split it is in."""

    split: str
    robot: str
    name: str
    capability: Path
    spec: Path
    interfaces: Path
    scenario: Path | None = None
    """The pair's own scenario file; ``None``: the shipped one for the capability, else
    scenarios derived from it (the development split's pairs)."""

    def key(self) -> str:
        """``split/robot/name``, unique over both splits."""
        return f"{self.split}/{self.robot}/{self.name}"


@dataclass
class Row:
    """How one skill went."""

    split: str
    robot: str
    name: str
    candidates: int = 1
    """Candidate skills of the first round (1: pass@1)."""
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
    winner: int | None = None
    """Best-of-N: the winning candidate (0: the greedy one)."""
    distinct: int | None = None
    """Best-of-N: candidates whose files differed from every earlier one."""


def dev_pairs() -> list[Pair]:
    """The development split: the shipped MR-1 pairs, then the paper's (when its data is there)."""
    found = []
    for ttl in sorted((ROOT / "capabilities").glob("*.ttl")):
        spec = ttl.with_name(ttl.stem + ".spec.yaml")
        found.append(Pair("dev", "mr1", ttl.stem, ttl, spec, RECORDING))
    report = SHARED / "interface-reports" / "ros2_system_report.json"
    if SHARED.is_dir():
        for ttl in sorted((SHARED / "capability-models").glob("*.ttl")):
            spec = SHARED / "skill-specs" / (ttl.stem.replace("-", "_") + ".json")
            found.append(Pair("dev", "cap2skill", ttl.stem, ttl, spec, report))
    else:
        print(f"note: {SHARED} not found; only the dev split's MR-1 pairs run", file=sys.stderr)
    return found


def test_pairs() -> list[Pair]:
    """The test split: ``eval/test/<robot>/<name>.ttl`` with its ``.spec.yaml`` and
    ``.scenario.yaml``; the MR-1's against the shipped recording, the others against
    ``eval/test/robots/<robot>.json``."""
    found = []
    for ttl in sorted(TEST_SPLIT.glob("*/*.ttl")):
        robot = ttl.parent.name
        interfaces = RECORDING if robot == "mr1" else TEST_SPLIT / "robots" / f"{robot}.json"
        found.append(
            Pair(
                "test",
                robot,
                ttl.stem,
                ttl,
                ttl.with_name(ttl.stem + ".spec.yaml"),
                interfaces,
                scenario=ttl.with_name(ttl.stem + ".scenario.yaml"),
            )
        )
    return found


def pairs(only: set[str], split: str = "all") -> list[Pair]:
    """The pairs of ``split`` (``dev``, ``test`` or ``all``), those ``only`` names when given."""
    found = []
    if split in ("dev", "all"):
        found += dev_pairs()
    if split in ("test", "all"):
        found += test_pairs()
    if only:
        found = [
            p for p in found if p.name in only or f"{p.robot}/{p.name}" in only or p.key() in only
        ]
    return found


class Progress:
    """Prints each answer of a pair's generation on stderr, and a wait for the model (another
    generation holds it) whenever the place in line changes."""

    def __init__(self) -> None:
        self.place: int | None = None

    def __call__(self, event: object) -> None:
        from skillwright.pipeline.events import AttemptFinished, ModelWaiting

        if isinstance(event, ModelWaiting):
            if event.place != self.place:
                self.place = event.place
                print(f"    {event.message}", file=sys.stderr, flush=True)
        elif isinstance(event, AttemptFinished):
            attempt = event.attempt
            print(
                f"    {attempt.target} #{attempt.number}: {attempt.finish}, "
                f"{attempt.completion_tokens or 0} tokens, {attempt.seconds:.1f} s",
                file=sys.stderr,
                flush=True,
            )


def run(pair: Pair, out: Path, attempts: int, model: str | None, candidates: int = 1) -> Row:
    from skillwright.errors import SkillwrightError
    from skillwright.pipeline import GenerationRequest, run_generation

    row = Row(pair.split, pair.robot, pair.name, candidates)
    on_event = Progress()

    request = GenerationRequest(
        capability=pair.capability,
        spec=pair.spec,
        interfaces=pair.interfaces,
        out_dir=out / f"n{candidates}" / pair.split / pair.robot / pair.name,
        model=model,
        attempts=attempts,
        candidates=candidates,
        scenario=pair.scenario,
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
        # A best-of-N first round's candidates are answers, not repairs.
        row.repairs = sum(a.number > 1 and a.candidate is None for a in answers)
        row.fixes = len(record.model.attempts) - len(answers)
        row.tokens = record.model.completion_tokens or 0
        row.hit_limit = sum(a.finish == "length" for a in record.model.attempts)
        row.looped = sum(a.finish == "repetition" for a in record.model.attempts)
        row.told = dict(Counter(c for a in record.model.attempts for c in a.problem_codes))
        row.fixed = dict(Counter(f.code for a in record.model.attempts for f in a.fixes))
        row.kept = dict(Counter(f.code for a in record.model.attempts if a.chosen for f in a.fixes))
        verdicts = record.model.candidates
        if verdicts:
            row.winner = next((v.index for v in verdicts if v.won), None)
            row.distinct = sum(v.duplicate_of is None for v in verdicts)
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


def behaved(row: Row) -> bool:
    """Whether the skill passed every oracle in every scenario of its simulation."""
    return row.behaved != "-" and not row.behaved.endswith("fail")


def totals(rows: list[Row]) -> dict[str, object]:
    """What the targets are judged by, for one split in one mode."""
    seconds = [r.seconds for r in rows if not r.failure]
    best = [r for r in rows if r.winner is not None]
    return {
        "candidates": rows[0].candidates if rows else 1,
        "skills": len(rows),
        "static_pass": sum(r.passed for r in rows),
        "ran_clean": sum(r.ran == "pass" for r in rows),
        "behaved": sum(behaved(r) for r in rows),
        "median_seconds": round(statistics.median(seconds), 1) if seconds else None,
        "total_seconds": round(sum(seconds), 1),
        "failures": sum(r.failure is not None for r in rows),
        "greedy_not_winner": sum(r.winner != 0 for r in best) if best else None,
        "distinct_candidates": sum(r.distinct or 0 for r in best) if best else None,
    }


def modes(rows: list[Row]) -> list[int]:
    """The modes (candidates per first round) the rows were written in, in order."""
    return sorted({r.candidates for r in rows})


def split_totals(rows: list[Row]) -> dict[str, dict[str, object]]:
    """:func:`totals` for each split and mode that has rows (``dev n1``, ``dev n4``, ...),
    development split first."""
    return {
        f"{split} n{mode}": totals(chosen)
        for split in SPLITS
        for mode in modes(rows)
        if (chosen := [r for r in rows if r.split == split and r.candidates == mode])
    }


def table(rows: list[Row]) -> str:
    head = (
        f"{'split':<5} {'N':>2} {'robot':<10} {'skill':<32} {'checks':<7} "
        f"{'errors by rule':<28} {'run':<5} {'sim':<9} {'won':>3} {'answers':>7} {'repairs':>7} "
        f"{'fixes':>5} {'tokens':>6} {'seconds':>8}"
    )
    lines = [head, "-" * len(head)]
    for row in rows:
        kinds = ", ".join(f"{k} {n}" for k, n in sorted(row.kinds.items())) or "-"
        verdict = "pass" if row.passed else ("ERROR" if row.failure else "fail")
        won = "-" if row.winner is None else str(row.winner)
        lines.append(
            f"{row.split:<5} {row.candidates:>2} {row.robot:<10} {row.name:<32} {verdict:<7} "
            f"{kinds:<28} {row.ran:<5} {row.behaved:<9} {won:>3} {row.answers:>7} "
            f"{row.repairs:>7} {row.fixes:>5} {row.tokens:>6} {row.seconds:>8.1f}"
        )
        if row.failure:
            lines.append(f"{'':<16} {row.failure}")
    lines.append("-" * len(head))
    lines += side_by_side(rows)
    seconds = [r.seconds for r in rows if not r.failure]
    lines += [
        f"answers cut at the token limit: {sum(r.hit_limit for r in rows)}; "
        f"stopped as loops: {sum(r.looped for r in rows)}",
        f"repairs: {sum(r.repairs for r in rows)} of {sum(r.answers for r in rows)} answers; "
        f"fixed by the checks without the model: {sum(r.fixes for r in rows)}",
        f"seconds per skill, both splits: median {statistics.median(seconds):.1f}, "
        f"max {max(seconds):.1f}, total {sum(seconds):.1f}"
        if seconds
        else "seconds per skill: -",
    ]
    return "\n".join([*lines, "", *rule_table(rows)])


def side_by_side(rows: list[Row]) -> list[str]:
    """One line per split and mode: the totals the targets are judged by, the wall time, and
    for best-of-N how often the greedy candidate did not win."""
    head = (
        f"{'split':<5} {'mode':<9} {'skills':>6} {'static':>6} {'ran':>4} {'behaved':>7} "
        f"{'median s':>8} {'wall s':>8}  greedy not the winner"
    )
    lines = [head]
    for key, counts in split_totals(rows).items():
        split, mode = key.split()
        n = int(mode[1:])
        median = counts["median_seconds"]
        spread = (
            "-"
            if counts["greedy_not_winner"] is None
            else f"{counts['greedy_not_winner']} of {counts['skills']} "
            f"({counts['distinct_candidates']} distinct candidates)"
        )
        lines.append(
            f"{split:<5} {'pass@1' if n == 1 else f'best-of-{n}':<9} {counts['skills']:>6} "
            f"{counts['static_pass']:>6} {counts['ran_clean']:>4} {counts['behaved']:>7} "
            f"{'-' if median is None else f'{median:.1f}':>8} {counts['total_seconds']:>8.1f}  "
            f"{spread}"
        )
    return lines


def summary(rows: list[Row]) -> dict[str, object]:
    """The contents of ``summary.json``: the totals per split, then every skill's row."""
    return {"splits": split_totals(rows), "skills": [asdict(r) for r in rows]}


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
    parser.add_argument(
        "--split",
        choices=("dev", "test", "all"),
        default="all",
        help="the development split, the test split (eval/test), or both (default)",
    )
    parser.add_argument(
        "--only",
        action="append",
        default=[],
        help="a pair: name, robot/name or split/robot/name (repeatable)",
    )
    parser.add_argument("--attempts", type=int, default=3, help="answers per method")
    parser.add_argument("--out", type=Path, default=ROOT / "eval-out", help="results folder")
    parser.add_argument("--model", default=None, help="models.toml id (default model)")
    parser.add_argument(
        "--candidates",
        type=int,
        action="append",
        default=[],
        help="a mode: candidate skills of the first round, 1 for pass@1 (repeatable; "
        "default: 1 and 4, side by side)",
    )
    args = parser.parse_args()
    chosen = pairs(set(args.only), args.split)
    if not chosen:
        print(f"error: no pair of the {args.split} split(s) matches --only", file=sys.stderr)
        return 2
    counts = sorted(set(args.candidates)) or [1, 4]
    if any(n < 1 or n > 8 for n in counts):
        print("error: --candidates takes 1 to 8", file=sys.stderr)
        return 2
    rows = []
    jobs = [(n, pair) for n in counts for pair in chosen]
    for index, (n, pair) in enumerate(jobs, start=1):
        mode = "pass@1" if n == 1 else f"best-of-{n}"
        print(f"[{index}/{len(jobs)}] {pair.key()} ({mode})", file=sys.stderr, flush=True)
        rows.append(run(pair, args.out, args.attempts, args.model, n))
        print(
            f"    -> {'pass' if rows[-1].passed else 'fail'} in {rows[-1].seconds:.1f} s",
            file=sys.stderr,
            flush=True,
        )
    args.out.mkdir(parents=True, exist_ok=True)
    target = args.out / "summary.json"
    target.write_text(json.dumps(summary(rows), indent=2) + "\n", encoding="utf-8")
    print(table(rows))
    print(f"results: {args.out} (summary.json, one folder per skill under n<N>/<split>/<robot>/)")
    return 0 if all(not r.failure for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
