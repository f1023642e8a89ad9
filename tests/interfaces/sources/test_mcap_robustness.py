"""Damaged recordings give a partial result or a clear error: never a crash or a hang.

Every rosbag2 test recording is cut at many offsets and has bytes flipped (hypothesis
picks where); each read runs on a watchdog thread so a hang fails the test instead of
stalling the suite. The Rust crate has its own exhaustive versions of these tests.
"""

from __future__ import annotations

import faulthandler
import os
import threading
import time
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from skillwright import errors
from skillwright.core import read_mcap
from tests.conftest import SHARED

RECORDINGS = sorted((SHARED / "data" / "mcap" / "rosbag2").glob("**/*.mcap"))
WATCHDOG_SECONDS = 20.0


def _read_with_watchdog(path: Path, mode: str) -> Any:
    """Reads ``path``; fails the test if the read does not finish in time."""
    outcome: dict[str, Any] = {}

    def run() -> None:
        try:
            outcome["result"] = read_mcap(path, mode)  # type: ignore[arg-type]
        except BaseException as error:  # handed to the test thread below
            outcome["error"] = error

    worker = threading.Thread(target=run, daemon=True)
    worker.start()
    worker.join(WATCHDOG_SECONDS)
    if worker.is_alive():
        pytest.fail(f"reading {path} ({mode}) did not finish in {WATCHDOG_SECONDS} s")
    if "error" in outcome:
        error = outcome["error"]
        # A clear error is fine; anything else (PanicException, TypeError, ...) is a bug.
        assert isinstance(error, errors.FileFormatError), repr(error)
        assert str(path) in str(error)
        assert "at byte" in str(error)
        return None
    return outcome["result"]


@pytest.mark.parametrize("path", RECORDINGS, ids=[p.name for p in RECORDINGS])
def test_recording_truncated_at_many_offsets(path: Path, tmp_path: Path, shared_data: Path) -> None:
    data = path.read_bytes()
    whole = read_mcap(path)
    cut_file = tmp_path / "cut.mcap"
    cut_file.write_bytes(data)
    step = max(1, len(data) // 150)
    offsets = {*range(0, len(data), step), *range(max(0, len(data) - 64), len(data))}
    # Longest first, so each cut is a cheap truncate of the previous one.
    for offset in sorted(offsets, reverse=True):
        os.truncate(cut_file, offset)
        for mode in ("auto", "scan"):
            result = _read_with_watchdog(cut_file, mode)
            if result is None:
                assert offset < 8 + 9, f"only a cut inside the magic may be an error ({offset})"
                continue
            assert result.partial
            assert result.stopped is not None
            assert result.stopped.offset <= offset
            # Truncation only loses data: nothing appears that the whole file lacks.
            assert result.message_count <= whole.message_count
            whole_topics = {c.topic for c in whole.channels}
            assert {c.topic for c in result.channels} <= whole_topics


@settings(
    max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    index=st.integers(min_value=0, max_value=len(RECORDINGS) - 1 if RECORDINGS else 0),
    flips=st.lists(
        st.tuples(st.floats(0, 1, exclude_max=True), st.integers(0, 7)), min_size=1, max_size=4
    ),
    mode=st.sampled_from(["auto", "scan", "full"]),
)
def test_recording_with_flipped_bits(
    index: int, flips: list[tuple[float, int]], mode: str, tmp_path: Path, shared_data: Path
) -> None:
    data = bytearray(RECORDINGS[index].read_bytes())
    for where, bit in flips:
        data[int(where * len(data))] ^= 1 << bit
    path = tmp_path / "flipped.mcap"
    path.write_bytes(bytes(data))
    _read_with_watchdog(path, mode)


def test_empty_file_is_a_clear_error(tmp_path: Path) -> None:
    path = tmp_path / "empty.mcap"
    path.write_bytes(b"")
    with pytest.raises(errors.FileFormatError, match=r"empty\.mcap: empty file.*at byte 0"):
        read_mcap(path)


def test_non_mcap_file_is_a_clear_error(tmp_path: Path) -> None:
    path = tmp_path / "bag.db3"
    path.write_bytes(b"SQLite format 3\x00" + bytes(100))
    with pytest.raises(errors.FileFormatError, match=r"bag\.db3: not an MCAP file"):
        read_mcap(path)


def test_folder_and_unknown_mode_are_invalid_arguments(tmp_path: Path) -> None:
    with pytest.raises(errors.InvalidArgumentError, match="is a folder"):
        read_mcap(tmp_path)
    path = tmp_path / "x.mcap"
    path.write_bytes(b"")
    with pytest.raises(errors.InvalidArgumentError, match="unknown MCAP read mode"):
        read_mcap(path, "fast")  # type: ignore[arg-type]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs POSIX named pipes")
def test_reading_releases_the_gil(tmp_path: Path) -> None:
    """The reader blocks opening a named pipe until someone writes to it; that someone is
    this test's main thread, which can only run if the reader let go of the GIL."""
    pipe = tmp_path / "pipe.mcap"
    os.mkfifo(pipe)
    outcome: dict[str, BaseException] = {}

    def read() -> None:
        try:
            read_mcap(pipe)
        except BaseException as error:  # checked below
            outcome["error"] = error

    # If the GIL were held, the main thread could not even wake up to fail the test;
    # faulthandler ends the process with a traceback instead of hanging the suite.
    faulthandler.dump_traceback_later(60, exit=True)
    try:
        worker = threading.Thread(target=read, daemon=True)
        worker.start()
        time.sleep(0.2)  # the worker is now blocked inside read_mcap, opening the pipe
        with pipe.open("wb"):
            pass
        worker.join(WATCHDOG_SECONDS)
    finally:
        faulthandler.cancel_dump_traceback_later()
    assert not worker.is_alive()
    assert isinstance(outcome.get("error"), errors.FileFormatError)
    assert "empty file" in str(outcome["error"])
