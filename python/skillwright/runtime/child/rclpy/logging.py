"""Stand-in of ``rclpy.logging``: log lines go to the run's trace."""

from __future__ import annotations

from enum import IntEnum

from _skillwright_child.core import core


class LoggingSeverity(IntEnum):
    UNSET = 0
    DEBUG = 10
    INFO = 20
    WARN = 30
    ERROR = 40
    FATAL = 50


_LEVEL_NAMES = {10: "debug", 20: "info", 30: "warn", 40: "error", 50: "fatal"}


class RcutilsLogger:
    """A named logger; the methods take one message and rclpy's keyword options."""

    def __init__(self, name: str = "") -> None:
        self.name = name
        self._level = LoggingSeverity.INFO
        self._once: set[tuple[int, str]] = set()
        self._last: dict[int, float] = {}
        self._skips: set[int] = set()

    def get_child(self, name: str) -> RcutilsLogger:
        if not name:
            raise ValueError("Child logger name must not be empty.")
        return RcutilsLogger(f"{self.name}.{name}" if self.name else name)

    def set_level(self, level: LoggingSeverity | int) -> None:
        self._level = LoggingSeverity(level)

    def get_effective_level(self) -> LoggingSeverity:
        return self._level

    def is_enabled_for(self, severity: LoggingSeverity | int) -> bool:
        return severity >= self._level

    def log(self, message: object, severity: LoggingSeverity | int, **kwargs: object) -> bool:
        allowed = {
            "name",
            "once",
            "throttle_duration_sec",
            "throttle_time_source_type",
            "skip_first",
        }
        unknown = set(kwargs) - allowed
        if unknown:
            raise TypeError(f"parameter(s) not supported: {', '.join(sorted(unknown))}")
        c = core()
        line = c.skill_line()
        if not self.is_enabled_for(severity):
            return False
        if kwargs.get("once"):
            if line in {key for key, _ in self._once}:
                return False
            self._once.add((line, ""))
        if kwargs.get("skip_first") and line not in self._skips:
            self._skips.add(line)
            return False
        throttle = kwargs.get("throttle_duration_sec")
        if throttle:
            last = self._last.get(line)
            if last is not None and c.now - last < float(throttle):  # type: ignore[arg-type]
                return False
            self._last[line] = c.now
        c.notify(
            "log",
            level=_LEVEL_NAMES.get(int(severity), "info"),
            name=str(kwargs.get("name") or self.name),
            text=str(message),
            line=line,
        )
        return True

    def debug(self, message: object, **kwargs: object) -> bool:
        return self.log(message, LoggingSeverity.DEBUG, **kwargs)

    def info(self, message: object, **kwargs: object) -> bool:
        return self.log(message, LoggingSeverity.INFO, **kwargs)

    def warning(self, message: object, **kwargs: object) -> bool:
        return self.log(message, LoggingSeverity.WARN, **kwargs)

    warn = warning

    def error(self, message: object, **kwargs: object) -> bool:
        return self.log(message, LoggingSeverity.ERROR, **kwargs)

    def fatal(self, message: object, **kwargs: object) -> bool:
        return self.log(message, LoggingSeverity.FATAL, **kwargs)


def get_logger(name: str) -> RcutilsLogger:
    if not name:
        raise ValueError("Logger name must not be empty.")
    return RcutilsLogger(name)


def set_logger_level(name: str, level: LoggingSeverity | int) -> None:
    return None
