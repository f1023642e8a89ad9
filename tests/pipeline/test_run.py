"""The whole pipeline: inputs to a checked skill in a folder, with its record."""

from __future__ import annotations

import hashlib
import json
import signal
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest

from skillwright.errors import (
    GenerationCancelledError,
    InputFileNotFoundError,
    InvalidArgumentError,
    ModelFileMissingError,
    OperationCancelledError,
)
from skillwright.interfaces.load import load_inventory
from skillwright.interfaces.sources.report import report_from_inventory
from skillwright.llm.base import GenerationOptions, Prompt, TextStream
from skillwright.pipeline import GenerationRecord, GenerationRequest, retrieve, run_generation
from skillwright.pipeline.events import (
    AttemptFinished,
    AttemptStarted,
    Event,
    GenerationStats,
    Notice,
    PrefixCacheStatus,
    StageFinished,
    StageStarted,
    TokenChunk,
)
from tests.conftest import SHIPPED_CAPABILITIES
from tests.fixtures.scripted import MethodScript
from tests.interfaces.test_load import cut_recording
from tests.llm.conftest import write_models_toml
from tests.pipeline.conftest import RECORDING, SET_VELOCITY, stems, use_model


def request(out: Path, stem: str = "set-velocity", **changes: object) -> GenerationRequest:
    values: dict[str, object] = {
        "capability": SHIPPED_CAPABILITIES / f"{stem}.ttl",
        "spec": SHIPPED_CAPABILITIES / f"{stem}.spec.yaml",
        "interfaces": RECORDING,
        "out_dir": out,
        "dense": False,
        "pinned": ("/cmd_vel", "/odom"),
        # The run and simulate stages have their own tests (test_behaviour.py).
        "run": False,
        "simulate": False,
    }
    values.update(changes)
    return GenerationRequest(**values)  # type: ignore[arg-type]


def test_the_skeleton_run_writes_the_skill_and_a_complete_record(tmp_path: Path) -> None:
    events: list[Event] = []
    outcome = run_generation(request(tmp_path / "out", skeleton=True), on_event=events.append)
    assert outcome.mode == "skeleton"
    assert sorted(p.name for p in outcome.out_dir.iterdir()) == ["record.json", "skill.py"]
    assert stems(events, StageStarted) == ["inputs", "retrieval", "skeleton", "checks", "outputs"]
    assert stems(events, StageFinished) == stems(events, StageStarted)

    record = GenerationRecord.load(outcome.record_path)
    capability = SHIPPED_CAPABILITIES / "set-velocity.ttl"
    assert record.inputs.capability.sha256 == hashlib.sha256(capability.read_bytes()).hexdigest()
    assert record.inputs.capability_iri.endswith("setVelocity/setVelocity")
    assert record.inputs.interfaces.interfaces == 77
    assert record.mode == "skeleton"
    assert record.model is None
    assert record.skeleton.unimplemented == [
        "starting",
        "execute",
        "completing",
        "stopping",
        "resetting",
    ]
    assert set(record.timings) == {"inputs", "retrieval", "skeleton", "checks"}
    assert not record.checks.passed
    assert {f.check for f in record.checks.findings} == {"placeholders"}
    assert any("skeleton only" in note for note in record.notes)
    assert record.files == ["skill.py", "record.json"]
    assert (
        outcome.skill_path.read_text(encoding="utf-8").count("        raise NotImplementedError(")
        == 5
    )


def test_retrieval_hits_and_the_users_pins_and_drops_are_recorded(tmp_path: Path) -> None:
    outcome = run_generation(
        request(tmp_path / "out", skeleton=True, pinned=("/scan",), dropped=("/odom",), k=2)
    )
    hits = outcome.record.retrieval.hits
    assert [h.name for h in hits if h.pinned] == ["/scan"]
    assert "/odom" not in [h.name for h in hits]
    assert outcome.record.retrieval.pinned == ["/scan"]
    assert outcome.record.retrieval.dropped == ["/odom"]
    assert len([h for h in hits if not h.pinned or h.score is not None]) >= 2
    assert "/scan" in outcome.skill_path.read_text(encoding="utf-8")


def _report_with_a_twin(tmp_path: Path) -> Path:
    """The MR-1 as a report lists it (no endpoint counts), with a second velocity topic."""
    base = load_inventory(RECORDING)
    driver = base.interface("/cmd_vel").model_copy(update={"name": "/driver/cmd_vel"})
    inventory = base.model_copy(update={"interfaces": [*base.interfaces, driver]})
    document, _ = report_from_inventory(inventory)
    report = tmp_path / "report.json"
    report.write_text(json.dumps(document), encoding="utf-8")
    return report


@pytest.mark.parametrize("pinned", [(), ("/cmd_vel",), ("/driver/cmd_vel",)])
def test_a_velocity_topic_the_report_cannot_tell_from_another_is_recorded_and_warned_about(
    tmp_path: Path, pinned: tuple[str, ...]
) -> None:
    events: list[Event] = []
    outcome = run_generation(
        request(
            tmp_path / "out",
            stem="move-forward",
            skeleton=True,
            interfaces=_report_with_a_twin(tmp_path),
            pinned=pinned,
        ),
        on_event=events.append,
    )
    [velocity] = [h for h in outcome.record.retrieval.hits if h.name == "/cmd_vel"]
    assert velocity.twins == ["/driver/cmd_vel"]
    warnings = [e.message for e in events if isinstance(e, Notice) and e.level == "warning"]
    warned = [w for w in warnings if "chosen over /driver/cmd_vel" in w]
    # a topic the user pinned, or one of its twins, is their choice: nothing to warn about
    assert len(warned) == (0 if pinned else 1)


@pytest.mark.parametrize("min_share", [0.1, 0.0])
def test_hits_far_behind_the_best_are_recorded_and_set_aside(
    tmp_path: Path, min_share: float
) -> None:
    # MR-1 move-forward: /odom and /cmd_vel, then /navigate_to_pose and /tf at a tenth of
    # the best score or less; a pinned interface is never set aside.
    outcome = run_generation(
        request(
            tmp_path / "out",
            stem="move-forward",
            skeleton=True,
            pinned=("/scan",),
            min_share=min_share,
        )
    )
    retrieval = outcome.record.retrieval
    aside = [h.name for h in retrieval.hits if h.set_aside]
    assert aside == (["/navigate_to_pose", "/tf"] if min_share else [])
    assert retrieval.min_share == min_share
    code = outcome.skill_path.read_text(encoding="utf-8")
    # Given with min_share 0, Nav2's action still gets no handle: nothing in move-forward's
    # specification or capability calls for a navigation goal (generation.wiring). The
    # pinned /scan keeps its handle all the same.
    assert "NavigateToPose" not in code
    not_wired = [
        n for n in outcome.record.skeleton.notes if n.startswith("retrieved but not wired")
    ]
    assert ["/navigate_to_pose" in n for n in not_wired] == ([] if min_share else [True])
    assert all(f'"{name}"' in code for name in ("/scan", "/cmd_vel", "/odom"))


@pytest.mark.parametrize(
    ("stem", "dropped", "added"),
    [
        ("mapping", (), True),
        ("mapping", ("/cmd_vel",), False),
        ("get-distance-to-nearest-object", (), False),
    ],
    ids=["mapping", "mapping-dropped", "get-distance"],
)
def test_a_state_that_stops_the_base_brings_its_velocity_command(
    tmp_path: Path, stem: str, dropped: tuple[str, ...], added: bool
) -> None:
    # MR-1 mapping: the first 4 are /map, /scan, Nav2 and the map saver, and its stopping
    # state publishes a zero velocity command, unless the user dropped it; a distance
    # reading moves nothing.
    outcome = run_generation(
        request(tmp_path / "out", stem=stem, skeleton=True, pinned=(), dropped=dropped)
    )
    hits = outcome.record.retrieval.hits
    extra = [h for h in hits if h.score is None]
    code = outcome.skill_path.read_text(encoding="utf-8")
    assert ('"/cmd_vel"' in code) is added
    assert ("def _stop_base" in code) is added
    if added:
        assert [h.name for h in hits[:4]] == [
            "/map",
            "/scan",
            "/navigate_to_pose",
            "/map_saver/save_map",
        ]
        (command,) = extra
        assert (command.name, command.pinned, command.set_aside) == ("/cmd_vel", False, False)
        assert command.reason.startswith("added: stopping asks to stop the base (")
        assert "zero velocity command" in command.reason
    else:
        assert extra == []


def test_an_unknown_pinned_interface_is_refused_before_anything_runs(tmp_path: Path) -> None:
    with pytest.raises(InvalidArgumentError, match=r"'/cmd_vell'.*did you mean /cmd_vel"):
        run_generation(request(tmp_path / "out", skeleton=True, pinned=("/cmd_vell",)))
    assert not (tmp_path / "out").exists()


def test_a_missing_capability_file_is_named(tmp_path: Path) -> None:
    with pytest.raises(InputFileNotFoundError, match=r"nope\.ttl"):
        run_generation(request(tmp_path / "out", capability=tmp_path / "nope.ttl"))


def test_without_an_installed_default_model_the_skeleton_is_written_and_said_so(
    tmp_path: Path,
) -> None:
    events: list[Event] = []
    outcome = run_generation(request(tmp_path / "out"), on_event=events.append)
    assert outcome.mode == "skeleton"
    warnings = [e.message for e in events if isinstance(e, Notice) and e.level == "warning"]
    assert len(warnings) == 1
    assert "qwen2.5-coder-1.5b-instruct" in warnings[0]
    assert "skeleton only" in warnings[0]


def test_a_model_asked_for_by_name_must_be_installed(tmp_path: Path) -> None:
    with pytest.raises(ModelFileMissingError, match=r"qwen2\.5-coder"):
        run_generation(request(tmp_path / "out", model="coder"))
    assert not (tmp_path / "out").exists()


def test_the_model_writes_each_state_and_the_skill_passes_the_checks(
    tmp_path: Path, models_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    model = MethodScript(dict(SET_VELOCITY), model_id="tiny")
    use_model(monkeypatch, model)
    events: list[Event] = []
    outcome = run_generation(
        request(tmp_path / "out", models_file=models_file), on_event=events.append
    )
    assert outcome.mode == "llm"
    assert outcome.report.passed, outcome.report.findings
    assert model.closed
    assert model.asked == ["starting", "execute", "completing", "stopping", "resetting"]
    assert [e.target for e in events if isinstance(e, AttemptStarted)] == model.asked
    assert sum(isinstance(e, AttemptFinished) for e in events) == 5
    assert "".join(e.text for e in events if isinstance(e, TokenChunk)).count("```") == 0
    assert [type(e) for e in events if isinstance(e, PrefixCacheStatus | GenerationStats)] == [
        PrefixCacheStatus,
        GenerationStats,
    ]
    files = sorted(p.name for p in outcome.out_dir.iterdir())
    assert files == ["conversation.txt", "record.json", "skill.py"]
    conversation = (outcome.out_dir / "conversation.txt").read_text(encoding="utf-8")
    assert conversation.startswith("===== system (cached prefix) =====")
    assert "===== task card =====\nSkill SetVelocitySkill" in conversation
    assert "===== assistant (attempt 1) =====" in conversation

    record = outcome.record
    assert record.schema_version == 2
    assert record.model is not None
    assert record.model.id == "tiny"
    assert record.model.states_written == [
        "starting",
        "execute",
        "completing",
        "stopping",
        "resetting",
    ]
    assert [a.target for a in record.model.attempts] == model.asked
    assert all(a.chosen and a.errors == 0 for a in record.model.attempts)
    assert record.model.max_tokens == 400
    assert record.model.attempts_allowed == 3
    assert record.model.run_repairs_allowed == 1
    assert record.model.card is not None
    assert record.model.card.startswith("Skill SetVelocity")
    assert set(record.timings) >= {"model", "generation", "checks"}
    code = outcome.skill_path.read_text(encoding="utf-8")
    assert "Behaviour: written by the local model tiny, one method at a time" in code
    assert json.loads(outcome.record_path.read_text(encoding="utf-8"))["mode"] == "llm"


class JudgingScript(MethodScript):
    """Writes the scripted methods and calls the interfaces of ``needed`` needed when asked
    to re-rank (a question with the re-ranking answer schema)."""

    needed: frozenset[str] = frozenset({"/odom", "/cmd_vel"})

    def stream(
        self,
        prompt: Prompt,
        options: GenerationOptions | None = None,
        cancel: threading.Event | None = None,
    ) -> TextStream:
        schema = None if options is None else options.json_schema
        if schema is None or "needed" not in schema["properties"]:
            return super().stream(prompt, options, cancel)
        self.prompts.append(prompt)
        name = prompt.messages[-1].content.splitlines()[0].removeprefix("Interface: ")
        answer = {"reason": f"judged {name}", "needed": name in self.needed}
        stream = TextStream(iter([json.dumps(answer)]))
        stream.finish_reason = "stop"
        return stream


def test_rerank_loads_the_model_in_retrieval_uses_it_to_write_and_records_its_verdicts(
    tmp_path: Path, models_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    model = JudgingScript(dict(SET_VELOCITY), model_id="tiny")
    loads: list[str | None] = []
    import skillwright.llm

    def load(_registry: object, model_id: str | None = None, **_: object) -> MethodScript:
        loads.append(model_id)
        return model

    monkeypatch.setattr(skillwright.llm, "load_generator", load)
    monkeypatch.setenv("SKILLWRIGHT_CACHE_DIR", str(tmp_path / "cache"))
    events: list[Event] = []
    outcome = run_generation(
        request(tmp_path / "out", models_file=models_file, rerank=True, pinned=()),
        on_event=events.append,
    )
    assert loads == [None]  # once, in retrieval; generation reuses it
    assert model.asked == ["starting", "execute", "completing", "stopping", "resetting"]
    assert model.closed
    retrieval = outcome.record.retrieval
    assert retrieval.rerank is not None
    assert (retrieval.rerank.model, retrieval.rerank.judged) == ("tiny", 8)
    assert [h.name for h in retrieval.hits[:2]] == ["/cmd_vel", "/odom"]
    assert all(h.needed is True for h in retrieval.hits[:2])
    assert [h.needed for h in retrieval.hits[2:]] == [False, False]
    assert retrieval.hits[0].judgement == "judged /cmd_vel"
    finished = {e.stage: e.detail for e in events if isinstance(e, StageFinished)}
    assert "re-ranked: 2 of 8 judged needed; 8 asked" in finished["retrieval"]
    assert finished["model"].startswith("loaded for re-ranking")


def test_attempts_and_their_findings_are_recorded(
    tmp_path: Path, models_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    wrong = """        self.logger.info("done")\n```"""
    answers = {**SET_VELOCITY, "completing": [wrong, *SET_VELOCITY["completing"]]}
    use_model(monkeypatch, MethodScript(answers, model_id="tiny"))
    outcome = run_generation(request(tmp_path / "out", models_file=models_file, attempts=2))
    assert outcome.report.passed
    assert outcome.record.model is not None
    tries = [a for a in outcome.record.model.attempts if a.target == "completing"]
    assert [(a.number, a.chosen) for a in tries] == [(1, False), (2, True)]
    assert tries[0].errors == 1
    assert "self.logger" in tries[1].problems[0]


def test_a_state_the_model_never_writes_keeps_its_placeholder_and_is_noted(
    tmp_path: Path, models_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    broken = """        if self.timer is not None\n            self.timer.cancel()\n```"""
    use_model(monkeypatch, MethodScript({**SET_VELOCITY, "stopping": [broken]}, model_id="tiny"))
    outcome = run_generation(request(tmp_path / "out", models_file=models_file, attempts=2))
    assert outcome.mode == "llm"
    assert not outcome.report.passed
    assert 'raise NotImplementedError("stopping' in outcome.skill_path.read_text(encoding="utf-8")
    assert outcome.record.model is not None
    assert outcome.record.model.states_missing == ["stopping"]
    assert any("no usable answer for stopping" in n for n in outcome.record.notes)


def test_cancelling_during_generation_writes_nothing(
    tmp_path: Path, models_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    model = MethodScript(dict(SET_VELOCITY), model_id="tiny")
    use_model(monkeypatch, model)
    cancel = threading.Event()

    def on_event(event: Event) -> None:
        if isinstance(event, TokenChunk):
            cancel.set()

    with pytest.raises(GenerationCancelledError):
        run_generation(
            request(tmp_path / "out", models_file=models_file), on_event=on_event, cancel=cancel
        )
    assert model.closed
    assert not (tmp_path / "out").exists()


@pytest.fixture
def ctrl_c_raises() -> Iterator[None]:
    """Ctrl-C as in a plain ``python`` process (a test runner may have changed it)."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


@pytest.mark.parametrize("stage", ["inputs", "retrieval", "skeleton", "checks", "outputs"])
def test_ctrl_c_in_a_stage_writes_nothing_and_says_which_stage(tmp_path: Path, stage: str) -> None:
    def on_event(event: Event) -> None:
        if isinstance(event, StageStarted) and event.stage == stage:
            raise KeyboardInterrupt

    out = tmp_path / "out"
    with pytest.raises(GenerationCancelledError) as info:
        run_generation(request(out, skeleton=True), on_event=on_event)
    assert str(info.value) == (
        f"generation interrupted in stage {stage}; nothing was written ({out} is as it was)"
    )
    assert info.value.exit_code == 130
    assert not out.exists()


@pytest.mark.usefixtures("ctrl_c_raises")
def test_ctrl_c_while_the_files_are_moved_in_comes_after_all_of_them_are(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.generation import output

    write_outputs = output.write_outputs

    def pressed_meanwhile(out_dir: Path, files: dict[str, str]) -> list[Path]:
        signal.raise_signal(signal.SIGINT)
        return write_outputs(out_dir, files)

    monkeypatch.setattr(output, "write_outputs", pressed_meanwhile)
    out = tmp_path / "out"
    with pytest.raises(GenerationCancelledError) as info:
        run_generation(request(out, skeleton=True))
    assert (
        str(info.value) == f"generation interrupted after writing {out}: its 2 files are complete"
    )
    assert sorted(p.name for p in out.iterdir()) == ["record.json", "skill.py"]
    assert json.loads((out / "record.json").read_text(encoding="utf-8"))["files"]


def test_rerunning_into_the_same_folder_backs_up_what_changed(tmp_path: Path) -> None:
    out = tmp_path / "out"
    run_generation(request(out, skeleton=True))
    (out / "skill.py").write_text("# my edits\n", encoding="utf-8")
    outcome = run_generation(request(out, skeleton=True))
    backed_up = [p for p in outcome.backups if p.name == "skill.py"]
    assert len(backed_up) == 1
    assert backed_up[0].read_text(encoding="utf-8") == "# my edits\n"


def test_retrieve_loads_the_inputs_and_ranks(tmp_path: Path) -> None:
    result = retrieve(
        SHIPPED_CAPABILITIES / "move-forward.ttl",
        SHIPPED_CAPABILITIES / "move-forward.spec.yaml",
        RECORDING,
        dense=False,
        k=3,
        dropped=("/backup",),
    )
    assert result.method == "lexical"
    assert len(result.hits) == 3
    assert {"/cmd_vel", "/odom"} <= {h.name for h in result.hits}
    assert "/backup" not in {h.name for h in result.hits}


def test_the_tiny_gguf_runs_through_every_stage_with_a_real_llama_cpp(
    tmp_path: Path, wordy_gguf: Path
) -> None:
    # The tiny model spends about a token per two characters: the prompt needs room.
    models_file = write_models_toml(tmp_path / "models.toml", wordy_gguf, context=32768)
    events: list[Event] = []
    outcome = run_generation(
        request(
            tmp_path / "out",
            stem="get-position",
            models_file=models_file,
            k=0,
            pinned=("/tf",),
            attempts=1,
        ),
        on_event=events.append,
    )
    assert outcome.mode == "llm"
    record = outcome.record
    assert record.model is not None
    assert record.model.file == str(wordy_gguf)
    assert record.model.sha256 == hashlib.sha256(wordy_gguf.read_bytes()).hexdigest()
    assert record.model.prompt_tokens is not None
    assert record.model.prompt_tokens > 1000
    # Random weights write no method: every answer fails one way or another, and is recorded.
    assert [a.target for a in record.model.attempts][:3] == ["starting", "execute", "completing"]
    assert all(a.finish in {"length", "unparsable", "repetition"} for a in record.model.attempts)
    assert record.model.attempts[0].prefix_cache in {"stored", "evaluated"}
    assert record.model.attempts[1].prefix_cache == "memory"
    assert any(isinstance(e, TokenChunk) for e in events)
    assert (outcome.out_dir / "conversation.txt").exists()
    assert stems(events, StageStarted) == [
        "inputs",
        "retrieval",
        "skeleton",
        "model",
        "generation",
        "checks",
        "outputs",
    ]


def test_retrieve_stops_once_the_embedding_model_is_loaded_if_cancelled_meanwhile(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import skillwright.llm.embeddings

    cancel = threading.Event()
    embedded: list[object] = []

    class Loaded:
        """What load_embedder returns; the user pressed Esc while it loaded."""

        def embed(self, texts: object) -> object:
            embedded.append(texts)
            raise AssertionError("embedded after the cancel")

    def load_then_cancel(*_args: object, **_kwargs: object) -> Loaded:
        cancel.set()
        return Loaded()

    monkeypatch.setattr(skillwright.llm.embeddings, "load_embedder", load_then_cancel)
    with pytest.raises(OperationCancelledError):
        retrieve(
            SHIPPED_CAPABILITIES / "move-forward.ttl",
            None,
            RECORDING,
            dense=True,
            cancel=cancel,
        )
    assert embedded == []


def test_retrieve_does_not_load_the_embedding_model_once_cancelled(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import skillwright.llm.embeddings
    from skillwright.interfaces import load

    cancel = threading.Event()
    real_load = load.load_inventory
    monkeypatch.setattr(
        load, "load_inventory", lambda *a, **k: (real_load(*a, **k), cancel.set())[0]
    )
    loads: list[object] = []
    monkeypatch.setattr(skillwright.llm.embeddings, "load_embedder", lambda *a: loads.append(a))
    with pytest.raises(OperationCancelledError, match="retrieval cancelled"):
        retrieve(
            SHIPPED_CAPABILITIES / "move-forward.ttl", None, RECORDING, dense=True, cancel=cancel
        )
    assert loads == []


def test_a_limit_the_capability_never_states_is_a_note_of_the_run(
    tmp_path: Path, shared_data: Path
) -> None:
    cap2skill = shared_data / "cap2skill"
    changes = {
        "capability": cap2skill / "capability-models" / "set-velocity.ttl",
        "spec": cap2skill / "skill-specs" / "set_velocity.json",
        "pinned": (),
        "skeleton": True,
    }
    record = run_generation(request(tmp_path / "out", **changes)).record
    [note] = [n for n in record.notes if "asks for a limit" in n]
    assert "maximum possible velocity" in note
    assert "the capability setVelocity does not give" in note


def test_a_recording_cut_short_is_a_note_of_the_run(tmp_path: Path) -> None:
    cut = cut_recording(tmp_path)
    record = run_generation(request(tmp_path / "out", interfaces=cut, skeleton=True)).record
    [note] = [n for n in record.notes if "read only up to byte" in n]
    assert note.startswith(f"{cut}: ")


class _Holder:
    """Another generation holding the model, in a thread of its own (a thread's own loads
    share the lock it holds)."""

    def __init__(self, model_file: Path) -> None:
        from skillwright.llm.model_lock import acquire_model_lock, note_activity

        self.taken = threading.Event()
        self.done = threading.Event()

        def hold() -> None:
            note_activity(skill="drive_square", stage="generation")
            lock = acquire_model_lock("tiny", model_file)
            self.taken.set()
            self.done.wait(60)
            lock.release()

        self.thread = threading.Thread(target=hold)
        self.thread.start()
        assert self.taken.wait(30)

    def release(self) -> None:
        self.done.set()
        self.thread.join(30)


def test_a_generation_waits_for_the_model_another_holds_and_says_so(
    tmp_path: Path, models_file: Path, wordy_gguf: Path
) -> None:
    from skillwright.pipeline.events import ModelWaiting

    holder = _Holder(wordy_gguf)
    cancel = threading.Event()
    events: list[Event] = []

    def on_event(event: Event) -> None:
        events.append(event)
        if (
            isinstance(event, ModelWaiting)
            and sum(isinstance(e, ModelWaiting) for e in events) == 2
        ):
            holder.release()
        if isinstance(event, TokenChunk):
            cancel.set()  # the model was loaded and writes: enough

    try:
        with pytest.raises(GenerationCancelledError):
            run_generation(
                request(tmp_path / "out", models_file=models_file), on_event=on_event, cancel=cancel
            )
    finally:
        holder.release()
    waits = [e for e in events if isinstance(e, ModelWaiting)]
    assert len(waits) >= 2
    assert waits[0].model == "tiny"
    assert waits[0].place == 1
    assert waits[0].holder is not None
    assert "skill drive_square, stage generation" in waits[0].holder
    assert waits[0].message.startswith("waiting for model tiny (wordy.gguf), in use by pid ")
    # It waited in the model stage, then went on to generate.
    started = [e.stage for e in events if isinstance(e, StageStarted)]
    assert started[-2:] == ["model", "generation"]
    assert any(isinstance(e, TokenChunk) for e in events)


def test_cancel_while_waiting_for_the_model_writes_nothing(
    tmp_path: Path, models_file: Path, wordy_gguf: Path
) -> None:
    from skillwright.pipeline.events import ModelWaiting

    holder = _Holder(wordy_gguf)
    cancel = threading.Event()

    def on_event(event: Event) -> None:
        if isinstance(event, ModelWaiting):
            cancel.set()  # Esc in the TUI

    out = tmp_path / "out"
    try:
        with pytest.raises(GenerationCancelledError) as info:
            run_generation(request(out, models_file=models_file), on_event=on_event, cancel=cancel)
    finally:
        holder.release()
    assert str(info.value) == (
        "generation stopped: waiting for model tiny cancelled; nothing was written "
        f"({out} is as it was)"
    )
    assert not out.exists()


def test_the_model_gets_handles_only_for_what_the_specification_calls_for(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, models_file: Path
) -> None:
    # set-velocity's first four hold /imu/data, which no state text, input or output names:
    # the card lists it as not wired and the skill has no subscription to it.
    model = MethodScript(dict(SET_VELOCITY), model_id="tiny")
    use_model(monkeypatch, model)
    outcome = run_generation(request(tmp_path / "out", models_file=models_file))
    given = [h.name for h in outcome.record.retrieval.hits if not h.set_aside]
    assert "/imu/data" in given
    assert outcome.report.passed, outcome.report.findings
    card = outcome.record.model.card if outcome.record.model else ""
    assert "Not wired (nothing in the specification calls for them; no handle): /imu/data" in (
        card or ""
    )
    assert "self.imu_data_msg" not in (card or "")
    code = outcome.skill_path.read_text(encoding="utf-8")
    assert "/imu/data" not in code
    assert any("not wired" in n and "/imu/data" in n for n in outcome.record.skeleton.notes)


def test_the_skeleton_sets_the_final_velocity_the_capability_asserts(tmp_path: Path) -> None:
    # MR-1 rotate asserts outAngularVelocity = 0.0: the skeleton's completing settles the
    # base on odometry and reports it; Nav2's /spin, retrieved, is not wired.
    outcome = run_generation(request(tmp_path / "out", stem="rotate", skeleton=True))
    code = outcome.skill_path.read_text(encoding="utf-8")
    completing = code[code.index("def completing") : code.index("@stopping")]
    assert "self._settle_base(5.0)\n        self.out_angular_velocity = 0.0" in completing
    assert "Spin" not in code
