"""The error hierarchy of skillwright.

Every error a user can cause derives from :class:`SkillwrightError` and carries a
message written for that user: what was wrong, where (file, line, IRI, topic or
model) and, where there is one, what to do about it. The command line prints these
messages without a traceback; anything else reaching the top is a bug.

Where the meaning matches a standard exception, the class derives from it as well,
so ordinary ``except FileNotFoundError`` or ``except ValueError`` clauses still work.
The Rust extension raises the classes defined here (see ``rust/python/src/errors.rs``).
"""

from __future__ import annotations

__all__ = [
    "CapabilityError",
    "FileFormatError",
    "InputFileError",
    "InputFileNotFoundError",
    "InvalidArgumentError",
    "SkillwrightError",
    "SpecError",
]


class SkillwrightError(Exception):
    """Base class of every error skillwright reports to its user."""

    exit_code: int = 2
    """Process exit status the command line uses for this error."""


class InputFileError(SkillwrightError, OSError):
    """A file the user named cannot be read."""


class InputFileNotFoundError(InputFileError, FileNotFoundError):
    """A file the user named does not exist."""


class FileFormatError(SkillwrightError, ValueError):
    """A file exists but its content is malformed; the message says where."""


class InvalidArgumentError(SkillwrightError, ValueError):
    """An option or argument has a value the operation cannot work with."""


class CapabilityError(SkillwrightError, ValueError):
    """A capability model cannot be read into a capability (syntax, structure, selection)."""


class SpecError(SkillwrightError, ValueError):
    """A skill specification is malformed or violates the specification rules."""
