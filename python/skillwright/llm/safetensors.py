"""Reading ``.safetensors`` weight files into NumPy arrays, without torch.

The format is small enough to read directly: eight bytes (little-endian unsigned) give the
length of a JSON header; the header maps each tensor's name to its dtype, shape and the byte
range of its data in the buffer that follows (``__metadata__`` holds free-form strings). Every
range is checked against the file before an array is made, so a truncated or damaged file is
reported with its name and the offending tensor instead of yielding wrong weights.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from skillwright.errors import InputFileNotFoundError, ModelFormatError

if TYPE_CHECKING:
    import numpy.typing as npt

__all__ = ["read_safetensors"]

# safetensors dtype names -> NumPy dtype strings (all little-endian in the file).
_DTYPES = {
    "F64": "<f8",
    "F32": "<f4",
    "F16": "<f2",
    "I64": "<i8",
    "I32": "<i4",
    "I16": "<i2",
    "I8": "i1",
    "U8": "u1",
    "BOOL": "?",
}

_HEADER_LIMIT = 100 * 1024 * 1024
"""Largest header accepted; the format's own reference reader refuses bigger ones too."""


def _fail(path: Path, problem: str) -> ModelFormatError:
    return ModelFormatError(
        f"weights file {path}: {problem}; the file is damaged or not a safetensors file "
        "(reinstall the model's package or copy the model folder again)"
    )


def _header(path: Path, data: bytes) -> dict[str, Any]:
    if len(data) < 8:
        raise _fail(path, f"only {len(data)} byte(s), shorter than the 8-byte header length")
    size = int.from_bytes(data[:8], "little")
    if size > _HEADER_LIMIT or 8 + size > len(data):
        raise _fail(path, f"header of {size} bytes does not fit the file's {len(data)} bytes")
    try:
        header = json.loads(data[8 : 8 + size].decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise _fail(path, f"header (bytes 8 to {8 + size}) is not JSON ({error})") from None
    if not isinstance(header, dict):
        raise _fail(path, "header is not a JSON object")
    return header


def read_safetensors(path: Path) -> dict[str, npt.NDArray[Any]]:
    """Every tensor of the file by name, as read-only NumPy arrays sharing one buffer."""
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise InputFileNotFoundError(f"weights file {path} does not exist") from None
    except OSError as error:
        raise _fail(path, f"cannot be read ({error.strerror or error})") from None
    header = _header(path, data)
    start = 8 + int.from_bytes(data[:8], "little")
    buffer = memoryview(data)[start:]
    tensors: dict[str, npt.NDArray[Any]] = {}
    for name, entry in header.items():
        if name == "__metadata__":
            continue
        tensors[name] = _tensor(path, name, entry, buffer)
    return tensors


def _tensor(path: Path, name: str, entry: Any, buffer: memoryview) -> npt.NDArray[Any]:
    import numpy as np

    try:
        dtype_name, shape, (begin, end) = entry["dtype"], entry["shape"], entry["data_offsets"]
    except (TypeError, KeyError, ValueError):
        raise _fail(path, f"tensor {name!r} lacks dtype, shape or data_offsets") from None
    if dtype_name not in _DTYPES:
        raise _fail(path, f"tensor {name!r} has dtype {dtype_name!r}, which is not supported")
    if not all(isinstance(n, int) and n >= 0 for n in [*shape, begin, end]):
        raise _fail(path, f"tensor {name!r} has a malformed shape or data offsets")
    dtype = np.dtype(_DTYPES[dtype_name])
    expected = math.prod(shape) * dtype.itemsize
    if end - begin != expected or end > len(buffer):
        raise _fail(
            path,
            f"tensor {name!r} ({dtype_name} {shape}) should take {expected} bytes, its data "
            f"offsets {begin}..{end} span {end - begin} of a {len(buffer)}-byte buffer",
        )
    return np.frombuffer(buffer[begin:end], dtype=dtype).reshape(shape)
