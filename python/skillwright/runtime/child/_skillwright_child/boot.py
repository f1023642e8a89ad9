"""Entry point of the sandbox: ``python -I -S -B boot.py --zygote FD SETUP``, a fork server.

It runs inside the sandbox the host built (bubblewrap's namespaces, read-only root,
seccomp allow-list; see ``skillwright.runtime.isolation``), or, with
``--unsafe-no-isolation``, as a plain process. Started as root inside the sandbox (the host
mapped root for bubblewrap's set-up), it first drops to the unprivileged ``drop_to`` user.
It imports the child's modules and the stand-ins once, says ``ready`` (its credentials tell
the host its process id) and then, on each request (a scratch folder, with the new child's
end of a socketpair and its output file passed along), forks a child. No skill code ever
runs in the fork server itself, so every child starts from the same untouched modules; a
child costs a fork instead of an interpreter and its imports. The server also reaps its
children on request and reports how they ended and what they used. FD is its end of a
``SOCK_SEQPACKET`` socketpair with the host; SETUP is JSON: the Rust extension's file
(``core``), what a child may read (``readable``), ``isolated`` and ``drop_to``.

A child, before any code of the skill runs, strongest first:

1. starts its own session, sends its credentials (the host learns its process id),
   dies with the fork server (``PR_SET_PDEATHSIG``) and moves into its scratch folder;
2. confines itself for good through the Rust extension: Landlock (write only in its
   scratch folder, read only what the sandbox holds, no signals to or abstract sockets of
   processes outside its domain, where the kernel has Landlock) and a seccomp program of
   its own (no new processes or programs, signals to itself only; without isolation the
   base allow-list too);
3. rlimits: address space, CPU seconds, open files, processes, file size, no core files;
4. the audit hook of ``guard.py``, which reports a refused action at the skill's line;
   the virtual clock; the message packages.
"""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import sys


def _looping_line(frame: object) -> int:
    """The line a frame interrupted by a signal is running. A loop that calls nothing is
    interrupted at its jump back, which belongs to the loop's header; the line of its body
    that ran last says better where it spins."""
    import dis

    line = frame.f_lineno  # type: ignore[attr-defined]
    here = frame.f_lasti  # type: ignore[attr-defined]
    before = None
    for instruction in dis.get_instructions(frame.f_code):  # type: ignore[attr-defined]
        if instruction.offset == here:
            if "JUMP_BACKWARD" in instruction.opname and before is not None:
                return before
            return line
        if instruction.positions is not None and instruction.positions.lineno not in (None, line):
            before = instruction.positions.lineno
    return line


def _interrupt_handler(core: object, core_module: object) -> object:
    """The handler of the host's interrupt (SIGUSR1) and of the CPU limit (SIGXCPU): it
    reports where the skill was and ends the state, or defers that while the child talks
    to the host."""

    def interrupted(signum: int, frame: object) -> None:
        reason = "busy" if signum == signal.SIGUSR1 else "cpu"
        stack = []
        walk = frame
        while walk is not None:
            if walk.f_code.co_filename == core.skill_file:  # type: ignore[attr-defined]
                line = _looping_line(walk) if walk is frame else walk.f_lineno  # type: ignore[attr-defined]
                stack.append([line, walk.f_code.co_name])  # type: ignore[attr-defined]
            walk = walk.f_back  # type: ignore[attr-defined]
        if core.in_io:  # type: ignore[attr-defined]
            core.deferred_interrupt = reason  # type: ignore[attr-defined]
            core.deferred_stack = stack[::-1]  # type: ignore[attr-defined]
            return
        core.notify("stack", reason=reason, frames=stack[::-1])  # type: ignore[attr-defined]
        raise core_module.Interrupted(reason)  # type: ignore[attr-defined]

    return interrupted


def _limit(limits: dict) -> None:
    import resource

    def set_limit(which: int, value: int) -> None:
        _, hard = resource.getrlimit(which)
        if hard != resource.RLIM_INFINITY:
            value = min(value, hard)
        resource.setrlimit(which, (value, value if which != resource.RLIMIT_CPU else hard))

    set_limit(resource.RLIMIT_AS, int(limits["address_space"]))
    set_limit(resource.RLIMIT_CPU, int(limits["cpu_seconds"]))
    set_limit(resource.RLIMIT_NOFILE, int(limits["open_files"]))
    set_limit(resource.RLIMIT_FSIZE, int(limits["file_size"]))
    set_limit(resource.RLIMIT_CORE, 0)
    if os.getuid() != 0:
        set_limit(resource.RLIMIT_NPROC, int(limits["processes"]))
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)


def _allow_packages(allowed: dict) -> None:
    """Makes the few third-party packages a skill may use importable (e.g. numpy), and
    imports them once in the fork server, so each child has them at no cost.

    Each is found at its own folder, never by listing the folder that holds it (the
    virtual environment's site-packages): the sandbox shows only the package, and lets no
    one list the rest. They are imported before a child's guard is installed: numpy
    loads its own native code (and ctypes, for ``ndarray.ctypes``) as it is imported,
    which a skill's own ``import ctypes`` may not do; what a skill then calls through
    them is still refused by the guard's ctypes events, and by the kernel below it."""
    import importlib
    import importlib.util

    class AllowedPackages:
        def find_spec(self, fullname: str, path: object = None, target: object = None) -> object:
            folder = allowed.get(fullname)
            if folder is None:
                return None
            package = os.path.join(folder, fullname)
            return importlib.util.spec_from_file_location(
                fullname,
                os.path.join(package, "__init__.py"),
                submodule_search_locations=[package],
            )

    sys.meta_path.append(AllowedPackages())
    for name in allowed:
        try:
            importlib.import_module(name)
        except ImportError:
            continue  # the skill that imports it gets the error, at its line


def main() -> None:
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    sys.path[:] = [root, *(p for p in sys.path[1:] if p)]
    if sys.argv[1:2] != ["--zygote"] or len(sys.argv) != 4:
        os.write(2, b"usage: boot.py --zygote FD SETUP\n")
        os._exit(2)
    import json

    _zygote(int(sys.argv[2]), json.loads(sys.argv[3]))


def _child(sock: socket.socket, scratch: str, isolation: dict) -> None:
    """Talks to the host and runs the skill; never returns."""
    from _skillwright_child import core as core_module
    from _skillwright_child import driver, guard, messages, patches
    from _skillwright_child.wire import HostGone, Wire

    wire = Wire(sock)
    try:
        hello = wire.request("hello", isolation=isolation, python=sys.version.split()[0])
    except HostGone:
        os._exit(3)
    config = hello["config"]
    source = config.get("source")
    if isinstance(source, str):
        with open(config["skill"], "w", encoding="utf-8") as stream:
            stream.write(source)
    _limit(config["limits"])
    core = core_module.Core(wire, config["skill"], int(config["epoch_ns"]))
    core_module.CORE = core
    if isinstance(config.get("message_packages"), list):
        core.catalog.know_packages(config["message_packages"])
    messages.install(core.catalog)
    patches.install(core)

    interrupted = _interrupt_handler(core, core_module)
    signal.signal(signal.SIGUSR1, interrupted)
    signal.signal(signal.SIGXCPU, interrupted)
    end = os._exit
    guard.install(scratch, config["read_roots"], sock.fileno())
    try:
        driver.run(core, config)
    except HostGone:
        end(3)
    except BaseException:
        # The child's own failure: its traceback goes to the output file the host reads.
        os.write(2, traceback_text().encode("utf-8", "replace"))
        end(4)
    end(0)


_PRELOAD = (
    "ctypes",
    "dis",
    "json",
    "traceback",
    "_skillwright_child.core",
    "_skillwright_child.driver",
    "_skillwright_child.guard",
    "_skillwright_child.messages",
    "_skillwright_child.patches",
    "_skillwright_child.wire",
    "rclpy",
    "rclpy.action",
    "rclpy.callback_groups",
    "rclpy.executors",
    "rclpy.qos",
    "rclpy.wait_for_message",
    "tf2_ros",
    "pyskillup.decorators.decorators",
    "pyskillup.decorator_check.decorator_check",
    "pyskillup.decorators.skill_interface",
)
"""What every child imports (its machinery, the stand-ins). The stand-ins read the clock
only when called, never at import, so importing them before the virtual clock is
installed changes nothing."""


_PR_SET_PDEATHSIG = 1
_PR_SET_DUMPABLE = 4


def _load_core(path: str) -> object:
    """The Rust extension (``skillwright._core``), from its file: the child has none of
    skillwright's Python package, only this."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("_core", path)
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot load the Rust extension from {path}")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _send_credentials(sock: socket.socket, data: bytes) -> None:
    """Sends ``data`` with this process's credentials, which the kernel translates into
    the receiver's view (its process id as the host sees it)."""
    import struct

    credentials = struct.pack("3i", os.getpid(), os.getuid(), os.getgid())
    sock.sendmsg([data], [(socket.SOL_SOCKET, socket.SCM_CREDENTIALS, credentials)])


_PR_CAPBSET_DROP = 24
_CAPABILITY_VERSION_3 = 0x20080522


def _drop_privileges(libc: object, user: int) -> None:
    """Becomes ``user`` with no capability left in any set: the bounding set emptied (with
    CAP_SETPCAP, which bubblewrap left for this), then the ids changed (which empties the
    permitted and effective sets), then the inheritable set cleared."""
    import ctypes

    for capability in range(64):
        libc.prctl(_PR_CAPBSET_DROP, capability, 0, 0, 0)  # type: ignore[attr-defined]
    os.setgroups([])
    os.setgid(user)
    os.setuid(user)
    header = (ctypes.c_uint32 * 2)(_CAPABILITY_VERSION_3, 0)
    data = (ctypes.c_uint32 * 6)()
    if libc.capset(header, data) != 0:  # type: ignore[attr-defined]
        raise OSError(ctypes.get_errno(), "capset: the inheritable capabilities stay")


def _zygote(control_fd: int, setup: dict) -> None:
    """Serves fork requests until the host closes the connection; never returns."""
    import ctypes
    import importlib
    import json

    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    drop_to = setup.get("drop_to")
    if drop_to is not None and os.getuid() == 0:
        # Root only in the sandbox's user namespace, mapped for bubblewrap's set-up: become
        # nobody (in the namespace and on the host) before anything else is loaded.
        _drop_privileges(libc, int(drop_to))
    # Neither the fork server's memory nor its children's can be read or written through
    # /proc by a process of the same user.
    libc.prctl(_PR_SET_DUMPABLE, 0, 0, 0, 0)
    core = _load_core(str(setup["core"]))
    for name in _PRELOAD:
        importlib.import_module(name)
    _allow_packages(setup.get("packages", {}))
    control = socket.socket(fileno=control_fd)
    _send_credentials(control, b"ready")
    while True:
        try:
            data, fds, _, _ = socket.recv_fds(control, 65536, 2)
        except OSError:
            os._exit(0)
        if not data:
            os._exit(0)
        request = json.loads(data)
        if request.get("op") == "fork" and len(fds) == 2:
            pid = os.fork()
            if pid == 0:
                control.close()
                _forked(fds[0], fds[1], request, setup, core, libc)
            for fd in fds:
                os.close(fd)
            reply: dict = {"pid": pid}
        elif request.get("op") == "reap":
            reply = _reap(int(request["pid"]))
        else:
            for fd in fds:
                os.close(fd)
            reply = {"error": "unknown request"}
        control.sendall(json.dumps(reply).encode("utf-8"))


def _forked(fd: int, output: int, request: dict, setup: dict, core: object, libc: object) -> None:
    """A child of the fork server: its own session, output, scratch folder and kernel
    confinement, then the skill; never returns."""
    try:
        os.setsid()
        os.dup2(output, 1)
        os.dup2(output, 2)
        os.close(output)
        sock = socket.socket(fileno=fd)
        _send_credentials(sock, b"\0")
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)  # type: ignore[attr-defined]
        scratch = str(request["scratch"])
        if request.get("make"):
            os.mkdir(scratch, 0o700)
        os.chdir(scratch)
        os.environ["HOME"] = scratch
        os.environ["TMPDIR"] = scratch
        confined = core.confine_child(  # type: ignore[attr-defined]
            os.getpid(), list(setup["readable"]), [scratch, "/dev/null"], not setup["isolated"]
        )
        isolation = {
            "landlock": str(confined["landlock"]),
            "seccomp": ", ".join(
                confined["seccomp"]
                if not setup["isolated"]
                else ["base", "fallbacks", *confined["seccomp"]]
            ),
            "uid": str(os.getuid()),
        }
        _child(sock, scratch, isolation)
    finally:
        os._exit(4)


def _reap(pid: int) -> dict:
    """Kills a child (the host has killed it already, unless the child never told the host
    who it is), waits for it and says how it ended."""
    with contextlib.suppress(OSError):
        os.kill(pid, signal.SIGKILL)
    try:
        _, status, usage = os.wait4(pid, 0)
    except ChildProcessError:
        return {"status": None}
    return {
        "status": os.waitstatus_to_exitcode(status),
        "cpu_seconds": usage.ru_utime + usage.ru_stime,
        "max_rss_kb": usage.ru_maxrss,
    }


def traceback_text() -> str:
    import traceback

    return traceback.format_exc()


if __name__ == "__main__":
    main()
