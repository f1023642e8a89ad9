"""``skillwright tui``: the terminal user interface.

Only click is imported here; Textual and the app load inside the command.
"""

from __future__ import annotations

from pathlib import Path

import click

__all__ = ["tui"]


@click.command()
@click.option(
    "--workspace",
    type=click.Path(file_okay=False, path_type=Path),
    help="Folder with capabilities, specifications, inventories and results "
    "[default: ./capabilities if present, else the current folder].",
)
@click.option(
    "--models",
    "models_file",
    type=click.Path(dir_okay=False, path_type=Path),
    help="models.toml to use instead of the configured one.",
)
def tui(workspace: Path | None, models_file: Path | None) -> None:
    """Drive the whole pipeline from the terminal: capability, specification, interfaces,
    retrieval, generation and history. The session is saved as you go."""
    from skillwright.errors import InputFileNotFoundError, InvalidArgumentError
    from skillwright.tui.workspace import resolve_workspace

    root = resolve_workspace(workspace, Path.cwd())
    if not root.exists():
        raise InputFileNotFoundError(f"workspace {root}: no such folder; create it or pick another")
    if not root.is_dir():
        raise InvalidArgumentError(f"workspace {root}: is a file; give a folder")
    if models_file is not None and not models_file.is_file():
        raise InputFileNotFoundError(f"models file {models_file}: no such file")

    from skillwright.tui.app import make_app

    make_app(root, models_file=models_file).run()
