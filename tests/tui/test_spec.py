"""The Specification tab: a form checked as you type, saved and loaded, never losing text."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
import yaml
from textual.widgets import Input, Select, Static, TextArea

from skillwright.spec import load_spec
from skillwright.tui.screens.open_path import OpenPathScreen
from skillwright.tui.screens.spec import SpecPane
from skillwright.tui.session import SpecDraft, load_session
from tests.tui.conftest import app_for, notifications, preset_session, running, wait_until

pytestmark = pytest.mark.anyio


def _status(app: object) -> str:
    return str(app.query_one("#spec-status", Static).render())  # type: ignore[attr-defined]


async def _open_form(pilot: object, app: object) -> SpecPane:
    await pilot.press("f3")  # type: ignore[attr-defined]
    pane = app.query_one(SpecPane)  # type: ignore[attr-defined]
    await wait_until(pilot, lambda: pane.ready)  # type: ignore[arg-type]
    return pane


async def test_the_form_is_checked_as_you_type(workspace: Path) -> None:
    app = app_for(workspace)
    async with running(app, (100, 40)) as pilot:
        pane = await _open_form(pilot, app)
        assert "name '' is not a valid identifier" in _status(app)
        assert pane.spec is None
        app.query_one("#spec-name", Input).focus()
        await pilot.press(*"2fast")
        await wait_until(pilot, lambda: "name '2fast' is not a valid identifier" in _status(app))
        await pilot.press("home", "delete")
        assert app.query_one("#spec-name", Input).value == "fast"
        await wait_until(pilot, lambda: "the 'execute' state is required" in _status(app))
        app.query_one("#state-execute", TextArea).focus()
        await pilot.press(*"Drive.")
        await wait_until(pilot, lambda: _status(app).startswith("✓ valid: execute"))
        assert pane.spec is not None
        assert pane.spec.name == "fast"
        assert pane.spec.states == {"execute": "Drive."}
        assert "not saved to a file yet" in _status(app)


async def test_choosing_a_capability_fills_an_empty_form_with_its_specification(
    workspace: Path,
) -> None:
    preset_session(workspace, capability="rotate.ttl")
    app = app_for(workspace)
    async with running(app, (100, 40)) as pilot:
        pane = await _open_form(pilot, app)
        await wait_until(pilot, lambda: pane.spec is not None and pane.spec.name == "rotate")
        assert pane.spec == load_spec(workspace / "rotate.spec.yaml")
        assert app.session.spec_path == "rotate.spec.yaml"
        assert "saved in rotate.spec.yaml" in _status(app)
        assert app.query_one("#spec-interface", Select).value == "REST"


async def test_what_was_typed_wins_over_the_capabilitys_specification(workspace: Path) -> None:
    draft = SpecDraft(name="mine", states={"execute": "My own words."})
    preset_session(workspace, capability="rotate.ttl", spec_draft=draft)
    app = app_for(workspace)
    async with running(app, (100, 40)) as pilot:
        pane = await _open_form(pilot, app)
        await wait_until(pilot, lambda: app.loaded.capability is not None)
        await pilot.pause(0.3)
        assert pane.spec is not None
        assert pane.spec.name == "mine"
        assert app.query_one("#state-execute", TextArea).text == "My own words."


@pytest.mark.parametrize("suffix", [".yaml", ".json"])
async def test_the_form_saves_to_the_format_the_file_name_asks_for(
    workspace: Path, suffix: str
) -> None:
    draft = SpecDraft(
        name="wave",
        description="Wave the arm.",
        skill_interface="MQTT",
        states={"execute": "Move the arm left and right.", "stopping": "Hold still."},
    )
    preset_session(workspace, spec_draft=draft)
    target = workspace / f"wave.spec{suffix}"
    app = app_for(workspace)
    async with running(app, (100, 40)) as pilot:
        pane = await _open_form(pilot, app)
        await pilot.press("ctrl+s")  # no file yet: asks where
        assert isinstance(app.screen, OpenPathScreen)
        app.screen.query_one("#open-path", Input).value = str(target)
        await pilot.press("enter")
        await wait_until(pilot, target.exists)
        assert load_spec(target) == pane.spec
        text = target.read_text(encoding="utf-8")
        if suffix == ".json":
            assert json.loads(text)["skill"]["states"][0] == {
                "name": "execute",
                "action": "Move the arm left and right.",
            }
        else:
            assert yaml.safe_load(text)["states"]["stopping"] == "Hold still."
        assert app.session.spec_path == f"wave.spec{suffix}"
        assert "saved in" in _status(app)
        # Ctrl+S again writes to the same file without asking.
        app.query_one("#state-stopping", TextArea).focus()
        await pilot.press("end", *" Now.")
        await wait_until(pilot, lambda: "unsaved changes" in _status(app))
        await pilot.press("ctrl+s")
        await wait_until(pilot, lambda: "Now." in target.read_text(encoding="utf-8"))
        assert not isinstance(app.screen, OpenPathScreen)


async def test_an_invalid_form_is_not_saved_and_says_why(workspace: Path) -> None:
    preset_session(workspace, spec_draft=SpecDraft(name="x"), spec_path="x.spec.yaml")
    app = app_for(workspace)
    async with running(app, (100, 40)) as pilot:
        await _open_form(pilot, app)
        await pilot.press("ctrl+s")
        await pilot.pause(0.2)
        assert not (workspace / "x.spec.yaml").exists()
        assert any("not saved" in n and "execute" in n for n in notifications(app))


async def test_a_specification_file_loads_into_the_form(workspace: Path) -> None:
    app = app_for(workspace)
    async with running(app, (100, 40)) as pilot:
        pane = await _open_form(pilot, app)
        select = app.query_one("#spec-file", Select)
        select.value = str(workspace / "mapping.spec.yaml")
        await wait_until(pilot, lambda: pane.spec is not None and pane.spec.name == "mapping")
        expected = load_spec(workspace / "mapping.spec.yaml")
        assert app.query_one("#state-execute", TextArea).text == expected.states["execute"]
        assert app.session.spec_draft.name == "mapping"


async def test_a_broken_specification_file_is_reported_and_the_form_kept(workspace: Path) -> None:
    (workspace / "bad.spec.yaml").write_text("name: [unclosed\n", encoding="utf-8")
    draft = SpecDraft(name="kept", states={"execute": "Stay."})
    preset_session(workspace, spec_draft=draft)
    app = app_for(workspace)
    async with running(app, (100, 40)) as pilot:
        pane = await _open_form(pilot, app)
        pane.load(workspace / "bad.spec.yaml")
        await wait_until(pilot, lambda: any("bad.spec.yaml" in n for n in notifications(app)))
        assert any("YAML syntax error" in n for n in notifications(app))
        assert app.query_one("#spec-name", Input).value == "kept"


_TYPE_AND_WAIT = textwrap.dedent(
    """
    import asyncio, sys
    from pathlib import Path
    from skillwright.tui.app import make_app
    from skillwright.tui.screens.spec import SpecPane

    async def main():
        app = make_app(Path(sys.argv[1]))
        app.save_delay = 0.05
        async with app.run_test(size=(100, 40)) as pilot:
            await pilot.pause()
            await pilot.press("f3")
            pane = app.query_one(SpecPane)
            while not pane.ready:
                await pilot.pause(0.05)
            app.query_one("#spec-name").focus()
            await pilot.press(*"survivor")
            app.query_one("#state-execute").focus()
            await pilot.press(*"Keep me.")
            print("typed", flush=True)
            await asyncio.sleep(600)  # killed before this ends

    asyncio.run(main())
    """
)


async def test_a_draft_typed_before_a_kill_is_back_on_the_next_start(workspace: Path) -> None:
    process = subprocess.Popen(
        [sys.executable, "-c", _TYPE_AND_WAIT, str(workspace)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    session_path = workspace / ".skillwright" / "session.json"
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            state, _ = load_session(session_path)
            if state.spec_draft.states.get("execute") == "Keep me.":
                break
            assert process.poll() is None, process.communicate()
            time.sleep(0.1)
        else:
            pytest.fail("the typed draft never reached the session file")
    finally:
        if process.poll() is None:
            os.kill(process.pid, signal.SIGKILL)  # no clean shutdown, no last save
        process.communicate(timeout=30)
    assert process.returncode == -signal.SIGKILL

    app = app_for(workspace)
    async with running(app, (100, 40)) as pilot:
        pane = app.query_one(SpecPane)
        await wait_until(pilot, lambda: pane.ready)
        assert app.query_one("#spec-name", Input).value == "survivor"
        assert app.query_one("#state-execute", TextArea).text == "Keep me."
        assert app.session.active_tab == "specification"
        assert pane.spec is not None
