"""Runs a skill's PackML states the way pySkillUp drives them, and reports to the host.

Normal run: load the module, create the skill, set its inputs on the attributes their
``@skill_parameter`` getters return, then starting -> execute -> completing, read the
outputs through the ``@skill_output`` getters, and resetting. A state that raises goes
to aborting -> clearing -> resetting. A Stop command (the host interrupts execute, or
it arrives at Complete) goes to stopping -> resetting; so does a state the host ends for
taking too long. After resetting the driver lets virtual time run on briefly, so that
anything the skill left running (a timer still commanding motion) shows in the trace.
"""

from __future__ import annotations

import base64
import contextlib
import marshal
import math
import sys
import threading
import types

from _skillwright_child.core import Core, Interrupted

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

ERROR_PATH = ("aborting", "clearing", "resetting")
STOP_PATH = ("stopping", "resetting")
_MAX_OUTPUT = 64 * 1024


class _Output:
    """``sys.stdout`` / ``sys.stderr`` of the skill: text goes to the trace, bounded."""

    def __init__(self, core: Core, stream: str) -> None:
        self._core = core
        self._stream = stream
        self._sent = 0
        self.encoding = "utf-8"
        self.errors = "replace"

    def write(self, text: str) -> int:
        if not isinstance(text, str):
            raise TypeError(f"write() argument must be str, not {type(text).__name__}")
        room = _MAX_OUTPUT - self._sent
        if room > 0 and text:
            chunk = text[:room]
            self._sent += len(chunk)
            self._core.notify(
                "output", stream=self._stream, text=chunk, line=self._core.skill_line()
            )
        return len(text)

    def flush(self) -> None:
        return None

    def isatty(self) -> bool:
        return False

    def writable(self) -> bool:
        return True


def _runtime_data(error: BaseException) -> dict | None:
    """What a stand-in attached to ``error``, or to the error it was raised from or during
    (a skill that wraps tf2's LookupException in its own RuntimeError keeps its cause)."""
    seen = 0
    while error is not None and seen < 8:
        data = getattr(error, "skillwright_data", None)
        if isinstance(data, dict):
            return data
        error = error.__cause__ or error.__context__  # type: ignore[assignment]
        seen += 1
    return None


def _kind(error: BaseException) -> str:
    marked = getattr(type(error), "kind", None)
    if isinstance(marked, str):
        return marked
    if isinstance(error, SyntaxError):
        return "syntax"
    if isinstance(error, ImportError):
        return "import"
    if isinstance(error, MemoryError):
        return "memory"
    if isinstance(error, SystemExit):
        return "exit"
    if isinstance(error, RecursionError):
        return "recursion"
    return "exception"


def _plain(value: Any) -> Any:
    """A JSON-safe form of an output value."""
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else repr(value)
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value[:100]]
    try:
        return repr(value)[:500]
    except Exception:
        return f"<{type(value).__name__}>"


def _named(code: types.CodeType, filename: str) -> types.CodeType:
    """``code`` and the code it holds (functions, classes) as compiled from ``filename``."""
    consts = tuple(
        _named(value, filename) if isinstance(value, types.CodeType) else value
        for value in code.co_consts
    )
    return code.replace(co_filename=filename, co_consts=consts)


class _Watch(property):
    """The runtime's property on a watched attribute: storing through it runs no skill code."""

    quiet = True


def _watchable(instance: Any, names: set) -> bool:
    """Whether ``instance`` keeps ``names`` in its ``__dict__`` with nothing in its class
    that handles them or attribute access in general (then properties can watch them)."""
    if not isinstance(getattr(instance, "__dict__", None), dict):
        return False
    cls = type(instance)
    hooks = ("__getattribute__", "__setattr__", "__delattr__")
    if any(getattr(cls, hook) is not getattr(object, hook) for hook in hooks):
        return False
    return not any(name in vars(klass) for klass in cls.__mro__ for name in names)


class Driver:
    """Loads the skill and runs its states."""

    def __init__(self, core: Core, config: dict) -> None:
        self.core = core
        self.config = config
        self.skill_file = config["skill"]
        self.instance: Any = None
        self.methods: dict[str, Any] = {}
        self.in_state = False
        self.reads: set[str] = set()
        self.writes: set[str] = set()
        self.threads: list[threading.Thread] = []
        self.reported: set[tuple[str, int]] = set()

    # --- reporting -----------------------------------------------------------------

    def _skill_frames(self, tb: types.TracebackType | None) -> list[list]:
        import traceback

        frames = []
        for entry in traceback.extract_tb(tb):
            if entry.filename == self.skill_file:
                frames.append([entry.lineno or 0, entry.name])
        return frames

    def report_error(self, phase: str, error: BaseException) -> None:
        frames = self._skill_frames(error.__traceback__)
        line = frames[-1][0] if frames else 0
        # A callback that fails fails again at every message; once is enough.
        key = (type(error).__name__, line)
        if key in self.reported:
            return
        self.reported.add(key)
        if isinstance(error, SyntaxError) and error.filename == self.skill_file:
            line = error.lineno or 0
        try:
            message = str(error)
        except Exception:
            message = "<unprintable>"
        data = _runtime_data(error)
        self.core.notify(
            "error",
            phase=phase,
            kind=_kind(error),
            type=type(error).__name__,
            message=message[:2000],
            line=line,
            frames=frames[-20:],
            data=data or {},
        )

    # --- loading -------------------------------------------------------------------

    def load(self) -> bool:
        """Imports the skill module and creates the skill; False when that failed."""
        self.core.notify("phase", name="load")
        try:
            packed = self.config.get("code")
            if isinstance(packed, str):
                # The host compiled the same text once for all the runs of a validation.
                code = _named(marshal.loads(base64.b64decode(packed)), self.skill_file)
            else:
                with open(self.skill_file, encoding="utf-8") as stream:
                    source = stream.read()
                code = compile(source, self.skill_file, "exec")
            module = types.ModuleType("skill")
            module.__file__ = self.skill_file
            sys.modules["skill"] = module
            exec(code, module.__dict__)
        except Interrupted:
            raise
        except BaseException as error:
            self.report_error("load", error)
            return False
        cls = module.__dict__.get(self.config["class"])
        if not isinstance(cls, type):
            self.core.notify(
                "error",
                phase="load",
                kind="structure",
                type="LookupError",
                message=f"no class {self.config['class']} after loading the module",
                line=0,
                frames=[],
            )
            return False
        self.core.notify("phase", name="init")
        try:
            self.instance = cls()
        except Interrupted:
            raise
        except BaseException as error:
            self.report_error("init", error)
            return False
        for klass in reversed(cls.__mro__):
            for value in vars(klass).values():
                state = getattr(value, "_pyskillup_state", None)
                if isinstance(state, str):
                    self.methods[state] = getattr(self.instance, value.__name__)
        return self._set_inputs() and self._watch()

    def _set_inputs(self) -> bool:
        """Sets each input where its getter reads it: ``self.x``, or the field of what
        ``__init__`` made (``self.goal.x``)."""
        for entry in self.config["inputs"]:
            try:
                *head, last = (entry.get("path") or entry["attr"]).split(".")
                target = self.instance
                for part in head:
                    target = getattr(target, part)
                setattr(target, last, entry["value"])
            except BaseException as error:
                self.report_error("inputs", error)
                return False
        return True

    def _watch(self) -> bool:
        """Swaps the instance's class for a subclass that notes input reads and output
        writes made while a state runs."""
        inputs = {entry["attr"] for entry in self.config["inputs"]}
        outputs = {entry["attr"] for entry in self.config["outputs"] if entry.get("attr")}
        base = type(self.instance)
        if _watchable(self.instance, inputs | outputs):
            watched = self._watched_by_properties(base, inputs, outputs)
        else:
            watched = self._watched_by_hooks(base, inputs, outputs)
        watched.__name__ = base.__name__
        watched.__qualname__ = base.__qualname__
        watched.__module__ = base.__module__
        # A class whose layout forbids the swap (C base, __slots__ clash) is run unwatched.
        with contextlib.suppress(TypeError):
            self.instance.__class__ = watched
        return True

    def _watched_by_properties(self, base: type, inputs: set, outputs: set) -> type:
        """Watches through one property per watched attribute (kept in the instance's
        ``__dict__`` as before), so reading any other attribute costs nothing extra: the
        skill's loops read ``self.<x>`` thousands of times."""
        driver = self

        def watched(name: str) -> property:
            def get(instance: Any) -> Any:
                if driver.in_state and name in inputs:
                    driver.reads.add(name)
                try:
                    return instance.__dict__[name]
                except KeyError:
                    message = f"'{type(instance).__name__}' object has no attribute '{name}'"
                    raise AttributeError(message, name=name, obj=instance) from None

            def set_(instance: Any, value: Any) -> None:
                if driver.in_state and name in outputs:
                    driver.writes.add(name)
                instance.__dict__[name] = value

            def delete(instance: Any) -> None:
                try:
                    del instance.__dict__[name]
                except KeyError:
                    raise AttributeError(name) from None

            return _Watch(get, set_, delete)

        class Watched(base):  # type: ignore[misc, valid-type]
            __slots__ = ()

        for name in inputs | outputs:
            setattr(Watched, name, watched(name))
        return Watched

    def _watched_by_hooks(self, base: type, inputs: set, outputs: set) -> type:
        """Watches through ``__getattribute__`` and ``__setattr__``, for classes that define
        the watched names themselves or hook attribute access."""
        driver = self

        class Watched(base):  # type: ignore[misc, valid-type]
            __slots__ = ()

            def __getattribute__(self, name: str) -> Any:
                if driver.in_state and name in inputs:
                    driver.reads.add(name)
                return super().__getattribute__(name)

            def __setattr__(self, name: str, value: Any) -> None:
                if driver.in_state and name in outputs:
                    driver.writes.add(name)
                super().__setattr__(name, value)

        return Watched

    # --- states --------------------------------------------------------------------

    def run_state(self, name: str) -> tuple[str, str | None]:
        """Runs one state: ``("done"|"absent"|"raised"|"interrupted", detail)``."""
        method = self.methods.get(name)
        if method is None:
            self.core.notify("state", name=name, phase="absent")
            return "absent", None
        self.core.notify("state", name=name, phase="begin")
        self.in_state = True
        try:
            method()
        except Interrupted as interrupt:
            self.in_state = False
            self.core.notify(
                "state", name=name, phase="end", outcome="interrupted", detail=interrupt.reason
            )
            return "interrupted", interrupt.reason
        except BaseException as error:
            self.in_state = False
            self.report_error(name, error)
            self.core.notify(
                "state", name=name, phase="end", outcome="raised", detail=type(error).__name__
            )
            return "raised", type(error).__name__
        self.in_state = False
        self.core.notify("state", name=name, phase="end", outcome="done")
        return "done", None

    def _commanded(self) -> str | None:
        """The transition the state that just returned asked of ``self.state_machine``."""
        machine = getattr(self.instance, "state_machine", None)
        requested = getattr(machine, "_requested", None)
        return requested if requested in {"stop", "abort"} else None

    def read_outputs(self) -> None:
        values: dict[str, Any] = {}
        getters = {}
        for klass in reversed(type(self.instance).__mro__):
            for attribute, value in vars(klass).items():
                mark = getattr(value, "_pyskillup_variable", None)
                if isinstance(mark, dict) and mark.get("kind") == "skill_output":
                    getters[mark.get("name")] = attribute
        for entry in self.config["outputs"]:
            attribute = getters.get(entry["name"])
            if attribute is None:
                continue
            try:
                values[entry["name"]] = _plain(getattr(self.instance, attribute)())
            except Interrupted:
                raise
            except BaseException as error:
                self.report_error(f"output {entry['name']}", error)
        self.core.notify("outputs", values=values)

    def _path(self, states: tuple[str, ...]) -> None:
        for state in states:
            outcome, _ = self.run_state(state)
            if outcome == "raised" and state != "resetting":
                remaining = (
                    ERROR_PATH[ERROR_PATH.index(state) + 1 :] if state in ERROR_PATH else ERROR_PATH
                )
                self._path(tuple(remaining))
                return
            if outcome == "interrupted" and state != "resetting":
                remaining = (
                    STOP_PATH[STOP_PATH.index(state) + 1 :] if state in STOP_PATH else STOP_PATH
                )
                self._path(tuple(remaining))
                return

    def run(self) -> None:
        """The whole episode the host planned."""
        stop_at_complete = bool(self.config.get("stop_at_complete"))
        for state in ("starting", "execute", "completing"):
            outcome, _ = self.run_state(state)
            if outcome == "raised" or self._commanded() == "abort":
                self._path(ERROR_PATH)
                return
            if outcome == "interrupted" or self._commanded() == "stop":
                self._path(STOP_PATH)
                return
        self.read_outputs()
        self._path(STOP_PATH if stop_at_complete else ("resetting",))

    def settle(self) -> None:
        """Lets virtual time run after the last state, then reports what is left."""
        self.core.notify("phase", name="settle")
        try:
            self.core.block(self.core.now + float(self.config["settle"]), None, "settle")
        except Interrupted:
            pass
        except BaseException as error:
            self.report_error("settle", error)
        self.core.notify(
            "watch",
            read=sorted(self.reads),
            written=sorted(self.writes),
            threads=[
                {"name": t.name, "line": getattr(t, "_skillwright_line", 0), "daemon": t.daemon}
                for t in self.threads
                if t.is_alive()
            ],
        )


def run(core: Core, config: dict) -> None:
    """Loads the skill, runs its states, and tells the host it is done."""
    driver = Driver(core, config)
    real_start = threading.Thread.start

    def start(thread: threading.Thread) -> None:
        thread._skillwright_line = core.skill_line()  # type: ignore[attr-defined]
        driver.threads.append(thread)
        real_start(thread)

    threading.Thread.start = start  # type: ignore[method-assign]
    sys.stdout = _Output(core, "stdout")  # type: ignore[assignment]
    sys.stderr = _Output(core, "stderr")  # type: ignore[assignment]
    try:
        if driver.load():
            driver.run()
            driver.settle()
    except Interrupted as interrupt:
        core.notify("phase", name=f"interrupted:{interrupt.reason}")
    core.notify("done")
