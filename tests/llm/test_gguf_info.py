"""The GGUF header reader: facts for `models list`, and exact errors for damaged files."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.errors import ModelFormatError
from skillwright.llm.gguf_info import read_gguf_info
from tests.fixtures.tiny_gguf import CHAT_TEMPLATE


def test_header_gives_architecture_context_quantisation_and_template(tiny_gguf: Path) -> None:
    info = read_gguf_info(tiny_gguf)
    assert info.version == 3
    assert info.architecture == "llama"
    assert info.name == "skillwright-tiny-test-llama"
    assert info.context_length == 8192
    assert info.quantisation == "F32"
    assert info.chat_template == CHAT_TEMPLATE
    assert info.tensor_count == 3 + 2 * 9
    assert info.metadata["tokenizer.ggml.tokens"] == 259  # arrays are reported by length
    assert info.data_end <= info.file_size == tiny_gguf.stat().st_size
    assert 100_000 < info.file_size < 1_000_000


def test_file_cut_inside_the_tensor_data_is_reported_as_truncated(
    tiny_gguf: Path, tmp_path: Path
) -> None:
    cut = tmp_path / "cut.gguf"
    data = tiny_gguf.read_bytes()
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(ModelFormatError, match=rf"truncated GGUF .* the file has {len(data) // 2}"):
        read_gguf_info(cut)


def test_file_cut_inside_the_header_names_the_byte_offset(tiny_gguf: Path, tmp_path: Path) -> None:
    cut = tmp_path / "cut.gguf"
    cut.write_bytes(tiny_gguf.read_bytes()[:200])
    with pytest.raises(
        ModelFormatError,
        match=r"truncated inside the GGUF header .* at byte \d+; copy the complete file",
    ):
        read_gguf_info(cut)


@pytest.mark.parametrize("content", [b"", b"PK\x03\x04 a zip file", b"<html>not found</html>"])
def test_file_that_is_not_gguf_says_so(tmp_path: Path, content: bytes) -> None:
    path = tmp_path / "model.gguf"
    path.write_bytes(content)
    with pytest.raises(
        ModelFormatError,
        match=r"not a GGUF model file .* at byte 0; skillwright runs GGUF files only",
    ):
        read_gguf_info(path)


def test_unsupported_version_is_reported(tiny_gguf: Path, tmp_path: Path) -> None:
    path = tmp_path / "v9.gguf"
    data = bytearray(tiny_gguf.read_bytes())
    data[4:8] = (9).to_bytes(4, "little")
    path.write_bytes(bytes(data))
    with pytest.raises(ModelFormatError, match="GGUF version 9 is not supported"):
        read_gguf_info(path)
