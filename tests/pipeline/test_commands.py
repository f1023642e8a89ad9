"""``skillwright generate`` as a user runs it."""

from __future__ import annotations

import json
import os
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from skillwright.cli import main
from tests.conftest import SHIPPED_CAPABILITIES
from tests.fixtures.scripted import MethodScript
from tests.pipeline.conftest import RECORDING, SET_VELOCITY, use_model


def args(out: Path, *extra: str, stem: str = "set-velocity") -> list[str]:
    return [
        "generate",
        "--capability",
        str(SHIPPED_CAPABILITIES / f"{stem}.ttl"),
        "--spec",
        str(SHIPPED_CAPABILITIES / f"{stem}.spec.yaml"),
        "--interfaces",
        str(RECORDING),
        "--no-dense",
        "-o",
        str(out),
        *extra,
    ]


def test_the_skeleton_is_written_with_progress_on_stderr_and_exit_1(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, args(tmp_path / "out", "--skeleton"), terminal_width=200)
    assert result.exit_code == 1, result.output
    assert "retrieval: top 4 interfaces (lexical)" in result.stderr
    assert "checks: static checks" in result.stderr
    assert "skeleton: " in result.stdout
    assert "[placeholders] raises NotImplementedError" in result.stdout
    assert "checks failed: 5 error(s)" in result.stdout
    assert (tmp_path / "out" / "skill.py").is_file()


def test_a_good_skill_from_the_model_runs_exits_0_and_json_prints_the_record(
    tmp_path: Path, models_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    use_model(monkeypatch, MethodScript(dict(SET_VELOCITY), model_id="tiny"))
    result = CliRunner().invoke(
        main,
        args(
            tmp_path / "out",
            "--models",
            str(models_file),
            "--pin",
            "/odom",
            "--pin",
            "/cmd_vel",
            "--attempts",
            "2",
            "--no-sim",
            "--json",
        ),
        terminal_width=200,
    )
    assert result.exit_code == 0, result.output
    record = json.loads(result.stdout)
    assert record["mode"] == "llm"
    assert record["checks"]["passed"] is True
    assert record["retrieval"]["pinned"] == ["/odom", "/cmd_vel"]
    assert record["model"]["attempts_allowed"] == 2
    assert "execute answer 1: ok" in result.stderr
    assert "run: the states in the sandbox" in result.stderr
    assert "simulate:" not in result.stderr
    assert record["run"]["passed"] is True
    assert record["simulation"] is None


def test_skeleton_and_model_together_are_refused(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, args(tmp_path / "out", "--skeleton", "--model", "coder"))
    assert result.exit_code == 2
    assert "--skeleton and --model exclude each other" in result.stderr


def test_bad_input_is_exit_2_with_the_file_named_and_no_output(tmp_path: Path) -> None:
    broken = tmp_path / "broken.ttl"
    broken.write_text("@prefix : <http://x#> .\n:a :b\n", encoding="utf-8")
    command = args(tmp_path / "out", "--skeleton")
    command[2] = str(broken)
    result = CliRunner().invoke(main, command)
    assert result.exit_code == 2
    assert "broken.ttl:" in result.stderr
    assert "Traceback" not in result.output
    assert not (tmp_path / "out").exists()


def test_the_default_output_folder_is_named_after_the_skill(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    command = args(tmp_path / "unused", "--skeleton")
    command = command[: command.index("-o")]
    result = CliRunner().invoke(main, command)
    assert result.exit_code == 1, result.output
    assert (tmp_path / "generated" / "set_velocity" / "record.json").is_file()


def test_line_numbers_in_findings_are_printed_as_numbers_not_emoji(tmp_path: Path) -> None:
    from skillwright.console import out_console
    from skillwright.rules.finding import Finding
    from skillwright.validation.commands import print_findings

    console = out_console()
    with console.capture() as captured:
        print_findings(
            console, "skill.py", [Finding(check="x", severity="error", line=100, message="m")]
        )
    assert captured.get().startswith("skill.py:100:0: error [x] m")


@pytest.mark.parametrize(("share", "aside"), [(None, True), ("0", False)])
def test_weak_hits_are_shown_set_aside_unless_min_share_is_0(
    tmp_path: Path, share: str | None, aside: bool
) -> None:
    extra = ["--skeleton", *(["--min-share", share] if share is not None else [])]
    result = CliRunner().invoke(
        main, args(tmp_path / "out", *extra, stem="move-forward"), terminal_width=200
    )
    progress = " ".join(result.stderr.split())
    assert ("set aside, under 0.1 of the best score: /navigate_to_pose, /tf" in progress) is aside
    assert ("aside" in result.stdout) is aside  # the table folds its reason column


def test_a_min_share_outside_0_to_1_is_refused(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, args(tmp_path / "out", "--skeleton", "--min-share", "2"))
    assert result.exit_code == 2
    assert "--min-share" in result.output
    assert not (tmp_path / "out").exists()


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs POSIX named pipes")
def test_ctrl_c_ends_generate_with_130_and_one_line_saying_what_was_kept(tmp_path: Path) -> None:
    """A real SIGINT to a real process: the capability is a named pipe nobody writes, so the
    process waits in its inputs stage until the signal comes."""
    capability = tmp_path / "capability.ttl"
    os.mkfifo(capability)
    out = tmp_path / "out"
    command = [
        sys.executable,
        "-m",
        "skillwright",
        *args(out, "--skeleton", "--no-run", "--no-sim"),
    ]
    command[command.index("--capability") + 1] = str(capability)
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert process.stderr is not None
    deadline = time.monotonic() + 60
    seen = ""
    while "inputs: " not in seen and time.monotonic() < deadline:
        ready, _, _ = select.select([process.stderr], [], [], 1.0)
        if ready:
            seen += process.stderr.readline()
    process.send_signal(signal.SIGINT)
    _, rest = process.communicate(timeout=60)
    stderr = seen + rest
    assert process.returncode == 130, stderr
    assert stderr.splitlines()[-1] == (
        f"error: generation interrupted in stage inputs; nothing was written ({out} is as it was)"
    )
    assert "Aborted" not in stderr
    assert "Traceback" not in stderr
    assert not out.exists()


def test_ctrl_c_after_the_files_are_written_says_they_are_complete(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.pipeline import commands

    def interrupted(_outcome: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(commands, "_summary", interrupted)
    out = tmp_path / "out"
    result = CliRunner().invoke(main, args(out, "--skeleton", "--no-run", "--no-sim"))
    assert result.exit_code == 130
    assert result.stderr.splitlines()[-1] == (
        f"error: generation interrupted after writing {out}: its files are complete"
    )
    assert (out / "skill.py").is_file()


def test_a_scenario_file_given_to_generate_reaches_the_request(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.errors import InvalidArgumentError
    from skillwright.pipeline import run as pipeline_run

    seen = []

    def capture(request: pipeline_run.GenerationRequest, **_: object) -> None:
        seen.append(request.scenario)
        raise InvalidArgumentError("stopped by the test")

    monkeypatch.setattr(pipeline_run, "run_generation", capture)
    scenario = tmp_path / "own.scenario.yaml"
    result = CliRunner().invoke(main, args(tmp_path / "out", "--scenario", str(scenario)))
    assert result.exit_code == 2, result.output
    result = CliRunner().invoke(main, args(tmp_path / "out"))
    assert seen == [scenario, None]


def test_candidates_reach_the_request_and_need_a_model(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.errors import InvalidArgumentError
    from skillwright.pipeline import run as pipeline_run

    seen = []

    def capture(request: pipeline_run.GenerationRequest, **_: object) -> None:
        seen.append(request.candidates)
        raise InvalidArgumentError("stopped by the test")

    monkeypatch.setattr(pipeline_run, "run_generation", capture)
    CliRunner().invoke(main, args(tmp_path / "out", "--candidates", "4"))
    CliRunner().invoke(main, args(tmp_path / "out"))
    assert seen == [4, 1]
    result = CliRunner().invoke(main, args(tmp_path / "out", "--skeleton", "--candidates", "2"))
    assert result.exit_code == 2
    assert "--candidates needs the model that --skeleton leaves out" in result.stderr
    result = CliRunner().invoke(main, args(tmp_path / "out", "--candidates", "9"))
    assert result.exit_code == 2
    assert "--candidates" in result.stderr


def test_generate_waits_for_a_model_in_use_and_ctrl_c_ends_the_wait_with_130(
    tmp_path: Path, models_file: Path, wordy_gguf: Path
) -> None:
    """A real second process: it says on stderr whom it waits for, and a SIGINT while it
    waits ends it with one line."""
    from skillwright.llm.model_lock import acquire_model_lock, note_activity

    note_activity(skill="patrol", stage="generation")
    lock = acquire_model_lock("tiny", wordy_gguf)
    out = tmp_path / "out"
    command = [
        sys.executable,
        "-m",
        "skillwright",
        *args(out, "--models", str(models_file), "--no-run", "--no-sim"),
    ]
    try:
        process = subprocess.Popen(
            command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
        )
        assert process.stderr is not None
        deadline = time.monotonic() + 120
        seen = ""
        while "waiting for model tiny" not in seen and time.monotonic() < deadline:
            ready, _, _ = select.select([process.stderr], [], [], 1.0)
            if ready:
                seen += process.stderr.readline()
        process.send_signal(signal.SIGINT)
        _, rest = process.communicate(timeout=60)
    finally:
        lock.release()
        note_activity(skill=None, stage=None)
    stderr = seen + rest
    assert process.returncode == 130, stderr
    waiting = next(line for line in stderr.splitlines() if "waiting for model" in line)
    assert waiting.strip().startswith(
        f"waiting for model tiny (wordy.gguf), in use by pid {os.getpid()} ("
    )
    assert "skill patrol, stage generation; next in line" in waiting
    assert stderr.splitlines()[-1] == (
        "error: generation stopped: interrupted while waiting for model tiny; nothing was "
        f"written ({out} is as it was)"
    )
    assert "Traceback" not in stderr
    assert not out.exists()


def _wait_event(place: int, seconds: float) -> object:
    from skillwright.pipeline.events import ModelWaiting

    message = f"waiting for model tiny (tiny.gguf), in use by pid 7; place {place} in line"
    return ModelWaiting("tiny", place, seconds, "pid 7", message)


def test_waiting_is_printed_when_the_place_changes_and_once_a_minute_off_a_terminal() -> None:
    import io

    from rich.console import Console

    from skillwright.pipeline.commands import _Progress
    from skillwright.pipeline.events import StageFinished

    stream = io.StringIO()
    progress = _Progress(Console(file=stream, force_terminal=False, width=40))
    for place, seconds in [(2, 0.0), (2, 0.5), (1, 1.0), (1, 30.0), (1, 61.0), (1, 61.5)]:
        progress(_wait_event(place, seconds))  # type: ignore[arg-type]
    progress(StageFinished("model", 62.0, "tiny"))
    lines = stream.getvalue().splitlines()
    assert [line.split("; ")[-1] for line in lines[:3]] == [
        "place 2 in line",
        "place 1 in line",
        "place 1 in line",
    ]
    assert len(lines) == 4  # not wrapped at 40 columns; then the stage's end
    assert lines[3].startswith("  done in 62.00 s")


def test_waiting_on_a_terminal_is_one_line_rewritten_and_kept_when_the_wait_ends() -> None:
    import io

    from rich.console import Console

    from skillwright.pipeline.commands import _Progress
    from skillwright.pipeline.events import StageFinished

    stream = io.StringIO()
    progress = _Progress(Console(file=stream, force_terminal=True, width=60, color_system=None))
    for seconds in (0.0, 0.5, 1.0):
        progress(_wait_event(1, seconds))  # type: ignore[arg-type]
    progress(StageFinished("model", 1.2, "tiny"))
    text = stream.getvalue()
    assert text.count("\r") == 3
    rewritten, rest = text.rsplit("\r", 1)
    assert all(len(part) <= 60 for part in rewritten.split("\r"))
    assert rest.startswith("\n  done in 1.20 s")
