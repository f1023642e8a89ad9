"""Benchmark of the local models layer (run by ``make bench``; never part of the tests).

1. Time to first token for a chat prompt with a ~4k-token fixed prefix: evaluated from scratch
   vs. restored from the on-disk prefix cache (a new model instance, as a new process would
   be) vs. still in memory. Target: restored <= 10 % of fresh.
2. Embedding throughput for 1 000 interface descriptions: cold (encoder) vs. cached (SQLite).

The generation model is the default of models.toml when its file is present (or ``--model ID``);
otherwise a synthetic random-weight llama GGUF of realistic per-token cost is built (the
test-fixture writer, bigger dimensions). Its numbers say how the cache scales, not how a
particular model answers.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO_ROOT))  # for tests.fixtures (the synthetic model writer)

from skillwright.errors import ModelError  # noqa: E402
from skillwright.llm.base import ChatMessage, GenerationOptions, Prompt  # noqa: E402
from skillwright.llm.config import LlamaCppModel, Registry, load_registry  # noqa: E402
from skillwright.llm.embeddings import Embedder, EmbeddingCache, load_encoder  # noqa: E402
from skillwright.llm.llamacpp import LlamaCppGenerator, load_llamacpp  # noqa: E402

PREFIX_TOKENS = 4000


def _synthetic_registry(folder: Path) -> Registry:
    from tests.fixtures.tiny_gguf import TinyLlamaSpec, write_tiny_llama

    # Shaped like a small real model (grouped-query attention, wide feed-forward, F16), so
    # compute per token and the size of the saved state relate roughly as they do for real ones.
    spec = TinyLlamaSpec(
        n_embd=1024, n_head=16, n_head_kv=2, n_ff=2816, n_layer=8, seed=7, half=True
    )
    model = write_tiny_llama(folder / "synthetic.gguf", spec)
    models = folder / "models.toml"
    models.write_text(
        f'[defaults]\ngeneration = "synthetic"\n[[llm]]\nid = "synthetic"\n'
        f'file = "{model.as_posix()}"\ncontext_length = 8192\n'
    )
    return load_registry(models)


def _prompt(generator: LlamaCppGenerator, question: str) -> Prompt:
    """A skill-style prompt whose system + few-shot prefix is about PREFIX_TOKENS tokens."""
    paragraph = (
        "A pySkillUp skill is a Python class; each PackML state is a method. Use the robot's "
        "real ROS 2 interfaces only, declare parameters and outputs from the capability. "
    )
    system = paragraph
    while (
        len(generator.llama.tokenize(system.encode(), add_bos=True, special=True))
        < PREFIX_TOKENS - 60
    ):
        system += paragraph
    examples = (
        ChatMessage("user", "Example: drive forward 1 m."),
        ChatMessage("assistant", "class DriveSkill(Skill): ..."),
    )
    return Prompt.chat(question, system=system, prefix=examples)


def _ttft(generator: LlamaCppGenerator, prompt: Prompt) -> tuple[float, str]:
    """Seconds until the first token: a one-token generation, start to end.

    (The first *text* chunk can come later: a token may be part of a character.)
    """
    started = time.perf_counter()
    stream = generator.stream(prompt, GenerationOptions(max_tokens=1))
    stream.text()
    elapsed = time.perf_counter() - started
    assert stream.completion_tokens == 1, stream.completion_tokens
    return elapsed, stream.prefix_cache


def bench_prefix_cache(
    registry: Registry, model_id: str | None, cache: Path
) -> list[tuple[str, float, str]]:
    entry = registry.generation_model(model_id)
    if not isinstance(entry, LlamaCppModel):
        raise SystemExit(f"{entry.id} is not a local llama.cpp model")
    fresh = load_llamacpp(entry, registry, cache=cache, prefix_cache=False)
    prompt = _prompt(fresh, "Write the skill for: drive 2 m at 0.3 m/s.")
    tokens = fresh.count_tokens(prompt)
    uncached, _ = _ttft(fresh, prompt)
    fresh.close()

    storing = load_llamacpp(entry, registry, cache=cache)
    stored, how = _ttft(storing, prompt)
    assert how == "stored", how
    storing.close()

    # The cores are shared: take the best of three for the short measurements.
    restored = memory = float("inf")
    for task in ("turn 90 degrees", "stop", "open the gripper"):
        restoring = load_llamacpp(entry, registry, cache=cache)
        seconds, how = _ttft(restoring, _prompt(restoring, f"Write the skill for: {task}."))
        assert how == "disk", how
        restored = min(restored, seconds)
        seconds, how = _ttft(restoring, _prompt(restoring, f"Write the skill to undo: {task}."))
        assert how == "memory", how
        memory = min(memory, seconds)
        restoring.close()
    size = sum(p.stat().st_size for p in (cache / "prefix").glob("*.bin"))
    print(f"model {entry.id}, prompt {tokens} tokens, saved state {size / 2**20:.1f} MB")
    return [
        ("TTFT, prefix evaluated (no cache)", uncached, "1.00"),
        ("TTFT, prefix evaluated + saved", stored, f"{stored / uncached:.2f}"),
        ("TTFT, prefix restored from disk (best of 3)", restored, f"{restored / uncached:.3f}"),
        ("TTFT, prefix still in memory (best of 3)", memory, f"{memory / uncached:.3f}"),
    ]


def _descriptions(count: int) -> list[str]:
    modules = ["base", "arm", "gripper", "lidar", "camera", "battery", "navigation", "docking"]
    verbs = ["publishes", "accepts", "reports", "streams", "serves", "controls"]
    things = [
        "velocity commands",
        "joint states",
        "diagnostics",
        "odometry",
        "goal poses",
        "parameter updates",
        "point clouds",
        "charge level",
    ]
    return [
        f"Interface /{modules[i % 8]}/{things[(i // 8) % 8].replace(' ', '_')}_{i} "
        f"{verbs[(i // 64) % 6]} {things[(i // 8) % 8]} of the {modules[i % 8]} module; "
        f"used by task {i % 13} and entity {i % 17}."
        for i in range(count)
    ]


def bench_embeddings(registry: Registry, cache: Path) -> list[tuple[str, float, str]]:
    encoder = load_encoder(registry)
    texts = _descriptions(1000)
    embedder = Embedder(encoder, EmbeddingCache(cache / "embeddings.sqlite"))
    started = time.perf_counter()
    embedder.embed(texts)
    cold = time.perf_counter() - started
    assert embedder.last.computed == 1000
    started = time.perf_counter()
    embedder.embed(texts)
    warm = time.perf_counter() - started
    assert embedder.last.computed == 0
    return [
        (f"embed 1000 descriptions, cold ({1000 / cold:.0f}/s)", cold, "1.00"),
        (f"embed 1000 descriptions, cached ({1000 / warm:.0f}/s)", warm, f"{warm / cold:.3f}"),
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", help="generation model id (default: models.toml's default)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="skillwright-bench-") as scratch:
        folder = Path(scratch)
        registry = load_registry()
        model_id = args.model
        try:
            entry = registry.generation_model(model_id)
            if isinstance(entry, LlamaCppModel) and not registry.resolve(entry.file).is_file():
                raise ModelError(f"{entry.id} is not present")
        except ModelError as reason:
            print(f"({reason}; using a synthetic random-weight GGUF model instead)")
            registry, model_id = _synthetic_registry(folder), "synthetic"
        rows = bench_prefix_cache(registry, model_id, folder / "cache")
        rows += bench_embeddings(load_registry(), folder / "cache")
    width = max(len(name) for name, _, _ in rows)
    print(f"{'measurement':<{width}}  {'seconds':>9}  {'ratio':>6}")
    for name, seconds, ratio in rows:
        print(f"{name:<{width}}  {seconds:>9.3f}  {ratio:>6}")


if __name__ == "__main__":
    main()
