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
    fd, temp = int(sys.argv[1]), sys.argv[2]
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    sys.path[:] = [root, *(p for p in sys.path[1:] if p)]
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
    messages.install(core.catalog)
    _allow_packages(config.get("packages", {}))
    patches.install(core)

    def interrupted(signum: int, frame: object) -> None:
        reason = "busy" if signum == signal.SIGUSR1 else "cpu"
        stack = []
        walk = frame
        while walk is not None:
            if walk.f_code.co_filename == core.skill_file:  # type: ignore[attr-defined]
                stack.append([walk.f_lineno, walk.f_code.co_name])  # type: ignore[attr-defined]
            walk = walk.f_back  # type: ignore[attr-defined]
        if core.in_io:
            core.deferred_interrupt = reason
            return
        core.notify("stack", reason=reason, frames=stack[::-1])
        raise core_module.Interrupted(reason)

    signal.signal(signal.SIGUSR1, interrupted)
    signal.signal(signal.SIGXCPU, interrupted)
    end = os._exit
    guard.install(temp, config["read_roots"], fd)
    try:
        driver.run(core, config)
    except HostGone:
        end(3)
    except BaseException:
        # The child's own failure: its traceback goes to the output file the host reads.
        os.write(2, traceback_text().encode("utf-8", "replace"))
        end(4)
    end(0)


def traceback_text() -> str:
    import traceback

    return traceback.format_exc()


if __name__ == "__main__":
    main()
