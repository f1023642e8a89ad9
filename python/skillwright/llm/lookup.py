"""Prompt-lookup decoding: greedy generation that verifies tokens copied from the prompt.

A skill prompt repeats itself: a repair quotes the method it asks to change, a helper's body
uses the names of the skeleton above it, the task card's attribute names come back in the
code. When the last few tokens written also occur earlier in the prompt or the answer, the
tokens that followed them there are a cheap guess (a *draft*) of what comes next. The draft
is evaluated together with the token just chosen, in one ``llama_decode`` call that asks for
the logits of every position; on a memory-bound CPU, evaluating a few tokens at once costs
little more than one, as the weights are read once for all of them.

Verification keeps the output that of plain greedy decoding: the logits after the chosen
token give the next token by arg-max, exactly as the greedy sampler picks it (the first of
equal maxima); where it equals the draft's first token, that token is already evaluated and
the logits after it give the one after, and so on. At the first disagreement (or after the
whole draft) the arg-max token is the next one chosen, and the cache entries of the rejected
draft tokens are removed. The arithmetic is the same; its rounding may not be: llama.cpp may
multiply a batch of several tokens with other matrix kernels than a single token, which sum
in another order, so a near tie can fall the other way. Measured on the random test model,
20 prompts of 1,000 greedy tokens each: one answer differed, at its 641st token, where the two
best logits (about 25.6) were 0.0007 apart. Only the greedy case can be verified this way:
sampling with a temperature, a grammar or a repeat penalty (whose sampler state would have to
follow every rejected guess) decodes one token at a time.

The drafter looks for the longest recent n-gram (from ``max_ngram`` down to ``min_ngram``
tokens) that ends the text so far and occurred before, and proposes the tokens after its
most recent earlier occurrence: the closest repetition is usually the one being copied.
"""

from __future__ import annotations

from collections.abc import Generator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from llama_cpp import Llama

__all__ = ["LookupCounts", "draft_from_history", "lookup_tokens"]


@dataclass
class LookupCounts:
    """What prompt-lookup decoding did in one generation (for statistics and benchmarks)."""

    decodes: int = 0
    """``llama_decode`` calls after the prompt (one per chosen token without a draft)."""
    drafted: int = 0
    """Draft tokens evaluated."""
    accepted: int = 0
    """Draft tokens that greedy decoding confirmed (each one saves a decode)."""


def draft_from_history(
    history: Sequence[int] | Any, *, max_ngram: int, min_ngram: int, size: int
) -> list[int]:
    """Up to ``size`` tokens that followed the latest earlier occurrence of the longest
    n-gram (``max_ngram`` down to ``min_ngram`` tokens) ending ``history``; empty when none
    recurs. ``history`` is the prompt and the tokens generated so far."""
    import numpy as np

    tokens = np.asarray(history, dtype=np.intc)
    length = len(tokens)
    if size <= 0:
        return []
    for n in range(min(max_ngram, length - 1), min_ngram - 1, -1):
        tail = tokens[length - n :]
        # Windows that start before the tail itself: starts 0 .. length - n - 1.
        windows = np.lib.stride_tricks.sliding_window_view(tokens[: length - 1], n)
        matches = np.flatnonzero((windows == tail).all(axis=1))
        if matches.size:
            start = int(matches[-1]) + n
            return [int(t) for t in tokens[start : start + size]]
    return []


def lookup_tokens(
    llama: Llama,
    prompt: Sequence[int],
    *,
    max_ngram: int,
    min_ngram: int,
    draft_size: int,
    max_tokens: int,
    counts: LookupCounts | None = None,
) -> Generator[int, None, None]:
    """Greedy tokens after ``prompt``, drafted from the prompt and verified in batches; see
    the module docstring. At most ``max_tokens`` tokens are chosen (the caller may stop
    earlier by closing the generator).

    The model's context is prepared as ``Llama.generate`` does it: the leading tokens it
    already holds are kept, the rest of the prompt is evaluated. When the generator ends or
    is closed, ``llama.input_ids[: llama.n_tokens]`` and the KV cache hold the prompt and every
    token chosen before the last one, which is what plain generation leaves behind.
    """
    import numpy as np

    counts = counts if counts is not None else LookupCounts()
    history = np.zeros(len(prompt) + max_tokens, dtype=np.intc)
    history[: len(prompt)] = prompt
    written = len(prompt)
    chosen = _evaluate_prompt(llama, list(prompt))
    room = min(llama.n_batch, llama.n_ctx()) - 1
    try:
        while True:
            history[written] = chosen
            written += 1
            yield chosen
            left = max_tokens - (written - len(prompt))
            if left <= 0:
                return
            draft = draft_from_history(
                history[:written],
                max_ngram=max_ngram,
                min_ngram=min_ngram,
                size=min(draft_size, left - 1, room),
            )
            accepted, chosen = _verify(llama, chosen, draft)
            counts.decodes += 1
            counts.drafted += len(draft)
            counts.accepted += len(accepted)
            for token in accepted:
                history[written] = token
                written += 1
                yield token
    finally:
        # Leave what plain generation leaves: the prompt and all chosen tokens but the last.
        _truncate(llama, max(len(prompt), written - 1))
        llama._requires_eval = True


def _evaluate_prompt(llama: Llama, prompt: list[int]) -> int:
    """Evaluates what the context lacks of ``prompt`` and returns the greedy next token."""
    import numpy as np

    reused = _shared_prefix(llama.input_ids[: llama.n_tokens], prompt)
    # The last prompt token is evaluated again when everything is cached: its logits are
    # needed and a restored state has none.
    reused = min(reused, len(prompt) - 1)
    _truncate(llama, reused)
    llama.eval(prompt[reused:])
    logits = np.ctypeslib.as_array(llama._ctx.get_logits_ith(-1), shape=(llama.n_vocab(),))
    return int(np.argmax(logits))


def _verify(llama: Llama, chosen: int, draft: list[int]) -> tuple[list[int], int]:
    """Evaluates ``chosen`` and ``draft`` in one batch; returns the draft tokens greedy
    decoding confirms (they stay in the cache, the rest are removed) and the token that
    follows them."""
    import llama_cpp
    import numpy as np

    batch = [chosen, *draft]
    start = llama.n_tokens
    llama._batch.set_batch(batch=batch, n_past=start, logits_all=True)
    llama._ctx.decode(llama._batch)
    llama.input_ids[start : start + len(batch)] = batch
    llama.n_tokens = start + len(batch)
    logits = np.ctypeslib.as_array(
        llama_cpp.llama_get_logits(llama.ctx), shape=(len(batch), llama.n_vocab())
    )
    picks = logits.argmax(axis=1)
    accepted = 0
    while accepted < len(draft) and int(picks[accepted]) == draft[accepted]:
        accepted += 1
    _truncate(llama, start + 1 + accepted)
    return draft[:accepted], int(picks[accepted])


def _truncate(llama: Llama, length: int) -> None:
    """Keeps the first ``length`` evaluated tokens of the context (the cache's and
    ``llama.n_tokens``); a no-op when it holds no more."""
    if llama.n_tokens > length or length == 0:
        llama._ctx.kv_cache_seq_rm(-1, length, -1)
        llama.n_tokens = min(llama.n_tokens, length)


def _shared_prefix(tokens: Any, other: Sequence[int]) -> int:
    import numpy as np

    n = min(len(tokens), len(other))
    if n == 0:
        return 0
    differ = np.flatnonzero(np.asarray(tokens[:n]) != np.asarray(other[:n], dtype=np.intc))
    return int(differ[0]) if differ.size else n
