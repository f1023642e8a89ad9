"""Entry point of the sandboxed child: ``python -I -S -B boot.py FD TEMP``.

Before any code of the skill runs, this sets up the sandbox, strongest first:

1. ``prctl(PR_SET_PDEATHSIG)``: the child dies with the host.
2. New network and PID namespaces (as root, or through a user namespace where the
   kernel allows unprivileged ones): no network device but a downed loopback, and every
   process the skill might start dies with the first process of the namespace.
   Without namespaces the audit hook alone refuses sockets, and the host kills the
   process group.
3. rlimits: address space, CPU seconds, open files, processes (per user, so not
   enforced for root), file size, no core files.
4. The audit hook of ``guard.py``; the virtual clock; the message packages.

FD is the child's end of the host's socketpair; TEMP its private temporary folder
(the working directory, ``HOME`` and ``TMPDIR``).

``python -I -S -B boot.py --zygote FD`` is a fork server instead: it imports the child's
modules and the stand-ins once, then on each request (a temporary folder, with the new
child's end of a socketpair passed along) forks a child that starts its own session,
moves into that folder and goes on exactly as above. No skill code ever runs in the fork
server itself, so every child starts from the same untouched modules; a child costs a
fork instead of an interpreter and its imports. The server also reaps its children on
request and reports how they ended and what they used. FD is its end of a
``SOCK_SEQPACKET`` socketpair with the host.
"""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import sys


def _isolate() -> dict:
    """Namespaces and the parent-death signal; returns what was achieved."""
    import ctypes

    libc = ctypes.CDLL(None, use_errno=True)
    pr_set_pdeathsig = 1
    libc.prctl(pr_set_pdeathsig, signal.SIGKILL, 0, 0, 0)
    clone_newnet, clone_newpid, clone_newuser = 0x40000000, 0x20000000, 0x10000000
    result = {"network": "audit-hook", "pid_namespace": False, "user_namespace": False}
    if libc.unshare(clone_newnet | clone_newpid) == 0:
        result.update(network="namespace", pid_namespace=True)
        return result
    uid, gid = os.getuid(), os.getgid()
    if libc.unshare(clone_newuser | clone_newnet | clone_newpid) == 0:
        try:
            with open("/proc/self/setgroups", "w") as stream:
                stream.write("deny")
            with open("/proc/self/uid_map", "w") as stream:
                stream.write(f"{uid} {uid} 1")
            with open("/proc/self/gid_map", "w") as stream:
                stream.write(f"{gid} {gid} 1")
        except OSError:
            pass
        result.update(network="namespace", pid_namespace=True, user_namespace=True)
        return result
    if libc.unshare(clone_newnet) == 0:
        result.update(network="namespace")
    return result


def _enter_pid_namespace(sock: socket.socket) -> None:
    """Forks so that the skill runs as the first process of the new PID namespace.

    The parent stays as the process the host started: it forwards the host's interrupt
    signal and exits with the child's status. If it dies, the child gets SIGKILL, and
    with it every process of the namespace.
    """
    import ctypes

    pid = os.fork()
    if pid == 0:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL, 0, 0, 0)
        return
    sock.close()

    def forward(signum: int, _frame: object) -> None:
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signum)

    signal.signal(signal.SIGUSR1, forward)
    signal.signal(signal.SIGTERM, forward)
    while True:
        try:
            _, status = os.waitpid(pid, 0)
        except ChildProcessError:
            os._exit(0)
        os._exit(os.waitstatus_to_exitcode(status) & 0xFF)


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
    """Makes the few third-party packages a skill may use importable (e.g. numpy)."""
    import importlib.machinery

    class AllowedPackages:
        def find_spec(self, fullname: str, path: object = None, target: object = None) -> object:
            folder = allowed.get(fullname)
            if folder is None:
                return None
            return importlib.machinery.PathFinder.find_spec(fullname, [folder])

    sys.meta_path.append(AllowedPackages())


def main() -> None:
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    sys.path[:] = [root, *(p for p in sys.path[1:] if p)]
    if sys.argv[1] == "--zygote":
        _zygote(int(sys.argv[2]))
    _child(int(sys.argv[1]), sys.argv[2])


def _child(fd: int, temp: str) -> None:
    """Isolates this process, talks to the host, runs the skill; never returns."""
    sock = socket.socket(fileno=fd)
    isolation = _isolate()
    if isolation["pid_namespace"]:
        _enter_pid_namespace(sock)

    from _skillwright_child import core as core_module
    from _skillwright_child import driver, guard, messages, patches
    from _skillwright_child.wire import HostGone, Wire

    wire = Wire(sock)
    try:
        isolation["sandbox"] = os.environ.get("SKILLWRIGHT_SANDBOX", "")
        isolation["folder"] = temp
        hello = wire.request("hello", isolation=isolation, python=sys.version.split()[0])
    except HostGone:
        os._exit(3)
    config = hello["config"]
    os.chdir(temp)
    _limit(config["limits"])
    core = core_module.Core(wire, config["skill"], int(config["epoch_ns"]))
    core_module.CORE = core
    if isinstance(config.get("message_packages"), list):
        core.catalog.know_packages(config["message_packages"])
    messages.install(core.catalog)
    _allow_packages(config.get("packages", {}))
    patches.install(core)

    interrupted = _interrupt_handler(core, core_module)
    signal.signal(signal.SIGUSR1, interrupted)
    signal.signal(signal.SIGXCPU, interrupted)
    end = os._exit
    guard.install(temp, config["read_roots"], sock.fileno())
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


def _zygote(control_fd: int) -> None:
    """Serves fork requests until the host closes the connection; never returns."""
    import ctypes
    import importlib
    import json

    libc = ctypes.CDLL(None, use_errno=True)
    pr_set_pdeathsig = 1
    libc.prctl(pr_set_pdeathsig, signal.SIGKILL, 0, 0, 0)
    for name in _PRELOAD:
        importlib.import_module(name)
    control = socket.socket(fileno=control_fd)
    while True:
        try:
            data, fds, _, _ = socket.recv_fds(control, 65536, 1)
        except OSError:
            os._exit(0)
        if not data:
            os._exit(0)
        request = json.loads(data)
        if request.get("op") == "fork" and len(fds) == 1:
            pid = os.fork()
            if pid == 0:
                control.close()
                _forked(fds[0], str(request["temp"]))
            os.close(fds[0])
            reply: dict = {"pid": pid}
        elif request.get("op") == "reap":
            reply = _reap(int(request["pid"]))
        else:
            for fd in fds:
                os.close(fd)
            reply = {"error": "unknown request"}
        control.sendall(json.dumps(reply).encode("utf-8"))


def _forked(fd: int, temp: str) -> None:
    """A child of the fork server: its own session, folder and output; never returns."""
    try:
        os.setsid()
        os.chdir(temp)
        output = os.open(os.path.join(temp, "child-output.txt"), os.O_WRONLY | os.O_CREAT, 0o600)
        os.dup2(output, 1)
        os.dup2(output, 2)
        os.close(output)
        os.environ["HOME"] = temp
        os.environ["TMPDIR"] = temp
        # The same command line as a child the host starts itself.
        sys.argv[1:] = [str(fd), temp]
        _child(fd, temp)
    finally:
        os._exit(4)


def _reap(pid: int) -> dict:
    """Waits for a child (the host has killed it) and says how it ended."""
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
