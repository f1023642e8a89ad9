"""The help screen: the flow and every key, one page."""

from __future__ import annotations

from typing import ClassVar

from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import VerticalScroll
from textual.screen import ModalScreen
from textual.widgets import Markdown

__all__ = ["HELP_TEXT", "HelpScreen"]

HELP_TEXT = """\
# skillwright

Work from left to right through the tabs; everything you choose and type is saved in the
workspace (`.skillwright/session.json`) as you go and restored on the next start.

| key | what |
|---|---|
| F1 | this help (Esc closes it) |
| F2 … F7 | Capability, Specification, Interfaces, Retrieval, Generation, History |
| Ctrl+P | command palette: every action by name |
| Ctrl+G | generate the skill with the current inputs |
| Esc | cancel the running job (loading, enrichment, ranking, generation) |
| Tab / Shift+Tab | next / previous field |
| Ctrl+Q | quit |

**Capability** — pick a model from the workspace list (Enter), or Ctrl+O to open any file.
A file holding several capabilities lists them above the summary: choose one with Enter.

**Specification** — name, description, skill interface and one text per PackML acting state
(`execute` is required). Checked as you type. Ctrl+S saves (JSON or YAML by the file's
suffix), Ctrl+O loads a file.

**Interfaces** — choose a source (saved inventory, `.mcap`, rosbag2 folder) or Ctrl+O to
open one (a reference-tool report too); "Live ROS 2" lists the running graph when ROS 2 is
sourced. `/` filters; the infrastructure box shows the plumbing. Ctrl+E describes and judges
every interface with the chosen engine (the rules, or the model chosen on the Generation tab)
and saves the inventory in the workspace. `p` pins the highlighted interface into
generation, `x` drops it.

**Retrieval** — Ctrl+R ranks the interfaces for the capability; `p` pins, `x` drops. The
generation record lists what you pinned and dropped.

**Generation** — choose a model (or the skeleton only), Ctrl+G generates. Tokens appear as
they are written; Esc cancels and nothing is written. Enter on a finding jumps to its line.

**History** — earlier results in `generated/`; Enter opens one, `m` marks it, `d` shows the
difference between the marked result and the highlighted one.
"""


class HelpScreen(ModalScreen[None]):
    """Keys and flow; Esc, F1 or q closes it."""

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("escape,f1,q", "dismiss", "Close"),
    ]

    def compose(self) -> ComposeResult:
        with VerticalScroll(id="help-dialog"):
            yield Markdown(HELP_TEXT)
