"""Generation on an OpenAI-compatible HTTP server (e.g. llama.cpp's ``llama-server``).

A team can share one large model on a GPU machine in the plant network. The server is
contacted only by :meth:`OpenAIGenerator.stream`, i.e. only when a user selects such a model;
loading the registry or listing models never opens a connection. Streaming uses server-sent
events of ``POST {base_url}/chat/completions``; a JSON schema is sent as ``response_format``
(llama.cpp's server turns it into a grammar). Only the standard library is used.
"""

from __future__ import annotations

import json
import os
import threading
import urllib.error
import urllib.request
from collections.abc import Iterator
from typing import Any

from skillwright.errors import ContextOverflowError, ModelServerError
from skillwright.llm.base import GenerationOptions, Prompt, TextStream
from skillwright.llm.config import OpenAIModel

__all__ = ["OpenAIGenerator"]


class OpenAIGenerator:
    """A model behind an OpenAI-compatible API; implements the ``TextGenerator`` contract.

    The server's tokenizer is not available here, so :meth:`count_tokens` returns ``None``; a
    request that does not fit is rejected by the server, and its message is passed on.
    """

    def __init__(self, entry: OpenAIModel) -> None:
        self.entry = entry
        """The model's ``models.toml`` entry."""
        self.model_id = entry.id
        self.context_length = entry.context_length

    def count_tokens(self, prompt: Prompt) -> int | None:
        """Always ``None``: the server's tokenizer is not available here."""
        return None

    def _request(self, prompt: Prompt, options: GenerationOptions, max_tokens: int) -> Any:
        sampling = self.entry.sampling
        messages = [{"role": m.role, "content": m.content} for m in prompt.messages]
        if prompt.answer_prefix:
            # A trailing assistant turn is continued by OpenAI-compatible servers that support
            # prefilling (llama.cpp's server does); the answer then starts after it.
            messages.append({"role": "assistant", "content": prompt.answer_prefix})
        body: dict[str, Any] = {
            "model": self.entry.model or self.entry.id,
            "messages": messages,
            "max_tokens": max_tokens,
            "temperature": sampling.temperature
            if options.temperature is None
            else options.temperature,
            "top_p": sampling.top_p if options.top_p is None else options.top_p,
            "seed": sampling.seed if options.seed is None else options.seed,
            "stream": True,
            # llama.cpp's server reuses the KV cache of a shared prompt prefix when asked.
            "cache_prompt": True,
        }
        if options.stop:
            body["stop"] = list(options.stop)
        if options.json_schema is not None:
            body["response_format"] = {
                "type": "json_schema",
                "json_schema": {"name": "answer", "schema": options.json_schema, "strict": True},
            }
        headers = {"Content-Type": "application/json", "Accept": "text/event-stream"}
        if self.entry.api_key_env:
            key = os.environ.get(self.entry.api_key_env)
            if not key:
                raise ModelServerError(
                    f"model {self.model_id!r}: the API key variable ${self.entry.api_key_env} is "
                    "not set; export it or remove `api_key_env` from the model's entry"
                )
            headers["Authorization"] = f"Bearer {key}"
        url = self.entry.base_url.rstrip("/") + "/chat/completions"
        request = urllib.request.Request(
            url, data=json.dumps(body).encode(), headers=headers, method="POST"
        )
        try:
            return urllib.request.urlopen(request, timeout=self.entry.timeout_s)
        except urllib.error.HTTPError as error:
            detail = error.read().decode("utf-8", errors="replace")[:500]
            raise ModelServerError(
                f"model {self.model_id!r}: {url} answered HTTP {error.code}: {detail}"
            ) from None
        except (urllib.error.URLError, OSError) as error:
            reason = getattr(error, "reason", error)
            raise ModelServerError(
                f"model {self.model_id!r}: cannot reach {url} ({reason}); check that the server "
                f"runs and `base_url` of {self.model_id!r} in your models.toml"
            ) from None

    def stream(
        self,
        prompt: Prompt,
        options: GenerationOptions | None = None,
        cancel: threading.Event | None = None,
    ) -> TextStream:
        """Starts a generation on the server; see the ``TextGenerator`` contract."""
        options = options or GenerationOptions()
        max_tokens = options.max_tokens or self.entry.sampling.max_tokens
        if max_tokens > self.context_length:
            raise ContextOverflowError(
                f"model {self.model_id!r}: max_tokens {max_tokens} exceeds the context of "
                f"{self.context_length} tokens; lower max_tokens or raise `context_length`"
            )
        stream = TextStream(iter(()))
        stream.chunks = self._generate(stream, prompt, options, max_tokens, cancel)
        return stream

    def _generate(
        self,
        stream: TextStream,
        prompt: Prompt,
        options: GenerationOptions,
        max_tokens: int,
        cancel: threading.Event | None,
    ) -> Iterator[str]:
        if cancel is not None and cancel.is_set():
            stream.finish_reason = "cancelled"
            return
        with self._request(prompt, options, max_tokens) as response:
            for raw in response:
                line = raw.decode("utf-8", errors="replace").strip()
                if not line.startswith("data:"):
                    continue  # blank separators, comments, event names
                data = line[len("data:") :].strip()
                if data == "[DONE]":
                    break
                try:
                    event = json.loads(data)
                except ValueError:
                    raise ModelServerError(
                        f"model {self.model_id!r}: the server sent a malformed event: {data[:200]}"
                    ) from None
                if "error" in event:
                    raise ModelServerError(
                        f"model {self.model_id!r}: server error: {event['error']}"
                    )
                usage = event.get("usage")
                if isinstance(usage, dict):
                    if isinstance(usage.get("prompt_tokens"), int):
                        stream.prompt_tokens = usage["prompt_tokens"]
                    if isinstance(usage.get("completion_tokens"), int):
                        stream.completion_tokens = usage["completion_tokens"]
                for choice in event.get("choices") or []:
                    text = (choice.get("delta") or {}).get("content")
                    if text:
                        yield text
                    reason = choice.get("finish_reason")
                    if reason in ("stop", "length"):
                        stream.finish_reason = reason
                if cancel is not None and cancel.is_set():
                    stream.finish_reason = "cancelled"
                    return
        if stream.finish_reason is None:
            stream.finish_reason = "stop"

    def close(self) -> None:
        """Nothing to release: every request opens and closes its own connection."""
