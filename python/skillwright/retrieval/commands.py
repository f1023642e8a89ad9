"""``skillwright retrieve``: the interfaces of a robot a capability needs, ranked.

Only click is imported at module level (``skillwright --help`` imports this module); the
capability reader, the inventory, the ranking and the embedding model load inside the
command, the embedding model only when dense scoring is on.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING

import click

from skillwright.cli_options import (
    capability_options,
    dense_option,
    interfaces_option,
    spec_option,
)

if TYPE_CHECKING:
    from skillwright.capability.model import Capability
    from skillwright.interfaces.inventory import Inventory
    from skillwright.retrieval.rerank import Reranking
    from skillwright.retrieval.retrieve import Embedder, Hit
    from skillwright.spec.model import SkillSpec

__all__ = ["retrieve"]


@click.command("retrieve")
@capability_options
@spec_option(required=False, extra_help=" Its state texts sharpen the ranking.")
@interfaces_option(required=True)
@click.option(
    "-k",
    "k",
    type=click.IntRange(min=1),
    default=4,
    show_default=True,
    help="How many interfaces to return.",
)
@click.option(
    "--all",
    "include_infrastructure",
    is_flag=True,
    help="Rank infrastructure interfaces too (logging, parameters, lifecycle, ...).",
)
@dense_option
@click.option(
    "--rerank",
    is_flag=True,
    help="Have the local generation model judge the best 8 candidates (needed or not, with "
    "a reason) and put the needed ones first. Answers are cached.",
)
@click.option(
    "--model",
    "model_id",
    metavar="ID",
    help="The generation model that re-ranks (default: as for `skillwright generate`).",
)
@click.option(
    "--models",
    "models_file",
    type=click.Path(path_type=Path, dir_okay=False),
    help="A models.toml naming the embedding model (default: as for `skillwright models`).",
)
@click.option("--json", "as_json", is_flag=True, help="Print the ranking as JSON.")
def retrieve(
    capability_file: Path,
    capability_iri: str | None,
    ontology_files: tuple[Path, ...],
    spec_file: Path | None,
    source: Path,
    k: int,
    include_infrastructure: bool,
    dense: bool,
    rerank: bool,
    model_id: str | None,
    models_file: Path | None,
    as_json: bool,
) -> None:
    """Rank the robot's interfaces for a capability and show the best K, with reasons.

    Each hit has a combined score, its dense (embedding) and lexical (BM25) parts, each
    scaled to 0..1 over the candidates, and a reason naming the capability or spec
    evidence that matched. Infrastructure interfaces are left out unless --all is given.
    With --rerank the local generation model judges the best candidates and its reasons
    are shown.
    """
    from skillwright.capability.reader import load_capability
    from skillwright.console import err_console, warn
    from skillwright.errors import InvalidArgumentError
    from skillwright.interfaces.load import load_inventory, read_warnings
    from skillwright.retrieval.rerank import DEPTH
    from skillwright.retrieval.retrieve import candidates, rank_interfaces, twin_notes
    from skillwright.spec.loader import load_spec

    capability = load_capability(
        capability_file, capability_iri=capability_iri, ontologies=ontology_files
    ).capability
    spec = load_spec(spec_file) if spec_file is not None else None
    inventory = load_inventory(source)
    warn(read_warnings(inventory))
    pool = candidates(inventory, include_infrastructure)
    if not pool:
        hint = "" if include_infrastructure else "; --all ranks infrastructure interfaces too"
        raise InvalidArgumentError(
            f"interface source {source}: none of its {len(inventory.interfaces)} interface(s) "
            f"is a candidate{hint}"
        )
    if model_id is not None and not rerank:
        raise InvalidArgumentError("--model names the re-ranking model; add --rerank")
    embed, embedding_id = _embedder(models_file, len(pool)) if dense else (None, None)
    started = time.perf_counter()
    hits = rank_interfaces(
        inventory,
        capability,
        spec,
        k=max(k, DEPTH) if rerank else k,
        include_infrastructure=include_infrastructure,
        embed=embed,
    )
    elapsed = time.perf_counter() - started
    err_console().print(
        f"ranked {len(pool)} interface(s) in {elapsed * 1e3:.0f} ms", highlight=False
    )
    method = "lexical" if embedding_id is None else f"hybrid, dense part by {embedding_id}"
    reranking = None
    if rerank:
        reranking = _rerank(models_file, model_id, inventory, capability, spec, hits)
        hits = reranking.hits
        method += f"; re-ranked by {reranking.model_id}"
    hits = hits[:k]
    if as_json:
        _print_json(
            capability.iri,
            spec_file,
            source,
            inventory,
            len(pool),
            k,
            embedding_id,
            hits,
            reranking,
        )
    else:
        _print_table(inventory, len(pool), include_infrastructure, method, hits)
    warn(twin_notes(hits))


def _rerank(
    models_file: Path | None,
    model_id: str | None,
    inventory: Inventory,
    capability: Capability,
    spec: SkillSpec | None,
    hits: list[Hit],
) -> Reranking:
    """The second stage with the generation model, its progress on stderr."""
    from skillwright.console import err_console
    from skillwright.llm import load_generator
    from skillwright.llm.config import load_registry
    from skillwright.retrieval.rerank import Reranker, default_cache

    registry = load_registry(models_file)
    entry = registry.generation_model(model_id)
    console = err_console()
    console.print(f"loading generation model {entry.id} to re-rank ...", highlight=False)
    generator = load_generator(registry, entry.id)
    try:

        def progress(done: int, total: int, name: str) -> None:
            console.print(f"judged {done}/{total}: {name}", highlight=False)

        reranking = Reranker(generator, cache=default_cache()).rerank(
            inventory, capability, spec, hits, progress=progress
        )
    finally:
        generator.close()
    for note in reranking.notes:
        console.print(f"warning: {note}", highlight=False)
    console.print(f"re-ranked: {reranking.summary()}", highlight=False)
    return reranking


def _embedder(models_file: Path | None, count: int) -> tuple[Embedder, str]:
    """The configured embedding model, announced on stderr (loading it takes a moment)."""
    from skillwright.console import err_console
    from skillwright.errors import ModelError
    from skillwright.llm.config import load_registry
    from skillwright.llm.embeddings import load_embedder

    registry = load_registry(models_file)
    entry = registry.embedding_model(None)
    console = err_console()
    console.print(f"loading embedding model {entry.id} ...", highlight=False)
    started = time.perf_counter()
    try:
        embedder = load_embedder(registry, entry.id)
    except ModelError as error:
        raise type(error)(f"{error}; or rank without it (leave out --dense)") from None
    console.print(
        f"loaded {entry.id} in {time.perf_counter() - started:.1f} s; "
        f"embedding {count} interface text(s) (cached ones are reused)",
        highlight=False,
    )
    return embedder.embed, entry.id  # type: ignore[return-value]


def _print_table(
    inventory: Inventory, pool: int, include_infrastructure: bool, method: str, hits: list[Hit]
) -> None:
    from rich.markup import escape
    from rich.table import Table

    from skillwright.console import out_console

    table = Table(show_edge=False, pad_edge=False)
    table.add_column("#", justify="right")
    table.add_column("Name", overflow="fold")
    table.add_column("Kind")
    table.add_column("Type", overflow="fold")
    table.add_column("Score", justify="right")
    table.add_column("Dense", justify="right")
    table.add_column("Lexical", justify="right")
    table.add_column("Reason", overflow="fold")
    judged = any(hit.judgement is not None for hit in hits)
    if judged:
        table.add_column("Needed")
        table.add_column("Model's reason", overflow="fold")
    for rank, hit in enumerate(hits, 1):
        row = [
            str(rank),
            escape(hit.name),
            hit.kind,
            escape(hit.type_name),
            f"{hit.score:.3f}",
            "-" if hit.dense is None else f"{hit.dense:.3f}",
            f"{hit.lexical:.3f}",
            escape(hit.reason),
        ]
        if judged:
            verdict = {True: "yes", False: "no", None: "-"}[hit.needed]
            row += [verdict, escape(hit.judgement or "")]
        table.add_row(*row)
    console = out_console()
    if console.is_terminal:
        console.print(table)
    else:
        # Piped output is not cut to 80 columns: names, types and reasons stay whole.
        from rich.measure import Measurement

        saved = console.width
        widest = Measurement.get(console, console.options.update_width(10_000), table).maximum
        console.width = max(saved, widest)
        try:
            console.print(table)
        finally:
            console.width = saved
    left_out = len(inventory.interfaces) - pool
    scope = (
        f"{pool} candidate(s)"
        if include_infrastructure or not left_out
        else f"{pool} candidate(s); {left_out} infrastructure interface(s) left out (--all)"
    )
    console.print(f"{len(hits)} of {scope}; ranking: {method}", soft_wrap=True, highlight=False)


def _print_json(
    capability_iri: str,
    spec_file: Path | None,
    source: Path,
    inventory: Inventory,
    pool: int,
    k: int,
    model_id: str | None,
    hits: list[Hit],
    reranking: Reranking | None,
) -> None:
    from dataclasses import asdict

    document = {
        "capability": capability_iri,
        "spec": None if spec_file is None else str(spec_file),
        "interfaces": str(source),
        "resource": inventory.resource.name,
        "candidates": pool,
        "k": k,
        "method": "lexical" if model_id is None else "hybrid",
        "embedding_model": model_id,
        "rerank": None
        if reranking is None
        else {
            "model": reranking.model_id,
            "judged": len(reranking.judgements),
            "asked": reranking.asked,
            "cached": reranking.cached,
            "seconds": round(reranking.seconds, 3),
            "notes": reranking.notes,
        },
        "hits": [asdict(h) for h in hits],
    }
    sys.stdout.write(json.dumps(document, indent=2) + "\n")
