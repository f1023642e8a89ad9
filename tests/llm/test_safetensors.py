"""Reading safetensors weight files: tensors come back exact, damage is reported by name."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from skillwright.errors import InputFileNotFoundError, ModelFormatError
from skillwright.llm.safetensors import read_safetensors


def write_safetensors(path: Path, tensors: dict[str, np.ndarray[Any, Any]]) -> Path:
    """A safetensors file as the format describes it (the test's own writer)."""
    codes = {np.dtype("<f4"): "F32", np.dtype("<i8"): "I64", np.dtype("<f2"): "F16"}
    header: dict[str, Any] = {"__metadata__": {"format": "np"}}
    blobs, offset = [], 0
    for name, array in tensors.items():
        blob = np.ascontiguousarray(array).tobytes()
        header[name] = {
            "dtype": codes[array.dtype],
            "shape": list(array.shape),
            "data_offsets": [offset, offset + len(blob)],
        }
        blobs.append(blob)
        offset += len(blob)
    text = json.dumps(header).encode()
    path.write_bytes(len(text).to_bytes(8, "little") + text + b"".join(blobs))
    return path


def with_header(path: Path, header: dict[str, Any], data: bytes = b"") -> Path:
    text = json.dumps(header).encode()
    path.write_bytes(len(text).to_bytes(8, "little") + text + data)
    return path


def test_tensors_come_back_with_their_dtype_shape_and_values(tmp_path: Path) -> None:
    tensors = {
        "weight": np.arange(12, dtype=np.float32).reshape(3, 4) / 7,
        "ids": np.array([[1, 2, 3]], dtype=np.int64),
        "half": np.array([0.5, -2.0], dtype=np.float16),
        "scalar": np.array(3.25, dtype=np.float32),
    }
    read = read_safetensors(write_safetensors(tmp_path / "m.safetensors", tensors))
    assert set(read) == set(tensors)
    for name, array in tensors.items():
        assert read[name].dtype == array.dtype
        np.testing.assert_array_equal(read[name], array)


def test_a_missing_file_is_named(tmp_path: Path) -> None:
    with pytest.raises(InputFileNotFoundError, match=r"nothing\.safetensors does not exist"):
        read_safetensors(tmp_path / "nothing.safetensors")


def test_a_truncated_file_names_the_tensor_whose_data_is_cut(tmp_path: Path) -> None:
    path = write_safetensors(tmp_path / "m.safetensors", {"w": np.ones((4, 4), np.float32)})
    path.write_bytes(path.read_bytes()[:-10])
    with pytest.raises(ModelFormatError, match=r"m\.safetensors: tensor 'w' \(F32 \[4, 4\]\)"):
        read_safetensors(path)


@pytest.mark.parametrize(
    ("content", "problem"),
    [
        (b"\x01\x02", r"only 2 byte\(s\)"),
        ((10_000).to_bytes(8, "little") + b"{}", r"header of 10000 bytes does not fit"),
        ((4).to_bytes(8, "little") + b"{no}", r"header \(bytes 8 to 12\) is not JSON"),
        ((2).to_bytes(8, "little") + b"[]", r"header is not a JSON object"),
    ],
)
def test_a_damaged_header_is_reported_with_where_it_broke(
    tmp_path: Path, content: bytes, problem: str
) -> None:
    path = tmp_path / "bad.safetensors"
    path.write_bytes(content)
    with pytest.raises(ModelFormatError, match=rf"bad\.safetensors: {problem}"):
        read_safetensors(path)


@pytest.mark.parametrize(
    ("entry", "problem"),
    [
        ({"dtype": "F32", "shape": [1]}, "lacks dtype, shape or data_offsets"),
        ({"dtype": "C64", "shape": [1], "data_offsets": [0, 8]}, "dtype 'C64'"),
        ({"dtype": "F32", "shape": [-1], "data_offsets": [0, 4]}, "malformed shape"),
        ({"dtype": "F32", "shape": [3], "data_offsets": [0, 8]}, "should take 12 bytes"),
    ],
)
def test_a_malformed_tensor_entry_names_the_tensor(
    tmp_path: Path, entry: dict[str, Any], problem: str
) -> None:
    path = with_header(tmp_path / "m.safetensors", {"t": entry}, bytes(16))
    with pytest.raises(ModelFormatError, match=rf"tensor 't'.*{problem}"):
        read_safetensors(path)
