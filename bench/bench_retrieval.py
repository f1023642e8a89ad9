"""Retrieval quality and speed: recall@1/4/8 per method on the labelled sets, and latency.

The alternative named for comparison is the paper's method: embed only the capability's
``rdfs:comment`` and rank the interfaces by the cosine with their descriptions (the
paper's LLM-written ones in the 33-interface setting, our rules engine's elsewhere), here
with the local all-MiniLM-L6-v2 instead of OpenAI's text-embedding-3-large.

Labelled sets (``tests/retrieval/labels``): the MR-1 (our nine capabilities and its
recording, 41 candidates, 22 needs) and the paper's robot (the paper's nine capability
models and specs against its full interface report, 107 interfaces of which our rules
keep 37 after leaving out infrastructure, and against the 33 the paper's filter kept; 18 needs),
and nineteen robots written down from public sources (``tests/retrieval/robots``: a TurtleBot 4,
a TIAGo, a UR5e, a Go2, a ROSbot XL with an arm and fourteen more, see
``tests/retrieval/labelled.py``) running the paper's capabilities, shown with their types' fields
as a live graph shows them; one more table gives their recall with type names only. A need is
an interface a correct skill needs, or a group of alternatives of which one is
enough. "fit@4" counts the needs that k=4 can hold at all (the MR-1's mapping needs 6).

Latency is per capability query over the MR-1 inventory: *warm* with every embedding in
the cache (a second run over the same inventory and capability), *cold* with no cache
(everything embedded); model loading is reported separately. Each is the median of
several runs, best of three rounds. Run: ``python bench/bench_retrieval.py``; needs
``../shared`` beside the repository for the paper's robot.

``--rerank MODEL`` measures the second stage instead (:mod:`skillwright.retrieval.rerank`):
the local generation model MODEL judges the default ranking's first 8 hits for every
capability of ``--sets`` (default: the HSR, the KMR iiwa, the Go2 and the Spot, the sets with
the most needs found at k=8 but not at k=4, which is all it can win), and recall@1/4/8
with and without it is printed with the seconds per capability, cold (an empty answer cache)
and cached (the same questions again). It needs the model's file installed, so ``make bench``
does not run it.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from tests.retrieval.labelled import LabelledSet, Ranker

    from skillwright.capability import Capability
    from skillwright.interfaces.inventory import Inventory
    from skillwright.retrieval.retrieve import Hit, Ranking
    from skillwright.spec import SkillSpec

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the labelled sets live with the tests

ROUNDS = 3


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rerank", metavar="MODEL", help="measure re-ranking with this model")
    parser.add_argument(
        "--sets",
        default="hsr,kmriiwa,go2,spot",
        help="labelled sets for --rerank (comma-separated)",
    )
    args = parser.parse_args(argv)
    os.environ["SKILLWRIGHT_CACHE_DIR"] = tempfile.mkdtemp(prefix="skillwright-bench-")
    if args.rerank:
        return rerank_comparison(args.rerank, args.sets.split(","))
    from tests.retrieval.labelled import SETS, load_set

    from skillwright.llm.config import load_registry
    from skillwright.llm.embeddings import load_embedder
    from skillwright.retrieval.retrieve import Ranking, rank_interfaces

    shared = (ROOT.parent / "shared" / "data").is_dir()
    sets = [s for s in SETS if shared or s == "mr1"]
    if not shared:
        print("note: ../shared not found; the paper's robot is skipped")

    started = time.perf_counter()
    embedder = load_embedder(load_registry())
    load_seconds = time.perf_counter() - started
    embed = embedder.embed

    def ours(ranking: Ranking, dense: bool) -> Ranker:
        def rank(inventory: Inventory, cap: Capability, spec: SkillSpec, k: int) -> list[str]:
            hits = rank_interfaces(
                inventory, cap, spec, k=k, embed=embed if dense else None, ranking=ranking
            )
            return [h.name for h in hits]

        return rank

    def no_spec(inventory: Inventory, cap: Capability, spec: SkillSpec, k: int) -> list[str]:
        return [h.name for h in rank_interfaces(inventory, cap, None, k=k)]

    def paper(inventory: Inventory, cap: Capability, spec: SkillSpec, k: int) -> list[str]:
        return paper_ranking(embed, inventory, cap, k)

    pooled = Ranking(facets=False, coverage=0.0)
    dense_pooled = Ranking(dense_weight=1.0, facets=False, coverage=0.0)
    hybrid_pooled = Ranking(dense_weight=0.3, facets=False, coverage=0.0)
    rrf = Ranking(dense_weight=0.5, fusion="rrf")
    words_only = Ranking(
        neutral_factor=1.0, auxiliary_factor=1.0, intent_factor=1.0, body_factor=1.0
    )
    one_view = Ranking(split_view_factor=0.0)
    methods: list[tuple[str, Ranker]] = [
        ("paper: rdfs:comment only, dense (alternative)", paper),
        ("dense, pooled query (all evidence, one text)", ours(dense_pooled, True)),
        ("dense, facets + coverage", ours(Ranking(dense_weight=1.0), True)),
        ("lexical, pooled query, by relevance", ours(pooled, False)),
        ("hybrid 0.3, pooled query, by relevance", ours(hybrid_pooled, True)),
        ("hybrid RRF 0.5, facets + coverage", ours(rrf, True)),
        ("lexical, words only (no type semantics)", ours(words_only, False)),
        ("hybrid 0.1, words only (no type semantics)", ours(words_only, True)),
        ("lexical + type semantics (default)", ours(Ranking(), False)),
        ("the same, a split view's scanners alternatives", ours(one_view, False)),
        ("hybrid 0.1 + type semantics (--dense)", ours(Ranking(), True)),
        ("lexical default, capability only (no spec)", no_spec),
    ]

    labelled = {name: load_set(name) for name in sets}
    print_recall(labelled, methods)
    print_fields_or_names(ours(Ranking(), False))
    print_written_descriptions(ours)
    print_other_body_hits(labelled, ours)
    leave_one_robot_out(labelled, ours)

    print(
        f"\nlatency per capability query, MR-1 inventory ({embedder.encoder.model_id} "
        f"loaded in {load_seconds:.1f} s)"
    )
    mr1 = labelled["mr1"]
    cases = mr1.cases

    def per_query(rank: Ranker) -> Callable[[], None]:
        def run() -> None:
            for case in cases:
                rank(mr1.inventory, case.capability, case.spec, 4)

        return run

    timings = [
        ("paper: rdfs:comment only (alternative)", paper),
        ("lexical, facets + coverage (default)", ours(Ranking(), False)),
        ("hybrid, facets + coverage (--dense)", ours(Ranking(), True)),
    ]
    warm = [best_median(per_query(rank), len(cases)) for _, rank in timings]
    cache, embedder.cache = embedder.cache, None
    cold = [best_median(per_query(rank), len(cases), repeats=1) for _, rank in timings]
    embedder.cache = cache
    print(f"{'method':48}{'warm':>12}{'cold':>12}{'warm vs paper':>16}")
    for (label, _), w, c in zip(timings, warm, cold, strict=True):
        print(f"{label:48}{w * 1e3:>9.2f} ms{c * 1e3:>9.1f} ms{warm[0] / w:>15.2f}x")
    return 0


def rerank_comparison(model_id: str, sets: Sequence[str]) -> int:
    """Recall@1/4/8 of the default ranking with and without the model's second stage, and
    its seconds per capability, cold and cached (the answer cache starts empty)."""
    from tests.retrieval.labelled import SETS, load_set

    from skillwright.errors import SkillwrightError
    from skillwright.llm import load_generator
    from skillwright.llm.config import load_registry
    from skillwright.retrieval.rerank import DEPTH, Reranker, default_cache
    from skillwright.retrieval.retrieve import rank_interfaces

    unknown = [name for name in sets if name not in SETS]
    if unknown:
        print(f"unknown set(s) {', '.join(unknown)}; choose from {', '.join(SETS)}")
        return 2
    registry = load_registry()
    started = time.perf_counter()
    try:
        generator = load_generator(registry, model_id)
    except SkillwrightError as error:  # an unknown id or a model not installed
        print(f"error: {error}")
        return 2
    load_seconds = time.perf_counter() - started
    reranker = Reranker(generator, cache=default_cache())
    first: dict[tuple[str, str], list[Hit]] = {}
    second: dict[tuple[str, str], list[Hit]] = {}
    cold: list[float] = []
    cold_cpu: list[float] = []
    cached: list[float] = []
    labelled = {name: load_set(name) for name in sets}
    for name, labelled_set in labelled.items():
        for case in labelled_set.cases:
            hits = rank_interfaces(labelled_set.inventory, case.capability, case.spec, k=DEPTH)
            first[(name, case.capability.iri)] = hits
            for spent in (cold, cached):
                cpu = time.process_time()
                result = reranker.rerank(labelled_set.inventory, case.capability, case.spec, hits)
                spent.append(result.seconds)
                if spent is cold:
                    cold_cpu.append(time.process_time() - cpu)
            second[(name, case.capability.iri)] = result.hits
            found = [
                "/".join(str(_found(case.needs, table[:k])) for k in (1, 4, 8))
                for table in (hits, result.hits)
            ]
            print(
                f"\n{name} {case.name}: found @1/4/8 {found[0]} -> {found[1]} of "
                f"{len(case.needs)} (cold {cold[-1]:.1f} s, {cold_cpu[-1]:.1f} s CPU; "
                f"{result.summary()}); needs: {case.needs}",
                flush=True,
            )
            for hit in result.hits:
                verdict = {True: "yes", False: "no ", None: " - "}[hit.needed]
                print(f"  {verdict} {hit.name}: {hit.judgement}")
            for note in result.notes:
                print(f"  note: {note}")
    generator.close()

    def from_table(table: dict[tuple[str, str], list[Hit]], name: str) -> Ranker:
        def rank(inventory: Inventory, cap: Capability, spec: SkillSpec, k: int) -> list[str]:
            return [h.name for h in table[(name, cap.iri)][:k]]

        return rank

    print("\nrecall: needs found @1 / @4 / @8 of all needs")
    print(f"{'method':48}" + "".join(f"{name:>12}" for name in sets))
    print(f"{'needs':48}" + "".join(f"{labelled[n].need_count:>12}" for n in sets))
    for label, table in (
        ("lexical default (first stage)", first),
        (f"lexical default + re-rank by {model_id}", second),
    ):
        cells = [recall_cell(labelled[name], from_table(table, name)) for name in sets]
        print(f"{label:48}" + "".join(f"{c:>12}" for c in cells))
    print(
        f"\nre-ranking {DEPTH} candidates per capability, {len(cold)} capabilities "
        f"({model_id} loaded in {load_seconds:.1f} s, {os.cpu_count()} cores): "
        f"cold median {statistics.median(cold):.1f} s wall (min {min(cold):.1f}, max "
        f"{max(cold):.1f}), {statistics.median(cold_cpu):.1f} s CPU; cached median "
        f"{statistics.median(cached) * 1e3:.1f} ms; load average "
        f"{os.getloadavg()[0]:.1f} at the end (other work on the machine slows the wall time)"
    )
    return 0


def _found(needs: Sequence[tuple[str, ...]], hits: Sequence[Hit]) -> int:
    names = {h.name for h in hits}
    return sum(any(n in names for n in need) for need in needs)


def _none(inventory: Inventory, cap: Capability, spec: SkillSpec, k: int) -> list[str]:
    return []


def recall_cell(labelled: LabelledSet, rank: Ranker) -> str:
    """``@1/@4/@8`` found, from one ranking of 8 (the greedy picks do not depend on k)."""
    from tests.retrieval.labelled import measure

    ranked: dict[str, list[str]] = {}

    def once(inventory: Inventory, cap: Capability, spec: SkillSpec, k: int) -> list[str]:
        if cap.iri not in ranked:
            ranked[cap.iri] = list(rank(inventory, cap, spec, 8))
        return ranked[cap.iri][:k]

    return "/".join(f"{measure(labelled, once, k).found:>2}" for k in (1, 4, 8))


def print_recall(labelled: dict[str, LabelledSet], methods: list[tuple[str, Ranker]]) -> None:
    """Recall@1/4/8 of each method on each labelled set, one row per method."""
    from tests.retrieval.labelled import measure

    print("\nrecall: needs found @1 / @4 / @8 of all needs (fit = needs k=4 can hold)")
    print(f"{'method':48}" + "".join(f"{name:>19}" for name in labelled))
    totals = "".join(
        f"{f'{s.need_count} (fit {measure(s, _none, 4).attainable})':>19}"
        for s in labelled.values()
    )
    print(f"{'needs':48}{totals}")
    for label, rank in methods:
        cells = [recall_cell(s, rank) for s in labelled.values()]
        print(f"{label:48}" + "".join(f"{c:>19}" for c in cells))


def print_fields_or_names(rank: Ranker) -> None:
    """The default's recall on each written robot with its types' fields, as a live graph
    shows them; with their names only, as a recording without schemas does; and read from
    the reference tool's report of the graph (no endpoint counts)."""
    from tests.retrieval.labelled import WRITTEN, load_set

    print("\nwritten robots, lexical default @1/4/8: with the fields of their types (a live")
    print("graph; the tables above), with type names only (a recording without schemas) and")
    print("read from the reference tool's report of the graph (no endpoint counts)")
    print(f"{'robot':14}{'fields':>12}{'names only':>12}{'report':>12}")
    forms: tuple[dict[str, bool], ...] = ({}, {"live": False}, {"report": True})
    totals = [[0, 0, 0] for _ in forms]
    for name in WRITTEN:
        cells = []
        for form, total in zip(forms, totals, strict=True):
            cell = recall_cell(load_set(name, **form), rank)
            for index, found in enumerate(cell.split("/")):
                total[index] += int(found)
            cells.append(cell.replace(" ", ""))
        print(f"{name:14}" + "".join(f"{c:>12}" for c in cells))
    sums = ["/".join(str(n) for n in total) for total in totals]
    print(f"{'all':14}" + "".join(f"{c:>12}" for c in sums))


def print_written_descriptions(ours: Callable[[Ranking, bool], Ranker]) -> None:
    """Recall on the robots the local model described (``bench/describe_robots.py``), as a
    report with descriptions would carry them: the written text in place of the rules'
    description (before), and beside it at several weights."""
    from tests.retrieval.labelled import described_robots, load_set

    from skillwright.retrieval.documents import WRITTEN_WEIGHT
    from skillwright.retrieval.retrieve import Ranking

    names = described_robots()
    if not names:
        return
    print("\nwritten robots described by the local model (a report with descriptions), lexical")
    print(
        f"@1/4/8, by the weight of the written words beside the rules' (default {WRITTEN_WEIGHT:g})"
    )
    replaced = Ranking(written_weight=1.0, rules_weight=0.0)
    settings = [
        (f"no written text (what weight {WRITTEN_WEIGHT:g} scores)", False, Ranking()),
        ("written text in place of the rules' (before)", True, replaced),
        *(
            (f"written text beside the rules' at {w:g}", True, Ranking(written_weight=w))
            for w in (0.1, 0.25, 0.5, 1.0)
        ),
    ]
    print(f"{'method':48}" + "".join(f"{n:>12}" for n in names))
    for label, described, ranking in settings:
        cells = [
            recall_cell(load_set(n, described=described), ours(ranking, False)).replace(" ", "")
            for n in names
        ]
        print(f"{label:48}" + "".join(f"{c:>12}" for c in cells))


def print_other_body_hits(
    labelled: dict[str, LabelledSet], ours: Callable[[Ranking, bool], Ranker]
) -> None:
    """The count of :func:`other_body_hits` per set for the default and its neighbours."""
    from skillwright.retrieval.retrieve import Ranking

    print("\nhits among the first 4 that serve the other part of the robot (an arm interface")
    print("for a base capability, or the reverse); a small model given one uses it")
    methods = [
        ("lexical + type semantics (default)", ours(Ranking(), False)),
        ("the same with body_factor 0.5", ours(Ranking(body_factor=0.5), False)),
        ("hybrid 0.1 + type semantics (--dense)", ours(Ranking(), True)),
    ]
    for label, rank in methods:
        cells = [str(other_body_hits(labelled[name], rank)) for name in labelled]
        print(f"{label:48}" + "".join(f"{c:>19}" for c in cells))


def other_body_hits(labelled: LabelledSet, rank: Ranker) -> int:
    """Hits among the first 4 whose type serves the other part of the robot than the
    capability's text names (:mod:`skillwright.retrieval.semantics`)."""
    from skillwright.retrieval.query import build_query
    from skillwright.retrieval.semantics import body_of, body_of_text

    types = {i.name: i for i in labelled.inventory.interfaces}
    count = 0
    for case in labelled.cases:
        body = body_of_text(build_query(case.capability, case.spec).facets[0].text)
        hits = rank(labelled.inventory, case.capability, case.spec, 4)[:4]
        count += sum(1 for h in hits if body is not None and body_of(types[h]) not in {None, body})
    return count


GRID = {
    "neutral_factor": (1.0, 0.8),
    "auxiliary_factor": (1.0, 0.5, 0.3),
    "intent_factor": (1.0, 0.5),
    "body_factor": (1.0, 0.5, 0.1),
    "split_view_factor": (1.0, 0.0),
}
"""The type-semantics settings leave-one-robot-out chooses among (lexical ranking)."""


def leave_one_robot_out(
    labelled: dict[str, LabelledSet], ours: Callable[[Ranking, bool], Ranker]
) -> None:
    """For each robot: the grid point with the most needs found @4 on the *other* robots
    (ties to the default), scored on the robot left out, next to the default's score."""
    import itertools

    from tests.retrieval.labelled import ROBOTS, measure

    from skillwright.retrieval.retrieve import Ranking

    points = [dict(zip(GRID, values, strict=True)) for values in itertools.product(*GRID.values())]
    default = Ranking()
    default_point = points.index({key: getattr(default, key) for key in GRID})
    words_only = points.index({key: values[0] for key, values in GRID.items()})
    found: dict[tuple[int, str], int] = {}
    started = time.perf_counter()
    for p, point in enumerate(points):
        rank = ours(Ranking(**point), False)  # type: ignore[arg-type]
        for name, labelled_set in labelled.items():
            found[(p, name)] = measure(labelled_set, rank, 4).found
    seconds = time.perf_counter() - started
    print(
        f"\nleave-one-robot-out, lexical, recall@4 ({len(points)} settings x {len(labelled)} "
        f"sets in {seconds:.0f} s): chosen on the other robots, scored on the one left out"
    )
    print(f"{'robot left out':16}{'held out':>10}{'default':>10}{'words only':>12}  chosen")
    for robot in sorted({ROBOTS[name] for name in labelled}):
        held = [n for n in labelled if ROBOTS[n] == robot]
        others = [n for n in labelled if ROBOTS[n] != robot]

        def on_others(p: int, others: list[str] = others) -> tuple[int, bool]:
            return (sum(found[(p, n)] for n in others), p == default_point)

        best = max(range(len(points)), key=on_others)
        total = sum(labelled[n].need_count for n in held)

        def score(p: int, held: list[str] = held, total: int = total) -> str:
            return f"{sum(found[(p, n)] for n in held)}/{total}"

        chosen = ", ".join(f"{k}={v}" for k, v in points[best].items())
        cells = f"{score(best):>10}{score(default_point):>10}{score(words_only):>12}"
        print(f"{robot:16}{cells}  {chosen}")


def paper_ranking(
    embed: Callable[[Sequence[str]], Any], inventory: Inventory, cap: Capability, k: int
) -> list[str]:
    """The paper's retrieval: the comment's embedding against the descriptions'."""
    import numpy as np

    from skillwright.retrieval.documents import describe
    from skillwright.retrieval.retrieve import candidates

    pool = candidates(inventory)
    texts = [describe(i).text() for i in pool]
    vectors = np.asarray(embed([cap.comment or cap.label, *texts]), dtype=np.float32)
    scores = vectors[1:] @ vectors[0]
    order = sorted(range(len(pool)), key=lambda i: (-float(scores[i]), pool[i].name))
    return [pool[i].name for i in order[:k]]


def best_median(call: Callable[[], None], queries: int, repeats: int = 5) -> float:
    """Seconds per query: the median over ``repeats`` runs, best of ``ROUNDS`` rounds."""
    call()  # warm up (and fill the embedding cache)
    best = float("inf")
    for _ in range(ROUNDS):
        spent = []
        for _ in range(repeats):
            start = time.perf_counter()
            call()
            spent.append(time.perf_counter() - start)
        best = min(best, statistics.median(spent))
    return best / queries


if __name__ == "__main__":
    sys.exit(main())
