"""One local model at a time: an advisory lock per model file, and who holds it.

On a small CPU, two generations at once do not share the machine, they ruin it for each
other: each decodes about twenty times slower than alone (the TUI and a CLI run on 2 cores
with the 1.5B default model: 0.3 to 0.5 tokens/s each). So a process takes the lock of
a model file before llama.cpp loads it and holds it until the model is closed; a second
generation (another CLI run, ``make eval``, the TUI, another thread) waits for it, and says
so: which model, its place in the line, and what the holder is doing.

Where the files are: ``<model file>.lock`` beside the model, when the models folder is
writable; otherwise (a read-only models folder) in ``$XDG_RUNTIME_DIR/skillwright/locks``
(else the cache folder's ``locks``), named after the model file and a hash of its absolute
path. The fallback only keeps apart the processes of one user, whose runtime folder it is.
Beside the lock: ``<lock>.json``, the holder's status (pid, command, skill, stage, tokens
written, when it took the lock; rewritten at most once a second, replaced atomically), and
``<lock>.queue/``, one file per waiter in the order they came, which is the order they get the
lock in.

The lock is ``fcntl.flock`` on the lock file: the kernel releases it when its holder exits,
however it ends, so a dead holder never blocks anyone; a status file or a waiter's file left
by a killed process is recognised (its pid is gone, or a waiter's file is not refreshed) and
ignored. The lock file is opened close-on-exec, so programs started meanwhile do not keep
it. Within a process, a thread that loads a model it already holds shares its lock (one
thread decodes one answer at a time anyway); another thread waits like another process.
"""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import json
import logging
import os
import secrets
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from skillwright.errors import OperationCancelledError
from skillwright.paths import cache_dir

__all__ = [
    "HolderStatus",
    "ModelLock",
    "ModelWait",
    "acquire_model_lock",
    "lock_path_for",
    "note_activity",
    "read_status",
]

log = logging.getLogger(__name__)

STATUS_INTERVAL = 1.0
"""Seconds between two rewrites of the holder's status for token counts alone."""
_POLL = 0.5
"""Seconds between a waiter's looks at the line and the lock."""
_STALE_TICKET = 10.0
"""A waiter's file not refreshed for this long belongs to a process that is gone."""


@dataclass(frozen=True)
class HolderStatus:
    """What the process holding a model's lock last said it was doing."""

    pid: int
    command: str
    """Its command line, shortened."""
    model: str
    """The model's id."""
    started_at: float
    """When it took the lock (seconds since the epoch)."""
    updated_at: float
    """When it last wrote this status."""
    skill: str | None = None
    """The skill it generates, when it generates one."""
    stage: str | None = None
    """The pipeline stage it is in."""
    tokens: int | None = None
    """Tokens the model has written since the lock was taken."""

    def describe(self, now: float | None = None) -> str:
        """One phrase: ``pid 4711 (skillwright generate ...) for 2:05, skill X, stage
        generation, 312 tokens written``."""
        now = time.time() if now is None else now
        held = max(0.0, now - self.started_at)
        parts = [f"pid {self.pid} ({self.command}) for {_clock(held)}"]
        if self.skill:
            parts.append(f"skill {self.skill}")
        if self.stage:
            parts.append(f"stage {self.stage}")
        if self.tokens is not None:
            parts.append(f"{self.tokens} tokens written")
        return ", ".join(parts)


@dataclass(frozen=True)
class ModelWait:
    """A waiter's view, reported every half second while it waits."""

    model: str
    """The model's id."""
    model_path: Path
    lock_path: Path
    place: int
    """1: next to get the model; 2: one waiter before this one; ..."""
    seconds: float
    """How long this one has waited."""
    holder: HolderStatus | None
    """The holder's status, ``None`` when it wrote none (or none readable)."""

    def message(self) -> str:
        """One line for a terminal or a status bar."""
        held = self.holder.describe() if self.holder is not None else "another process"
        ahead = "next in line" if self.place == 1 else f"place {self.place} in line"
        return (
            f"waiting for model {self.model} ({self.model_path.name}), in use by {held}; "
            f"{ahead}, waited {_clock(self.seconds)}"
        )


def _clock(seconds: float) -> str:
    whole = int(seconds)
    if whole < 60:
        return f"{whole} s"
    minutes, secs = divmod(whole, 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes}:{secs:02d}"


def lock_path_for(model_path: Path) -> Path:
    """Where the lock of ``model_path`` is (see the module docstring)."""
    if os.access(model_path.parent, os.W_OK):
        return model_path.with_name(model_path.name + ".lock")
    absolute = str(model_path.resolve())
    key = hashlib.sha256(absolute.encode("utf-8")).hexdigest()[:16]
    runtime = os.environ.get("XDG_RUNTIME_DIR")
    base = Path(runtime) / "skillwright" if runtime and Path(runtime).is_dir() else cache_dir()
    return base / "locks" / f"{model_path.name}-{key}.lock"


def read_status(lock_path: Path) -> HolderStatus | None:
    """The holder's status beside ``lock_path``, or ``None`` when there is none, it cannot
    be read (a partial or foreign file), or its process is gone."""
    try:
        data = json.loads(_status_path(lock_path).read_text(encoding="utf-8"))
        status = HolderStatus(
            pid=int(data["pid"]),
            command=str(data["command"]),
            model=str(data["model"]),
            started_at=float(data["started_at"]),
            updated_at=float(data["updated_at"]),
            skill=None if data.get("skill") is None else str(data["skill"]),
            stage=None if data.get("stage") is None else str(data["stage"]),
            tokens=None if data.get("tokens") is None else int(data["tokens"]),
        )
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return status if _alive(status.pid) else None


def _status_path(lock_path: Path) -> Path:
    return lock_path.with_name(lock_path.name + ".json")


def _queue_path(lock_path: Path) -> Path:
    return lock_path.with_name(lock_path.name + ".queue")


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True  # another user's process
    return True


def _command() -> str:
    """This process's command line, shortened: ``skillwright generate --capability ...``
    (``python -m skillwright`` shows as ``skillwright``, ``python -c`` as ``python -c``)."""
    first = Path(sys.argv[0]) if sys.argv and sys.argv[0] else Path("python")
    name = first.parent.name if first.name == "__main__.py" else first.name
    name = "python -c" if name == "-c" else name
    text = " ".join([name, *sys.argv[1:]])
    return text if len(text) <= 60 else text[:59] + "…"


_activity = threading.local()
_registry_lock = threading.Lock()
_held: dict[Path, _Hold] = {}


def note_activity(**fields: str | None) -> None:
    """Records what this thread is doing (``skill=``, ``stage=``) for the status of the model
    locks it holds and takes later; the status is rewritten at once when it changed."""
    current: dict[str, str | None] = getattr(_activity, "fields", {})
    changed = {k: v for k, v in fields.items() if current.get(k) != v}
    if not changed:
        return
    _activity.fields = {**current, **changed}
    me = threading.get_ident()
    with _registry_lock:
        holds = [hold for hold in _held.values() if hold.owner == me]
    for hold in holds:
        hold.write_status(force=True)


class _Hold:
    """One process's hold on a lock file: the locked descriptor and the status it writes."""

    def __init__(self, lock_path: Path, fd: int, model: str) -> None:
        self.lock_path = lock_path
        self.fd = fd
        self.model = model
        self.owner = threading.get_ident()
        self.users = 1
        self.started_at = time.time()
        self.tokens: int | None = None
        self.fields: dict[str, str | None] = dict(getattr(_activity, "fields", {}))
        self.written_at = 0.0

    def write_status(self, *, force: bool = False) -> None:
        """Rewrites the status file, unless it was written less than a second ago (the
        thread's activity is read only in the owner thread, which calls this)."""
        now = time.monotonic()
        if not force and now - self.written_at < STATUS_INTERVAL:
            return
        self.written_at = now
        if threading.get_ident() == self.owner:
            self.fields = dict(getattr(_activity, "fields", {}))
        status = {
            "pid": os.getpid(),
            "command": _command(),
            "model": self.model,
            "skill": self.fields.get("skill"),
            "stage": self.fields.get("stage"),
            "tokens": self.tokens,
            "started_at": self.started_at,
            "updated_at": time.time(),
        }
        target = _status_path(self.lock_path)
        try:
            fd, temporary = tempfile.mkstemp(dir=target.parent, prefix=".status-", suffix=".tmp")
            with os.fdopen(fd, "w", encoding="utf-8") as stream:
                json.dump(status, stream)
            Path(temporary).replace(target)
        except OSError as error:
            # Waiters then only say that someone else holds the model.
            log.debug("could not write the model lock status %s: %s", target, error)

    def close(self) -> None:
        with contextlib.suppress(OSError):
            current = read_status(self.lock_path)
            if current is not None and current.pid == os.getpid():
                _status_path(self.lock_path).unlink()
        fcntl.flock(self.fd, fcntl.LOCK_UN)
        os.close(self.fd)


class ModelLock:
    """A held model lock; :meth:`release` it when the model is closed."""

    def __init__(self, hold: _Hold) -> None:
        self._hold = hold
        self._released = False
        self.lock_path = hold.lock_path
        """The lock file."""

    def progress(self, tokens: int, *, at_once: bool = False) -> None:
        """The model has written ``tokens`` tokens since the lock was taken; the status says
        so within a second, or now when ``at_once`` (an answer ended)."""
        if tokens == self._hold.tokens and not at_once:
            return
        self._hold.tokens = tokens
        self._hold.write_status(force=at_once)

    def release(self) -> None:
        """Gives the model up (once; later calls do nothing)."""
        if self._released:
            return
        self._released = True
        with _registry_lock:
            self._hold.users -= 1
            last = self._hold.users == 0
            if last:
                del _held[self._hold.lock_path]
        if last:
            self._hold.close()


def acquire_model_lock(
    model: str,
    model_path: Path,
    *,
    on_wait: Callable[[ModelWait], None] | None = None,
    cancel: threading.Event | None = None,
) -> ModelLock:
    """Takes the lock of ``model_path`` (model id ``model``), waiting for its holder and for
    the waiters that came first.

    While it waits it calls ``on_wait`` every half second (by default it logs a warning when
    it starts waiting and when its place or the holder changes). ``cancel`` set, or Ctrl-C,
    ends the wait with :class:`~skillwright.errors.OperationCancelledError`.
    """
    lock_path = lock_path_for(model_path)
    me = threading.get_ident()
    with _registry_lock:
        hold = _held.get(lock_path)
        if hold is not None and hold.owner == me:
            hold.users += 1
            return ModelLock(hold)
    lock_path.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(lock_path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o666)
    try:
        _wait_for(fd, model, model_path, lock_path, on_wait or _Announcer(), cancel)
    except BaseException:
        os.close(fd)
        raise
    hold = _Hold(lock_path, fd, model)
    with _registry_lock:
        _held[lock_path] = hold
    hold.write_status(force=True)
    return ModelLock(hold)


def _try_lock(fd: int) -> bool:
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    return True


def _wait_for(
    fd: int,
    model: str,
    model_path: Path,
    lock_path: Path,
    on_wait: Callable[[ModelWait], None],
    cancel: threading.Event | None,
) -> None:
    queue = _queue_path(lock_path)
    if not _waiters(queue) and _try_lock(fd):
        return
    queue.mkdir(exist_ok=True)
    ticket = queue / f"{time.time_ns():020d}-{os.getpid()}-{secrets.token_hex(4)}"
    ticket.write_text(json.dumps({"pid": os.getpid(), "command": _command()}), encoding="utf-8")
    started = time.monotonic()
    try:
        while True:
            ahead = [name for name in _waiters(queue) if name < ticket.name]
            if not ahead and _try_lock(fd):
                return
            on_wait(
                ModelWait(
                    model=model,
                    model_path=model_path,
                    lock_path=lock_path,
                    place=len(ahead) + 1,
                    seconds=time.monotonic() - started,
                    holder=read_status(lock_path),
                )
            )
            if cancel is not None:
                cancel.wait(_POLL)
                if cancel.is_set():
                    raise OperationCancelledError(f"waiting for model {model} cancelled")
            else:
                time.sleep(_POLL)
            with contextlib.suppress(OSError):
                os.utime(ticket)
    except KeyboardInterrupt:
        raise OperationCancelledError(f"interrupted while waiting for model {model}") from None
    finally:
        ticket.unlink(missing_ok=True)


def _waiters(queue: Path) -> list[str]:
    """The waiters' files of live processes, in the order they came; stale ones removed."""
    try:
        entries = list(os.scandir(queue))
    except OSError:
        return []
    names = []
    now = time.time()
    for entry in entries:
        parts = entry.name.split("-")
        try:
            pid = int(parts[1])
            fresh = now - entry.stat().st_mtime < _STALE_TICKET
        except (IndexError, ValueError, OSError):
            continue
        if fresh and _alive(pid):
            names.append(entry.name)
        else:
            with contextlib.suppress(OSError):
                Path(entry.path).unlink()
    return sorted(names)


class _Announcer:
    """The default report of a wait: a logged warning when it starts and whenever the place
    in line or the holder changes (a CLI shows warnings on stderr)."""

    def __init__(self) -> None:
        self.last: tuple[int, int | None] | None = None

    def __call__(self, wait: ModelWait) -> None:
        key = (wait.place, None if wait.holder is None else wait.holder.pid)
        if key != self.last:
            self.last = key
            log.warning("%s", wait.message())
