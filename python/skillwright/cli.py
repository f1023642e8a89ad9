"""The headless command line: ``skillwright COMMAND ...``.

Start-up must stay fast (``skillwright --help`` well under a second), so this module
imports only click. Each command lives in the module of its pipeline stage and is
loaded when it is used; heavy libraries load inside the command's body.

Errors the user can cause (:class:`~skillwright.errors.SkillwrightError`) are printed
as one plain message on stderr with exit status 2 (or the error's own status); no
traceback reaches the user for them. Ctrl-C ends a command with status 130.
"""

from __future__ import annotations

import importlib
import logging
import sys
from typing import Any

import click

__all__ = ["main"]

# name -> "module:attribute" of a click command or group; loaded on first use.
COMMANDS: dict[str, str] = {
    "capability": "skillwright.capability.commands:capability",
    "check": "skillwright.validation.commands:check",
    "discover": "skillwright.interfaces.commands:discover",
    "generate": "skillwright.pipeline.commands:generate",
    "inventory": "skillwright.interfaces.inventory_commands:inventory",
    "models": "skillwright.llm.commands:models",
    "retrieve": "skillwright.retrieval.commands:retrieve",
    "rules": "skillwright.validation.commands:rules",
    "run": "skillwright.runtime.commands:run",
    "spec": "skillwright.spec.commands:spec",
    "tui": "skillwright.tui.commands:tui",
    "validate": "skillwright.sim.commands:validate",
}


class LazyGroup(click.Group):
    """A click group whose subcommands are imported only when needed."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted([*super().list_commands(ctx), *COMMANDS])

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        if cmd_name in COMMANDS:
            module_name, attribute = COMMANDS[cmd_name].split(":")
            command = getattr(importlib.import_module(module_name), attribute)
            assert isinstance(command, click.Command)
            return command
        return super().get_command(ctx, cmd_name)

    def invoke(self, ctx: click.Context) -> Any:
        from skillwright.errors import SkillwrightError

        try:
            return super().invoke(ctx)
        except SkillwrightError as error:
            click.echo(f"error: {error}", err=True)
            ctx.exit(error.exit_code)
        except KeyboardInterrupt:
            # The commands that know what an interrupt leaves say it themselves (as an
            # OperationCancelledError, above); any other ends here, with the status a shell
            # gives a command stopped by Ctrl-C rather than click's "Aborted!" and 1.
            click.echo(f"error: {ctx.invoked_subcommand or 'skillwright'} interrupted", err=True)
            ctx.exit(130)


class _WarningLines(logging.Handler):
    """Prints skillwright's warnings (and llama.cpp's, routed into logging) as
    ``warning: ...`` lines on stderr."""

    def emit(self, record: logging.LogRecord) -> None:
        click.echo(f"{record.levelname.lower()}: {record.getMessage()}", err=True)


def _print_version(ctx: click.Context, _param: click.Parameter, value: bool) -> None:
    if not value or ctx.resilient_parsing:
        return
    from skillwright import __version__
    from skillwright.core import core_version

    click.echo(f"skillwright {__version__} (core {core_version()})")
    ctx.exit()


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.option(
    "--version",
    is_flag=True,
    expose_value=False,
    is_eager=True,
    callback=_print_version,
    help="Show the version of skillwright and its Rust core, then exit.",
)
def main() -> None:
    """skillwright: write and check ROS 2 robot skills from capability models, offline.

    Give it a capability (OWL/Turtle, CaSk ontology family), a skill specification
    (behaviour per PackML state) and the robot's interfaces; it finds the interfaces
    the capability needs, generates a pySkillUp skill with a local model and checks it.
    """
    logger = logging.getLogger("skillwright")
    if not any(isinstance(h, _WarningLines) for h in logger.handlers):
        handler = _WarningLines(logging.WARNING)
        logger.addHandler(handler)
        logger.propagate = False


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
