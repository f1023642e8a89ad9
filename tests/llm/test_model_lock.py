"""One model at a time: the lock beside the model file, the holder's status, the line of
waiters, release on errors and cancels, and two real processes sharing the tiny model."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest

from skillwright.errors import ModelError, OperationCancelledError
from skillwright.llm import load_generator
from skillwright.llm import model_lock as lock_module
from skillwright.llm.config import Registry, load_registry
from skillwright.llm.model_lock import (
    HolderStatus,
    ModelLock,
    ModelWait,
    acquire_model_lock,
    lock_path_for,
    note_activity,
    read_status,
)
from tests.llm.conftest import write_models_toml

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def model_file(tmp_path: Path) -> Path:
    """A model file that is never loaded: the lock only needs its path."""
    path = tmp_path / "models" / "fake.gguf"
    path.parent.mkdir()
    path.write_bytes(b"GGUF")
    return path


def _wait_until(condition: object, seconds: float = 30.0) -> None:
    deadline = time.monotonic() + seconds
    while not condition():  # type: ignore[operator]
        if time.monotonic() > deadline:
            raise AssertionError("timed out")
        time.sleep(0.05)


def _holder(model_file: Path, release: Path, *, stage: str = "generation") -> subprocess.Popen[str]:
    """Another process that takes the lock, says what it does, and holds it until ``release``
    exists."""
    script = textwrap.dedent(
        f"""
        import sys, time
        from pathlib import Path
        from skillwright.llm.model_lock import acquire_model_lock, note_activity
        note_activity(skill="drive_square", stage={stage!r})
        lock = acquire_model_lock("fake", Path({str(model_file)!r}))
        lock.progress(312)
        time.sleep(1.1)
        lock.progress(313)
        print("held", flush=True)
        while not Path({str(release)!r}).exists():
            time.sleep(0.05)
        lock.release()
        print("released", flush=True)
        """
    )
    process = subprocess.Popen(
        [sys.executable, "-c", script], stdout=subprocess.PIPE, text=True, cwd=ROOT
    )
    assert process.stdout is not None
    assert process.stdout.readline().strip() == "held"
    return process


class _OtherThread:
    """Holds the lock in another thread (this thread's own loads would share it)."""

    def __init__(self, model_file: Path) -> None:
        self.taken = threading.Event()
        self.done = threading.Event()
        self.thread = threading.Thread(target=self._hold, args=(model_file,))
        self.thread.start()
        assert self.taken.wait(30)

    def _hold(self, model_file: Path) -> None:
        lock = acquire_model_lock("fake", model_file)
        self.taken.set()
        self.done.wait(30)
        lock.release()

    def release(self) -> None:
        self.done.set()
        self.thread.join(30)


def test_the_lock_lies_beside_the_model_file(model_file: Path) -> None:
    assert lock_path_for(model_file) == model_file.with_name("fake.gguf.lock")


def test_a_read_only_models_folder_puts_the_lock_in_the_runtime_folder(
    model_file: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    runtime = tmp_path / "run"
    runtime.mkdir()
    monkeypatch.setenv("XDG_RUNTIME_DIR", str(runtime))
    real_access = os.access

    def access(path: object, mode: int) -> bool:
        if Path(str(path)) == model_file.parent and mode == os.W_OK:
            return False
        return real_access(path, mode)  # type: ignore[arg-type]

    monkeypatch.setattr(lock_module.os, "access", access)
    path = lock_path_for(model_file)
    assert path.parent == runtime / "skillwright" / "locks"
    assert path.name.startswith("fake.gguf-")
    # Keyed by the model's absolute path: another file of the same name has another lock.
    other = tmp_path / "elsewhere" / "fake.gguf"
    assert lock_path_for(other) != path
    lock = acquire_model_lock("fake", model_file)
    try:
        assert path.is_file()
        assert read_status(path) is not None
    finally:
        lock.release()


def test_the_holder_writes_its_status_and_removes_it_on_release(model_file: Path) -> None:
    note_activity(skill="drive_square", stage="generation")
    try:
        lock = acquire_model_lock("fake", model_file)
        status = read_status(lock.lock_path)
        assert status is not None
        assert (status.pid, status.model, status.skill, status.stage, status.tokens) == (
            os.getpid(),
            "fake",
            "drive_square",
            "generation",
            None,
        )
        note_activity(stage="checks")  # a stage change is written at once
        status = read_status(lock.lock_path)
        assert status is not None
        assert status.stage == "checks"
        lock.release()
        assert read_status(lock.lock_path) is None
        assert not lock.lock_path.with_name("fake.gguf.lock.json").exists()
    finally:
        note_activity(skill=None, stage=None)


def test_token_counts_are_written_at_most_once_a_second(model_file: Path) -> None:
    lock = acquire_model_lock("fake", model_file)
    try:
        lock.progress(5)
        first = read_status(lock.lock_path)
        assert first is not None
        assert first.tokens is None  # written at the start, under a second ago
        time.sleep(lock_module.STATUS_INTERVAL + 0.05)
        lock.progress(9)
        later = read_status(lock.lock_path)
        assert later is not None
        assert later.tokens == 9
    finally:
        lock.release()


@pytest.mark.parametrize(
    "content",
    [
        "",
        '{"pid": 12',
        "not json",
        json.dumps({"pid": "x", "command": "c"}),
        json.dumps(["a list"]),
    ],
)
def test_a_partial_or_foreign_status_is_read_as_none(model_file: Path, content: str) -> None:
    lock_path = lock_path_for(model_file)
    lock_path.with_name(lock_path.name + ".json").write_text(content, encoding="utf-8")
    assert read_status(lock_path) is None


def test_the_status_of_a_process_that_is_gone_is_ignored(model_file: Path) -> None:
    gone = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"],
        check=True,
        capture_output=True,
        text=True,
    )
    pid = int(gone.stdout)
    lock_path = lock_path_for(model_file)
    status = {
        "pid": pid,
        "command": "skillwright generate",
        "model": "fake",
        "started_at": time.time(),
        "updated_at": time.time(),
    }
    lock_path.with_name(lock_path.name + ".json").write_text(json.dumps(status), "utf-8")
    assert read_status(lock_path) is None
    # Nor does it hold the lock: the kernel released it when the process ended.
    acquire_model_lock("fake", model_file).release()


def test_a_second_process_waits_prints_the_holders_status_and_proceeds_after_release(
    model_file: Path, tmp_path: Path
) -> None:
    release = tmp_path / "release"
    holder = _holder(model_file, release)
    waits: list[ModelWait] = []

    def on_wait(wait: ModelWait) -> None:
        waits.append(wait)
        if len(waits) == 3:
            release.touch()

    try:
        started = time.monotonic()
        lock = acquire_model_lock("fake", model_file, on_wait=on_wait)
        waited = time.monotonic() - started
    finally:
        release.touch()
        rest, _ = holder.communicate(timeout=30)
    assert rest.strip() == "released"
    lock.release()
    assert len(waits) >= 3
    assert waited >= 1.0
    first = waits[0]
    assert first.place == 1
    assert first.holder is not None
    assert (first.holder.pid, first.holder.skill, first.holder.stage, first.holder.tokens) == (
        holder.pid,
        "drive_square",
        "generation",
        313,
    )
    message = first.message()
    assert message.startswith("waiting for model fake (fake.gguf), in use by pid ")
    assert "skill drive_square, stage generation, 313 tokens written; next in line" in message
    # The waiter left no file in the line.
    queue = model_file.with_name("fake.gguf.lock.queue")
    assert not list(queue.iterdir())


def test_waiters_get_the_model_in_the_order_they_came(model_file: Path) -> None:
    holder = acquire_model_lock("fake", model_file)
    order: list[str] = []
    places: dict[str, list[int]] = {"first": [], "second": []}
    done = {"first": threading.Event(), "second": threading.Event()}

    def wait_for_it(name: str) -> None:
        lock = acquire_model_lock(
            "fake", model_file, on_wait=lambda w: places[name].append(w.place)
        )
        order.append(name)
        done[name].wait(30)
        lock.release()

    first = threading.Thread(target=wait_for_it, args=("first",))
    first.start()
    _wait_until(lambda: places["first"])
    second = threading.Thread(target=wait_for_it, args=("second",))
    second.start()
    _wait_until(lambda: places["second"])
    assert places["second"][-1] == 2
    holder.release()
    _wait_until(lambda: order == ["first"])
    _wait_until(lambda: places["second"][-1] == 1)
    done["first"].set()
    _wait_until(lambda: order == ["first", "second"])
    done["second"].set()
    first.join(30)
    second.join(30)
    assert places["first"]
    assert set(places["first"]) == {1}


def test_a_waiter_that_vanished_does_not_keep_its_place(model_file: Path) -> None:
    queue = model_file.with_name("fake.gguf.lock.queue")
    queue.mkdir()
    stale = queue / f"{1:020d}-{os.getpid()}-cafe0000"
    stale.write_text("{}", encoding="utf-8")
    old = time.time() - 60
    os.utime(stale, (old, old))  # a waiter refreshes its file every half second
    lock = acquire_model_lock("fake", model_file, on_wait=lambda _w: pytest.fail("waited"))
    lock.release()
    assert not stale.exists()


def test_the_same_thread_loading_again_shares_its_lock(model_file: Path) -> None:
    first = acquire_model_lock("fake", model_file)
    second = acquire_model_lock("fake", model_file, on_wait=lambda _w: pytest.fail("waited"))
    first.release()
    first.release()  # a second release of the same handle does nothing
    others: list[ModelWait] = []
    thread = threading.Thread(
        target=lambda: acquire_model_lock("fake", model_file, on_wait=others.append).release()
    )
    thread.start()
    _wait_until(lambda: others)  # still held through ``second``
    second.release()
    thread.join(30)
    assert not thread.is_alive()


def test_cancel_ends_the_wait_and_leaves_the_line(model_file: Path) -> None:
    holder = _OtherThread(model_file)
    cancel = threading.Event()
    try:
        with pytest.raises(OperationCancelledError, match="waiting for model fake cancelled"):
            acquire_model_lock("fake", model_file, on_wait=lambda _w: cancel.set(), cancel=cancel)
    finally:
        holder.release()
    assert not list(model_file.with_name("fake.gguf.lock.queue").iterdir())
    acquire_model_lock("fake", model_file).release()


def test_ctrl_c_while_waiting_is_a_cancel_with_exit_status_130(
    model_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    holder = _OtherThread(model_file)

    def interrupted(_seconds: float) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(lock_module.time, "sleep", interrupted)
    try:
        with pytest.raises(OperationCancelledError) as info:
            acquire_model_lock("fake", model_file, on_wait=lambda _w: None)
    finally:
        holder.release()
    assert str(info.value) == "interrupted while waiting for model fake"
    assert info.value.exit_code == 130


def test_the_default_report_is_a_warning_when_the_place_or_holder_changes(
    model_file: Path, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    release = tmp_path / "release"
    holder = _holder(model_file, release)
    timer = threading.Timer(1.6, release.touch)
    timer.start()
    try:
        with caplog.at_level("WARNING", logger="skillwright.llm.model_lock"):
            acquire_model_lock("fake", model_file).release()
    finally:
        release.touch()
        holder.communicate(timeout=30)
        timer.cancel()
    lines = [r.getMessage() for r in caplog.records if r.name == "skillwright.llm.model_lock"]
    assert len(lines) == 1  # three or more looks, one place, one holder
    assert lines[0].startswith("waiting for model fake")


def test_holder_status_describes_itself() -> None:
    status = HolderStatus(
        pid=7,
        command="skillwright tui",
        model="coder",
        started_at=1000.0,
        updated_at=1100.0,
        skill="patrol",
        stage="checks",
        tokens=40,
    )
    assert status.describe(now=1125.0) == (
        "pid 7 (skillwright tui) for 2:05, skill patrol, stage checks, 40 tokens written"
    )


# --- with the tiny GGUF model ---------------------------------------------------------------


def test_a_loaded_model_holds_its_lock_until_closed(tiny_registry: Registry, cache: Path) -> None:
    generator = load_generator(tiny_registry, "tiny", cache=cache)
    entry = tiny_registry.generation_model("tiny")
    path = lock_path_for(tiny_registry.resolve(entry.file))  # type: ignore[union-attr]
    status = read_status(path)
    assert status is not None
    assert status.model == "tiny"
    waits: list[ModelWait] = []
    loaded = threading.Event()

    def second() -> None:
        load_generator(tiny_registry, "tiny", cache=cache, on_wait=waits.append).close()
        loaded.set()

    thread = threading.Thread(target=second)
    thread.start()
    _wait_until(lambda: waits)
    assert not loaded.is_set()
    generator.close()
    thread.join(60)
    assert loaded.is_set()


def test_a_model_llama_cpp_cannot_load_releases_its_lock(tmp_path: Path, cache: Path) -> None:
    import gguf

    odd = tmp_path / "odd.gguf"
    writer = gguf.GGUFWriter(str(odd), "no-such-architecture")
    writer.write_header_to_file()
    writer.write_kv_data_to_file()
    writer.write_tensors_to_file()
    writer.close()
    registry = load_registry(write_models_toml(tmp_path / "models.toml", odd))
    with pytest.raises(ModelError, match=r"llama\.cpp could not load"):
        load_generator(registry, "tiny", cache=cache)
    assert lock_path_for(odd).is_file()  # it was taken before llama.cpp failed
    other: list[ModelLock] = []
    thread = threading.Thread(
        target=lambda: other.append(
            acquire_model_lock("tiny", odd, on_wait=lambda _w: pytest.fail("waited"))
        )
    )
    thread.start()
    thread.join(30)
    assert other
    other[0].release()


def test_a_generator_dropped_without_close_gives_the_model_up(
    tiny_registry: Registry, cache: Path
) -> None:
    import gc

    generator = load_generator(tiny_registry, "tiny", cache=cache)
    del generator
    gc.collect()
    # Another thread, as this one's own loads would share a lock still held.
    loaded: list[bool] = []
    thread = threading.Thread(
        target=lambda: loaded.append(
            load_generator(
                tiny_registry, "tiny", cache=cache, on_wait=lambda _w: pytest.fail("waited")
            ).close()
            is None
        )
    )
    thread.start()
    thread.join(60)
    assert loaded == [True]


def test_two_processes_share_the_tiny_model_one_after_the_other(
    tiny_registry: Registry, tmp_path: Path, cache: Path
) -> None:
    """The holder generates and reports its tokens; the second process waits, names the
    holder, and loads the model once the first closes it."""
    models = tiny_registry.origin
    release = tmp_path / "release"
    script = textwrap.dedent(
        f"""
        import time
        from pathlib import Path
        from skillwright.llm import load_generator
        from skillwright.llm.base import GenerationOptions, Prompt
        from skillwright.llm.config import load_registry
        from skillwright.llm.model_lock import note_activity
        note_activity(skill="set_velocity", stage="generation")
        generator = load_generator(load_registry(Path({str(models)!r})), "tiny",
                                   cache=Path({str(cache)!r}))
        prompt = Prompt.chat("Which topic moves the robot?")
        written = 0
        for _ in range(2):
            stream = generator.stream(prompt, GenerationOptions(max_tokens=10))
            stream.text()
            written += stream.completion_tokens
        print(written, flush=True)
        while not Path({str(release)!r}).exists():
            time.sleep(0.05)
        generator.close()
        """
    )
    holder = subprocess.Popen(
        [sys.executable, "-c", script], stdout=subprocess.PIPE, text=True, cwd=ROOT
    )
    assert holder.stdout is not None
    written = int(holder.stdout.readline())
    waits: list[ModelWait] = []

    def on_wait(wait: ModelWait) -> None:
        waits.append(wait)
        release.touch()

    try:
        generator = load_generator(tiny_registry, "tiny", cache=cache, on_wait=on_wait)
    finally:
        release.touch()
        holder.communicate(timeout=60)
    generator.close()
    assert holder.returncode == 0
    holder_status = waits[0].holder
    assert holder_status is not None
    assert (holder_status.pid, holder_status.skill, holder_status.tokens) == (
        holder.pid,
        "set_velocity",
        written,  # each answer's end is written at once
    )
