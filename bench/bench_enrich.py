"""Benchmark of enrichment (run by ``make bench``; never part of the tests).

1. The rules engine over the Cap2Skill paper's 107 interfaces and the MR-1's 77.
2. The LLM engine over a sample of the paper's interfaces: a first run, which asks the model
   (the named alternative), and a second one, where every answer comes from the answer cache.
   (What the shared prompt prefix saves across processes is measured by bench_llm.py.)

The generation model is ``--model ID`` when given and its file is present; otherwise a
synthetic random-weight llama GGUF of realistic per-token cost (the test-fixture writer,
bigger dimensions). Its byte-level vocabulary makes prompts about four times as many tokens
as a real tokenizer would, and its answers are bounded (small answer limits) so that random
weights finish them; its numbers show how the caches scale, not how a model answers.
Needs ``../shared`` beside the repository for the paper's report.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO_ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO_ROOT))  # for tests.fixtures (the synthetic model writer)

from skillwright.errors import ModelError  # noqa: E402
from skillwright.interfaces.enrich import (  # noqa: E402
    AnswerLimits,
    EnrichmentCache,
    LlmEngine,
    RulesEngine,
    enrich,
)
from skillwright.interfaces.inventory import Inventory  # noqa: E402
from skillwright.interfaces.load import load_inventory  # noqa: E402
from skillwright.llm.config import LlamaCppModel, Registry, load_registry  # noqa: E402
from skillwright.llm.llamacpp import load_llamacpp  # noqa: E402

REPORT = REPO_ROOT.parent / "shared" / "data" / "cap2skill" / "interface-reports"
MR1 = REPO_ROOT / "capabilities" / "recordings" / "mr1"
SAMPLE = 6


def _synthetic_registry(folder: Path) -> Registry:
    from tests.fixtures.tiny_gguf import TinyLlamaSpec, write_tiny_llama

    spec = TinyLlamaSpec(
        n_embd=1024, n_head=16, n_head_kv=2, n_ff=2816, n_layer=8, seed=7, half=True
    )
    model = write_tiny_llama(folder / "synthetic.gguf", spec)
    models = folder / "models.toml"
    models.write_text(
        f'[defaults]\ngeneration = "synthetic"\n[[llm]]\nid = "synthetic"\n'
        f'file = "{model.as_posix()}"\ncontext_length = 8192\nbatch_size = 512\n'
    )
    return load_registry(models)


def _timed(function: Any) -> tuple[float, Any]:
    start = time.perf_counter()
    result = function()
    return time.perf_counter() - start, result


def _rules(inventory: Inventory, repeat: int = 5) -> float:
    best = float("inf")
    for _ in range(repeat):
        seconds, _ = _timed(lambda: enrich(inventory, RulesEngine()))
        best = min(best, seconds)
    return best


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--model", help="a generation model id of models.toml (real weights)")
    args = parser.parse_args()
    if not REPORT.is_dir():
        print(f"skipped: {REPORT} not found")
        return 0
    paper = load_inventory(REPORT / "ros2_system_report.json")
    mr1 = load_inventory(MR1)
    rows: list[tuple[str, float, str]] = []
    for label, inventory in (("paper robot", paper), ("MR-1", mr1)):
        seconds = _rules(inventory)
        per = seconds / len(inventory.interfaces) * 1e6
        rows.append(
            (f"rules engine, {label} ({len(inventory.interfaces)})", seconds, f"{per:.0f} us/if")
        )

    with tempfile.TemporaryDirectory(prefix="skillwright-bench-enrich-") as scratch:
        folder = Path(scratch)
        registry = load_registry()
        limits: AnswerLimits | None = None
        max_tokens: int | None = None
        try:
            entry = registry.generation_model(args.model) if args.model else None
            if entry is None or not isinstance(entry, LlamaCppModel):
                raise ModelError("no local model chosen")
            load_llamacpp(entry, registry, cache=folder / "probe").close()
        except ModelError as error:
            print(f"({error}; using a synthetic random-weight GGUF model instead)")
            registry = _synthetic_registry(folder)
            entry = registry.generation_model()
            assert isinstance(entry, LlamaCppModel)
            limits, max_tokens = AnswerLimits(text_chars=12, item_chars=8, items=1), 600
        sample = paper.model_copy(
            update={"interfaces": paper.interfaces[:: len(paper.interfaces) // SAMPLE][:SAMPLE]}
        )
        n = len(sample.interfaces)

        generator = load_llamacpp(entry, registry, cache=folder / "prefix")
        try:
            engine = LlmEngine(generator, max_tokens=max_tokens, limits=limits)
            cache = EnrichmentCache(folder / "answers.sqlite")
            cold, report = _timed(lambda: enrich(sample, engine, cache=cache))
            warm, _ = _timed(lambda: enrich(sample, engine, cache=cache))
        finally:
            generator.close()
        label = f"llm {entry.id}, {n} interfaces"
        rows.append((f"{label}, first run: asks the model (alternative)", cold, "1.00"))
        rows.append((f"{label}, second run: answer cache", warm, f"{warm / cold:.5f}"))
        per_rules = rows[0][1] / len(paper.interfaces)
        rows.append(
            (
                "rules engine, one interface, vs llm first run",
                per_rules,
                f"{per_rules * n / cold:.6f}",
            )
        )
        if report.notes:
            print(f"({len(report.notes)} of {n} answers fell back to the rules; not cached)")

    width = max(len(r[0]) for r in rows)
    print(f"{'measurement':<{width}}  {'seconds':>9}  {'ratio':>12}")
    for name, seconds, ratio in rows:
        print(f"{name:<{width}}  {seconds:>9.4f}  {ratio:>12}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
