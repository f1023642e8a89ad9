"""The OpenAI-compatible HTTP backend, against a small server on 127.0.0.1."""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any, ClassVar

import pytest

from skillwright.errors import ContextOverflowError, ModelServerError
from skillwright.llm import load_generator
from skillwright.llm.base import GenerationOptions, Prompt, TextGenerator
from skillwright.llm.config import load_registry
from skillwright.llm.openai_http import OpenAIGenerator

PROMPT = Prompt.chat("Which topic moves the robot?", system="You write ROS 2 skills.")


class FakeServer(BaseHTTPRequestHandler):
    """Streams a fixed answer as server-sent events and records what it was sent."""

    requests: ClassVar[list[dict[str, Any]]] = []
    status: ClassVar[int] = 200
    pieces: ClassVar[list[str]] = ["Use ", "/cmd", "_vel", "."]

    def do_POST(self) -> None:
        body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
        type(self).requests.append(
            {"path": self.path, "body": body, "auth": self.headers.get("Authorization")}
        )
        if self.status != 200:
            self.send_response(self.status)
            self.end_headers()
            self.wfile.write(b'{"error": "model overloaded"}')
            return
        self.send_response(200)
        self.send_header("Content-Type", "text/event-stream")
        self.end_headers()
        for index, piece in enumerate(self.pieces):
            last = index == len(self.pieces) - 1
            event = {
                "choices": [
                    {"delta": {"content": piece}, "finish_reason": "stop" if last else None}
                ]
            }
            self.wfile.write(f"data: {json.dumps(event)}\n\n".encode())
            self.wfile.flush()
        self.wfile.write(b"data: [DONE]\n\n")

    def log_message(self, format: str, *args: Any) -> None:
        """Quiet."""


@pytest.fixture
def server() -> Iterator[str]:
    FakeServer.requests = []
    FakeServer.status = 200
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), FakeServer)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{httpd.server_address[1]}/v1"
    httpd.shutdown()
    httpd.server_close()


def _generator(tmp_path: Path, base_url: str, extra: str = "") -> OpenAIGenerator:
    path = tmp_path / "models.toml"
    path.write_text(
        f'[[llm]]\nid = "gpu"\nbackend = "openai"\nbase_url = "{base_url}"\nmodel = "big"\n'
        f"context_length = 4096\n{extra}"
    )
    generator = load_generator(load_registry(path), "gpu")
    assert isinstance(generator, OpenAIGenerator)
    return generator


@pytest.mark.loopback
def test_streams_the_servers_chunks(tmp_path: Path, server: str) -> None:
    generator = _generator(tmp_path, server)
    assert isinstance(generator, TextGenerator)
    stream = generator.stream(PROMPT, GenerationOptions(max_tokens=50, stop=("\n",)))
    assert list(stream) == ["Use ", "/cmd", "_vel", "."]
    assert stream.finish_reason == "stop"
    [request] = FakeServer.requests
    assert request["path"] == "/v1/chat/completions"
    body = request["body"]
    assert body["model"] == "big"
    assert body["stream"] is True
    assert body["messages"][0] == {"role": "system", "content": "You write ROS 2 skills."}
    assert (body["max_tokens"], body["temperature"], body["stop"]) == (50, 0.0, ["\n"])
    assert request["auth"] is None


@pytest.mark.loopback
def test_json_schema_is_sent_as_response_format(tmp_path: Path, server: str) -> None:
    schema = {"type": "object", "properties": {"ok": {"type": "boolean"}}}
    _generator(tmp_path, server).stream(PROMPT, GenerationOptions(json_schema=schema)).text()
    sent = FakeServer.requests[0]["body"]["response_format"]
    assert sent["type"] == "json_schema"
    assert sent["json_schema"]["schema"] == schema


@pytest.mark.loopback
def test_api_key_comes_from_the_named_variable(
    tmp_path: Path, server: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("PLANT_KEY", "s3cret")
    _generator(tmp_path, server, 'api_key_env = "PLANT_KEY"\n').stream(PROMPT).text()
    assert FakeServer.requests[0]["auth"] == "Bearer s3cret"


def test_missing_api_key_variable_is_reported_before_connecting(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("PLANT_KEY", raising=False)
    generator = _generator(tmp_path, "http://192.0.2.7:8080/v1", 'api_key_env = "PLANT_KEY"\n')
    with pytest.raises(ModelServerError, match=r"\$PLANT_KEY is not set"):
        generator.stream(PROMPT).text()


@pytest.mark.loopback
def test_cancel_stops_reading_the_stream(tmp_path: Path, server: str) -> None:
    cancel = threading.Event()
    stream = _generator(tmp_path, server).stream(PROMPT, cancel=cancel)
    assert next(stream) == "Use "
    cancel.set()
    assert list(stream) == []
    assert stream.finish_reason == "cancelled"


@pytest.mark.loopback
def test_server_error_is_reported_with_status_and_body(tmp_path: Path, server: str) -> None:
    FakeServer.status = 503
    with pytest.raises(ModelServerError, match=r"model 'gpu': .* answered HTTP 503: .*overloaded"):
        _generator(tmp_path, server).stream(PROMPT).text()


@pytest.mark.loopback
def test_unreachable_server_names_the_url_and_the_setting(tmp_path: Path) -> None:
    import socket

    with socket.socket() as probe:  # a port that was free a moment ago: nobody listens there
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    generator = _generator(tmp_path, f"http://127.0.0.1:{port}/v1")
    with pytest.raises(
        ModelServerError, match=rf"cannot reach http://127.0.0.1:{port}/v1/chat.*base_url"
    ):
        generator.stream(PROMPT).text()


def test_max_tokens_beyond_the_context_is_refused_up_front(tmp_path: Path) -> None:
    generator = _generator(tmp_path, "http://192.0.2.7:8080/v1")
    with pytest.raises(ContextOverflowError, match="exceeds the context of 4096"):
        generator.stream(PROMPT, GenerationOptions(max_tokens=5000))


def test_configured_server_is_not_contacted_until_used(tmp_path: Path) -> None:
    # The network guard fails this test on any connection attempt.
    generator = _generator(tmp_path, "http://192.0.2.7:8080/v1")
    stream = generator.stream(PROMPT)  # lazy: the request goes out on first iteration
    assert generator.count_tokens(PROMPT) is None
    assert stream.finish_reason is None
