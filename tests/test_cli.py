"""The command line starts fast and turns user errors into messages, not tracebacks."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from skillwright.cli import main

HEAVY_MODULES = [
    "rdflib",
    "pydantic",
    "rich",
    "yaml",
    "numpy",
    "torch",
    "sentence_transformers",
    "tokenizers",
    "llama_cpp",
    "gguf",
    "jinja2",
    "transformers",
    "textual",
    "mujoco",
    "matplotlib",
    "rosbags",
    "rclpy",
    "skillwright._core",
]


def test_help_imports_no_heavy_module() -> None:
    code = (
        "import sys, json\n"
        "from skillwright.cli import main\n"
        "try:\n"
        "    main(['--help'], standalone_mode=False)\n"
        "finally:\n"
        f"    print(json.dumps([m for m in {HEAVY_MODULES!r} if m in sys.modules]))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60
    )
    loaded = json.loads(result.stdout.strip().splitlines()[-1])
    assert loaded == []


def test_version_names_package_and_core() -> None:
    result = CliRunner().invoke(main, ["--version"])
    assert result.exit_code == 0
    assert result.output.startswith("skillwright ")
    assert "(core " in result.output


def test_help_lists_commands() -> None:
    result = CliRunner().invoke(main, ["--help"])
    assert result.exit_code == 0
    assert "capability models" in result.output


def test_ctrl_c_in_any_command_is_exit_130_with_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.capability import reader

    def interrupted(*_args: object, **_kwargs: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(reader, "load_capability", interrupted)
    result = CliRunner().invoke(main, ["capability", "show", str(tmp_path / "x.ttl")])
    assert result.exit_code == 130
    assert result.stderr == "error: capability interrupted\n"
