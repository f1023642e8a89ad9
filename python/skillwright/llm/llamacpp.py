"""Generation with a local GGUF model through llama-cpp-python, with a prompt prefix cache.

The chat prompt is rendered with the model's chat template (from ``models.toml`` or, by
default, the GGUF file) and tokenised in two parts: the fixed prefix and the rest. The prefix
is evaluated once, its llama.cpp state saved (see :mod:`skillwright.llm.prefix_cache`), and
restored for later prompts; the rest is evaluated on top of it. The fresh and the restored
path evaluate exactly the same batches, so they give the same tokens.

Within a process the context's state after each generation is also kept in memory (up to a
byte budget, least recently used dropped first). A prompt that branches off an earlier one --
a repair asked after the turns that came later, a helper asked after the repairs -- continues
from the kept state that shares most of its tokens instead of evaluating them again.
"""

from __future__ import annotations

import atexit
import codecs
import functools
import json
import logging
import os
import threading
import time
import weakref
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from skillwright.errors import ContextOverflowError, InvalidArgumentError, ModelError
from skillwright.llm.base import ChatMessage, GenerationOptions, Prompt, TextStream
from skillwright.llm.batch import BatchAnswer, BatchFinish, ChunkSink
from skillwright.llm.config import LlamaCppModel, Registry, cache_dir
from skillwright.llm.files import (
    ChecksumCache,
    ModelFile,
    check_model_file,
    inspect_model_file,
)
from skillwright.llm.lookup import LookupCounts, lookup_tokens
from skillwright.llm.model_lock import ModelLock, ModelWait, acquire_model_lock
from skillwright.llm.prefix_cache import PrefixCache, PrefixState, prefix_key

if TYPE_CHECKING:
    from llama_cpp import Llama
    from llama_cpp.llama_grammar import LlamaGrammar

__all__ = ["LlamaCppGenerator", "load_llamacpp", "render_chat", "route_native_logs"]

PrefixUse = Literal["off", "memory", "disk", "stored", "evaluated"]
"""How a prompt's fixed prefix was obtained (see :attr:`TextStream.prefix_cache`)."""

log = logging.getLogger(__name__)
native_log = logging.getLogger("skillwright.llama_cpp")
"""Where llama.cpp's own log lines go (see :func:`route_native_logs`)."""

# ggml's log levels (ggml.h): 0 none, 1 debug, 2 info, 3 warn, 4 error, 5 continues the last
# line. llama.cpp's "info" lines are hundreds of load details, so they become DEBUG here.
_NATIVE_LEVELS = {
    0: logging.DEBUG,
    1: logging.DEBUG,
    2: logging.DEBUG,
    3: logging.WARNING,
    4: logging.ERROR,
}
_native: list[Any] = []  # holds the ctypes callback: it must outlive every call into llama.cpp


def route_native_logs() -> None:
    """Sends llama.cpp's own log output to the Python logger ``skillwright.llama_cpp``.

    By default llama-cpp-python prints them straight to the process's stderr, where they
    garble a terminal UI; as log records they reach whatever handler the CLI or the TUI has.
    Pieces of a line (ggml sends some in parts) are joined before they are logged.
    """
    if _native:
        return
    import ctypes

    import llama_cpp

    pending: list[str] = []
    level_of_line = [logging.DEBUG]

    def forward(level: int, text: bytes, _user_data: Any) -> None:
        if level != 5:
            level_of_line[0] = _NATIVE_LEVELS.get(level, logging.DEBUG)
        pending.append(text.decode("utf-8", errors="replace"))
        if pending[-1].endswith("\n"):
            line = "".join(pending).strip()
            pending.clear()
            if line:
                native_log.log(level_of_line[0], "llama.cpp: %s", line)

    _native.append(llama_cpp.llama_log_callback(forward))
    llama_cpp.llama_log_set(_native[0], ctypes.c_void_p(0))


def render_chat(
    template: str,
    messages: Sequence[ChatMessage],
    *,
    bos_token: str = "",
    eos_token: str = "",
    add_generation_prompt: bool = True,
) -> str:
    """Renders chat turns with a Hugging Face style Jinja2 chat template (sandboxed)."""
    import jinja2.ext
    from jinja2.sandbox import ImmutableSandboxedEnvironment

    def raise_exception(message: str) -> None:
        raise InvalidArgumentError(f"the chat template rejects the prompt: {message}")

    environment = ImmutableSandboxedEnvironment(
        trim_blocks=True, lstrip_blocks=True, extensions=[jinja2.ext.loopcontrols]
    )
    # Templates expect transformers' tojson (plain JSON, not jinja's HTML-escaped one).
    environment.filters["tojson"] = lambda value, indent=None: json.dumps(
        value, ensure_ascii=False, indent=indent
    )
    try:
        compiled = environment.from_string(template)
    except jinja2.TemplateSyntaxError as error:
        raise InvalidArgumentError(f"chat template line {error.lineno}: {error.message}") from None
    return compiled.render(
        messages=[{"role": m.role, "content": m.content} for m in messages],
        bos_token=bos_token,
        eos_token=eos_token,
        add_generation_prompt=add_generation_prompt,
        raise_exception=raise_exception,
    )


class LlamaCppGenerator:
    """A GGUF model loaded in this process; implements :class:`~skillwright.llm.base.TextGenerator`
    and :class:`~skillwright.llm.batch.BatchGenerator`.

    One generation runs at a time per model; starting a second stream while one is open raises.
    """

    def __init__(
        self,
        entry: LlamaCppModel,
        model_file: ModelFile,
        llama: Llama,
        *,
        prefix_cache: PrefixCache | None,
        origin: Path,
        kept_state_bytes: int = 2 << 30,
        lock: ModelLock | None = None,
    ) -> None:
        self.entry = entry
        """The model's ``models.toml`` entry."""
        self.model_file = model_file
        """The checked file it was loaded from."""
        self.llama = llama
        """The llama-cpp-python model (for callers that need more than this contract)."""
        self.prefix_cache = prefix_cache
        """Where evaluated prefixes are saved, or ``None`` to evaluate them every time."""
        self.model_id = entry.id
        self.context_length = entry.context_length
        import llama_cpp

        self.max_sequences = int(llama_cpp.llama_n_seq_max(llama.ctx))
        """The most sequences one :meth:`generate_batch` may decode: what the context was
        made for (``batch_sequences`` in models.toml)."""
        self._origin = origin
        self._busy = threading.Lock()
        self._closed = False
        self._lock = lock
        self._written = 0
        if lock is not None:
            # A generator dropped without close() still gives the model up when collected.
            weakref.finalize(self, lock.release)
        template = entry.chat_template or model_file.info.chat_template
        if template is None:
            raise ModelError(
                f"model {entry.id!r}: {model_file.path} stores no chat template; set "
                f"`chat_template` of {entry.id!r} in your models.toml"
            )
        self._template = template
        self._kept = _KeptStates(kept_state_bytes)
        self._bos = self._special_text(llama.token_bos())
        self._eos = self._special_text(llama.token_eos())

    def _special_text(self, token: int) -> str:
        if token < 0:
            return ""
        return self.llama.detokenize([token], special=True).decode("utf-8", errors="replace")

    def _tokenize(self, text: str) -> list[int]:
        tokens = self.llama.tokenize(text.encode("utf-8"), add_bos=True, special=True)
        bos = self.llama.token_bos()
        if len(tokens) > 1 and tokens[0] == tokens[1] == bos:
            tokens = tokens[1:]  # the template wrote BOS and the tokenizer added one
        return tokens

    def render(self, messages: Sequence[ChatMessage], *, add_generation_prompt: bool) -> str:
        """The prompt text the model sees for these turns."""
        return render_chat(
            self._template,
            messages,
            bos_token=self._bos,
            eos_token=self._eos,
            add_generation_prompt=add_generation_prompt,
        )

    def prompt_tokens(self, prompt: Prompt) -> tuple[list[int], list[int]]:
        """The prompt's tokens split into (fixed prefix, rest); the prefix may be empty.

        The whole prompt is tokenised at once, exactly as without a cache; the prefix is the
        part of it that the fixed turns alone tokenise to (a merge across the boundary only
        shortens it by a token).
        """
        self._check_open()
        rendered = self.render(prompt.messages, add_generation_prompt=True)
        whole = self._tokenize(rendered + prompt.answer_prefix)
        if not prompt.prefix_messages:
            return [], whole
        head = self._tokenize(
            self.render(prompt.messages[: prompt.prefix_messages], add_generation_prompt=False)
        )
        shared = 0
        for ours, theirs in zip(head, whole, strict=False):
            if ours != theirs:
                break
            shared += 1
        if shared < len(head) - 1:
            log.warning(
                "model %s: the chat template renders the prefix differently inside the whole "
                "prompt; the prefix cache is not used for this prompt",
                self.model_id,
            )
            return [], whole
        return whole[:shared], whole[shared:]

    def count_tokens(self, prompt: Prompt) -> int:
        """Tokens the rendered prompt takes."""
        prefix, rest = self.prompt_tokens(prompt)
        return len(prefix) + len(rest)

    def stream(
        self,
        prompt: Prompt,
        options: GenerationOptions | None = None,
        cancel: threading.Event | None = None,
    ) -> TextStream:
        """Starts a generation; see :class:`~skillwright.llm.base.TextGenerator`."""
        options = options or GenerationOptions()
        max_tokens = options.max_tokens or self.entry.sampling.max_tokens
        prefix, rest = self.prompt_tokens(prompt)
        used = len(prefix) + len(rest)
        if used + max_tokens > self.context_length:
            trained = self.model_file.info.context_length
            hint = f" (the model was trained with up to {trained})" if trained else ""
            raise ContextOverflowError(
                f"model {self.model_id!r}: the prompt takes {used} tokens and up to "
                f"{max_tokens} may be generated, {used + max_tokens} in all, but the context "
                f"holds {self.context_length}; raise `context_length` of {self.model_id!r} in "
                f"your models.toml{hint}, lower max_tokens, or shorten the prompt "
                f"(settings from {self._origin})"
            )
        grammar = _grammar(options.json_schema) if options.json_schema is not None else None
        stream = TextStream(iter(()), prompt_tokens=used)
        stream.chunks = self._generate(
            stream,
            prefix,
            rest,
            max_tokens=max_tokens,
            options=options,
            grammar=grammar,
            cancel=cancel,
        )
        return stream

    def generate_batch(
        self,
        prompt: Prompt,
        options: Sequence[GenerationOptions],
        *,
        on_chunk: ChunkSink | None = None,
        cancel: threading.Event | None = None,
    ) -> list[BatchAnswer]:
        """One answer per entry of ``options``, decoded together; see
        :class:`~skillwright.llm.batch.BatchGenerator`.

        The prompt is put into the context as for :meth:`stream` (the live context, a kept
        state or the prefix cache, then the rest evaluated in the same batches) as sequence 0;
        its cache cells are then shared with sequences 1..N-1 (``llama_memory_seq_cp``: in the
        unified KV cache the context was made with, a cell belongs to several sequences, so
        nothing is copied). Each sequence gets the sampler chain :meth:`stream` would build for
        its options (llama-cpp-python's own, with its temperature and seed: greedy at 0), and
        its first token is sampled from the prompt's last logits. Every step then decodes the
        last token of every live sequence in one ``llama_decode`` call, at that sequence's
        own position, and samples each one's next token from its row of logits. A sequence
        ends on its own: end of text, a stop string, ``max_tokens``, or ``on_chunk`` returning
        true; ``cancel`` ends them all (``"cancelled"``, text so far).

        An answer is that of :meth:`stream` with the same options, up to rounding: the
        weights multiply several tokens at once, and a sequence's attention sums over cells
        interleaved with the other sequences' (masked) ones, so a near tie between two tokens
        can fall the other way. Prompt lookup does not apply (every sequence decodes one token
        per step). Afterwards the context holds the prompt alone, as sequence 0.
        """
        options = list(options)
        if not options:
            return []
        if len(options) > self.max_sequences:
            raise InvalidArgumentError(
                f"model {self.model_id!r}: {len(options)} answers asked for in one batch, but "
                f"its context was made for at most {self.max_sequences}; set "
                f"`batch_sequences = {len(options)}` for {self.model_id!r} in your models.toml "
                f"(settings from {self._origin}) or ask for fewer"
            )
        limits = [option.max_tokens or self.entry.sampling.max_tokens for option in options]
        prefix, rest = self.prompt_tokens(prompt)
        used = len(prefix) + len(rest)
        self._check_batch_fits(used, limits)
        grammars = [
            _grammar(option.json_schema) if option.json_schema is not None else None
            for option in options
        ]
        if not self._busy.acquire(blocking=False):
            raise ModelError(
                f"model {self.model_id!r} is already generating; finish or close that stream first"
            )
        started = time.perf_counter()
        try:
            self._check_open()
            whole = prefix + rest
            save = all(option.save_prefix for option in options)
            prepared = self._prepare(prefix, whole, cancel, save=save)
            sequences = [_Sequence(option.stop) for option in options]
            how: PrefixUse = "off"
            reused = 0
            if prepared is None:
                for sequence in sequences:
                    sequence.finish = "cancelled"
            else:
                how, reused = prepared
                self._decode_batch(whole, sequences, options, limits, grammars, on_chunk, cancel)
        finally:
            self._busy.release()
        seconds = round(time.perf_counter() - started, 3)
        return [
            BatchAnswer(
                text="".join(sequence.parts),
                finish_reason=sequence.finish,
                prompt_tokens=used,
                reused_tokens=reused,
                completion_tokens=sequence.written,
                seconds=seconds,
                prefix_cache=how,
            )
            for sequence in sequences
        ]

    def _check_batch_fits(self, used: int, limits: Sequence[int]) -> None:
        """Raises :class:`ContextOverflowError` when a sequence's positions would run past
        ``context_length`` or the prompt and all answers past the KV cache's cells."""
        trained = self.model_file.info.context_length
        hint = f" (the model was trained with up to {trained})" if trained else ""
        longest = max(limits)
        if used + longest > self.context_length:
            raise ContextOverflowError(
                f"model {self.model_id!r}: the prompt takes {used} tokens and up to {longest} "
                f"may be generated, {used + longest} in all, but the context holds "
                f"{self.context_length}; raise `context_length` of {self.model_id!r} in your "
                f"models.toml{hint}, lower max_tokens, or shorten the prompt "
                f"(settings from {self._origin})"
            )
        cells = self.llama.n_ctx()
        if used + sum(limits) > cells:
            raise ContextOverflowError(
                f"model {self.model_id!r}: the prompt takes {used} tokens and {len(limits)} "
                f"answers of up to {longest} tokens may be generated beside it, "
                f"{used + sum(limits)} in all, but the context has room for {cells}; ask for "
                f"fewer answers or lower max_tokens, or raise `context_length` (or "
                f"`sampling.max_tokens`, which sizes the room for answers) of "
                f"{self.model_id!r} in your models.toml{hint} (settings from {self._origin})"
            )

    def _decode_batch(
        self,
        whole: list[int],
        sequences: list[_Sequence],
        options: Sequence[GenerationOptions],
        limits: Sequence[int],
        grammars: Sequence[LlamaGrammar | None],
        on_chunk: ChunkSink | None,
        cancel: threading.Event | None,
    ) -> None:
        """Evaluates the rest of the prompt on sequence 0, shares it with the others and
        decodes them all together (see :meth:`generate_batch`); leaves the prompt alone in
        the context."""
        import llama_cpp

        llama = self.llama
        memory = llama._ctx.memory
        for seq in range(1, self.max_sequences):
            llama_cpp.llama_memory_seq_rm(memory, seq, -1, -1)
        samplers: list[Any] = []
        batch = llama_cpp.llama_batch_init(len(sequences), 0, 1)
        try:
            if not self._evaluate_prompt(whole, cancel):
                for sequence in sequences:
                    sequence.finish = "cancelled"
                return
            samplers = self._samplers(options, grammars)
            for seq in range(1, len(sequences)):
                llama_cpp.llama_memory_seq_cp(memory, 0, seq, 0, -1)
            tokens = [sampler.sample(llama._ctx, -1) for sampler in samplers]
            position = len(whole)
            while True:
                stepping = self._take_tokens(sequences, tokens, limits, on_chunk)
                if not stepping:
                    break
                if cancel is not None and cancel.is_set():
                    for index in stepping:
                        sequences[index].finish = "cancelled"
                    break
                self._decode_step(batch, [(index, tokens[index]) for index in stepping], position)
                for row, index in enumerate(stepping):
                    tokens[index] = samplers[index].sample(llama._ctx, row)
                position += 1
        finally:
            for sampler in samplers:
                sampler.close()
            llama_cpp.llama_batch_free(batch)
            # Only the prompt stays, as sequence 0; stream() and the prefix cache see it.
            for seq in range(1, self.max_sequences):
                llama_cpp.llama_memory_seq_rm(memory, seq, -1, -1)
            kept = min(llama.n_tokens, len(whole))
            llama._ctx.kv_cache_seq_rm(0, kept, -1)
            llama.n_tokens = kept
            llama._requires_eval = True
        self._written += sum(sequence.written for sequence in sequences)
        if self._lock is not None:
            self._lock.progress(self._written, at_once=True)
        if all(sequence.finish != "cancelled" for sequence in sequences):
            self._kept.keep(PrefixState(tuple(whole), self._state_bytes()))

    def _samplers(
        self, options: Sequence[GenerationOptions], grammars: Sequence[LlamaGrammar | None]
    ) -> list[Any]:
        """One sampler chain per sequence: the one ``Llama.generate`` builds for
        :meth:`stream` with these options (penalties, grammar, then greedy at temperature 0,
        else top-k, top-p, min-p, temperature and a distribution seeded with its seed)."""
        llama = self.llama
        sampling = self.entry.sampling
        samplers = []
        for option, grammar in zip(options, grammars, strict=True):
            llama.set_seed(sampling.seed if option.seed is None else option.seed)
            samplers.append(
                llama._init_sampler(
                    top_k=sampling.top_k,
                    top_p=sampling.top_p if option.top_p is None else option.top_p,
                    min_p=sampling.min_p,
                    temp=sampling.temperature if option.temperature is None else option.temperature,
                    repeat_penalty=sampling.repeat_penalty,
                    grammar=grammar,
                )
            )
        return samplers

    def _take_tokens(
        self,
        sequences: Sequence[_Sequence],
        tokens: Sequence[int],
        limits: Sequence[int],
        on_chunk: ChunkSink | None,
    ) -> list[int]:
        """Adds each live sequence's newly sampled token to its answer (ending it at the end
        of text, a stop string, its ``max_tokens`` or the sink's word); returns the indices of
        the sequences whose token is to be decoded next."""
        import llama_cpp

        vocab = self.llama._model.vocab
        stepping = []
        for index, sequence in enumerate(sequences):
            if sequence.finish is not None:
                continue
            if llama_cpp.llama_vocab_is_eog(vocab, tokens[index]):
                sequence.end("stop", on_chunk, index)
                continue
            sequence.written += 1
            if self._lock is not None:
                self._lock.progress(self._written + sum(s.written for s in sequences))
            if sequence.take(self.llama.detokenize([tokens[index]]), on_chunk, index):
                continue
            if sequence.written >= limits[index]:
                sequence.end("length", on_chunk, index)
                continue
            stepping.append(index)
        return stepping

    def _decode_step(self, batch: Any, rows: Sequence[tuple[int, int]], position: int) -> None:
        """Decodes one token per (sequence, token) row at ``position``, logits for each, in
        one ``llama_decode`` call."""
        import llama_cpp

        batch.n_tokens = len(rows)
        for row, (seq, token) in enumerate(rows):
            batch.token[row] = token
            batch.pos[row] = position
            batch.n_seq_id[row] = 1
            batch.seq_id[row][0] = seq
            batch.logits[row] = True
        code = llama_cpp.llama_decode(self.llama.ctx, batch)
        if code != 0:
            raise ModelError(
                f"model {self.model_id!r}: llama.cpp could not decode a batch of {len(rows)} "
                f"sequences (llama_decode returned {code}); ask for fewer answers or lower "
                "max_tokens"
            )

    def _evaluate_prompt(self, whole: list[int], cancel: threading.Event | None) -> bool:
        """Evaluates what the context lacks of ``whole`` (the last token at least, whose
        logits the first tokens are sampled from) in the batches ``Llama.generate`` uses;
        false if cancelled."""
        llama = self.llama
        start = min(_shared_length(llama.input_ids[: llama.n_tokens], whole), len(whole) - 1)
        llama._ctx.kv_cache_seq_rm(0, start, -1)
        llama.n_tokens = start
        for begin in range(start, len(whole), llama.n_batch):
            if cancel is not None and cancel.is_set():
                return False
            llama.eval(whole[begin : begin + llama.n_batch])
        return True

    def _generate(
        self,
        stream: TextStream,
        prefix: list[int],
        rest: list[int],
        *,
        max_tokens: int,
        options: GenerationOptions,
        grammar: LlamaGrammar | None,
        cancel: threading.Event | None,
    ) -> Iterator[str]:

        if not self._busy.acquire(blocking=False):
            raise ModelError(
                f"model {self.model_id!r} is already generating; finish or close that stream first"
            )
        try:
            self._check_open()
            whole = prefix + rest
            llama = self.llama
            prepared = self._prepare(prefix, whole, cancel, save=options.save_prefix)
            if prepared is None:
                stream.finish_reason = "cancelled"
                return
            stream.prefix_cache, stream.reused_tokens = prepared
            if cancel is not None and cancel.is_set():
                stream.finish_reason = "cancelled"
                return
            for text in self._decode(stream, whole, max_tokens, options, grammar, cancel):
                if self._lock is not None:
                    self._lock.progress(self._written + (stream.completion_tokens or 0))
                yield text
            self._written += stream.completion_tokens or 0
            if self._lock is not None:
                self._lock.progress(self._written, at_once=True)
            if stream.finish_reason != "cancelled":
                self._kept.keep(
                    PrefixState(
                        tuple(llama.input_ids[: llama.n_tokens].tolist()), self._state_bytes()
                    )
                )
        finally:
            self._busy.release()

    def _prepare(
        self,
        prefix: list[int],
        whole: list[int],
        cancel: threading.Event | None,
        *,
        save: bool,
    ) -> tuple[PrefixUse, int] | None:
        """Puts the longest reusable start of ``whole`` into the context: a kept state that
        shares more of it than the live context does, else the prefix (restored or evaluated);
        returns how the prefix was obtained and how many leading tokens are reused, or
        ``None`` if cancelled. The caller evaluates the rest."""
        llama = self.llama
        live = _shared_length(llama.input_ids[: llama.n_tokens], whole)
        kept = self._kept.closest(whole)
        if kept is not None and kept[1] > live and kept[1] >= len(prefix):
            self._load_state(kept[0])
            self._kept.keep(kept[0])  # now the most recently used
            return "memory", kept[1]
        if not prefix:
            return "off", live
        how = self._restore_prefix(prefix, cancel, save=save)
        if how is None:
            return None
        live = max(len(prefix), live) if how == "memory" else len(prefix)
        return how, live if how in ("memory", "disk") else 0

    def _decode(
        self,
        stream: TextStream,
        prompt: list[int],
        max_tokens: int,
        options: GenerationOptions,
        grammar: LlamaGrammar | None,
        cancel: threading.Event | None,
    ) -> Iterator[str]:
        """Samples up to ``max_tokens`` tokens after ``prompt`` and yields their text.

        The token loop is ours rather than llama-cpp-python's create_completion: that one
        detokenises the whole answer after every token and holds back bytes that are not yet
        valid UTF-8 (so a model that writes such bytes streams nothing, ever slower). Here each
        token's bytes go through an incremental decoder, and only text that could begin a stop
        string is held back.
        """
        import llama_cpp

        llama = self.llama
        sampling = self.entry.sampling
        llama.set_seed(sampling.seed if options.seed is None else options.seed)
        decoder = codecs.getincrementaldecoder("utf-8")(errors="replace")
        splitter = _StopSplitter(options.stop)
        temperature = sampling.temperature if options.temperature is None else options.temperature
        drafting = _lookup_applies(self.entry, options, temperature, grammar)
        counts = LookupCounts()
        tokens = (
            lookup_tokens(
                llama,
                prompt,
                max_ngram=self.entry.prompt_lookup.max_ngram,
                min_ngram=self.entry.prompt_lookup.min_ngram,
                draft_size=self.entry.prompt_lookup.draft_tokens,
                max_tokens=max_tokens,
                counts=counts,
            )
            if drafting
            else llama.generate(
                prompt,
                top_k=sampling.top_k,
                top_p=sampling.top_p if options.top_p is None else options.top_p,
                min_p=sampling.min_p,
                temp=temperature,
                repeat_penalty=sampling.repeat_penalty,
                grammar=grammar,
            )
        )
        written = 0
        finish: Literal["stop", "length", "cancelled"] = "length"
        try:
            for token in tokens:
                if cancel is not None and cancel.is_set():
                    finish = "cancelled"
                    break
                if llama_cpp.llama_vocab_is_eog(llama._model.vocab, token):
                    finish = "stop"
                    break
                written += 1
                stream.completion_tokens = written
                text, stopped = splitter.feed(decoder.decode(llama.detokenize([token])))
                if text:
                    yield text
                if stopped:
                    finish = "stop"
                    break
                if written >= max_tokens:
                    break
                # Checked after each token: a cancel set while the caller handled the last
                # chunk stops generation before another token is computed.
                if cancel is not None and cancel.is_set():
                    finish = "cancelled"
                    break
        finally:
            tokens.close()
        stream.completion_tokens = written
        if drafting:
            stream.drafted_tokens, stream.accepted_tokens = counts.drafted, counts.accepted
        if finish != "cancelled":
            tail, _ = splitter.feed(decoder.decode(b"", final=True), final=True)
            if tail:
                yield tail
        stream.finish_reason = finish

    def _cache_context(self) -> str:
        import llama_cpp

        # A context made for several sequences (one KV cache they share) is keyed apart from
        # a one-sequence context: its saved state is not promised to load into the other.
        sequences = f";n_seq_max={self.max_sequences}" if self.max_sequences > 1 else ""
        return (
            f"n_ctx={self.llama.n_ctx()};n_batch={self.llama.n_batch}{sequences};"
            f"llama-cpp-python={llama_cpp.__version__}"
        )

    def _restore_prefix(
        self, prefix: list[int], cancel: threading.Event | None, *, save: bool = True
    ) -> PrefixUse | None:
        """Puts the prefix's state into the context; returns how, or ``None`` if cancelled.
        A newly evaluated prefix is saved to the disk cache only when ``save``."""
        llama = self.llama
        n = len(prefix)
        if llama.n_tokens >= n and llama.input_ids[:n].tolist() == prefix:
            return "memory"
        key = prefix_key(self.model_file.sha256 or "nosum", prefix, context=self._cache_context())
        if self.prefix_cache is not None:
            saved = self.prefix_cache.load(key, prefix)
            if saved is not None:
                try:
                    self._load_state(saved)
                except (RuntimeError, ValueError) as error:
                    self.prefix_cache.discard(key, f"llama.cpp could not restore it ({error})")
                else:
                    return "disk"
        llama.reset()  # type: ignore[no-untyped-call]
        for start in range(0, n, llama.n_batch):
            if cancel is not None and cancel.is_set():
                llama.reset()  # type: ignore[no-untyped-call]
                return None
            llama.eval(prefix[start : start + llama.n_batch])
        if self.prefix_cache is None or not save:
            return "evaluated"
        try:
            self.prefix_cache.store(key, PrefixState(tuple(prefix), self._state_bytes()))
        except OSError as error:
            log.warning("could not save the prefix cache (%s); continuing without it", error)
            return "evaluated"
        return "stored"

    def _state_bytes(self) -> bytes:
        # Llama.save_state() also copies the score matrix (n_batch x vocabulary floats, ~300 MB
        # for a 150k-token vocabulary) that only log-probabilities need; take just the state.
        import ctypes

        import llama_cpp

        size = llama_cpp.llama_state_get_size(self.llama.ctx)
        buffer = (ctypes.c_uint8 * size)()
        written = llama_cpp.llama_state_get_data(self.llama.ctx, buffer, size)
        return bytes(memoryview(buffer)[:written])

    def _load_state(self, saved: PrefixState) -> None:
        import numpy as np
        from llama_cpp import LlamaState

        llama = self.llama
        ids = np.zeros(len(llama.input_ids), dtype=np.intc)
        ids[: len(saved.tokens)] = saved.tokens
        llama.load_state(
            LlamaState(
                input_ids=ids,
                scores=np.zeros((1, llama.n_vocab()), dtype=np.single),
                n_tokens=len(saved.tokens),
                llama_state=saved.state,
                llama_state_size=len(saved.state),
                seed=self.entry.sampling.seed,
            )
        )

    def close(self) -> None:
        """Frees the model's memory; the generator cannot be used afterwards."""
        if not self._closed:
            self._closed = True
            self._kept = _KeptStates(0)
            self.llama.close()
            if self._lock is not None:
                self._lock.release()

    def _check_open(self) -> None:
        # llama.cpp would crash the process on a freed model; refuse instead.
        if self._closed:
            raise ModelError(f"model {self.model_id!r} was closed; load it again to use it")


class _Sequence:
    """One answer of a batch as it is decoded: its text, tokens and end."""

    def __init__(self, stops: Sequence[str]) -> None:
        self.parts: list[str] = []
        self.written = 0
        self.finish: BatchFinish | None = None
        self._decoder = codecs.getincrementaldecoder("utf-8")(errors="replace")
        self._splitter = _StopSplitter(stops)

    def take(self, piece: bytes, on_chunk: ChunkSink | None, index: int) -> bool:
        """Adds a token's bytes; true when the answer ended (a stop string, or the sink
        asked to stop it)."""
        text, stopped = self._splitter.feed(self._decoder.decode(piece))
        if text and self._show(text, on_chunk, index):
            self.finish = "stopped"
            return True
        if stopped:
            self.finish = "stop"
        return stopped

    def end(self, finish: BatchFinish, on_chunk: ChunkSink | None, index: int) -> None:
        """Ends the answer, passing on the text held back (as :meth:`stream` does)."""
        self.finish = finish
        tail, _ = self._splitter.feed(self._decoder.decode(b"", final=True), final=True)
        if tail and self._show(tail, on_chunk, index):
            self.finish = "stopped"

    def _show(self, text: str, on_chunk: ChunkSink | None, index: int) -> bool:
        self.parts.append(text)
        return on_chunk is not None and on_chunk(index, text)


class _StopSplitter:
    """Passes streamed text on up to the first stop string, holding back only a tail that
    could be the start of one."""

    def __init__(self, stops: Sequence[str]) -> None:
        self.stops = [stop for stop in stops if stop]
        self.pending = ""

    def feed(self, text: str, *, final: bool = False) -> tuple[str, bool]:
        """Text that is safe to show, and whether a stop string was reached."""
        self.pending += text
        cuts = [self.pending.find(stop) for stop in self.stops]
        found = [cut for cut in cuts if cut >= 0]
        if found:
            shown, self.pending = self.pending[: min(found)], ""
            return shown, True
        keep = 0 if final else self._open_tail()
        cut = len(self.pending) - keep
        shown, self.pending = self.pending[:cut], self.pending[cut:]
        return shown, False

    def _open_tail(self) -> int:
        """Length of the longest end of the pending text that begins some stop string."""
        longest = 0
        for stop in self.stops:
            for size in range(min(len(stop) - 1, len(self.pending)), longest, -1):
                if self.pending.endswith(stop[:size]):
                    longest = size
                    break
        return longest


def _lookup_applies(
    entry: LlamaCppModel,
    options: GenerationOptions,
    temperature: float,
    grammar: LlamaGrammar | None,
) -> bool:
    """Whether this answer is decoded with prompt lookup: asked for (by the options, else
    the model's setting) and verifiable, that is greedy (temperature 0), unconstrained by
    a grammar and without a repeat penalty (see :mod:`skillwright.llm.lookup`)."""
    wanted = entry.prompt_lookup.enabled if options.prompt_lookup is None else options.prompt_lookup
    return (
        wanted and temperature == 0.0 and grammar is None and entry.sampling.repeat_penalty == 1.0
    )


def _shared_length(tokens: Sequence[int] | Any, other: Sequence[int]) -> int:
    """How many leading tokens ``tokens`` and ``other`` have in common."""
    import numpy as np

    n = min(len(tokens), len(other))
    if n == 0:
        return 0
    differ = np.flatnonzero(np.asarray(tokens[:n]) != np.asarray(other[:n], dtype=np.intc))
    return int(differ[0]) if differ.size else n


class _KeptStates:
    """Context states after earlier generations, in memory, within ``budget`` bytes."""

    def __init__(self, budget: int) -> None:
        self.budget = budget
        self._states: list[PrefixState] = []  # least recently used first

    def closest(self, tokens: Sequence[int]) -> tuple[PrefixState, int] | None:
        """The kept state sharing the most leading tokens with ``tokens``, and how many."""
        best: tuple[PrefixState, int] | None = None
        for state in self._states:
            shared = _shared_length(state.tokens, tokens)
            if shared and (best is None or shared > best[1]):
                best = (state, shared)
        return best

    def keep(self, state: PrefixState) -> None:
        """Keeps ``state`` (replacing one with the same tokens), dropping the least recently
        used ones beyond the budget; a state larger than the budget is not kept."""
        self._states = [s for s in self._states if s.tokens != state.tokens]
        if len(state.state) > self.budget:
            return
        self._states.append(state)
        while sum(len(s.state) for s in self._states) > self.budget:
            self._states.pop(0)


def _grammar(schema: dict[str, Any]) -> LlamaGrammar:
    from llama_cpp.llama_grammar import LlamaGrammar

    try:
        return LlamaGrammar.from_json_schema(json.dumps(schema), verbose=False)
    except (ValueError, TypeError, KeyError, NotImplementedError) as error:
        raise InvalidArgumentError(
            f"the JSON schema cannot be turned into a grammar: {error}; simplify the schema"
        ) from None


@functools.cache
def _close_null_files_at_exit() -> None:
    """Has the two ``/dev/null`` files closed at exit that llama-cpp-python opens when imported
    (it redirects native output into them while a model loads) and never closes; Python
    would report them as unclosed files when the process ends."""
    from llama_cpp import _utils

    for name in ("outnull_file", "errnull_file"):
        handle = getattr(_utils, name, None)
        if handle is not None:
            atexit.register(handle.close)


def _generation_threads() -> int:
    """Threads for generating tokens when models.toml does not say.

    Generation is memory-bound, so on big machines half the cores (llama-cpp-python's own
    default) is enough; on small ones every core counts: measured on 2 cores with the 1.5B
    default model, 6.2 tokens/s with 2 threads against 4.4 with 1.
    """
    cores = os.cpu_count() or 1
    return cores if cores <= 4 else cores // 2


def load_llamacpp(
    entry: LlamaCppModel,
    registry: Registry,
    *,
    cache: Path | None = None,
    prefix_cache: bool = True,
    on_wait: Callable[[ModelWait], None] | None = None,
    cancel: threading.Event | None = None,
) -> LlamaCppGenerator:
    """Checks a model's file (presence, GGUF header, checksum) and loads it with llama.cpp.

    ``cache`` defaults to :func:`~skillwright.llm.config.cache_dir`; saved prefix states go to
    its ``prefix`` folder unless ``prefix_cache`` is false.

    The model file's lock (:mod:`skillwright.llm.model_lock`) is taken before llama.cpp loads
    it and held until the generator is closed: while another generation holds it, this waits,
    calling ``on_wait`` with its place and the holder's status; ``cancel`` ends the wait.
    """
    folder = cache or cache_dir()
    checksums = ChecksumCache(folder / "checksums.json")
    # The prefix cache keys states by the model's checksum, so only it needs one computed.
    check = check_model_file if prefix_cache else inspect_model_file
    model_file = check(entry, registry, checksums)
    trained = model_file.info.context_length
    if trained is not None and entry.context_length > trained:
        log.warning(
            "model %s: context_length %d exceeds the %d tokens it was trained with; "
            "answers near the end of a long prompt may degrade",
            entry.id,
            entry.context_length,
            trained,
        )
    _close_null_files_at_exit()
    route_native_logs()
    lock = acquire_model_lock(entry.id, model_file.path, on_wait=on_wait, cancel=cancel)
    try:
        return _load(entry, registry, model_file, folder, prefix_cache=prefix_cache, lock=lock)
    except BaseException:
        lock.release()
        raise


def _context_cells(entry: LlamaCppModel, trained: int | None) -> int:
    """Tokens the context's KV cache holds: ``context_length`` for the prompt and one answer,
    and ``sampling.max_tokens`` more for each further sequence of a batch, so that a prompt
    that fits one answer also fits ``batch_sequences`` of the default length (the prompt's
    cells are shared, each answer's are its own).

    Not beyond the context the model was trained with (``trained``) unless ``context_length``
    itself is: llama.cpp warns of a training-context overflow when a context's cells exceed
    it, which the extra cells are not (no sequence's positions pass ``context_length``);
    a batch that does not fit the cells is refused with both numbers."""
    cells = entry.context_length + (entry.batch_sequences - 1) * entry.sampling.max_tokens
    if trained is not None and entry.context_length <= trained:
        cells = min(cells, trained)
    return cells


def _make_context_for_sequences(llama: Llama, sequences: int) -> None:
    """Replaces the context llama-cpp-python made (for one sequence: its ``Llama`` has no
    parameter for more) with one of the same parameters for ``sequences`` sequences.

    The KV cache is *unified* (``kv_unified``): all sequences share its cells and each
    sequence may use all of them, so a prompt's cells can belong to every sequence at once
    (``llama_memory_seq_cp`` adds sequence ids, nothing is copied), and one sequence alone
    (``stream()``) still has the whole context. Without it llama.cpp splits the cells into
    ``n_ctx / n_seq_max`` per sequence and copies the prompt into each part. The old context
    is freed first, so the two KV caches are never held at once.
    """
    import contextlib

    from llama_cpp import _internals

    params = llama.context_params
    params.n_seq_max = sequences
    params.kv_unified = True
    llama._ctx.close()  # type: ignore[no-untyped-call]
    context = _internals.LlamaContext(model=llama._model, params=params, verbose=llama.verbose)
    llama._ctx = llama._stack.enter_context(contextlib.closing(context))


def _load(
    entry: LlamaCppModel,
    registry: Registry,
    model_file: ModelFile,
    folder: Path,
    *,
    prefix_cache: bool,
    lock: ModelLock,
) -> LlamaCppGenerator:
    from llama_cpp import Llama

    started = time.perf_counter()
    try:
        llama = Llama(
            model_path=str(model_file.path),
            n_ctx=_context_cells(entry, model_file.info.context_length),
            n_batch=min(entry.batch_size, entry.context_length),
            n_threads=entry.threads or _generation_threads(),
            # Prompt evaluation is compute-bound: use every core unless told otherwise
            # (llama-cpp-python's default is half of them).
            n_threads_batch=entry.threads or os.cpu_count() or 1,
            seed=entry.sampling.seed,
            verbose=False,
        )
    except (ValueError, RuntimeError, OSError) as error:
        raise ModelError(
            f"model {entry.id!r}: llama.cpp could not load {model_file.path} ({error}); the file "
            "may be damaged or need a newer llama-cpp-python: copy it again or try another build"
        ) from None
    if entry.batch_sequences > 1:
        try:
            _make_context_for_sequences(llama, entry.batch_sequences)
        except ValueError as error:
            llama.close()
            raise ModelError(
                f"model {entry.id!r}: llama.cpp could not make a context for "
                f"{entry.batch_sequences} sequences ({error}); lower `batch_sequences` or "
                f"`context_length` of {entry.id!r} in {registry.origin}"
            ) from None
    log.info("model %s loaded in %.2f s", entry.id, time.perf_counter() - started)
    return LlamaCppGenerator(
        entry,
        model_file,
        llama,
        prefix_cache=PrefixCache(folder / "prefix") if prefix_cache else None,
        origin=registry.origin,
        lock=lock,
    )
