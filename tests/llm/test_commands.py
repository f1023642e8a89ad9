"""`skillwright models list|check` on the shipped models.toml plus a user file."""

from __future__ import annotations

import hashlib
from pathlib import Path

import pytest
from click.testing import CliRunner

from skillwright.cli import main
from skillwright.console import out_console
from tests.llm.conftest import write_models_toml


@pytest.fixture(autouse=True)
def wide_console(monkeypatch: pytest.MonkeyPatch) -> None:
    """A console wide enough that table rows are not wrapped (rich reads COLUMNS once)."""
    monkeypatch.setenv("COLUMNS", "250")
    out_console.cache_clear()
    yield
    out_console.cache_clear()


def _invoke(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.output


def test_list_on_the_shipped_file_reports_the_llm_missing_and_minilm_present() -> None:
    code, output = _invoke("models", "list")
    assert code == 0, output
    lines = {line.split()[1]: line for line in output.splitlines() if line.startswith("│ ")}
    assert "missing" in lines["qwen2.5-coder-1.5b-instruct"]
    assert "generation (default)" in lines["qwen2.5-coder-1.5b-instruct"]
    assert "present" in lines["all-minilm-l6-v2"]
    assert "256" in lines["all-minilm-l6-v2"]  # MiniLM's max_seq_length
    assert "- model 'qwen2.5-coder-1.5b-instruct': file" in output
    assert "never downloads" in output


def test_list_reads_size_quantisation_and_context_from_the_header(
    tiny_gguf: Path, tmp_path: Path
) -> None:
    models = write_models_toml(tmp_path / "models.toml", tiny_gguf)
    code, output = _invoke("models", "--models", str(models), "list")
    assert code == 0, output
    [line] = [line for line in output.splitlines() if line.startswith("│ tiny ")]
    assert "present (no sha256 set)" in line
    assert "F32" in line
    assert "768 / 8192" in line
    assert "KiB" in line


def test_list_reports_a_checksum_mismatch(tiny_gguf: Path, tmp_path: Path) -> None:
    models = write_models_toml(tmp_path / "models.toml", tiny_gguf)
    models.write_text(
        models.read_text().replace("threads = 1", f'threads = 1\nsha256 = "{"0" * 64}"')
    )
    code, output = _invoke("models", "--models", str(models), "list")
    assert code == 0, output
    assert "checksum mismatch" in output
    assert hashlib.sha256(tiny_gguf.read_bytes()).hexdigest() in output.replace("\n", "")


def test_check_loads_generates_and_prints_speed(tiny_gguf: Path, tmp_path: Path) -> None:
    models = write_models_toml(tmp_path / "models.toml", tiny_gguf)
    code, output = _invoke("models", "--models", str(models), "check", "t", "--tokens", "8")
    assert code == 0, output
    assert "tiny: loaded in" in output
    assert "time to first token:" in output
    assert "tokens/s" in output


def test_check_of_the_embedding_model_prints_throughput() -> None:
    code, output = _invoke("models", "check", "minilm")
    assert code == 0, output
    assert "all-minilm-l6-v2: loaded in" in output
    assert "384 dimensions" in output
    assert "texts/s" in output


def test_check_of_a_missing_model_is_one_error_line() -> None:
    code, output = _invoke("models", "check", "coder")
    assert code == 2
    assert output.startswith("error: model 'qwen2.5-coder-1.5b-instruct': file ")


def test_missing_models_file_is_an_error(tmp_path: Path) -> None:
    code, output = _invoke("models", "--models", str(tmp_path / "none.toml"), "list")
    assert code == 2
    assert "none.toml: models file not found" in output


def test_unknown_key_in_the_user_file_fails_the_command(tmp_path: Path) -> None:
    models = tmp_path / "models.toml"
    models.write_text("[defaults]\ngenration = 'x'\n")
    code, output = _invoke("models", "--models", str(models), "list")
    assert code == 2
    assert "unknown key 'defaults.genration'" in output


def test_list_shows_a_server_model_without_contacting_it(tmp_path: Path) -> None:
    # The suite's network guard fails the test on any connection attempt.
    models = tmp_path / "models.toml"
    models.write_text(
        '[[llm]]\nid = "plant-gpu"\nbackend = "openai"\nbase_url = "http://192.0.2.7:8080/v1"\n'
    )
    code, output = _invoke("models", "--models", str(models), "list")
    assert code == 0, output
    [line] = [line for line in output.splitlines() if line.startswith("│ plant-gpu ")]
    assert "server (not contacted)" in line
    assert "http://192.0.2.7:8080/v1" in line
