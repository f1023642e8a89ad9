"""Fixtures shared by the whole test suite.

Every test runs with the network cut off: opening an internet socket fails the test.
That is how the suite proves skillwright works offline. A test that talks to a server it
starts itself on this machine marks itself ``@pytest.mark.loopback``.
"""

from __future__ import annotations

import logging
import socket
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent
SHARED = REPO_ROOT.parent / "shared"
SHIPPED_CAPABILITIES = REPO_ROOT / "capabilities"


class NetworkAccessError(OSError):
    """Raised when a test opens an internet socket.

    An ``OSError`` so that library code cleans up its socket as for any refused
    connection; the attempt is also recorded and fails the test at teardown, even when
    the code under test swallows the error.
    """


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers", "loopback: the test may connect to servers on 127.0.0.1 / ::1 only"
    )
    config.addinivalue_line(
        "markers", "network_guard_selftest: the test checks the network guard itself"
    )


def _is_loopback(address: Any) -> bool:
    host = address[0] if isinstance(address, tuple) else address
    return host in {"127.0.0.1", "::1", "localhost"}


@pytest.fixture(autouse=True)
def _no_network(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    allow_loopback = request.node.get_closest_marker("loopback") is not None
    real_connect = socket.socket.connect
    real_connect_ex = socket.socket.connect_ex
    attempts: list[Any] = []

    def guard(sock: socket.socket, address: Any) -> None:
        if sock.family == socket.AF_UNIX:
            return
        if allow_loopback and _is_loopback(address):
            return
        attempts.append(address)
        raise NetworkAccessError(f"test tried to open a network connection to {address!r}")

    def connect(sock: socket.socket, address: Any) -> None:
        guard(sock, address)
        real_connect(sock, address)

    def connect_ex(sock: socket.socket, address: Any) -> int:
        guard(sock, address)
        return real_connect_ex(sock, address)

    monkeypatch.setattr(socket.socket, "connect", connect)
    monkeypatch.setattr(socket.socket, "connect_ex", connect_ex)
    yield
    if attempts and request.node.get_closest_marker("network_guard_selftest") is None:
        pytest.fail(f"the test tried to reach the network: {attempts!r}")


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """``../shared/data`` beside the repository; tests that need it skip without it."""
    data = SHARED / "data"
    if not data.is_dir():
        pytest.skip(f"reference data not found at {data} (CI has it beside the repository)")
    return data


@pytest.fixture(autouse=True)
def _fresh_skillwright_logger() -> Iterator[None]:
    """Undoes what a CLI run did to the ``skillwright`` logger (its stderr handler, no
    propagation): a test after it would otherwise see warnings on stderr that its own code
    never printed, and caplog would miss them."""
    logger = logging.getLogger("skillwright")
    handlers, propagate = list(logger.handlers), logger.propagate
    yield
    logger.handlers[:] = handlers
    logger.propagate = propagate
