"""Typed stubs of the Rust extension ``skillwright._core`` (checked by ``make lint``)."""

from os import PathLike

__all__ = ["__version__", "sha256_file"]
__version__: str

def sha256_file(path: str | PathLike[str]) -> str:
    """Lower-case hex SHA-256 of the file at ``path``.

    Raises ``InputFileNotFoundError`` when it does not exist, ``InputFileError`` when it
    cannot be read and ``InvalidArgumentError`` when it is a folder.
    """
