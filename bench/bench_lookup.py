"""Prompt-lookup decoding against plain greedy decoding: the same prompts, the same process.

The prompts are the product's own: ``skillwright generate``'s pipeline writes a shipped
capability's skill (set-velocity on the MR-1 recording, ``--capability`` for another) with the
model, greedy, and every prompt it sends is recorded together with its options. Then one
more prompt, a repair in the style of :mod:`skillwright.generation.repair`: ``execute`` asked
again with a problem, after all the turns (so its earlier answer is in the context) and
prefilled with that answer's first lines, the case where an answer repeats the most text.

Each recorded prompt is answered twice more, without and with prompt lookup (the order
alternates between prompts, so a drifting machine favours neither), and for each the decode
rate is taken from the first token to the last (the prompt's evaluation, the same in both,
is left out). Printed: per prompt the tokens, both rates, their ratio, the drafted and
accepted tokens and whether the answers are identical; then the totals. ``--sweep`` tries a
few drafting settings besides the model's.

The model is models.toml's default (or ``--model ID``) when its file is present; otherwise (or
with ``--tiny``) the tiny random-weight test model (the wordy one) answers, which says how the
machinery behaves, not whether it pays: its tokens cost microseconds, so Python's share
dominates, and its random answers repeat nothing.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import threading
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO_ROOT))  # for tests.fixtures (the tiny model writer)

import skillwright.llm  # noqa: E402
from skillwright.errors import ModelError  # noqa: E402
from skillwright.llm.base import GenerationOptions, Prompt, TextGenerator, TextStream  # noqa: E402
from skillwright.llm.config import LlamaCppModel, PromptLookup, Registry, load_registry  # noqa: E402
from skillwright.llm.llamacpp import LlamaCppGenerator, load_llamacpp  # noqa: E402

CAPABILITIES = REPO_ROOT / "capabilities"
RECORDING = CAPABILITIES / "recordings" / "mr1"
SWEEP = ((2, 1, 4), (3, 1, 8), (4, 2, 16))
"""Drafting settings ``--sweep`` tries besides the model's: (max_ngram, min_ngram, draft)."""


@dataclass(frozen=True)
class Asked:
    """A prompt the pipeline sent, with its options."""

    label: str
    prompt: Prompt
    options: GenerationOptions


class _Recorder:
    """The loaded model as the pipeline sees it, recording every prompt it is sent."""

    def __init__(self, generator: LlamaCppGenerator) -> None:
        self.generator = generator
        self.model_id = generator.model_id
        self.context_length = generator.context_length
        self.asked: list[tuple[Prompt, GenerationOptions]] = []

    def count_tokens(self, prompt: Prompt) -> int:
        return self.generator.count_tokens(prompt)

    def stream(
        self,
        prompt: Prompt,
        options: GenerationOptions | None = None,
        cancel: threading.Event | None = None,
    ) -> TextStream:
        options = options or GenerationOptions()
        self.asked.append((prompt, options))
        return self.generator.stream(prompt, options, cancel)

    def close(self) -> None:
        """The pipeline closes its model when done; this one is closed by the benchmark."""


def _tiny_registry(folder: Path) -> Registry:
    from tests.fixtures.tiny_gguf import GENERATION_WORDS, TinyLlamaSpec, write_tiny_llama

    model = write_tiny_llama(folder / "wordy.gguf", TinyLlamaSpec(words=GENERATION_WORDS))
    models = folder / "models.toml"
    models.write_text(
        f'[defaults]\ngeneration = "tiny"\n[[llm]]\nid = "tiny"\nfile = "{model.as_posix()}"\n'
        "context_length = 16384\n[llm.sampling]\nmax_tokens = 320\n",
        encoding="utf-8",
    )
    return load_registry(models)


def record_prompts(
    generator: LlamaCppGenerator,
    capability: str,
    out: Path,
    *,
    attempts: int,
    models_file: Path | None,
) -> list[Asked]:
    """The prompts ``generate`` sends for ``capability`` (greedy ones only), and the
    repair-style prompt after them."""
    from skillwright.pipeline import GenerationRequest, run_generation

    recorder = _Recorder(generator)

    def load(_registry: object, _model: str | None = None, **_: object) -> TextGenerator:
        return recorder

    real_load = skillwright.llm.load_generator
    skillwright.llm.load_generator = load  # type: ignore[assignment]
    try:
        run_generation(
            GenerationRequest(
                capability=CAPABILITIES / f"{capability}.ttl",
                spec=CAPABILITIES / f"{capability}.spec.yaml",
                interfaces=RECORDING,
                out_dir=out,
                model=generator.model_id,
                models_file=models_file,
                dense=False,
                attempts=attempts,
                run=False,
                simulate=False,
            )
        )
    finally:
        skillwright.llm.load_generator = real_load
    asked: list[Asked] = []
    for prompt, options in recorder.asked:
        if options.temperature not in (None, 0.0):
            continue  # sampled repairs: prompt lookup verifies greedy answers only
        ask = prompt.messages[-1].content.splitlines()[-1]
        asked.append(Asked(f"{len(asked) + 1}: {ask}", prompt, options))
    asked.append(_repair_prompt(generator, recorder.asked))
    return asked


def _repair_prompt(
    generator: LlamaCppGenerator, asked: list[tuple[Prompt, GenerationOptions]]
) -> Asked:
    """``execute`` asked again after every turn of the conversation (its earlier answer
    among them), prefilled with the first half of that answer."""
    from skillwright.generation.conversation import Conversation, Turn, repair_ask

    prompt, options = max(asked, key=lambda item: len(item[0].messages))
    answer = generator.stream(prompt, options).text()
    turns = prompt.messages[prompt.prefix_messages :]
    asks = [m.content for m in turns if m.role == "user"]
    answers = [
        m.content.removeprefix("```python\n").removesuffix("\n```")
        for m in turns
        if m.role == "assistant"
    ]
    answers.append(prompt.answer_prefix.removeprefix("```python\n") + answer)
    card, asks[0] = asks[0].rsplit("\n\n", 1)  # the first request carries the task card
    conversation = Conversation(card, [Turn(a, b) for a, b in zip(asks, answers, strict=True)])
    execute = next((t for t in conversation.turns if t.ask.startswith("Write `execute`")), None)
    execute = execute or conversation.turns[-1]
    lines = execute.answer.splitlines(keepends=True)
    prefill = "".join(lines[: max(2, len(lines) // 2)])
    problem = "the method ignores an input the capability declares; use it"
    again = conversation.prompt(repair_ask(execute.ask, [problem]), prefill)
    return Asked("repair of execute, its answer in the context", again, options)


@dataclass
class Measured:
    text: str
    tokens: int
    seconds: float
    drafted: int | None
    accepted: int | None

    @property
    def rate(self) -> float:
        return (self.tokens - 1) / self.seconds if self.seconds > 0 and self.tokens > 1 else 0.0


def measure(generator: LlamaCppGenerator, asked: Asked, *, lookup: bool) -> Measured:
    """One answer; its decode time runs from the first token to the end."""
    import time

    options = asked.options.model_copy(update={"prompt_lookup": lookup})
    stream = generator.stream(asked.prompt, options)
    first: float | None = None
    parts = []
    for chunk in stream:
        if first is None:
            first = time.perf_counter()
        parts.append(chunk)
    end = time.perf_counter()
    return Measured(
        "".join(parts),
        stream.completion_tokens or 0,
        0.0 if first is None else end - first,
        stream.drafted_tokens,
        stream.accepted_tokens,
    )


def compare(
    generator: LlamaCppGenerator, prompts: list[Asked], setting: PromptLookup
) -> list[tuple[Asked, Measured, Measured]]:
    """Each prompt without and with prompt lookup (``setting``), in alternating order."""
    generator.entry = generator.entry.model_copy(update={"prompt_lookup": setting})
    rows = []
    for index, asked in enumerate(prompts):
        if index % 2 == 0:
            plain = measure(generator, asked, lookup=False)
            drafted = measure(generator, asked, lookup=True)
        else:
            drafted = measure(generator, asked, lookup=True)
            plain = measure(generator, asked, lookup=False)
        rows.append((asked, plain, drafted))
    return rows


def report(setting: PromptLookup, rows: list[tuple[Asked, Measured, Measured]]) -> Iterator[str]:
    yield (
        f"prompt lookup: max_ngram {setting.max_ngram}, min_ngram {setting.min_ngram}, "
        f"draft_tokens {setting.draft_tokens}"
    )
    head = (
        f"{'prompt':<56} {'tokens':>6} {'plain t/s':>9} {'lookup t/s':>10} {'ratio':>6} "
        f"{'drafted':>7} {'accepted':>8} {'same':>5}"
    )
    yield head
    yield "-" * len(head)
    for asked, plain, drafted in rows:
        ratio = drafted.rate / plain.rate if plain.rate else 0.0
        yield (
            f"{asked.label[:56]:<56} {plain.tokens:>6} {plain.rate:>9.1f} {drafted.rate:>10.1f} "
            f"{ratio:>6.2f} {drafted.drafted or 0:>7} {drafted.accepted or 0:>8} "
            f"{'yes' if plain.text == drafted.text else 'NO':>5}"
        )
    tokens = sum(p.tokens - 1 for _, p, _ in rows if p.tokens > 1)
    plain_s = sum(p.seconds for _, p, _ in rows)
    lookup_s = sum(d.seconds for _, _, d in rows)
    ratios = [d.rate / p.rate for _, p, d in rows if p.rate and d.rate]
    n_drafted = sum(d.drafted or 0 for _, _, d in rows)
    n_accepted = sum(d.accepted or 0 for _, _, d in rows)
    same = sum(p.text == d.text for _, p, d in rows)
    yield "-" * len(head)
    if plain_s > 0 and lookup_s > 0:
        yield (
            f"all prompts: {tokens} tokens; plain {tokens / plain_s:.1f} tokens/s, lookup "
            f"{tokens / lookup_s:.1f} tokens/s, ratio {plain_s / lookup_s:.2f} "
            f"(median per prompt {statistics.median(ratios):.2f})"
            if ratios
            else f"all prompts: {tokens} tokens"
        )
    share = f" ({n_accepted / n_drafted:.0%})" if n_drafted else ""
    yield (
        f"drafted {n_drafted} tokens, accepted {n_accepted}{share}; "
        f"identical answers {same} of {len(rows)}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", help="generation model id (default: models.toml's default)")
    parser.add_argument(
        "--capability", default="set-velocity", help="a shipped capability's stem (capabilities/)"
    )
    parser.add_argument(
        "--attempts", type=int, default=1, help="answers per method when recording (1: no repairs)"
    )
    parser.add_argument("--sweep", action="store_true", help="also try other drafting settings")
    parser.add_argument(
        "--tiny", action="store_true", help="the tiny test model even when a real one is installed"
    )
    args = parser.parse_args()
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
                "show the machinery, not whether prompt lookup pays on a real model)"
            )
            registry, model_id = _tiny_registry(folder), "tiny"
            models_file = registry.origin
            entry = registry.generation_model(model_id)
        assert isinstance(entry, LlamaCppModel)
        generator = load_llamacpp(entry, registry, cache=folder / "cache")
        try:
            print(f"model {generator.model_id}; recording the prompts of {args.capability} ...")
            prompts = record_prompts(
                generator,
                args.capability,
                folder / "out",
                attempts=args.attempts,
                models_file=models_file,
            )
            print(f"{len(prompts)} prompts\n")
            settings = [entry.prompt_lookup.model_copy(update={"enabled": True})]
            if args.sweep:
                settings += [
                    PromptLookup(enabled=True, max_ngram=big, min_ngram=small, draft_tokens=size)
                    for big, small, size in SWEEP
                    if (big, small, size)
                    != (settings[0].max_ngram, settings[0].min_ngram, settings[0].draft_tokens)
                ]
            for setting in settings:
                for line in report(setting, compare(generator, prompts, setting)):
                    print(line)
                print()
        finally:
            generator.close()


if __name__ == "__main__":
    main()
