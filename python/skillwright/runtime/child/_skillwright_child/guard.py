"""An audit hook (PEP 578) that reports what a skill has no business doing, at its line.

Refused: starting programs or processes (``os.system``, ``subprocess``, ``os.fork``,
``os.exec*``, ``os.posix_spawn``, ...), loading native code (``ctypes``), opening
internet sockets and resolving host names, signalling other processes, writing,
renaming or deleting anything outside the run's scratch folder, and reading files
outside the Python standard library, the child's own code and that folder.

This hook is the sandbox's reporter, not its boundary: Python code in the same process
can switch it off (it is an object like any other). What keeps the host safe is below
Python, set up before the skill's code runs: bubblewrap's user, mount, PID and network
namespaces and its read-only root, seccomp, and the child's own Landlock and seccomp
programs (``skillwright.runtime.isolation``, ``boot.py``). Those refuse the same actions
whether or not this hook is there; the hook turns the common ones into a
``SandboxViolation`` at the skill's line, which the repair loop can act on, instead of an
``OSError`` from deep inside a library.
"""

from __future__ import annotations

import os
import socket
import sys

_PROCESS_EVENTS = {
    "os.system": "run a shell command",
    "os.exec": "replace the process with another program",
    "os.fork": "fork the process",
    "os.forkpty": "fork the process",
    "os.posix_spawn": "start a program",
    "os.spawn": "start a program",
    "os.startfile": "start a program",
    "subprocess.Popen": "start a program",
    "pty.spawn": "start a program",
    "ctypes.dlopen": "load native code",
    "ctypes.dlsym": "load native code",
    "ctypes.dlsym/handle": "load native code",
    "ctypes.call_function": "call native code",
    "ctypes.cdata": "touch raw memory",
    "ctypes.addressof": "touch raw memory",
    "socket.getaddrinfo": "resolve a host name",
    "socket.gethostbyname": "resolve a host name",
    "socket.gethostbyaddr": "resolve a host name",
    "socket.sethostname": "change the host name",
    "os.setuid": "change the user",
    "os.chroot": "change the root folder",
    "sys._current_frames": "inspect the runtime's threads",
    "mmap.__new__": "map memory or files",
}
_PATH_EVENTS = {
    "os.remove": (0,),
    "os.rmdir": (0,),
    "os.mkdir": (0,),
    "os.rename": (0, 1),
    "os.link": (0, 1),
    "os.symlink": (0, 1),
    "os.chmod": (0,),
    "os.chown": (0,),
    "os.truncate": (0,),
    "os.utime": (0,),
    "os.chflags": (0,),
    "os.lchflags": (0,),
    "os.setxattr": (0,),
    "os.removexattr": (0,),
    "shutil.rmtree": (0,),
    "shutil.move": (0, 1),
    "shutil.copyfile": (1,),
    "shutil.copytree": (1,),
    "shutil.chown": (0,),
    "os.chdir": (0,),
}
_NATIVE_MODULES = {"ctypes", "_ctypes", "_posixsubprocess", "cffi", "_cffi_backend"}
_WRITE_FLAGS = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_TRUNC | os.O_APPEND
_NETWORK_FAMILIES = {socket.AF_INET, socket.AF_INET6} | (
    {socket.AF_PACKET} if hasattr(socket, "AF_PACKET") else set()
)


class SandboxViolation(PermissionError):
    """The skill tried something the sandbox refuses."""

    kind = "sandbox"


class _Guard:
    """The hook's state and its decisions."""

    def __init__(self, temp: str, read_roots: list[str], own_socket: int) -> None:
        self.temp = os.path.realpath(temp)
        self.roots = (*(os.path.realpath(r) for r in read_roots), self.temp)
        self.own_socket = own_socket
        self.own_pid = os.getpid()
        self.busy = False

    def inside(self, path: object, folders: tuple[str, ...]) -> bool:
        if isinstance(path, int):
            return path == self.own_socket or path <= 2
        try:
            resolved = os.path.realpath(os.fspath(path))  # type: ignore[arg-type]
        except (TypeError, ValueError):
            return False
        return any(resolved == f or resolved.startswith(f + os.sep) for f in folders)

    def __call__(self, event: str, args: tuple) -> None:
        # realpath and friends raise audit events of their own; they are the guard's.
        if self.busy:
            return
        self.busy = True
        try:
            self.check(event, args)
        finally:
            self.busy = False

    def check(self, event: str, args: tuple) -> None:
        if event == "open":
            self.check_open(*args[:3])
        elif event in _PROCESS_EVENTS:
            _refuse(_PROCESS_EVENTS[event])
        elif event in _PATH_EVENTS:
            for index in _PATH_EVENTS[event]:
                target = args[index] if index < len(args) else None
                if target is not None and not self.inside(target, (self.temp,)):
                    _refuse(f"change {target} (only its temporary folder is writable)")
        elif event == "import" and args[0].split(".")[0] in _NATIVE_MODULES:
            if args[0] == "_posixsubprocess":
                _refuse("import subprocess (it starts programs)")
            _refuse(f"import {args[0]} (native code)")
        elif event == "socket.__new__" and len(args) > 1 and args[1] in _NETWORK_FAMILIES:
            _refuse("open a network socket (it has no network)")
        elif event in {"socket.connect", "socket.bind", "socket.sendto", "socket.sendmsg"}:
            address = args[1] if len(args) > 1 else None
            if not isinstance(address, (str, bytes)):
                _refuse(f"reach {address!r} over the network (it has no network)")
        elif event == "os.kill" and args[0] not in (self.own_pid, 0):
            _refuse("signal another process")
        elif event == "os.killpg":
            _refuse("signal a process group")

    def check_open(self, path: object, mode: object, flags: int) -> None:
        if path is None:
            return
        writing = bool(flags & _WRITE_FLAGS) or any(c in str(mode or "") for c in "wax+")
        if writing and not self.inside(path, (self.temp,)):
            _refuse(f"write {path} (only its temporary folder is writable)")
        if not writing and not self.inside(path, self.roots):
            _refuse(f"read {path} (outside what a skill needs)")


def _refuse(what: str) -> None:
    raise SandboxViolation(f"the sandbox does not let a skill {what}")


def _no_exit(status: int) -> None:
    """``os._exit`` for skills: ending the process is refused, with the skill's line."""
    raise SandboxViolation(
        f"the sandbox does not let a skill end its process (os._exit({status!r})); raise an "
        "exception to abort"
    )


def install(temp: str, read_roots: list[str], own_socket: int) -> None:
    """Installs the hook: writes only under ``temp``, reads only under ``read_roots``.

    ``os._exit`` raises no audit event, so it is replaced for the skill (the driver keeps
    the real one to end the child).
    """
    for name in list(sys.modules):
        if name.split(".")[0] in _NATIVE_MODULES:
            del sys.modules[name]
    import posix

    os._exit = _no_exit  # type: ignore[assignment]
    posix._exit = _no_exit  # type: ignore[assignment]
    sys.addaudithook(_Guard(temp, read_roots, own_socket))
