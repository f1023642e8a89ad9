"""The commands that take a capability, a spec and interfaces name them the same way."""

from __future__ import annotations

import click
import pytest

from skillwright.cli import COMMANDS, main


@pytest.mark.parametrize("name", ["check", "retrieve", "generate"])
def test_capability_spec_and_interfaces_options_agree(name: str) -> None:
    assert name in COMMANDS
    command = main.get_command(click.Context(main), name)
    assert command is not None
    options = {p.name: p for p in command.params if isinstance(p, click.Option)}
    assert options["capability_file"].opts == ["--capability"]
    assert options["capability_iri"].opts == ["--capability-iri"]
    assert options["spec_file"].opts == ["--spec"]
    assert options["source"].opts == ["--interfaces"]
    assert options["capability_file"].required
