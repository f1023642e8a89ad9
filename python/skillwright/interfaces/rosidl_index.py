"""Standard ROS 2 services and actions from installed interface packages (the ament index).

ROS 2 finds its interfaces through the ament resource index: every interface package
installs ``share/ament_index/resource_index/rosidl_interfaces/<pkg>``, a list of its
files (``msg/X.msg``, ``srv/Y.srv``, ``action/Z.action``), and the files themselves under
``share/<pkg>/`` (what ``ros2 interface list`` and ``rosidl_runtime_py.get_interfaces``
read). rosbags' type stores have a distribution's messages but none of its services or
actions, so ``nav_msgs/srv/GetMap`` or ``std_srvs/srv/Trigger`` would be unknown; this
module reads them from the index of:

- the folders in ``SKILLWRIGHT_ROS_INTERFACES`` (``os.pathsep``-separated prefixes);
- ``<sys.prefix>/ros-interfaces/<distro>``, where ``make setup`` installs the pinned
  PyPI wheels of the core interface packages of ROS 2 Jazzy (``ros-nav-msgs``,
  ``ros-std-srvs``, ``ros-rcl-interfaces``, ... built from the ROS 2 release sources; see
  the Makefile's ``ROS_INTERFACES``), without their compiled dependencies, since only
  the definition files are read;
- ``AMENT_PREFIX_PATH`` when ``ROS_DISTRO`` names the same distribution (a sourced ROS 2
  installation).

A service ``pkg/srv/T`` becomes the messages ``pkg/srv/T_Request`` and
``pkg/srv/T_Response``, an action ``pkg/action/T`` becomes ``_Goal``, ``_Result`` and
``_Feedback`` (the names rosidl generates), each as full ros2msg text with the ``MSG:``
blocks of the messages it uses. Packages outside the core set (``nav2_msgs``,
``slam_toolbox``) are no standard types: a robot's inventory must define them.
"""

from __future__ import annotations

import hashlib
import os
import re
import sys
from collections.abc import Callable
from functools import cache
from pathlib import Path
from typing import Final

from skillwright.interfaces.ros2msg import BUILTIN_TYPES, normalize_type_name

__all__ = [
    "ENV_VARIABLE",
    "expand",
    "index_files",
    "index_fingerprint",
    "index_texts",
    "interface_prefixes",
    "top_block",
]

ENV_VARIABLE: Final = "SKILLWRIGHT_ROS_INTERFACES"
_RESOURCE: Final = Path("share") / "ament_index" / "resource_index" / "rosidl_interfaces"
_SEPARATOR: Final = "=" * 80
_SEPARATOR_LINE: Final = re.compile(r"^={3,}\s*$")
_BASE: Final = re.compile(r"^([A-Za-z][A-Za-z0-9_]*(?:/[A-Za-z][A-Za-z0-9_]*){0,2})")
_PARTS: Final = {"srv": ("Request", "Response"), "action": ("Goal", "Result", "Feedback")}


def interface_prefixes(distro: str) -> list[Path]:
    """The install prefixes whose ament index is read for ``distro``, in order."""
    wanted = distro.strip().lower()
    prefixes = [Path(p) for p in os.environ.get(ENV_VARIABLE, "").split(os.pathsep) if p]
    prefixes.append(Path(sys.prefix) / "ros-interfaces" / wanted)
    if os.environ.get("ROS_DISTRO", "").strip().lower() == wanted:
        prefixes.extend(Path(p) for p in os.environ.get("AMENT_PREFIX_PATH", "").split(":") if p)
    return [p for p in dict.fromkeys(prefixes) if (p / _RESOURCE).is_dir()]


def index_files(distro: str) -> dict[str, str]:
    """Every ``.msg``, ``.srv`` and ``.action`` file the index lists for ``distro``, by
    type name (``nav_msgs/srv/GetMap``); the first prefix that has a type wins."""
    found: dict[str, str] = {}
    for prefix in interface_prefixes(distro):
        for resource in sorted((prefix / _RESOURCE).iterdir()):
            package = resource.name
            try:
                listed = resource.read_text(encoding="utf-8").splitlines()
            except (OSError, UnicodeDecodeError):
                continue
            for entry in listed:
                namespace, _, file_name = entry.strip().partition("/")
                stem, dot, suffix = file_name.rpartition(".")
                if not dot or suffix != namespace or namespace not in {"msg", "srv", "action"}:
                    continue  # the .idl twin of each file, and anything unexpected
                name = f"{package}/{namespace}/{stem}"
                if name in found:
                    continue
                try:
                    found[name] = (prefix / "share" / package / entry.strip()).read_text(
                        encoding="utf-8"
                    )
                except (OSError, UnicodeDecodeError):
                    continue
    return found


def index_fingerprint(distro: str) -> str:
    """A short digest of what the index holds for ``distro`` (its prefixes and resource
    files with their sizes and times), to key caches by."""
    digest = hashlib.sha256()
    for prefix in interface_prefixes(distro):
        digest.update(str(prefix).encode())
        for resource in sorted((prefix / _RESOURCE).iterdir()):
            stat = resource.stat()
            digest.update(f"{resource.name}:{stat.st_size}:{stat.st_mtime_ns};".encode())
    return digest.hexdigest()[:12]


def top_block(text: str) -> str:
    """The first block of a ros2msg text (the type's own fields, without ``MSG:`` blocks)."""
    lines: list[str] = []
    for line in text.splitlines():
        if _SEPARATOR_LINE.match(line.strip()):
            break
        lines.append(line)
    return "\n".join(lines)


def _references(text: str, package: str) -> list[str]:
    """The full names of the message types the fields of one block use."""
    names: list[str] = []
    for raw in text.splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line or line == "---":
            continue
        tokens = line.split(None, 1)
        if len(tokens) < 2:
            continue
        type_text, rest = tokens
        if "=" in type_text or rest.lstrip().split(None, 1)[0].find("=") >= 0:
            continue  # a constant (``uint8 FOO=1``) names a builtin type only
        match = _BASE.match(type_text)
        if match is None or match.group(1) in BUILTIN_TYPES:
            continue
        names.append(normalize_type_name(match.group(1), package))
    return names


def expand(name: str, text: str, blocks: Callable[[str], str | None]) -> str:
    """``text`` (the block of type ``name``) with the ``MSG:`` block of every message it
    uses, directly or through others; ``blocks`` gives a message's own block or ``None``."""
    out = [text.rstrip("\n")]
    seen: set[str] = set()
    pending = list(reversed(_references(text, name.split("/", 1)[0])))
    while pending:
        dependency = pending.pop()
        if dependency in seen:
            continue
        seen.add(dependency)
        block = blocks(dependency)
        if block is None:
            continue
        package, _, type_name = dependency.split("/")
        out.append(f"{_SEPARATOR}\nMSG: {package}/{type_name}\n{block.rstrip()}")
        pending.extend(reversed(_references(block, package)))
    return "\n".join(out) + "\n"


def _split(text: str, count: int) -> list[str] | None:
    """The ``count`` parts of a ``.srv`` (2) or ``.action`` (3) file, or ``None``."""
    parts: list[list[str]] = [[]]
    for line in text.splitlines():
        if line.split("#", 1)[0].strip() == "---":
            parts.append([])
        else:
            parts[-1].append(line)
    return ["\n".join(p) for p in parts] if len(parts) == count else None


def index_texts(distro: str, messages: dict[str, str] | None = None) -> dict[str, str]:
    """The index's types for ``distro`` as full ros2msg texts by message name: every
    message, and the request and response of every service and the goal, result and
    feedback of every action under rosidl's names (``nav_msgs/srv/GetMap_Request``).

    ``messages`` holds full texts from elsewhere (the rosbags store), used for the
    messages a definition uses when the index lacks them.
    """
    return dict(_index_texts(distro, tuple(sorted((messages or {}).items()))))


@cache
def _index_texts(distro: str, messages: tuple[tuple[str, str], ...]) -> tuple[tuple[str, str], ...]:
    files = index_files(distro)
    known = dict(messages)

    def blocks(type_name: str) -> str | None:
        own = files.get(type_name)
        if own is not None:
            return own
        other = known.get(type_name)
        return top_block(other) if other is not None else None

    out: dict[str, str] = {}
    for name, text in files.items():
        namespace = name.split("/")[1]
        if namespace == "msg":
            out[name] = expand(name, text, blocks)
            continue
        names = _PARTS[namespace]
        parts = _split(text, len(names))
        if parts is None:
            continue
        for part, body in zip(names, parts, strict=True):
            out[f"{name}_{part}"] = expand(f"{name}_{part}", body, blocks)
    return tuple(sorted(out.items()))
