"""N answers to one prompt batched in one llama.cpp context against the same N answers in turn.

The prompts are the product's own: ``skillwright generate``'s pipeline writes a shipped
capability's skill (set-velocity on the MR-1 recording, ``--capability`` for another) with the
model and every prompt it sends is recorded (as ``bench/bench_lookup.py`` does); ``--prompts``
of them are measured, spread over the conversation (its first and its last, the longest, and
evenly between), so the prompt lengths are those best-of-N decodes after.

For each prompt and each width N (``--widths``, default 1, 2, 4): N answers, the first greedy
and the others sampled at ``--temperature`` with seeds 1..N-1, each of up to ``--max-tokens``
tokens, are decoded once with ``generate_batch`` (one ``llama_decode`` per step for all live
sequences) and once one after another with ``stream()`` (the order alternates between prompts,
so a drifting machine favours neither). Before each, the prompt is already in the context (a
one-token answer puts it there), so both times are decoding, not prompt evaluation. Printed per
prompt and width: the answers' tokens, the wall time and tokens/s of both, the ratio of the
batch's time to one sequence's batch (what N answers cost against one) and of the answers in
turn to the batch (the speed-up), and how many batched answers equal their streamed twin.
``--context-cost`` also loads the model with a one-sequence context and compares ``stream()``'s
rate there with the rate in the batching context (what the wider context costs a single answer).

The model is models.toml's default (or ``--model ID``) when its file is present; otherwise (or
with ``--tiny``) the tiny random-weight test model (the wordy one) answers, which shows the
machinery, not what batching saves: its tokens cost microseconds, so Python's share dominates.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO_ROOT))  # for tests.fixtures (the tiny model writer), bench_lookup

from bench.bench_lookup import Asked, record_prompts  # noqa: E402

from skillwright.errors import ModelError  # noqa: E402
from skillwright.llm.base import GenerationOptions  # noqa: E402
from skillwright.llm.config import LlamaCppModel, Registry, load_registry  # noqa: E402
from skillwright.llm.llamacpp import LlamaCppGenerator, load_llamacpp  # noqa: E402


def _tiny_registry(folder: Path, width: int) -> Registry:
    from tests.fixtures.tiny_gguf import GENERATION_WORDS, TinyLlamaSpec, write_tiny_llama

    model = write_tiny_llama(folder / "wordy.gguf", TinyLlamaSpec(words=GENERATION_WORDS))
    models = folder / "models.toml"
    models.write_text(
        f'[defaults]\ngeneration = "tiny"\n[[llm]]\nid = "tiny"\nfile = "{model.as_posix()}"\n'
        f"context_length = 16384\nbatch_sequences = {width}\n[llm.sampling]\nmax_tokens = 320\n",
        encoding="utf-8",
    )
    return load_registry(models)


def pick(prompts: list[Asked], count: int) -> list[Asked]:
    """``count`` prompts spread over the conversation: the first, the last, between them."""
    if count >= len(prompts):
        return prompts
    if count <= 1:
        return [prompts[-1]]
    step = (len(prompts) - 1) / (count - 1)
    return [prompts[round(index * step)] for index in range(count)]


def options_for(width: int, *, temperature: float, max_tokens: int) -> list[GenerationOptions]:
    """The first answer greedy, the others sampled with seeds 1..width-1 (best-of-N's mix)."""
    greedy = GenerationOptions(max_tokens=max_tokens, temperature=0.0)
    return [greedy] + [
        GenerationOptions(max_tokens=max_tokens, temperature=temperature, seed=seed)
        for seed in range(1, width)
    ]


@dataclass(frozen=True)
class Timed:
    texts: tuple[str, ...]
    tokens: int
    seconds: float

    @property
    def rate(self) -> float:
        return self.tokens / self.seconds if self.seconds > 0 else 0.0


def _warm(generator: LlamaCppGenerator, asked: Asked) -> None:
    """Puts the prompt into the context (a one-token answer), so that what is timed next is
    decoding."""
    generator.stream(asked.prompt, GenerationOptions(max_tokens=1)).text()


def batched(
    generator: LlamaCppGenerator, asked: Asked, options: Sequence[GenerationOptions]
) -> Timed:
    _warm(generator, asked)
    started = time.perf_counter()
    answers = generator.generate_batch(asked.prompt, options)
    seconds = time.perf_counter() - started
    return Timed(
        tuple(a.text for a in answers), sum(a.completion_tokens or 0 for a in answers), seconds
    )


def in_turn(
    generator: LlamaCppGenerator, asked: Asked, options: Sequence[GenerationOptions]
) -> Timed:
    _warm(generator, asked)
    texts, tokens, seconds = [], 0, 0.0
    for option in options:
        started = time.perf_counter()
        stream = generator.stream(asked.prompt, option)
        texts.append(stream.text())
        seconds += time.perf_counter() - started
        tokens += stream.completion_tokens or 0
    return Timed(tuple(texts), tokens, seconds)


@dataclass(frozen=True)
class Row:
    asked: Asked
    tokens: int
    width: int
    batch: Timed
    turn: Timed


def compare(
    generator: LlamaCppGenerator,
    prompts: list[Asked],
    widths: Sequence[int],
    *,
    temperature: float,
    max_tokens: int,
) -> list[Row]:
    rows = []
    for index, asked in enumerate(prompts):
        length = generator.count_tokens(asked.prompt)
        for width in widths:
            options = options_for(width, temperature=temperature, max_tokens=max_tokens)
            if index % 2 == 0:
                batch = batched(generator, asked, options)
                turn = in_turn(generator, asked, options)
            else:
                turn = in_turn(generator, asked, options)
                batch = batched(generator, asked, options)
            rows.append(Row(asked, length, width, batch, turn))
    return rows


def report(rows: list[Row]) -> Iterator[str]:
    head = (
        f"{'prompt':<44} {'tokens':>6} {'N':>2} {'answer t':>8} {'batch s':>8} "
        f"{'batch t/s':>9} {'turn s':>8} {'turn t/s':>8} {'vs one':>6} {'speed-up':>8} "
        f"{'same':>5}"
    )
    yield head
    yield "-" * len(head)
    one: dict[str, float] = {}
    for row in rows:
        if row.width == 1:
            one[row.asked.label] = row.batch.seconds
        base = one.get(row.asked.label)
        versus = f"{row.batch.seconds / base:>6.2f}" if base else f"{'-':>6}"
        speedup = row.turn.seconds / row.batch.seconds if row.batch.seconds else 0.0
        same = sum(a == b for a, b in zip(row.batch.texts, row.turn.texts, strict=True))
        yield (
            f"{row.asked.label[:44]:<44} {row.tokens:>6} {row.width:>2} {row.batch.tokens:>8} "
            f"{row.batch.seconds:>8.2f} {row.batch.rate:>9.1f} {row.turn.seconds:>8.2f} "
            f"{row.turn.rate:>8.1f} {versus} {speedup:>8.2f} {same:>2}/{row.width:<2}"
        )
    yield "-" * len(head)
    for width in sorted({row.width for row in rows}):
        chosen = [row for row in rows if row.width == width]
        tokens = sum(row.batch.tokens for row in chosen)
        batch_s = sum(row.batch.seconds for row in chosen)
        turn_s = sum(row.turn.seconds for row in chosen)
        ones = sum(one.get(row.asked.label, 0.0) for row in chosen)
        versus = f", {batch_s / ones:.2f}x the time of one sequence" if ones else ""
        yield (
            f"N={width}: {tokens} tokens; batched {tokens / batch_s:.1f} tokens/s in "
            f"{batch_s:.2f} s{versus}; in turn {turn_s:.2f} s, {turn_s / batch_s:.2f}x the "
            "batch's time"
            if batch_s > 0
            else f"N={width}: nothing decoded"
        )
    yield (
        "(vs one: the batch's time against one sequence's batch on the same prompt; speed-up: "
        "the answers in turn against the batch; same: batched answers equal to their stream())"
    )


def context_cost(
    entry: LlamaCppModel, registry: Registry, folder: Path, prompts: list[Asked], max_tokens: int
) -> Iterator[str]:
    """``stream()``'s greedy rate in a one-sequence context against the batching one."""
    rates: dict[int, float] = {}
    for width in (entry.batch_sequences, 1):
        generator = load_llamacpp(
            entry.model_copy(update={"batch_sequences": width}), registry, cache=folder / "cache"
        )
        try:
            greedy = options_for(1, temperature=0.0, max_tokens=max_tokens)
            timed = [in_turn(generator, asked, greedy) for asked in prompts]
        finally:
            generator.close()
        seconds = sum(t.seconds for t in timed)
        rates[width] = sum(t.tokens for t in timed) / seconds if seconds else 0.0
    wide = entry.batch_sequences
    ratio = rates[wide] / rates[1] if rates[1] else 0.0
    yield (
        f"stream() greedy: {rates[1]:.1f} tokens/s in a one-sequence context, {rates[wide]:.1f} "
        f"in the {wide}-sequence context (ratio {ratio:.2f})"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", help="generation model id (default: models.toml's default)")
    parser.add_argument(
        "--capability", default="set-velocity", help="a shipped capability's stem (capabilities/)"
    )
    parser.add_argument("--widths", default="1,2,4", help="batch widths N, e.g. 1,2,4,8")
    parser.add_argument("--prompts", type=int, default=2, help="recorded prompts measured")
    parser.add_argument("--max-tokens", type=int, default=128, help="tokens per answer at most")
    parser.add_argument("--temperature", type=float, default=0.7, help="of the sampled answers")
    parser.add_argument(
        "--context-cost",
        action="store_true",
        help="also compare stream() in a one-sequence context with the batching one",
    )
    parser.add_argument(
        "--tiny", action="store_true", help="the tiny test model even when a real one is installed"
    )
    args = parser.parse_args()
    widths = sorted({int(width) for width in args.widths.split(",")})
    with tempfile.TemporaryDirectory(prefix="skillwright-bench-") as scratch:
        folder = Path(scratch)
        registry = load_registry()
        model_id = args.model
        models_file: Path | None = None
        try:
            entry = registry.generation_model(model_id)
            if not isinstance(entry, LlamaCppModel):
                raise SystemExit(f"{entry.id} is not a local llama.cpp model")
            if args.tiny:
                raise ModelError("--tiny")
            if not registry.resolve(entry.file).is_file():
                raise ModelError(f"{entry.id} is not installed")
        except ModelError as reason:
            print(
                f"({reason}; the tiny random-weight test model answers instead: its numbers "
                "show the machinery, not what batching saves on a real model)"
            )
            registry, model_id = _tiny_registry(folder, max(widths)), "tiny"
            models_file = registry.origin
            entry = registry.generation_model(model_id)
        assert isinstance(entry, LlamaCppModel)
        entry = entry.model_copy(update={"batch_sequences": max(widths)})
        generator = load_llamacpp(entry, registry, cache=folder / "cache")
        try:
            print(f"model {generator.model_id}; recording the prompts of {args.capability} ...")
            recorded = record_prompts(
                generator, args.capability, folder / "out", attempts=1, models_file=models_file
            )
            prompts = pick(recorded, args.prompts)
            print(
                f"{len(recorded)} prompts recorded, {len(prompts)} measured; widths {widths}, "
                f"up to {args.max_tokens} tokens per answer, sampled at {args.temperature}\n"
            )
            for line in report(
                compare(
                    generator,
                    prompts,
                    widths,
                    temperature=args.temperature,
                    max_tokens=args.max_tokens,
                )
            ):
                print(line)
        finally:
            generator.close()
        if args.context_cost:
            print()
            for line in context_cost(entry, registry, folder, prompts, args.max_tokens):
                print(line)


if __name__ == "__main__":
    main()
