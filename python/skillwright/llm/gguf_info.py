"""Reads what ``models list`` shows from a GGUF file's header, without loading the model.

The reader walks the header (metadata and tensor directory) with plain ``struct`` reads, so it
needs only a few kilobytes of a multi-gigabyte file and can say precisely where a damaged file
goes wrong: a bad magic number, a header cut short, or tensor data that ends beyond the end of
the file (a truncated download). Type sizes and file-type names come from the ``gguf`` package.
"""

from __future__ import annotations

import struct
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, BinaryIO

from skillwright.errors import ModelFormatError

__all__ = ["GGUFInfo", "read_gguf_info"]

_MAGIC = b"GGUF"
_DEFAULT_ALIGNMENT = 32
# GGUF value types (see the GGUF specification): scalar formats by type id.
_SCALARS = {
    0: "<B",
    1: "<b",
    2: "<H",
    3: "<h",
    4: "<I",
    5: "<i",
    6: "<f",
    7: "<?",
    10: "<Q",
    11: "<q",
    12: "<d",
}
_STRING, _ARRAY = 8, 9


@dataclass(frozen=True)
class GGUFInfo:
    """Facts about a GGUF model file taken from its header."""

    path: Path
    """The file read."""
    version: int
    """GGUF format version."""
    file_size: int
    """Size of the file in bytes."""
    architecture: str | None
    """``general.architecture`` (e.g. ``llama``, ``qwen2``)."""
    name: str | None
    """``general.name``, if set."""
    context_length: int | None
    """Context length the model was trained with (``<arch>.context_length``)."""
    quantisation: str
    """Quantisation (e.g. ``Q4_K_M``), from ``general.file_type`` or the tensors' types."""
    parameters: int
    """Number of weights over all tensors."""
    tensor_count: int
    """Number of tensors."""
    data_end: int
    """Byte offset where the last tensor's data ends; the file must be at least this long."""
    chat_template: str | None
    """The Jinja2 chat template stored in the file, if any."""
    metadata: dict[str, Any] = field(repr=False)
    """Scalar metadata values; arrays are replaced by their length."""


class _Reader:
    def __init__(self, stream: BinaryIO, path: Path, size: int) -> None:
        self.stream = stream
        self.path = path
        self.size = size

    def fail(self, message: str, offset: int | None = None, todo: str = "") -> ModelFormatError:
        at = f" at byte {offset}" if offset is not None else ""
        todo = todo or "copy the complete file again or get another build of the model"
        return ModelFormatError(f"{self.path}: {message}{at}; {todo}")

    def read(self, count: int, what: str) -> bytes:
        offset = self.stream.tell()
        if count > self.size - offset:
            raise self.fail(
                f"truncated inside the GGUF header ({what} needs {count} bytes, "
                f"{self.size - offset} left)",
                offset,
            )
        return self.stream.read(count)

    def scalar(self, fmt: str, what: str) -> Any:
        return struct.unpack(fmt, self.read(struct.calcsize(fmt), what))[0]

    def string(self, what: str) -> str:
        length = self.scalar("<Q", what)
        raw = self.read(length, what)
        return raw.decode("utf-8", errors="replace")

    def value(self, kind: int, key: str) -> Any:
        if kind in _SCALARS:
            return self.scalar(_SCALARS[kind], f"value of {key}")
        if kind == _STRING:
            return self.string(f"value of {key}")
        if kind == _ARRAY:
            item_kind = self.scalar("<I", f"array type of {key}")
            count = self.scalar("<Q", f"array length of {key}")
            if item_kind in _SCALARS:
                # Numeric arrays (token scores, types) are skipped, not parsed.
                self.read(count * struct.calcsize(_SCALARS[item_kind]), f"array {key}")
            elif item_kind in (_STRING, _ARRAY):
                for _ in range(count):
                    self.value(item_kind, key)
            else:
                raise self.fail(f"unknown array item type {item_kind} in {key}")
            return count
        raise self.fail(f"unknown value type {kind} for key {key!r}", self.stream.tell() - 4)


def _quantisation(metadata: dict[str, Any], tensor_types: Counter[int]) -> str:
    import gguf

    file_type = metadata.get("general.file_type")
    if isinstance(file_type, int):
        try:
            return gguf.LlamaFileType(file_type).name.removeprefix("MOSTLY_").removeprefix("ALL_")
        except ValueError:
            pass
    if tensor_types:
        kind = tensor_types.most_common(1)[0][0]
        try:
            return gguf.GGMLQuantizationType(kind).name
        except ValueError:
            return f"type {kind}"
    return "unknown"


def read_gguf_info(path: Path) -> GGUFInfo:
    """Reads and checks a GGUF file's header; raises :class:`ModelFormatError` if it is damaged.

    The check covers the magic number, the version, every metadata entry, the tensor directory
    and that the file is long enough to hold every tensor's data.
    """
    import gguf

    with path.open("rb") as stream:
        size = path.stat().st_size
        reader = _Reader(stream, path, size)
        magic = stream.read(4)
        if magic != _MAGIC:
            raise reader.fail(
                f"not a GGUF model file (starts with {magic!r}, expected {_MAGIC!r})",
                0,
                "skillwright runs GGUF files only: get a .gguf build of the model",
            )
        version = reader.scalar("<I", "version")
        if version not in (2, 3):
            raise reader.fail(f"GGUF version {version} is not supported (only 2 and 3)", 4)
        tensor_count = reader.scalar("<Q", "tensor count")
        kv_count = reader.scalar("<Q", "metadata count")
        metadata: dict[str, Any] = {}
        for _ in range(kv_count):
            key = reader.string("metadata key")
            kind = reader.scalar("<I", f"type of {key}")
            metadata[key] = reader.value(kind, key)
        tensor_types: Counter[int] = Counter()
        parameters = 0
        relative_end = 0
        for _ in range(tensor_count):
            name = reader.string("tensor name")
            dims = reader.scalar("<I", f"dimension count of {name}")
            if dims > 8:
                raise reader.fail(f"tensor {name!r} claims {dims} dimensions", stream.tell() - 4)
            shape = [reader.scalar("<Q", f"shape of {name}") for _ in range(dims)]
            kind = reader.scalar("<I", f"type of {name}")
            offset = reader.scalar("<Q", f"offset of {name}")
            elements = 1
            for extent in shape:
                elements *= extent
            try:
                block, type_size = gguf.GGML_QUANT_SIZES[gguf.GGMLQuantizationType(kind)]
            except (ValueError, KeyError):
                raise reader.fail(f"tensor {name!r} has unknown type {kind}") from None
            tensor_types[kind] += elements
            parameters += elements
            relative_end = max(relative_end, offset + elements // block * type_size)
        alignment = metadata.get("general.alignment", _DEFAULT_ALIGNMENT)
        if not isinstance(alignment, int) or alignment <= 0:
            alignment = _DEFAULT_ALIGNMENT
        data_start = -(-stream.tell() // alignment) * alignment
    data_end = data_start + relative_end
    if data_end > size:
        raise ModelFormatError(
            f"{path}: truncated GGUF file: its tensors need {data_end} bytes, the file has "
            f"{size} (it ends at byte {size}); copy the complete file again"
        )
    architecture = metadata.get("general.architecture")
    context = metadata.get(f"{architecture}.context_length") if architecture else None
    template = metadata.get("tokenizer.chat_template")
    model_name = metadata.get("general.name")
    return GGUFInfo(
        path=path,
        version=version,
        file_size=size,
        architecture=architecture if isinstance(architecture, str) else None,
        name=model_name if isinstance(model_name, str) else None,
        context_length=context if isinstance(context, int) else None,
        quantisation=_quantisation(metadata, tensor_types),
        parameters=parameters,
        tensor_count=tensor_count,
        data_end=data_end,
        chat_template=template if isinstance(template, str) else None,
        metadata=metadata,
    )
