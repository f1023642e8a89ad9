"""The sandbox's root holds only what a skill needs, and a kernel that refuses it stops the run."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from skillwright.errors import SandboxUnavailableError
from skillwright.runtime import isolation
from skillwright.runtime.isolation import NO_ISOLATION_OPTION, bwrap_binary, layout, unavailable
from tests.conftest import REPO_ROOT
from tests.runtime.conftest import MR1_RECORDING, skill_path

SKILLWRIGHT = [sys.executable, "-m", "skillwright.cli"]


def test_the_root_holds_the_interpreter_its_library_and_the_runtime_only() -> None:
    root = layout()

    assert root.interpreter == os.path.realpath(sys.executable)
    assert root.interpreter in root.files
    assert str(isolation.CHILD_ROOT) in root.folders
    assert root.core in root.files
    bound = [*root.folders, *root.files]
    # No user's home, no host /tmp, no configuration beyond the loader's cache, and of the
    # repository and the virtual environment only the runtime's code, the extension and
    # the allowed packages.
    for path in bound:
        # the repository and its virtual environment may lie anywhere (a clone under /tmp)
        inside = path.startswith((str(REPO_ROOT), sys.base_prefix))
        assert inside or not path.startswith(("/home", "/tmp", "/var", "/run", "/srv", "/opt/")), (
            path
        )
        assert not path.startswith("/etc") or path == "/etc/ld.so.cache", path
        assert path != str(REPO_ROOT)
        assert not path.startswith(f"{sys.prefix}/bin"), path
    venv = [p for p in bound if p.startswith(str(REPO_ROOT))]
    allowed = {str(Path(folder) / name) for name, folder in root.packages}
    for path in venv:
        assert (
            path.startswith(str(isolation.CHILD_ROOT))
            or path == root.core
            or any(path.startswith(a) for a in allowed)
        ), path


def test_the_loader_is_reached_through_the_links_it_is_named_by() -> None:
    loader = isolation._elf_interpreter(layout().interpreter)
    if loader is None:
        pytest.skip("a static interpreter needs no loader")
    hops, real = isolation._links_to(loader)
    assert Path(real).is_file()
    assert set(hops) <= set(layout().links)
    assert any(real.startswith(folder + "/") for folder in layout().folders)


@pytest.mark.parametrize(
    ("said", "setting"),
    [
        (
            "bwrap: setting up uid map: Permission denied",
            "kernel.apparmor_restrict_unprivileged_userns=0",
        ),
        (
            "bwrap: No permissions to create a new namespace, likely because the kernel does "
            "not allow non-privileged user namespaces.",
            "kernel.unprivileged_userns_clone=1",
        ),
        (
            "bwrap: Creating new namespace failed: nesting depth or "
            "/proc/sys/user/max_*_namespaces exceeded (ENOSPC)",
            "user.max_user_namespaces",
        ),
        ("bwrap: Creating new namespace failed: Operation not permitted", "seccomp=unconfined"),
    ],
    ids=["apparmor", "debian", "max-namespaces", "container"],
)
def test_a_refused_sandbox_names_the_setting_to_change(said: str, setting: str) -> None:
    error = unavailable(f"some noise\n{said}\n")

    assert isinstance(error, SandboxUnavailableError)
    message = str(error)
    assert said in message
    assert setting in message
    assert NO_ISOLATION_OPTION in message
    assert "\n" not in message


def _refusing_kernel() -> list[str]:
    """A command prefix under which creating a user namespace fails as on a kernel that
    refuses them (bubblewrap's --disable-userns), the rest of the machine as it is."""
    try:
        binary = bwrap_binary()
    except SandboxUnavailableError as error:
        pytest.skip(str(error))
    prefix = [binary, "--unshare-user", "--disable-userns"]
    if os.getuid() == 0:
        prefix += ["--uid", "0", "--gid", "0"]
    prefix += ["--bind", "/", "/", "--proc", "/proc", "--dev", "/dev", "--"]
    probe = subprocess.run([*prefix, "true"], capture_output=True, check=False)
    if probe.returncode != 0:
        pytest.skip(f"this machine cannot nest the test's namespace: {probe.stderr.decode()}")
    return prefix


def _lines(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if line.strip()]


def test_run_fails_closed_on_a_kernel_that_refuses_user_namespaces(tmp_path: Path) -> None:
    prefix = _refusing_kernel()
    command = ["run", str(skill_path("get_position")), "--interfaces", str(MR1_RECORDING)]

    refused = subprocess.run(
        [*prefix, *SKILLWRIGHT, *command], capture_output=True, text=True, check=False
    )

    assert refused.returncode == 2, refused.stderr
    [line] = _lines(refused.stderr)
    assert line.startswith("error: the sandbox cannot start (bwrap: ")
    assert "user.max_user_namespaces" in line
    assert "Traceback" not in refused.stderr
    assert refused.stdout == ""

    report = tmp_path / "report.json"
    allowed = subprocess.run(
        [*prefix, *SKILLWRIGHT, *command, NO_ISOLATION_OPTION, "-o", str(report)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert allowed.returncode == 0, allowed.stderr
    assert "warning: --unsafe-no-isolation" in allowed.stderr
    episode = json.loads(report.read_text())["trace"]["episodes"][0]
    assert episode["isolation"]["namespaces"] == "none (--unsafe-no-isolation)"


def test_validate_and_generate_fail_closed_and_write_nothing(tmp_path: Path) -> None:
    prefix = _refusing_kernel()
    capabilities = REPO_ROOT / "capabilities"
    validate = [
        "validate",
        str(skill_path("get_position")),
        "--capability",
        str(capabilities / "get-position.ttl"),
        "--interfaces",
        str(MR1_RECORDING),
        "-o",
        str(tmp_path / "validation"),
    ]
    generate = [
        "generate",
        "--capability",
        str(capabilities / "get-position.ttl"),
        "--spec",
        str(capabilities / "get-position.spec.yaml"),
        "--interfaces",
        str(MR1_RECORDING),
        "--skeleton",
        "-o",
        str(tmp_path / "generated"),
    ]
    for command in (validate, generate):
        result = subprocess.run(
            [*prefix, *SKILLWRIGHT, *command], capture_output=True, text=True, check=False
        )
        assert result.returncode == 2, (command[0], result.stderr)
        errors = [line for line in _lines(result.stderr) if line.startswith("error:")]
        assert len(errors) == 1, result.stderr
        assert "the sandbox cannot start" in errors[0]
        assert "Traceback" not in result.stderr
    assert not (tmp_path / "validation").exists()
    assert not (tmp_path / "generated").exists()


def test_a_bwrap_that_refuses_is_reported_not_retried(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    fake = tmp_path / "bwrap"
    fake.write_text(
        "#!/bin/sh\necho 'bwrap: setting up uid map: Permission denied' >&2\nexit 1\n",
        encoding="utf-8",
    )
    fake.chmod(0o755)
    monkeypatch.setenv("SKILLWRIGHT_BWRAP", str(fake))
    from skillwright.runtime.sandbox import check_isolation

    with pytest.raises(SandboxUnavailableError, match="apparmor_restrict_unprivileged_userns"):
        check_isolation()
