"""The cancel switch engine calls look at between their steps."""

from __future__ import annotations

import threading

import pytest

from skillwright.cancel import raise_if_cancelled
from skillwright.errors import GenerationCancelledError, OperationCancelledError


def test_nothing_happens_without_a_switch_or_while_it_is_off() -> None:
    raise_if_cancelled(None, "reading")
    raise_if_cancelled(threading.Event(), "reading")


def test_a_set_switch_raises_with_what_was_cancelled() -> None:
    cancel = threading.Event()
    cancel.set()
    with pytest.raises(OperationCancelledError, match=r"^reading x\.ttl cancelled$") as info:
        raise_if_cancelled(cancel, "reading x.ttl")
    assert info.value.exit_code == 130


def test_a_cancelled_generation_is_a_cancelled_operation() -> None:
    assert issubclass(GenerationCancelledError, OperationCancelledError)
    assert GenerationCancelledError.exit_code == 130
