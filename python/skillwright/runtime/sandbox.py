"""Starting the sandboxed children, talking to them, and making sure nothing of them survives.

Children come from a fork server (``boot.py --zygote``): it has imported the child's
modules once and forks a child per run. With isolation (the default) the fork server runs
inside the kernel boundary of :mod:`skillwright.runtime.isolation` (bubblewrap's
namespaces, a read-only root of its own, an unprivileged user, seccomp), and every child
confines itself further before its skill is loaded (Landlock, a seccomp program of its
own). Without it (``--unsafe-no-isolation``) the same fork server runs as a plain process
of the host's and only the child's own confinement, the rlimits and the audit hook
remain; the run's record says which it was.

A child starts its own session (process group), writes its output to a file of the
host's, and holds one end of a socketpair; its first byte on that socket carries its
credentials, so the host learns its process id as the host sees it (the fork server
lives in a PID namespace of its own). :meth:`SandboxProcess.close` kills the process
group, has the fork server reap the child and report its resource use, and removes the
host's folder of the run. A :class:`ChildPool` owns one fork server and keeps the next
child started while the current one runs.
"""

from __future__ import annotations

import compileall
import contextlib
import json
import os
import select
import shutil
import signal
import socket
import struct
import subprocess
import tempfile
import time
import uuid
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any, Final

from skillwright.errors import SandboxUnavailableError
from skillwright.runtime import isolation
from skillwright.runtime.isolation import CHILD_ROOT
from skillwright.runtime.scenario import Limits

__all__ = [
    "CHILD_ROOT",
    "MARKER_VARIABLE",
    "ChildPool",
    "ForkServer",
    "SandboxError",
    "SandboxProcess",
    "check_isolation",
    "limits_config",
]

MARKER_VARIABLE: Final = "SKILLWRIGHT_SANDBOX"
"""Environment variable every sandboxed process carries, with the id of the fork server
it came from as its value (tests find stray processes by it)."""


class SandboxError(OSError):
    """The fork server did not answer as it should (it died, or was killed)."""


_CLOCK_TICKS: Final = os.sysconf("SC_CLK_TCK")
_CREDENTIALS: Final = struct.Struct("3i")
_READY_SECONDS: Final = 60.0
"""How long a fork server may take to boot (a loaded machine), and a child to say hello."""


@cache
def _prepare_child_code() -> None:
    """Compiles the child's modules once, so the child (which writes no bytecode) starts
    fast; an install folder that cannot be written just makes the child compile in memory."""
    with contextlib.suppress(OSError):
        compileall.compile_dir(str(CHILD_ROOT), quiet=2, workers=1)


def _receive_credentials(
    sock: socket.socket, timeout: float, size: int
) -> tuple[bytes, int | None]:
    """The next ``size`` bytes on ``sock`` (at most one packet of a packet socket) and the
    process id its sender's credentials give, as this process sees it."""
    ready, _, _ = select.select([sock], [], [], timeout)
    if not ready:
        return b"", None
    try:
        data, ancillary, _, _ = sock.recvmsg(size, socket.CMSG_SPACE(_CREDENTIALS.size))
    except OSError:
        return b"", None
    for level, kind, payload in ancillary:
        if level == socket.SOL_SOCKET and kind == socket.SCM_CREDENTIALS:
            pid, _, _ = _CREDENTIALS.unpack(payload[: _CREDENTIALS.size])
            return data, pid
    return data, None


@dataclass
class SandboxProcess:
    """A running child and what is needed to talk to it and to end it."""

    pid: int
    """Process id of the child as the host sees it (also its process group and session)."""
    inner_pid: int
    """Its process id in the fork server's PID namespace (what the server reaps)."""
    sock: socket.socket
    temp: Path
    """The host's folder of the run: the child's output (and, without isolation, the
    child's scratch folder too)."""
    scratch: str
    """The child's scratch folder and ``$HOME``, as the child sees it."""
    marker: str
    server: ForkServer
    """The fork server it came from, which reaps it."""
    started: float = field(default_factory=time.monotonic)
    rusage: dict[str, float] = field(default_factory=dict)
    exit_status: int | None = None
    source: str = ""
    """The skill's text, which the child writes into its scratch folder."""
    skill_name: str = "skill.py"

    @property
    def skill_path(self) -> str:
        """Where the skill's file is, as the child sees it."""
        return f"{self.scratch}/{self.skill_name}"

    @property
    def isolated(self) -> bool:
        """Whether the child runs inside the kernel boundary."""
        return self.server.isolated

    def running(self) -> bool:
        """Whether the child has not ended yet."""
        if self.exit_status is not None:
            return False
        try:
            stat = Path(f"/proc/{self.pid}/stat").read_bytes()
        except OSError:
            return False
        return stat[stat.rfind(b")") + 2 :][:1] not in (b"Z", b"X")

    def cpu_seconds(self) -> float | None:
        """CPU time the child has used so far, or ``None`` where ``/proc`` does not say."""
        try:
            fields = Path(f"/proc/{self.pid}/stat").read_text().rsplit(")", 1)[1].split()
            # utime and stime are fields 14 and 15 of stat, 12 and 13 after the name.
            return (int(fields[11]) + int(fields[12])) / _CLOCK_TICKS
        except (OSError, ValueError, IndexError):
            return None

    def interrupt(self) -> None:
        """Asks the child to stop the state that runs (it reports where it was)."""
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.kill(self.pid, signal.SIGUSR1)

    def place(self, skill_source: str, skill_name: str) -> None:
        """Gives the child its skill (sent with the answer to its ``hello``); the run's
        wall deadline counts from here."""
        self.source = skill_source
        self.skill_name = skill_name
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
        # SIGKILL reaches the child at once, but it may take a moment to die on a busy
        # machine. Nothing of the run may outlive close(), so wait until the group is gone.
        _wait_until_group_gone(self.pid)
        shutil.rmtree(self.temp, ignore_errors=True)

    def _reap(self) -> tuple[int, float | None, float]:
        """Waits for the killed child: its exit status, CPU seconds and peak memory (kB)."""
        try:
            answer = self.server.reap(self.inner_pid)
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


def _environment(home: str, marker: str) -> dict[str, str]:
    return {
        "PATH": "/usr/bin:/bin",
        "HOME": home,
        "TMPDIR": home,
        "LANG": "C.UTF-8",
        "LC_ALL": "C.UTF-8",
        "TZ": "UTC",
        "OPENBLAS_NUM_THREADS": "1",
        "OMP_NUM_THREADS": "1",
        "MKL_NUM_THREADS": "1",
        MARKER_VARIABLE: marker,
    }


def _pipe_with(data: bytes) -> int:
    """The read end of a pipe that holds ``data`` and then ends (a seccomp program for
    bubblewrap; a few kilobytes, well within a pipe's buffer)."""
    read_end, write_end = os.pipe()
    try:
        os.write(write_end, data)
    finally:
        os.close(write_end)
    return read_end


class ForkServer:
    """A running fork server and its end of the control socket.

    ``isolated``: inside bubblewrap's namespaces (see :mod:`skillwright.runtime.isolation`);
    else a plain process of the host's. Either way it has its own session, a scrubbed
    environment and a private folder of the host's for its output. The constructor starts
    it without waiting; the first :meth:`fork` waits until it has booted, and raises
    :class:`~skillwright.errors.SandboxUnavailableError` when bubblewrap could not build
    the sandbox. :meth:`close` kills it and everything of its process group.
    """

    def __init__(self, *, isolated: bool = True) -> None:
        _prepare_child_code()
        self.isolated = isolated
        self.temp = Path(tempfile.mkdtemp(prefix="skillwright-forks-")).resolve()
        self.marker = uuid.uuid4().hex
        self.pid: int | None = None
        """The fork server's own process id, once it has said it is ready."""
        self._ready = False
        root = isolation.layout()
        as_root = os.getuid() == 0
        setup = {
            "core": root.core,
            "readable": root.readable(),
            "isolated": isolated,
            "drop_to": isolation.NOBODY if isolated and as_root else None,
            "packages": dict(root.packages),
        }
        host_end, server_end = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        host_end.setsockopt(socket.SOL_SOCKET, socket.SO_PASSCRED, 1)
        self.control = host_end
        command = [
            root.interpreter,
            "-I",
            "-S",
            "-B",
            str(CHILD_ROOT / "_skillwright_child" / "boot.py"),
            "--zygote",
            str(server_end.fileno()),
            json.dumps(setup),
        ]
        inherited = [server_end.fileno()]
        handshake: tuple[int, int] | None = None
        home = isolation.SCRATCH_ROOT if isolated else str(self.temp)
        try:
            if isolated:
                prefix, inherited, handshake = self._bwrap(root, as_root, inherited)
                command = [*prefix, "--", *command]
            with (self.temp / "server-output.txt").open("wb") as output:
                self.process = subprocess.Popen(
                    command,
                    stdin=subprocess.DEVNULL,
                    stdout=output,
                    stderr=subprocess.STDOUT,
                    pass_fds=inherited,
                    cwd=self.temp,
                    env=_environment(home, self.marker),
                    start_new_session=True,
                )
        except BaseException:
            host_end.close()
            shutil.rmtree(self.temp, ignore_errors=True)
            raise
        finally:
            server_end.close()
            for fd in inherited[1:]:
                with contextlib.suppress(OSError):
                    os.close(fd)
        if handshake is not None:
            try:
                self._map_user(*handshake)
            except BaseException:
                self.close()
                raise

    def _bwrap(
        self, root: isolation.Layout, as_root: bool, inherited: list[int]
    ) -> tuple[list[str], list[int], tuple[int, int] | None]:
        """bubblewrap's command line, the descriptors it inherits, and (started as root)
        the host's ends of the user-namespace handshake."""
        from skillwright._core import seccomp_programs

        binary = isolation.bwrap_binary()
        base, fallbacks = seccomp_programs()
        base_fd, fallback_fd = _pipe_with(base), _pipe_with(fallbacks)
        inherited = [*inherited, base_fd, fallback_fd]
        prefix = [binary, *isolation.bwrap_arguments(root, as_root=as_root)]
        prefix += ["--add-seccomp-fd", str(base_fd), "--add-seccomp-fd", str(fallback_fd)]
        if not as_root:
            return prefix, inherited, None
        info_read, info_write = os.pipe()
        block_read, block_write = os.pipe()
        inherited += [info_write, block_read]
        prefix += ["--info-fd", str(info_write), "--userns-block-fd", str(block_read)]
        return prefix, inherited, (info_read, block_write)

    def _map_user(self, info_read: int, block_write: int) -> None:
        """Writes the map of the user namespace bubblewrap made (started as root): root
        for its own set-up, nobody for the fork server, which drops to it at once."""
        try:
            text = b""
            deadline = time.monotonic() + _READY_SECONDS
            while b"child-pid" not in text or not text.rstrip().endswith(b"}"):
                ready, _, _ = select.select([info_read], [], [], deadline - time.monotonic())
                chunk = os.read(info_read, 4096) if ready else b""
                if not chunk:
                    self.process.wait(timeout=_READY_SECONDS)
                    raise isolation.unavailable(self._output())
                text += chunk
            pid = int(json.loads(text)["child-pid"])
            nobody = isolation.NOBODY
            mapping = f"0 0 1\n{nobody} {nobody} 1\n"
            try:
                Path(f"/proc/{pid}/setgroups").write_text("allow")
                Path(f"/proc/{pid}/uid_map").write_text(mapping)
                Path(f"/proc/{pid}/gid_map").write_text(mapping)
            except OSError as error:
                raise isolation.unavailable(
                    f"bwrap: setting up uid map of the sandbox: {error.strerror}"
                ) from None
            os.write(block_write, b"1")
        finally:
            os.close(info_read)
            os.close(block_write)

    def _output(self) -> str:
        try:
            return (self.temp / "server-output.txt").read_text(errors="replace")
        except OSError:
            return ""

    def wait_ready(self) -> None:
        """Waits for the server's first word, which carries its process id."""
        if self._ready:
            return
        data, pid = _receive_credentials(self.control, _READY_SECONDS, 64)
        if data != b"ready":
            with contextlib.suppress(subprocess.TimeoutExpired):
                self.process.wait(timeout=5.0)
            output = self._output()
            if self.isolated and "bwrap:" in output:
                raise isolation.unavailable(output)
            raise SandboxError(
                "the sandbox's fork server did not start"
                + (f": {output.strip()[-400:]}" if output.strip() else "")
            )
        self.pid = pid
        self._ready = True

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
        """A new child with a private folder, booting towards its ``hello``."""
        self.wait_ready()
        temp = Path(tempfile.mkdtemp(prefix="skillwright-run-")).resolve()
        scratch = (
            f"{isolation.SCRATCH_ROOT}/run-{uuid.uuid4().hex[:16]}" if self.isolated else str(temp)
        )
        host_end, child_end = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            host_end.setsockopt(socket.SOL_SOCKET, socket.SO_PASSCRED, 1)
            with (temp / "child-output.txt").open("wb") as output:
                answer = self._ask(
                    {"op": "fork", "scratch": scratch, "make": self.isolated},
                    [child_end.fileno(), output.fileno()],
                )
            inner = answer.get("pid")
            if not isinstance(inner, int):
                raise SandboxError(f"the sandbox's fork server refused a child: {answer}")
            child_end.close()
            # Exactly the one byte: the child may have sent its hello right after it.
            first, pid = _receive_credentials(host_end, _READY_SECONDS, 1)
            if first != b"\0" or pid is None:
                with contextlib.suppress(SandboxError):
                    self.reap(inner)
                tail = (temp / "child-output.txt").read_text(errors="replace").strip()
                raise SandboxError(
                    "a sandboxed child did not start" + (f": {tail[-400:]}" if tail else "")
                )
            host_end.setsockopt(socket.SOL_SOCKET, socket.SO_PASSCRED, 0)
        except BaseException:
            host_end.close()
            shutil.rmtree(temp, ignore_errors=True)
            raise
        finally:
            child_end.close()
        return SandboxProcess(
            pid=pid,
            inner_pid=inner,
            sock=host_end,
            temp=temp,
            scratch=scratch,
            marker=self.marker,
            server=self,
        )

    def reap(self, pid: int) -> dict[str, Any]:
        """Kills child ``pid`` (its id in the server's namespace) if it still runs, waits for it:
        ``status``, ``cpu_seconds``, ``max_rss_kb``."""
        return self._ask({"op": "reap", "pid": pid})

    def alive(self) -> bool:
        """Whether the server still runs."""
        return self.process.poll() is None

    def cpu_seconds(self) -> float | None:
        """CPU time the server itself has used (booting, forking; not its children's), or
        ``None`` where ``/proc`` does not say (or before it is ready)."""
        if self.pid is None:
            return None
        try:
            stat = Path(f"/proc/{self.pid}/stat").read_text()
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
    ``ahead=False`` starts each child only when it is taken. ``isolated=False`` runs the
    fork server without the kernel boundary (``--unsafe-no-isolation``).
    """

    def __init__(self, *, ahead: bool = True, isolated: bool = True) -> None:
        self.ahead = ahead
        self.isolated = isolated
        self._spare: SandboxProcess | None = None
        self._server: ForkServer | None = None

    @property
    def server(self) -> ForkServer | None:
        """The pool's fork server, once it has started one."""
        return self._server

    def warm(self) -> None:
        """Starts the fork server without waiting for it, so that it boots (on another
        core) while the caller prepares its first run."""
        if self._server is None:
            self._server = ForkServer(isolated=self.isolated)

    def _start(self) -> SandboxProcess:
        if self._server is not None and not self._server.alive():
            self._server.close()
            self._server = None
        if self._server is None:
            self._server = ForkServer(isolated=self.isolated)
        try:
            return self._server.fork()
        except SandboxUnavailableError:
            raise
        except SandboxError:
            # A server that died (killed from outside) is replaced once.
            self._server.close()
            self._server = ForkServer(isolated=self.isolated)
            return self._server.fork()

    def take(self, skill_source: str, skill_name: str = "skill.py") -> SandboxProcess:
        """A booted (or booting) child that gets ``skill_source`` as its skill
        (``<scratch>/<skill_name>``)."""
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


def check_isolation() -> None:
    """Starts a sandboxed fork server and ends it: raises
    :class:`~skillwright.errors.SandboxUnavailableError` (naming the kernel setting) where
    the sandbox cannot be built, before a caller spends minutes on what it would run."""
    server = ForkServer(isolated=True)
    try:
        server.wait_ready()
    finally:
        server.close()


def limits_config(limits: Limits) -> dict[str, int]:
    """The limits as the child's ``boot.py`` applies them."""
    return {
        "address_space": limits.memory_mb * 1024 * 1024,
        "cpu_seconds": limits.cpu_seconds,
        "open_files": limits.open_files,
        "processes": limits.processes,
        "file_size": limits.file_size_mb * 1024 * 1024,
    }
