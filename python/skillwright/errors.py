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

from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from skillwright.capability.model import CapabilityChoice

__all__ = [
    "CapabilityError",
    "CapabilitySelectionError",
    "ConfigError",
    "ContextOverflowError",
    "FileFormatError",
    "GenerationCancelledError",
    "InputFileError",
    "InputFileNotFoundError",
    "InvalidArgumentError",
    "ModelChecksumError",
    "ModelError",
    "ModelFileMissingError",
    "ModelFormatError",
    "ModelServerError",
    "OperationCancelledError",
    "Ros2UnavailableError",
    "SandboxUnavailableError",
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


class CapabilitySelectionError(CapabilityError):
    """A file holds several capabilities and none (or no single one) was chosen."""

    def __init__(self, message: str, choices: Sequence[CapabilityChoice]) -> None:
        super().__init__(message)
        self.choices = list(choices)
        """The capabilities of the file, to choose from."""


class SpecError(SkillwrightError, ValueError):
    """A skill specification is malformed or violates the specification rules."""


class ConfigError(SkillwrightError, ValueError):
    """A configuration file (e.g. ``models.toml``) is malformed; the message names file and key."""


class ModelError(SkillwrightError):
    """A model cannot be used: unknown id, failed load or generation; the message names it."""


class ModelFileMissingError(ModelError, FileNotFoundError):
    """A model's file is not where ``models.toml`` says; the message says where to put it."""


class ModelChecksumError(ModelError, ValueError):
    """A model file's SHA-256 differs from the one in ``models.toml``."""


class ModelFormatError(ModelError, ValueError):
    """A model file is not a (complete) GGUF file; the message names the byte offset."""


class ContextOverflowError(ModelError, ValueError):
    """Prompt plus requested output do not fit the model's context; nothing is truncated."""


class ModelServerError(ModelError, ConnectionError):
    """A configured model server (OpenAI-compatible HTTP) failed or could not be reached."""


class OperationCancelledError(SkillwrightError):
    """The user cancelled a long operation (reading, ranking, generating); its work stopped
    at the next step and nothing it would have produced was kept."""

    exit_code = 130


class GenerationCancelledError(OperationCancelledError):
    """The user cancelled a generation; nothing was written."""


class Ros2UnavailableError(SkillwrightError):
    """The live ROS 2 graph cannot be reached: rclpy is not importable (ROS 2 not sourced
    in this shell, or built for another Python) or no node could be started."""


class SandboxUnavailableError(SkillwrightError):
    """The kernel refuses what the skill sandbox is built on (user, mount, PID and network
    namespaces through bubblewrap), or bubblewrap is missing; the message names the setting
    to change. Nothing was run."""
