"""SVG snapshots of the main screens at 80x24 (the smallest supported) and 160x48, and of
results of a generation from 80x24 to 200x50.

Update them after a deliberate change of the layout with ``pytest --snapshot-update`` and
look at the SVG files under ``__snapshots__/`` before committing them.
"""

from __future__ import annotations

import hashlib
import json
import shutil
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import pytest
from textual.pilot import Pilot
from textual.widgets import Input, Select, TabbedContent, TextArea
from textual.widgets.input import Selection

from skillwright.pipeline import GenerationRequest, run_generation
from skillwright.tui.screens.base import Pane
from skillwright.tui.screens.generation import GenerationPane
from skillwright.tui.screens.history import HistoryPane
from skillwright.tui.widgets.simulation import SimulationView
from tests.conftest import SHIPPED_CAPABILITIES
from tests.fixtures.scripted import MethodScript
from tests.pipeline.conftest import use_model
from tests.tui.conftest import app_for, preset_session, wait_until, write_models

SIZES = [(80, 24), (160, 48)]


def _inputs(workspace: Path, tab: str) -> None:
    preset_session(
        workspace,
        capability="move-forward.ttl",
        spec_path="move-forward.spec.yaml",
        interfaces="recordings/mr1",
        dense=False,
        active_tab=tab,
    )


def _focus_in_active_tab(app: Any) -> bool:
    """The focus is on the main widget of the tab shown, or in the tab when it has none (its
    first activation can come late on a busy machine), so the footer shows that tab's keys."""
    tabs = app.query_one("#tabs", TabbedContent)
    pane = tabs.get_pane(tabs.active)
    if app.focused is None or pane not in app.focused.ancestors_with_self:
        return False
    primaries = [p.primary for p in pane.query(Pane) if p.primary]
    return not primaries or any(app.focused in pane.query(p) for p in primaries)


def _settled(
    extra: Callable[[Any], object] = lambda app: True, *, primary: bool = True
) -> Callable[[Pilot[Any]], Awaitable[None]]:
    """Waits for the inputs to load and ``extra`` (and with ``primary``, for the focus on the
    tab's main widget); then hides what changes from run to run."""

    async def run_before(pilot: Pilot[Any]) -> None:
        app = pilot.app
        await wait_until(
            pilot,
            lambda: (
                app.loaded.capability is not None
                and app.loaded.inventory is not None
                and app.spec_pane().spec is not None
                and app.query_one("#generation-model", Select).value is not Select.NULL
                and (not primary or _focus_in_active_tab(app))
                and extra(app)
            ),
        )
        app.clear_notifications()
        for widget in [*app.query(Input), *app.query(TextArea)]:
            widget.cursor_blink = False
        if isinstance(app.focused, Input):
            # Whether the focused input's text is selected depends on how its focus arrived
            # (Textual selects on a widget's focus, not on focus the app's own brings back),
            # which varied from run to run on a busy machine: the snapshot shows it selected.
            app.focused.selection = Selection(0, len(app.focused.value))
        await pilot.wait_for_scheduled_animations()
        await pilot.pause()

    return run_before


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
@pytest.mark.parametrize("tab", ["capability", "specification", "interfaces", "generation"])
def test_screen_with_the_inputs_loaded(
    snap_compare: Any, workspace: Path, models_file: Path, tab: str, size: tuple[int, int]
) -> None:
    _inputs(workspace, tab)
    app = app_for(workspace, models_file)
    assert snap_compare(app, terminal_size=size, run_before=_settled())


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
def test_retrieval_screen_with_ranked_interfaces(
    snap_compare: Any, workspace: Path, models_file: Path, size: tuple[int, int]
) -> None:
    _inputs(workspace, "retrieval")
    app = app_for(workspace, models_file)

    async def rank(pilot: Pilot[Any]) -> None:
        await _settled()(pilot)
        await pilot.press("ctrl+r")
        await _settled(lambda app: app.loaded.hits)(pilot)

    assert snap_compare(app, terminal_size=size, run_before=rank)


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
def test_history_screen_with_two_results(
    snap_compare: Any, workspace: Path, models_file: Path, size: tuple[int, int]
) -> None:
    for name, k in (("move_forward-20250101-080000", 2), ("move_forward-20250102-080000", 4)):
        run_generation(
            GenerationRequest(
                capability=workspace / "move-forward.ttl",
                spec=workspace / "move-forward.spec.yaml",
                interfaces=workspace / "recordings" / "mr1",
                out_dir=workspace / "generated" / name,
                skeleton=True,
                dense=False,
                k=k,
            )
        )
    _inputs(workspace, "history")
    app = app_for(workspace, models_file)
    run_before = _settled(lambda app: len(app.query_one(HistoryPane).entries) == 2)
    assert snap_compare(app, terminal_size=size, run_before=run_before)


def test_help_screen(snap_compare: Any, workspace: Path, models_file: Path) -> None:
    _inputs(workspace, "capability")
    app = app_for(workspace, models_file)

    async def help_shown(pilot: Pilot[Any]) -> None:
        await _settled()(pilot)
        await pilot.press("f1")

    assert snap_compare(app, terminal_size=(80, 24), run_before=help_shown)


# --- results of a generation ---------------------------------------------------------------------
RESULT = "set_velocity-20250101-080000"
"""The result folder's name in the workspaces of the result snapshots."""

SNAPSHOT_ROOT = Path("/tmp/skillwright-snapshots")
"""Where the result snapshots' workspaces are made: the result header shows the folder's
absolute path, which must be the same in every run of the tests."""


def _steady(folder: Path) -> None:
    """Puts the same numbers in place of what changes from run to run in the record of
    ``folder`` (the time it was made, wall times, speeds): the snapshot shows the layout."""
    path = folder / "record.json"
    record = json.loads(path.read_text(encoding="utf-8"))
    record["created"] = "2025-01-01T08:00:00+00:00"
    record["timings"] = dict.fromkeys(record["timings"], 1.0)
    for part in ("run", "simulation"):
        if record.get(part):
            record[part]["seconds"] = 1.0
            for episode in record[part].get("episodes", []):
                episode["wall_seconds"] = 1.0
    if record.get("simulation") and record["simulation"].get("speed"):
        record["simulation"]["speed"] = 10.0
    if record.get("model"):
        record["model"]["tokens_per_second"] = 10.0
        for attempt in record["model"]["attempts"]:
            attempt["seconds"] = 1.0
    path.write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")


@pytest.fixture(scope="module")
def made_results(tmp_path_factory: pytest.TempPathFactory, wordy_gguf: Path) -> dict[str, Path]:
    """Two results of set-velocity written by the pipeline with a scripted model: ``failed``
    (its execute reads the velocity before the base reaches it: an output oracle fails in
    the simulation) and ``passed`` (it waits, then reads it: every oracle passes)."""
    from tests.pipeline.conftest import SET_VELOCITY
    from tests.pipeline.test_behaviour import MEASURED_EXECUTE

    root = tmp_path_factory.mktemp("made")
    models = write_models(root / "models.toml", wordy_gguf, max_tokens=400)
    made = {}
    with pytest.MonkeyPatch.context() as monkeypatch:
        monkeypatch.setenv("MPLCONFIGDIR", str(tmp_path_factory.getbasetemp() / "matplotlib"))
        for name, execute in (("failed", SET_VELOCITY["execute"]), ("passed", [MEASURED_EXECUTE])):
            use_model(monkeypatch, MethodScript({**SET_VELOCITY, "execute": execute}, "tiny"))
            out = root / name / RESULT
            run_generation(
                GenerationRequest(
                    capability=SHIPPED_CAPABILITIES / "set-velocity.ttl",
                    spec=SHIPPED_CAPABILITIES / "set-velocity.spec.yaml",
                    interfaces=SHIPPED_CAPABILITIES / "recordings" / "mr1",
                    out_dir=out,
                    models_file=models,
                    dense=False,
                    pinned=("/cmd_vel", "/odom"),
                    attempts=1,
                )
            )
            _steady(out)
            made[name] = out
    return made


def _result_workspace(request: pytest.FixtureRequest, result: Path) -> Path:
    """A workspace at a fixed path, per test, with ``result`` as the last one shown."""
    name = hashlib.sha256(request.node.name.encode()).hexdigest()[:8]
    workspace = SNAPSHOT_ROOT / name / "workspace"
    if workspace.parent.exists():
        shutil.rmtree(workspace.parent)
    shutil.copytree(SHIPPED_CAPABILITIES, workspace)
    shutil.copytree(result, workspace / "generated" / RESULT)
    request.addfinalizer(lambda: shutil.rmtree(workspace.parent, ignore_errors=True))
    preset_session(
        workspace,
        capability="set-velocity.ttl",
        spec_path="set-velocity.spec.yaml",
        interfaces="recordings/mr1",
        dense=False,
        active_tab="generation",
        last_result=f"generated/{RESULT}",
    )
    return workspace


def _result_shown(app: Any) -> bool:
    return app.query_one(GenerationPane).shown is not None


LAYOUT_SIZES = [(80, 24), (120, 40), (160, 48), (200, 50)]


@pytest.mark.slow
@pytest.mark.parametrize("size", LAYOUT_SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
def test_a_failed_generation_keeps_its_code_readable_beside_the_findings(
    snap_compare: Any,
    request: pytest.FixtureRequest,
    made_results: dict[str, Path],
    models_file: Path,
    size: tuple[int, int],
) -> None:
    app = app_for(_result_workspace(request, made_results["failed"]), models_file)
    assert snap_compare(app, terminal_size=size, run_before=_settled(_result_shown))


@pytest.mark.slow
def test_a_failed_generation_shows_red_marks_and_the_oracle_table(
    snap_compare: Any,
    request: pytest.FixtureRequest,
    made_results: dict[str, Path],
    models_file: Path,
) -> None:
    app = app_for(_result_workspace(request, made_results["failed"]), models_file)

    async def simulation(pilot: Pilot[Any]) -> None:
        await _settled(_result_shown)(pilot)
        await pilot.press("v")
        await _settled(lambda app: app.query_one(SimulationView).verdicts, primary=False)(pilot)

    assert snap_compare(app, terminal_size=(120, 40), run_before=simulation)


@pytest.mark.slow
def test_a_passed_generation_shows_its_path_and_speed_plot(
    snap_compare: Any,
    request: pytest.FixtureRequest,
    made_results: dict[str, Path],
    models_file: Path,
) -> None:
    app = app_for(_result_workspace(request, made_results["passed"]), models_file)

    async def plot(pilot: Pilot[Any]) -> None:
        await _settled(_result_shown)(pilot)
        await pilot.press("v")
        view = pilot.app.query_one(SimulationView)
        await _settled(lambda app: view.trajectories and view.size.width > 0, primary=False)(pilot)
        view.scroll_to_widget(pilot.app.query_one("#simulation-plot"), animate=False, top=True)
        await pilot.pause()

    assert snap_compare(app, terminal_size=(120, 40), run_before=plot)
