"""Benchmark of the TUI (run by ``make bench``; never part of the tests).

1. Start-up: from launching ``skillwright tui`` in a pseudo-terminal until the first screen
   (the tab bar) has been written to it, as a user would see it. Compared with the same app
   when every engine library (rdflib, pydantic, NumPy, llama.cpp, the embedding encoder with
   tokenizers, and the pipeline) is imported before it starts, which is what importing the
   engine at the top of the app's modules would cost. Target: first paint under 1 s.
2. Responsiveness: how long a key takes to change the screen (switch tab, type a character)
   while the app is idle and while a generation worker runs the tiny test model.

Each start-up is measured ``--rounds`` times; the table shows the best and the median.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import pty
import select
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

REPO_ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO_ROOT))  # for tests.fixtures (the tiny model writer)

ENGINE = (
    "import rdflib, pydantic, numpy, yaml, llama_cpp, tokenizers; "
    "import skillwright.llm.bert, skillwright.pipeline.run, skillwright.capability.reader, "
    "skillwright.interfaces.load, skillwright.spec.loader; "
)
LAUNCH = "from skillwright.cli import main; main(['tui', '--workspace', sys.argv[1]])"


def first_paint(workspace: Path, preload: str = "", timeout: float = 60.0) -> float:
    """Seconds from starting the process until the tab bar appears on its terminal."""
    master, slave = pty.openpty()
    env = os.environ | {"TERM": "xterm-256color", "COLUMNS": "100", "LINES": "30"}
    started = time.perf_counter()
    process = subprocess.Popen(
        [sys.executable, "-c", f"import sys; {preload}{LAUNCH}", str(workspace)],
        stdin=slave,
        stdout=slave,
        stderr=slave,
        env=env,
        start_new_session=True,
    )
    os.close(slave)
    seen = b""
    try:
        while b"Specification" not in seen:
            if time.perf_counter() - started > timeout:
                raise RuntimeError(f"no first paint in {timeout} s: {seen[-500:]!r}")
            ready, _, _ = select.select([master], [], [], 0.05)
            if ready:
                try:
                    seen += os.read(master, 65536)
                except OSError:  # the child closed the terminal
                    break
        return time.perf_counter() - started
    finally:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()
        os.close(master)


def _fresh_workspace(root: Path) -> Path:
    workspace = root / "workspace"
    if workspace.exists():
        shutil.rmtree(workspace)
    shutil.copytree(REPO_ROOT / "capabilities", workspace)
    return workspace


def startup_table(rounds: int) -> None:
    with tempfile.TemporaryDirectory() as folder:
        root = Path(folder)
        rows = []
        for label, preload in (("tui (lazy engine)", ""), ("engine imported first", ENGINE)):
            times = [first_paint(_fresh_workspace(root), preload) for _ in range(rounds)]
            rows.append((label, min(times), statistics.median(times)))
    lazy = rows[0][1]
    print(f"{'start-up to first paint':<26}{'best s':>9}{'median s':>10}{'ratio':>8}")
    for label, best, median in rows:
        print(f"{label:<26}{best:>9.3f}{median:>10.3f}{best / lazy:>8.2f}")


async def _until(
    pilot: Any, condition: Callable[[], object], what: str, limit: float = 120
) -> None:
    deadline = time.monotonic() + limit
    while not condition():
        if time.monotonic() > deadline:
            raise RuntimeError(f"waited {limit} s for {what}")
        await pilot.pause(0.02)


async def _key_latencies(workspace: Path, models: Path) -> tuple[list[float], list[float]]:
    from textual import events

    from skillwright.tui.app import make_app
    from skillwright.tui.screens.generation import GenerationPane
    from skillwright.tui.session import SessionState, save_session

    save_session(
        workspace / ".skillwright" / "session.json",
        SessionState(
            capability="get-position.ttl",
            spec_path="get-position.spec.yaml",
            interfaces="recordings/mr1",
            k=0,
            pinned=("/tf",),
            dense=False,
            active_tab="generation",
        ),
    )
    app = make_app(workspace, models_file=models)

    async def key(pilot: object, name: str, done: object) -> float:
        started = time.perf_counter()
        app._driver.send_message(events.Key(name, name if len(name) == 1 else None))  # type: ignore[union-attr]
        deadline = started + 30
        while not done():  # type: ignore[operator]
            if time.perf_counter() > deadline:
                raise RuntimeError(f"key {name} not handled in 30 s")
            await asyncio.sleep(0.002)
        return time.perf_counter() - started

    def tab(name: str) -> object:
        return lambda: app.query_one("#tabs").active == name  # type: ignore[attr-defined]

    async def round_trip(pilot: object) -> list[float]:
        out = []
        for _ in range(5):
            out.append(await key(pilot, "f2", tab("capability")))
            out.append(await key(pilot, "f6", tab("generation")))
        return out

    async with app.run_test(size=(120, 40)) as pilot:
        pane = app.query_one(GenerationPane)
        await _until(
            pilot,
            lambda: app.loaded.capability and app.loaded.inventory and app.spec_pane().spec,
            "inputs loaded",
        )
        idle = await round_trip(pilot)
        pane.start()
        await _until(pilot, lambda: "model" in pane.stages or not pane.running, "model stage")
        busy = await round_trip(pilot)
        if not pane.running:
            raise RuntimeError("the generation ended before the keys were measured")
        pane.cancel_job()
        await _until(pilot, lambda: not pane.running, "generation cancelled")
    return idle, busy


def latency_table() -> None:
    from tests.fixtures.tiny_gguf import write_tiny_llama
    from tests.tui.conftest import write_models

    with tempfile.TemporaryDirectory() as folder:
        root = Path(folder)
        os.environ["XDG_CACHE_HOME"] = str(root / "cache")
        models = write_models(
            root / "models.toml", write_tiny_llama(root / "tiny.gguf"), max_tokens=1500
        )
        idle, busy = asyncio.run(_key_latencies(_fresh_workspace(root), models))
    base = statistics.median(idle)
    print(f"\n{'key to screen (tab switch)':<30}{'median ms':>10}{'max ms':>9}{'ratio':>8}")
    for label, values in (("idle", idle), ("during generation", busy)):
        median = statistics.median(values)
        print(f"{label:<30}{median * 1000:>10.1f}{max(values) * 1000:>9.1f}{median / base:>8.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5, help="start-ups per variant")
    args = parser.parse_args()
    startup_table(args.rounds)
    latency_table()


if __name__ == "__main__":
    main()
