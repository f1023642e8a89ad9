"""The cancel switch engine calls look at between their steps, and Ctrl-C held back."""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator

import pytest

from skillwright.cancel import interrupts_held, raise_if_cancelled
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


@pytest.fixture
def ctrl_c_raises() -> Iterator[None]:
    """Ctrl-C as in a plain ``python`` process (a test runner may have changed it)."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


@pytest.mark.usefixtures("ctrl_c_raises")
def test_ctrl_c_in_a_held_block_comes_once_the_block_is_done() -> None:
    done: list[str] = []

    def block() -> None:
        with interrupts_held():
            signal.raise_signal(signal.SIGINT)
            done.append("the rest of the block")

    with pytest.raises(KeyboardInterrupt):
        block()
    assert done == ["the rest of the block"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


@pytest.mark.usefixtures("ctrl_c_raises")
def test_a_held_block_that_fails_gives_its_error_not_the_interrupt() -> None:
    def block() -> None:
        with interrupts_held():
            signal.raise_signal(signal.SIGINT)
            raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        block()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


@pytest.mark.usefixtures("ctrl_c_raises")
def test_a_held_block_without_ctrl_c_changes_nothing() -> None:
    with interrupts_held():
        pass
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_outside_the_main_thread_nothing_is_held() -> None:
    seen: list[object] = []

    def work() -> None:
        with interrupts_held():
            seen.append(signal.getsignal(signal.SIGINT))

    before = signal.getsignal(signal.SIGINT)
    worker = threading.Thread(target=work)
    worker.start()
    worker.join()
    assert seen == [before]
