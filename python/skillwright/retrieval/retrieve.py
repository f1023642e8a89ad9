"""Stage 4: rank a robot's interfaces for a capability.

Every candidate interface is scored against every facet of the query (the capability,
each input and output, each sentence of each specified state; see
:mod:`skillwright.retrieval.query`): BM25 between their weighted terms and, when an
embedder is given, the cosine between their embeddings (exact, through the Rust index),
mixed with a small dense share.

The hits are then picked greedily. Each pick maximises a mix of the interface's overall
relevance (its facet scores, weighted) and its *coverage gain*: how much better than the
hits already picked it matches each facet. A capability rarely needs two interfaces for the
same piece of evidence, so once ``/cmd_vel`` covers the velocity facets, ``/cmd_vel_nav``
gains nothing, and the sentence of the stopping state that publishes a zero velocity, or
the output that needs a pose in the map frame, can win a place of its own. Interfaces
of a type already picked are discounted too (a global and a local costmap), except the
other scanners of a split view: ``/scan2`` on the corner opposite ``/scan`` sees what
``/scan`` cannot, so it is no alternative to it.

Infrastructure interfaces (logging, parameters, lifecycle plumbing) are left out unless
asked for. ``bench/bench_retrieval.py`` measures every choice made here on two labelled
sets, against the paper's comment-only embedding search.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

from skillwright.cancel import raise_if_cancelled
from skillwright.capability.model import Capability
from skillwright.interfaces.inventory import Interface, Inventory
from skillwright.retrieval.documents import (
    WRITTEN_WEIGHT,
    describe,
    interface_role,
    interface_terms,
    interface_text,
)
from skillwright.retrieval.lexical import BM25
from skillwright.retrieval.query import Facet, Query, build_query
from skillwright.retrieval.semantics import (
    body_of,
    body_of_text,
    conventional,
    directness,
    merges,
    split_view,
    unreached,
)
from skillwright.retrieval.text import split_words
from skillwright.spec.model import SkillSpec

__all__ = ["DENSE_WEIGHT", "Embedder", "Hit", "Ranking", "candidates", "rank_interfaces"]

Embedder = Callable[[Sequence[str]], Sequence[Sequence[float]]]
"""Texts -> unit-length vectors (the local embedding model)."""

DENSE_WEIGHT = 0.1
"""Share of the dense score in the mix when an embedder is given. Small on purpose: with
all-MiniLM-L6-v2 a larger share lowered recall on both labelled sets (see the bench)."""


@dataclass(frozen=True)
class Ranking:
    """How the scores are combined. The defaults measured best on both labelled sets;
    ``bench/bench_retrieval.py`` compares the alternatives."""

    dense_weight: float = DENSE_WEIGHT
    """Share of the dense score when an embedder is given (1.0: dense only)."""
    facets: bool = True
    """Score each facet of the query; ``False`` pools all evidence into one query."""
    fusion: Literal["weighted", "rrf"] = "weighted"
    """``weighted`` mixes scaled scores; ``rrf`` fuses the dense and lexical rankings of
    each facet by reciprocal rank (rank r counts ``1 / (rrf_k + r)``)."""
    rrf_k: int = 60
    """The constant of reciprocal-rank fusion."""
    coverage: float = 0.8
    """Share of the coverage gain (versus overall relevance) when picking each hit;
    0 ranks by relevance alone."""
    scale_floor: float = 0.3
    """Each facet's lexical scores are divided by its best score, but by no less than this
    share of the best score of any facet: a facet with little evidence (a boilerplate
    resetting state) stays weak, while a short facet with a clear match (a stopping
    state's zero velocity command) counts fully. 0 scales each facet alone."""
    duplicate_type_factor: float = 0.0
    """Relevance factor for a candidate whose type an already picked hit has. At 0 only
    evidence no earlier hit covered can pick it: a second velocity command topic (Nav2's
    /cmd_vel_nav beside /cmd_vel) is an alternative to the first, and a small model given
    both drives the wrong one. Measured on the labelled sets: recall@4 the same everywhere
    and one more on the Go2 than at 0.5."""
    split_view_factor: float = 1.0
    """Relevance factor, in place of :attr:`duplicate_type_factor`, for a sensor stream
    whose every picked hit of its type is another part of one split view (see
    :func:`~skillwright.retrieval.semantics.split_view`): the MMO-700's ``/scan2`` after its
    ``/scan``. A second corner's scanner sees what the first does not, so it is no
    alternative to it."""
    neutral_factor: float = 0.8
    """Evidence factor for a candidate whose type :mod:`~skillwright.retrieval.semantics`
    does not know (a direct type counts fully)."""
    auxiliary_factor: float = 0.5
    """Evidence factor for a candidate of an auxiliary type (a composite behaviour, a
    kinematics service, a controller's state); below 1 the direct interfaces win ties."""
    intent_factor: float = 0.5
    """Evidence factor where a state's sentence and a candidate disagree on the direction:
    a sentence that sends ("Set the velocity to zero") and a topic that is read (odometry),
    or one that reads ("Print the current velocity") and a command topic; 1 ignores it."""
    body_factor: float = 0.1
    """Evidence factor for a candidate whose type moves or senses the other part of the
    robot than the capability's text names (an arm action for a base capability). Recall is
    the same from 0.5 down to 0 on every labelled set; at 0.5 nine hits in the first 4 were
    for the other part (the paper's robot's joint trajectory action for navigate-to-point),
    and a small model given one uses it. At 0.1 there are none."""
    written_weight: float = WRITTEN_WEIGHT
    """Weight of a description somebody wrote (a report's, a model's) beside the rules
    engine's (see :mod:`~skillwright.retrieval.documents`)."""
    rules_weight: float = 1.0
    """Weight of the rules engine's description where a written one exists; 0 with a
    ``written_weight`` of 1 lets the written one take its place (how it was before)."""
    unreached_factor: float = 0.1
    """Evidence factor for an interface the live graph shows nobody at the other end of
    (see :func:`~skillwright.retrieval.semantics.unreached`): a command topic no one reads
    drives nothing, however well its name fits."""


@dataclass(frozen=True)
class Hit:
    """One ranked interface."""

    name: str
    kind: str
    type_name: str
    score: float
    """What the pick maximised (relevance mixed with coverage gain); descends with rank."""
    dense: float | None
    """Dense part, facet-weighted, each facet scaled 0..1 over the candidates; None
    without an embedder."""
    lexical: float
    """Lexical (BM25) part, facet-weighted, scaled like :attr:`dense`."""
    reason: str
    """Which capability or spec evidence matched which of the interface's terms."""
    facets: tuple[str, ...] = ()
    """Keys of the facets the hit covered best when it was picked, strongest first."""
    needed: bool | None = None
    """The re-ranking model's verdict (:mod:`~skillwright.retrieval.rerank`); ``None`` when
    it was not asked or gave no usable answer."""
    judgement: str | None = None
    """The re-ranking model's reason for its verdict; ``None`` when it was not asked."""
    twins: tuple[str, ...] = ()
    """Candidates the interface list cannot tell apart from this hit (see :func:`twins`):
    one of them may be the topic the robot actually uses."""


def candidates(inventory: Inventory, include_infrastructure: bool = False) -> list[Interface]:
    """The interfaces retrieval may return."""
    out = []
    for interface in inventory.interfaces:
        if include_infrastructure:
            out.append(interface)
        elif interface.relevance is not None:
            if interface.relevance.relevant:
                out.append(interface)
        elif interface.infrastructure is None:
            out.append(interface)
    return out


def _scaled(values: Sequence[float]) -> list[float]:
    low, high = min(values), max(values)
    if high - low <= 1e-12:
        return [0.0 for _ in values]
    return [(v - low) / (high - low) for v in values]


def _floored(rows: Sequence[Sequence[float]], floor: float) -> list[list[float]]:
    overall = max((max(row) for row in rows), default=0.0)
    out = []
    for row in rows:
        high = max(*row, floor * overall)
        out.append([v / high if high > 0 else 0.0 for v in row])
    return out


def _ranks(values: Sequence[float]) -> list[int]:
    order = sorted(range(len(values)), key=lambda i: -values[i])
    ranks = [0] * len(values)
    for rank, index in enumerate(order, 1):
        ranks[index] = rank
    return ranks


def _cosines(
    embed: Embedder, queries: Sequence[str], texts: Sequence[str], kinds: Sequence[str]
) -> list[list[float]]:
    """Cosine of every query with every text, through the exact Rust index."""
    import numpy as np

    from skillwright.retrieval.index import VectorIndex

    vectors = np.asarray(embed([*queries, *texts]), dtype=np.float32)
    count = len(queries)
    index = VectorIndex(vectors.shape[1])
    ids = np.arange(len(texts), dtype=np.int64)
    index.add(ids, vectors[count:], kind=list(kinds), source="inventory")
    found = index.search_batch(vectors[:count], k=len(texts))
    out = []
    for row_ids, row_scores in zip(found.ids.tolist(), found.scores.tolist(), strict=True):
        row = [0.0] * len(texts)
        for column, score in zip(row_ids, row_scores, strict=True):
            row[column] = float(score)
        out.append(row)
    return out


@dataclass
class _Scores:
    """Per facet (rows) and candidate (columns): lexical, dense and mixed scores."""

    lexical: list[list[float]]
    dense: list[list[float]] | None
    mixed: list[list[float]]


def _facet_scores(
    facets: Sequence[Facet],
    documents: Sequence[dict[str, float]],
    dense_raw: list[list[float]] | None,
    ranking: Ranking,
) -> _Scores:
    lexical_raw = BM25(documents).scores_many([f.terms for f in facets])
    lexical = _floored(lexical_raw, ranking.scale_floor)
    # Cosines of a small model bunch together whatever the text; per facet min-max
    # spreads them over 0..1 so that only the ranking within a facet matters.
    dense = None if dense_raw is None else [_scaled(row) for row in dense_raw]
    if dense is None or dense_raw is None:
        return _Scores(lexical, None, lexical)
    share = ranking.dense_weight
    if ranking.fusion == "rrf":
        mixed = []
        for lexical_row, dense_row in zip(lexical_raw, dense_raw, strict=True):
            by_lexical, by_dense = _ranks(lexical_row), _ranks(dense_row)
            fused = [
                (1.0 - share) / (ranking.rrf_k + x) + share / (ranking.rrf_k + d)
                for x, d in zip(by_lexical, by_dense, strict=True)
            ]
            mixed.append(_scaled(fused))
    else:
        mixed = [
            [share * d + (1.0 - share) * x for d, x in zip(drow, xrow, strict=True)]
            for drow, xrow in zip(dense, lexical, strict=True)
        ]
    return _Scores(lexical, dense, mixed)


def _weighted(rows: Sequence[Sequence[float]], weights: Sequence[float], i: int) -> float:
    return sum(w * row[i] for w, row in zip(weights, rows, strict=True)) / sum(weights)


def _shared_terms(facet: Facet, document: dict[str, float], limit: int = 3) -> list[str]:
    shared = [t for t in facet.terms if t in document]
    shared.sort(key=lambda t: -(facet.terms[t] * document[t]))
    return shared[:limit]


def _reason(
    facets: Sequence[Facet], scores: _Scores, order: list[int], document: dict[str, float], i: int
) -> str:
    """``the stopping state: command, zero, velocity; capability rotate: turn``."""
    parts = []
    for f in order[:2]:
        facet = facets[f]
        terms = _shared_terms(facet, document)
        similar = scores.dense is not None and scores.dense[f][i] > scores.lexical[f][i]
        evidence = ", ".join(terms)
        if similar:
            evidence = f"similar text{'; ' + evidence if evidence else ''}"
        parts.append(f"{facet.label}: {evidence or 'similar text'}")
    return "; ".join(parts) if parts else "no evidence matched"


def _apply_type_semantics(
    mixed: list[list[float]], pool: Sequence[Interface], facets: Sequence[Facet], ranking: Ranking
) -> None:
    """Weighs each facet's scores (in place) by what the candidates' types do
    (:mod:`~skillwright.retrieval.semantics`): the direction of a state's sentence, how
    direct they are and which part of the robot they serve."""
    factors = {
        "direct": 1.0,
        "neutral": ranking.neutral_factor,
        "auxiliary": ranking.auxiliary_factor,
    }
    roles = [interface_role(i) for i in pool]
    if ranking.intent_factor != 1.0:
        for f, facet in enumerate(facets):
            if facet.intent is not None:
                row = mixed[f]
                for i, role in enumerate(roles):
                    if role is not None and role != facet.intent:
                        row[i] *= ranking.intent_factor
    prior = [factors[directness(i)] for i in pool]
    body = body_of_text(facets[0].text) if facets else None
    if body is not None and ranking.body_factor != 1.0:
        other = [(b is not None and b != body) for b in map(body_of, pool)]
        prior = [p * (ranking.body_factor if o else 1.0) for p, o in zip(prior, other, strict=True)]
    if ranking.unreached_factor != 1.0:
        prior = [
            p * (ranking.unreached_factor if unreached(i, role) else 1.0)
            for p, i, role in zip(prior, pool, roles, strict=True)
        ]
    for row in mixed:
        row[:] = [v * p for v, p in zip(row, prior, strict=True)]
    for merged, parts in _merges(pool).items():
        for row in mixed:
            row[merged] = max(row[merged], *(row[p] for p in parts))
    for plain, variants in _variants(pool, roles).items():
        for row in mixed:
            for v in variants:
                row[v] = min(row[v], row[plain])


def _merges(pool: Sequence[Interface]) -> dict[int, list[int]]:
    """Each sensor stream that merges others of its kind (:func:`~skillwright.retrieval.
    semantics.merges`), with the streams of its type beside it in the same namespace: its
    parts. A merged stream sees what each part sees, so it has at least the evidence of the
    best of them; its longer name (the KMR iiwa's ``/scan_concatenated`` beside ``/scan`` and
    ``/scan_2``) costs it a little of every word's weight."""
    merged = {i for i, interface in enumerate(pool) if merges(interface)}
    out: dict[int, list[int]] = {}
    for i in sorted(merged):
        parts = [j for j in _neighbours(pool, i) if j not in merged]
        if parts:
            out[i] = parts
    return out


def _neighbours(pool: Sequence[Interface], i: int) -> list[int]:
    """The other topics of ``pool[i]``'s type in its namespace."""
    namespace = pool[i].name.rsplit("/", 1)[0]
    return [
        j
        for j, other in enumerate(pool)
        if j != i
        and other.kind == "topic"
        and other.type_name == pool[i].type_name
        and other.name.rsplit("/", 1)[0] == namespace
    ]


def _variants(pool: Sequence[Interface], roles: Sequence[str | None]) -> dict[int, list[int]]:
    """Each topic under its type's conventional name (:func:`~skillwright.retrieval.
    semantics.conventional`) that reaches somebody, with the other topics of its type in the
    same namespace: variants of it, which score no more than it does on any facet. Their
    extra words may match the query by chance: the HSR's ``/dynamic_obstacle_map`` matched
    "obstacle" in the mapping spec, its ``/static_distance_ros_map`` the input "distance", and
    both came before SLAM Toolbox's ``/map``."""
    out: dict[int, list[int]] = {}
    for i, interface in enumerate(pool):
        if not conventional(interface) or unreached(interface, roles[i]):
            continue
        variants = _neighbours(pool, i)
        if variants:
            out[i] = variants
    return out


def rank_interfaces(
    inventory: Inventory,
    capability: Capability,
    spec: SkillSpec | None = None,
    *,
    k: int = 4,
    include_infrastructure: bool = False,
    embed: Embedder | None = None,
    ranking: Ranking | None = None,
    cancel: threading.Event | None = None,
) -> list[Hit]:
    """The ``k`` interfaces the capability most likely needs, in the order they were picked.

    ``cancel`` is looked at between the phases (describing, embedding, scoring) and before
    each pick (see :mod:`skillwright.cancel`).
    """
    what = "ranking the interfaces"
    raise_if_cancelled(cancel, what)
    ranking = ranking or Ranking()
    pool = candidates(inventory, include_infrastructure)
    if not pool or k <= 0:
        return []
    query = build_query(capability, spec)
    facets = query.facets if ranking.facets else [_pooled(query)]
    descriptions = [describe(i) for i in pool]
    documents = [
        interface_terms(i, d, ranking.written_weight, ranking.rules_weight)
        for i, d in zip(pool, descriptions, strict=True)
    ]
    dense_raw = None
    if embed is not None:
        raise_if_cancelled(cancel, what)
        texts = [interface_text(i, d) for i, d in zip(pool, descriptions, strict=True)]
        dense_raw = _cosines(embed, [f.text for f in facets], texts, [i.kind for i in pool])
    raise_if_cancelled(cancel, what)
    scores = _facet_scores(facets, documents, dense_raw, ranking)
    _apply_type_semantics(scores.mixed, pool, facets, ranking)
    weights = [f.weight for f in facets]
    total = sum(weights)
    relevance = [_weighted(scores.mixed, weights, i) for i in range(len(pool))]
    covered = [0.0] * len(facets)
    # candidates in relevance order, so that ties go to the more relevant; among equals, a
    # stream that merges the others, then the plainer name: a robot's merged /scan over its
    # half-view /b_scan and /f_scan, whose extra word the query does not know (the MuR620
    # picked /b_scan by the alphabet)
    merged = {i for i, interface in enumerate(pool) if merges(interface)}
    remaining = sorted(
        range(len(pool)),
        key=lambda i: (
            -relevance[i],
            i not in merged,
            len(split_words(pool[i].name)),
            pool[i].name,
        ),
    )
    picked: list[Interface] = []
    hits: list[Hit] = []
    while remaining and len(hits) < k:
        raise_if_cancelled(cancel, what)

        def gains(i: int, covered: list[float] = covered) -> list[float]:
            return [
                w * max(0.0, row[i] - c)
                for w, row, c in zip(weights, scores.mixed, covered, strict=True)
            ]

        def objective(i: int) -> float:
            factor = _type_factor(pool[i], picked, ranking)
            mix = (1.0 - ranking.coverage) * relevance[i] * factor
            return mix + ranking.coverage * sum(gains(i)) / total

        values = [objective(i) for i in remaining]
        position = max(range(len(remaining)), key=lambda p: (values[p], -p))
        best = remaining.pop(position)
        gained = gains(best)
        # explain by the facets it covered; a hit that adds no coverage by its strongest
        order = sorted(
            range(len(facets)),
            key=lambda f: (-gained[f], -weights[f] * scores.mixed[f][best]),
        )
        interface = pool[best]
        hits.append(
            Hit(
                twins=twins(
                    interface,
                    [pool[j] for j in remaining],
                    relevance[best],
                    [relevance[j] for j in remaining],
                ),
                name=interface.name,
                kind=interface.kind,
                type_name=interface.type_name,
                score=values[position],
                dense=None if scores.dense is None else _weighted(scores.dense, weights, best),
                lexical=_weighted(scores.lexical, weights, best),
                reason=_split_view_note(interface, picked)
                + _reason(facets, scores, order, documents[best], best),
                facets=tuple(facets[f].key for f in order[:2] if gained[f] > 1e-9),
            )
        )
        picked.append(interface)
        covered = [max(c, row[best]) for c, row in zip(covered, scores.mixed, strict=True)]
    return hits


TWIN_SHARE = 0.8
"""A candidate is a twin of a hit when it scores at least this share of the hit's relevance."""

_TWIN_FAMILIES = frozenset({"geometry_msgs/msg/Twist", "nav_msgs/msg/Odometry"})
"""The base's command and measurement, where the wrong one of two topics leaves the robot
standing or the skill reading nothing."""


def twins(
    hit: Interface,
    others: Sequence[Interface],
    relevance: float,
    others_relevance: Sequence[float],
) -> tuple[str, ...]:
    """The topics of ``others`` a list without endpoint counts cannot tell apart from
    ``hit``: a base velocity command or odometry topic of the same type, in the same role,
    scoring at least :data:`TWIN_SHARE` of its relevance, both without publisher and
    subscriber counts. A report carries no counts; on a Stretch Nav2's behaviour server
    publishes a ``/cmd_vel`` that nothing reads beside the driver's ``/stretch/cmd_vel``, and
    on a Spot the controller server subscribes to an ``/odom`` that nothing publishes beside
    the driver's ``/odometry``: by name the first of each looks like the one to use, and
    only the user, or the live graph, can say."""
    family = _family(hit.type_name)
    if hit.kind != "topic" or hit.endpoints is not None or family not in _TWIN_FAMILIES:
        return ()
    role = interface_role(hit)
    return tuple(
        other.name
        for other, score in zip(others, others_relevance, strict=True)
        if other.kind == "topic"
        and other.endpoints is None
        and _family(other.type_name) == family
        and interface_role(other) == role
        and score >= TWIN_SHARE * relevance
    )


def twin_notes(hits: Sequence[Hit]) -> list[str]:
    """A warning for each hit with :attr:`Hit.twins`: what to check and how to swap."""
    notes = []
    for hit in hits:
        if not hit.twins:
            continue
        others = ", ".join(hit.twins)
        first = hit.twins[0]
        notes.append(
            f"{hit.name} ({hit.type_name}) was chosen over {others} of the same type by its "
            "name alone: the interface list has no publisher or subscriber counts to tell "
            f"which one the robot uses. Check with `ros2 topic info -v {hit.name}`; if it is "
            f"{first}, generate with --drop {hit.name} --pin {first}"
        )
    return notes


def _type_factor(candidate: Interface, picked: Sequence[Interface], ranking: Ranking) -> float:
    """The relevance factor for the types already picked: a type picked before makes the
    candidate an alternative to that hit, unless each such hit is another part of its split
    view."""
    family = _family(candidate.type_name)
    same = [p for p in picked if _family(p.type_name) == family]
    if not same:
        return 1.0
    if all(split_view(candidate, p) for p in same):
        return ranking.split_view_factor
    return ranking.duplicate_type_factor


def _split_view_note(hit: Interface, picked: Sequence[Interface]) -> str:
    """``another side of the view of /scan; `` for the second scanner of a split view."""
    parts = [p.name for p in picked if split_view(hit, p)]
    return f"another side of the view of {', '.join(parts)}; " if parts else ""


def _family(type_name: str) -> str:
    """A type with the others that carry the same thing: a Twist and a TwistStamped; a pose
    estimate in the map (AMCL's or SLAM Toolbox's ``/pose``) and tf, which gives the same
    map -> base_link pose. Odometry stays apart: it carries the measured velocity too."""
    if type_name in _MAP_POSE:
        return "map pose"
    return type_name.removesuffix("Stamped")


_MAP_POSE = {"geometry_msgs/msg/PoseWithCovarianceStamped", "tf2_msgs/msg/TFMessage"}


def _pooled(query: Query) -> Facet:
    """All evidence as one facet: the single-query ranking, kept for comparison."""
    return Facet(key="query", label="query", text=query.text, terms=query.terms, weight=1.0)
