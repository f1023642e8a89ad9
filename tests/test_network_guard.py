"""The suite's own network guard works, so 'no socket opens' means something."""

from __future__ import annotations

import socket

import pytest

from tests.conftest import NetworkAccessError

pytestmark = pytest.mark.network_guard_selftest


def test_opening_an_internet_socket_fails_the_test() -> None:
    with (
        socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock,
        pytest.raises(NetworkAccessError, match=r"192\.0\.2\.1"),
    ):
        sock.connect(("192.0.2.1", 80))


def test_create_connection_is_blocked_too() -> None:
    with pytest.raises(NetworkAccessError):
        socket.create_connection(("192.0.2.1", 443), timeout=0.1)
