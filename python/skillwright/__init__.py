"""skillwright: offline generation and checking of ROS 2 robot skills from capability models.

The package is a set of pipeline stages, each a function from documents to documents:
``capability`` and ``spec`` read the user's inputs; later stages discover interfaces,
retrieve the relevant ones, generate a skill and check it. ``cli`` drives them headless.
Importing this package is cheap: heavy libraries load inside the stage that needs them.
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

__all__ = ["__version__"]

try:
    __version__ = version("skillwright")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"
