"""The child's core, on its own: what it tells the host when an interrupt had to wait for
the end of an exchange."""

from __future__ import annotations

import sys
from typing import Any

import pytest

from skillwright.runtime.sandbox import CHILD_ROOT


class FakeWire:
    def __init__(self) -> None:
        self.sent: list[tuple[str, dict[str, Any]]] = []

    def notify(self, op: str, **fields: Any) -> None:
        self.sent.append((op, fields))

    def request(self, op: str, **fields: Any) -> dict[str, Any]:
        self.sent.append((op, fields))
        return {}


@pytest.fixture
def child_core(monkeypatch: pytest.MonkeyPatch) -> Any:
    monkeypatch.syspath_prepend(str(CHILD_ROOT))
    from _skillwright_child import core

    yield core
    for name in [m for m in sys.modules if m.startswith("_skillwright_child")]:
        monkeypatch.delitem(sys.modules, name)


def test_an_interrupt_deferred_during_a_publish_still_reports_where_the_skill_was(
    child_core: Any,
) -> None:
    wire = FakeWire()
    core = child_core.Core(wire, "skill.py", 0)
    # The signal came while the core was sending: the handler kept the reason and the stack.
    core.deferred_interrupt = "cpu"
    core.deferred_stack = [[31, "execute"]]

    with pytest.raises(child_core.Interrupted) as raised:
        core.notify("publish", id=1, msg={})

    assert raised.value.reason == "cpu"
    assert [op for op, _ in wire.sent] == ["publish", "stack"]
    assert wire.sent[1][1]["reason"] == "cpu"
    assert wire.sent[1][1]["frames"] == [[31, "execute"]]
    assert core.deferred_interrupt is None
    assert core.deferred_stack == []
