"""Starting the sandboxed child process and making sure nothing of it survives.

The child is ``python -I -S -B boot.py``: isolated mode (no user site, no ``PYTHON*``
variables, no current folder on ``sys.path``), no site-packages, no bytecode written. It
runs in a new session (its own process group), with a scrubbed environment, in a
private temporary folder that is also its ``HOME`` and ``TMPDIR``, and holds one end of
a socketpair. ``boot.py`` then adds namespaces, rlimits and the audit hook before the
skill's code runs (see there).

Children come from a fork server (``boot.py --zygote``, started the same way): it has
imported the child's modules once and forks a child per run, which then starts its own
session and isolates itself exactly as a directly started child does. A
:class:`ChildPool` owns one fork server and keeps the next child started while the
current one runs.

:meth:`SandboxProcess.close` kills the process group (and, with a PID namespace, every
process the skill could have started), reaps the child with its resource use, and
removes the temporary folder.
"""

from __future__ import annotations

import compileall
import contextlib
import importlib.util
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import sysconfig
import tempfile
import time
import uuid
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any, Final

from skillwright.runtime.scenario import Limits

__all__ = [
    "CHILD_ROOT",
    "MARKER_VARIABLE",
    "ChildPool",
    "ForkServer",
    "SandboxError",
    "SandboxProcess",
    "start_child",
]

CHILD_ROOT: Final = Path(__file__).resolve().with_name("child")
"""The child's ``sys.path`` root: its own package and the stand-ins."""

MARKER_VARIABLE: Final = "SKILLWRIGHT_SANDBOX"
"""Environment variable every sandboxed process carries, with the id of the run (or of the
fork server it came from) as its value (tests find stray processes by it)."""


class SandboxError(OSError):
    """The fork server did not answer as it should (it died, or was killed)."""


_ALLOWED_PACKAGES: Final = ("numpy",)
_CLOCK_TICKS: Final = os.sysconf("SC_CLK_TCK")
"""Third-party packages a skill may import besides ROS 2's, where the host has them."""


@cache
def _prepare_child_code() -> None:
    """Compiles the child's modules once, so the child (which writes no bytecode) starts
    fast; an install folder that cannot be written just makes the child compile in memory."""
    with contextlib.suppress(OSError):
        compileall.compile_dir(str(CHILD_ROOT), quiet=2, workers=1)


@cache
def allowed_packages() -> tuple[tuple[str, str], ...]:
    """``(name, folder holding it)`` of the allowed packages installed here."""
    found = []
    for name in _ALLOWED_PACKAGES:
        spec = importlib.util.find_spec(name)
        if spec is not None and spec.submodule_search_locations:
            package = Path(next(iter(spec.submodule_search_locations)))
            found.append((name, str(package.parent)))
    return tuple(found)


def read_roots() -> list[str]:
    """Folders the child may read: the standard library, its own code, allowed packages."""
    return list(_read_roots())


@cache
def _read_roots() -> tuple[str, ...]:
    paths = sysconfig.get_paths()
    roots = {paths["stdlib"], paths["platstdlib"], str(CHILD_ROOT)}
    for name, folder in allowed_packages():
        roots.add(str(Path(folder) / name))
        roots.update(str(p) for p in Path(folder).glob(f"{name}.libs"))
        roots.update(str(p) for p in Path(folder).glob(f"{name}-*.dist-info"))
    roots.update({"/dev/null", "/dev/urandom"})
    return tuple(sorted(roots))


@dataclass
class SandboxProcess:
    """A running child and what is needed to talk to it and to end it."""

    pid: int
    """Process id of the child (also its process group and session)."""
    sock: socket.socket
    temp: Path
    marker: str
    popen: subprocess.Popen[bytes] | None = None
    """The child when the host started it itself."""
    server: ForkServer | None = None
    """The fork server it came from, which reaps it."""
    started: float = field(default_factory=time.monotonic)
    rusage: dict[str, float] = field(default_factory=dict)
    exit_status: int | None = None

    def running(self) -> bool:
        """Whether the child has not ended yet."""
        if self.exit_status is not None:
            return False
        if self.popen is not None:
            return self.popen.poll() is None
        try:
            stat = Path(f"/proc/{self.pid}/stat").read_bytes()
        except OSError:
            return False
        return stat[stat.rfind(b")") + 2 :][:1] not in (b"Z", b"X")

    def cpu_seconds(self) -> float | None:
        """CPU time the child and its first process (in a PID namespace) have used so far,
        or ``None`` where ``/proc`` does not say."""
        total = 0.0
        pids = [self.pid]
        try:
            children = Path(f"/proc/{self.pid}/task/{self.pid}/children")
            pids += [int(p) for p in children.read_text().split()]
            for pid in pids:
                fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
                # utime and stime are fields 14 and 15 of stat, 12 and 13 after the name.
                total += (int(fields[11]) + int(fields[12])) / _CLOCK_TICKS
        except (OSError, ValueError, IndexError):
            return None
        return total

    def interrupt(self) -> None:
        """Asks the child to stop the state that runs (it reports where it was)."""
        with contextlib.suppress(ProcessLookupError):
            os.kill(self.pid, signal.SIGUSR1)

    def place(self, skill_source: str, skill_name: str) -> None:
        """Writes the skill into the child's folder (before the child is told where it is);
        the run's wall deadline counts from here."""
        (self.temp / skill_name).write_text(skill_source, encoding="utf-8")
        self.started = time.monotonic()

    def output_tail(self, limit: int = 4000) -> str:
        """The end of what the child wrote to its own stdout/stderr (crash messages)."""
        path = self.temp / "child-output.txt"
        try:
            with path.open("rb") as stream:
                stream.seek(0, os.SEEK_END)
                size = stream.tell()
                stream.seek(max(0, size - limit))
                return stream.read().decode("utf-8", "replace")
        except OSError:
            return ""

    def close(self) -> None:
        """Kills every process of the child's group, reaps the child, removes its folder."""
        if self.exit_status is not None:
            return
        # The skill's process (in a PID namespace) is killed before its parent reaps it, so
        # the parent's resource use may miss it; /proc still counts it at this point.
        seen = self.cpu_seconds()
        with contextlib.suppress(OSError):
            self.sock.close()
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(self.pid, signal.SIGKILL)
        status, cpu, rss_kb = self._reap()
        self.exit_status = status
        if cpu is not None:
            self.rusage = {
                "cpu_seconds": round(max(cpu, seen or 0.0), 3),
                "max_rss_mb": round(rss_kb / 1024, 1),
            }
        # The skill runs in a process the child forked (in its own PID namespace where the
        # kernel allows); SIGKILL reaches it at once but it may take a moment to die on a busy
        # machine. Nothing of the run may outlive close(), so wait until the group is gone.
        _wait_until_group_gone(self.pid)
        shutil.rmtree(self.temp, ignore_errors=True)

    def _reap(self) -> tuple[int, float | None, float]:
        """Waits for the killed child: its exit status, CPU seconds and peak memory (kB)."""
        if self.popen is not None:
            if self.popen.returncode is not None:
                return self.popen.returncode, None, 0.0
            try:
                _, status, usage = os.wait4(self.pid, 0)
            except ChildProcessError:
                self.popen.returncode = 0
                return 0, None, 0.0
            self.popen.returncode = os.waitstatus_to_exitcode(status)
            return self.popen.returncode, usage.ru_utime + usage.ru_stime, usage.ru_maxrss
        assert self.server is not None
        try:
            answer = self.server.reap(self.pid)
        except SandboxError:
            # The server is gone, and its children with it (they die with their parent).
            return -signal.SIGKILL, None, 0.0
        if answer.get("status") is None:
            return 0, None, 0.0
        return int(answer["status"]), float(answer["cpu_seconds"]), float(answer["max_rss_kb"])


def _live_members(group: int) -> list[int]:
    """Processes of process group ``group`` that are not zombies (from /proc)."""
    members = []
    # Raw reads: this runs after every run, and Path objects for every process of the
    # machine cost milliseconds.
    for entry in os.scandir("/proc"):
        name = entry.name
        if not name.isdigit():
            continue
        try:
            descriptor = os.open(f"/proc/{name}/stat", os.O_RDONLY)
        except OSError:
            continue
        try:
            stat = os.read(descriptor, 512)
        except OSError:
            continue
        finally:
            os.close(descriptor)
        # Fields after the command name (which may hold spaces): state ppid pgrp ...
        fields = stat[stat.rfind(b")") + 2 :].split(maxsplit=3)
        if len(fields) > 2 and int(fields[2]) == group and fields[0] != b"Z":
            members.append(int(name))
    return members


def _wait_until_group_gone(group: int, timeout: float = 5.0) -> None:
    deadline = time.monotonic() + timeout
    # A killed process is usually gone within a millisecond: look again soon, then less often.
    delay = 0.0005
    while _live_members(group) and time.monotonic() < deadline:
        time.sleep(delay)
        delay = min(2 * delay, 0.01)


def _environment(temp: Path, marker: str) -> dict[str, str]:
    return {
        "PATH": "/usr/bin:/bin",
        "HOME": str(temp),
        "TMPDIR": str(temp),
        "LANG": "C.UTF-8",
        "LC_ALL": "C.UTF-8",
        "TZ": "UTC",
        "OPENBLAS_NUM_THREADS": "1",
        "OMP_NUM_THREADS": "1",
        "MKL_NUM_THREADS": "1",
        MARKER_VARIABLE: marker,
    }


def start_child() -> SandboxProcess:
    """Starts a child in a private temporary folder; it boots (interpreter, namespaces,
    its own modules) and then waits for the host's answer to its ``hello``, so the skill
    can be placed (:meth:`SandboxProcess.place`) any time before that answer."""
    _prepare_child_code()
    temp = Path(tempfile.mkdtemp(prefix="skillwright-run-")).resolve()
    marker = uuid.uuid4().hex
    host_end, child_end = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        with (temp / "child-output.txt").open("wb") as output:
            process = subprocess.Popen(
                [
                    sys.executable,
                    "-I",
                    "-S",
                    "-B",
                    str(CHILD_ROOT / "_skillwright_child" / "boot.py"),
                    str(child_end.fileno()),
                    str(temp),
                ],
                stdin=subprocess.DEVNULL,
                stdout=output,
                stderr=subprocess.STDOUT,
                pass_fds=(child_end.fileno(),),
                cwd=temp,
                env=_environment(temp, marker),
                start_new_session=True,
            )
    except BaseException:
        host_end.close()
        shutil.rmtree(temp, ignore_errors=True)
        raise
    finally:
        child_end.close()
    return SandboxProcess(pid=process.pid, sock=host_end, temp=temp, marker=marker, popen=process)


class ForkServer:
    """A running fork server (``boot.py --zygote``) and its end of the control socket.

    Started like a child (its own session, the scrubbed environment, a private folder);
    :meth:`close` kills it and everything of its process group.
    """

    def __init__(self) -> None:
        _prepare_child_code()
        self.temp = Path(tempfile.mkdtemp(prefix="skillwright-forks-")).resolve()
        self.marker = uuid.uuid4().hex
        host_end, server_end = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        try:
            with (self.temp / "server-output.txt").open("wb") as output:
                self.process = subprocess.Popen(
                    [
                        sys.executable,
                        "-I",
                        "-S",
                        "-B",
                        str(CHILD_ROOT / "_skillwright_child" / "boot.py"),
                        "--zygote",
                        str(server_end.fileno()),
                    ],
                    stdin=subprocess.DEVNULL,
                    stdout=output,
                    stderr=subprocess.STDOUT,
                    pass_fds=(server_end.fileno(),),
                    cwd=self.temp,
                    env=_environment(self.temp, self.marker),
                    start_new_session=True,
                )
        except BaseException:
            host_end.close()
            shutil.rmtree(self.temp, ignore_errors=True)
            raise
        finally:
            server_end.close()
        self.control = host_end

    def _ask(self, request: dict[str, object], fds: list[int] | None = None) -> dict[str, Any]:
        data = json.dumps(request).encode("utf-8")
        try:
            socket.send_fds(self.control, [data], fds or [])
            answer = self.control.recv(65536)
        except OSError as error:
            raise SandboxError(f"the sandbox's fork server is gone ({error})") from None
        if not answer:
            raise SandboxError("the sandbox's fork server is gone")
        reply: dict[str, Any] = json.loads(answer)
        return reply

    def fork(self) -> SandboxProcess:
        """A new child in a private temporary folder, booting towards its ``hello``."""
        temp = Path(tempfile.mkdtemp(prefix="skillwright-run-")).resolve()
        host_end, child_end = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            answer = self._ask({"op": "fork", "temp": str(temp)}, [child_end.fileno()])
            pid = answer.get("pid")
            if not isinstance(pid, int):
                raise SandboxError(f"the sandbox's fork server refused a child: {answer}")
        except BaseException:
            host_end.close()
            shutil.rmtree(temp, ignore_errors=True)
            raise
        finally:
            child_end.close()
        return SandboxProcess(pid=pid, sock=host_end, temp=temp, marker=self.marker, server=self)

    def reap(self, pid: int) -> dict[str, Any]:
        """Waits for child ``pid`` (killed already): ``status``, ``cpu_seconds``,
        ``max_rss_kb``."""
        return self._ask({"op": "reap", "pid": pid})

    def alive(self) -> bool:
        """Whether the server still runs."""
        return self.process.poll() is None

    def cpu_seconds(self) -> float | None:
        """CPU time the server itself has used (booting, forking; not its children's), or
        ``None`` where ``/proc`` does not say."""
        try:
            stat = Path(f"/proc/{self.process.pid}/stat").read_text()
            fields = stat.rsplit(")", 1)[1].split()
            return (int(fields[11]) + int(fields[12])) / _CLOCK_TICKS
        except (OSError, ValueError, IndexError):
            return None

    def close(self) -> None:
        """Kills the server and waits until nothing of its group is left."""
        with contextlib.suppress(OSError):
            self.control.close()
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(self.process.pid, signal.SIGKILL)
        with contextlib.suppress(ChildProcessError):
            self.process.wait()
        _wait_until_group_gone(self.process.pid)
        shutil.rmtree(self.temp, ignore_errors=True)


class ChildPool:
    """Hands out sandboxed children, keeping one started ahead of need.

    Children are forked from the pool's fork server (started with the first child), which
    makes a child cost a fork rather than an interpreter and its imports. The lockstep
    keeps one core busy at a time (host or child), so the spare started while a run goes
    on boots on the other core and the next run finds it waiting. Every child is used
    once; :meth:`close` ends the spare nobody took and the fork server.
    ``ahead=False`` starts each child only when it is taken; ``fork=False`` starts each
    child as a fresh interpreter (what a run cost before the fork server).
    """

    def __init__(self, *, ahead: bool = True, fork: bool = True) -> None:
        self.ahead = ahead
        self.fork = fork
        self._spare: SandboxProcess | None = None
        self._server: ForkServer | None = None

    @property
    def server(self) -> ForkServer | None:
        """The pool's fork server, once it has started one."""
        return self._server

    def warm(self) -> None:
        """Starts the fork server without waiting for it, so that it boots (on another
        core) while the caller prepares its first run."""
        if self.fork and self._server is None:
            self._server = ForkServer()

    def _start(self) -> SandboxProcess:
        if not self.fork:
            return start_child()
        if self._server is not None and not self._server.alive():
            self._server.close()
            self._server = None
        if self._server is None:
            self._server = ForkServer()
        try:
            return self._server.fork()
        except SandboxError:
            # A server that died (killed from outside) is replaced once.
            self._server.close()
            self._server = ForkServer()
            return self._server.fork()

    def take(self, skill_source: str, skill_name: str = "skill.py") -> SandboxProcess:
        """A booted (or booting) child holding a private copy of the skill
        (``<temp>/<skill_name>``)."""
        child, self._spare = self._spare, None
        if child is not None and not child.running():
            child.close()
            child = None
        if child is None:
            child = self._start()
        try:
            child.place(skill_source, skill_name)
        except BaseException:
            child.close()
            raise
        return child

    def prepare(self) -> None:
        """Starts a spare child unless one is waiting (or the pool starts none ahead)."""
        if self.ahead and self._spare is None:
            self._spare = self._start()

    def close(self) -> None:
        """Ends the spare child, if any, and the fork server."""
        child, self._spare = self._spare, None
        if child is not None:
            child.close()
        server, self._server = self._server, None
        if server is not None:
            server.close()

    def __enter__(self) -> ChildPool:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()


def limits_config(limits: Limits) -> dict[str, int]:
    """The limits as the child's ``boot.py`` applies them."""
    return {
        "address_space": limits.memory_mb * 1024 * 1024,
        "cpu_seconds": limits.cpu_seconds,
        "open_files": limits.open_files,
        "processes": limits.processes,
        "file_size": limits.file_size_mb * 1024 * 1024,
    }
