"""Stand-in of ``rclpy.qos``: the QoS profiles and policies skills pass around."""

from __future__ import annotations

from enum import IntEnum


class HistoryPolicy(IntEnum):
    SYSTEM_DEFAULT = 0
    KEEP_LAST = 1
    KEEP_ALL = 2
    UNKNOWN = 3


class ReliabilityPolicy(IntEnum):
    SYSTEM_DEFAULT = 0
    RELIABLE = 1
    BEST_EFFORT = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class DurabilityPolicy(IntEnum):
    SYSTEM_DEFAULT = 0
    TRANSIENT_LOCAL = 1
    VOLATILE = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class LivelinessPolicy(IntEnum):
    SYSTEM_DEFAULT = 0
    AUTOMATIC = 1
    MANUAL_BY_TOPIC = 3
    UNKNOWN = 4
    BEST_AVAILABLE = 5


# The names older rclpy releases used; skills still import them.
QoSHistoryPolicy = HistoryPolicy
QoSReliabilityPolicy = ReliabilityPolicy
QoSDurabilityPolicy = DurabilityPolicy
QoSLivelinessPolicy = LivelinessPolicy


class QoSProfile:
    """A quality-of-service profile; ``depth`` is required with ``KEEP_LAST`` history."""

    def __init__(self, **kwargs: object) -> None:
        allowed = {
            "history",
            "depth",
            "reliability",
            "durability",
            "lifespan",
            "deadline",
            "liveliness",
            "liveliness_lease_duration",
            "avoid_ros_namespace_conventions",
        }
        unknown = set(kwargs) - allowed
        if unknown:
            raise TypeError(
                f"Invalid arguments passed to constructor: {', '.join(sorted(unknown))}"
            )
        history = kwargs.get("history", HistoryPolicy.KEEP_LAST)
        if history == HistoryPolicy.KEEP_LAST and "depth" not in kwargs:
            raise ValueError("A QoSProfile with 'history' KEEP_LAST requires 'depth' to be set")
        self.history = HistoryPolicy(history)
        self.depth = int(kwargs.get("depth", 0))  # type: ignore[call-overload]
        self.reliability = ReliabilityPolicy(kwargs.get("reliability", ReliabilityPolicy.RELIABLE))
        self.durability = DurabilityPolicy(kwargs.get("durability", DurabilityPolicy.VOLATILE))
        self.liveliness = kwargs.get("liveliness", LivelinessPolicy.SYSTEM_DEFAULT)
        self.lifespan = kwargs.get("lifespan")
        self.deadline = kwargs.get("deadline")
        self.liveliness_lease_duration = kwargs.get("liveliness_lease_duration")
        self.avoid_ros_namespace_conventions = bool(kwargs.get("avoid_ros_namespace_conventions"))

    def __repr__(self) -> str:
        return (
            f"QoSProfile(history={self.history.name}, depth={self.depth}, "
            f"reliability={self.reliability.name}, durability={self.durability.name})"
        )


qos_profile_sensor_data = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=5,
    reliability=ReliabilityPolicy.BEST_EFFORT,
    durability=DurabilityPolicy.VOLATILE,
)
qos_profile_system_default = QoSProfile(
    history=HistoryPolicy.SYSTEM_DEFAULT,
    depth=0,
    reliability=ReliabilityPolicy.SYSTEM_DEFAULT,
    durability=DurabilityPolicy.SYSTEM_DEFAULT,
)
qos_profile_services_default = QoSProfile(depth=10)
qos_profile_parameters = QoSProfile(depth=1000)
qos_profile_parameter_events = QoSProfile(depth=1000)
qos_profile_action_status_default = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


class QoSPresetProfiles:
    """The preset profiles by name; each member's ``value`` is the profile."""

    class _Preset:
        def __init__(self, name: str, value: QoSProfile) -> None:
            self.name = name
            self.value = value

    SYSTEM_DEFAULT = _Preset("SYSTEM_DEFAULT", qos_profile_system_default)
    SENSOR_DATA = _Preset("SENSOR_DATA", qos_profile_sensor_data)
    SERVICES_DEFAULT = _Preset("SERVICES_DEFAULT", qos_profile_services_default)
    PARAMETERS = _Preset("PARAMETERS", qos_profile_parameters)
    PARAMETER_EVENTS = _Preset("PARAMETER_EVENTS", qos_profile_parameter_events)
    ACTION_STATUS_DEFAULT = _Preset("ACTION_STATUS_DEFAULT", qos_profile_action_status_default)


def profile_of(qos_profile: object) -> QoSProfile:
    """What ``create_publisher`` / ``create_subscription`` accept: a depth or a profile."""
    if isinstance(qos_profile, bool):
        raise TypeError("qos_profile must be a QoSProfile or an int (the history depth)")
    if isinstance(qos_profile, int):
        if qos_profile < 0:
            raise ValueError("the history depth must be greater than or equal to zero")
        return QoSProfile(depth=qos_profile)
    if isinstance(qos_profile, QoSProfile):
        return qos_profile
    raise TypeError(
        f"qos_profile must be a QoSProfile or an int (the history depth), "
        f"not {type(qos_profile).__name__}"
    )


def describe(profile: QoSProfile) -> dict:
    """The profile as the host reads it."""
    reliability = {
        ReliabilityPolicy.BEST_EFFORT: "best_effort",
        ReliabilityPolicy.RELIABLE: "reliable",
        ReliabilityPolicy.SYSTEM_DEFAULT: "reliable",
    }.get(profile.reliability, "best_available")
    durability = {
        DurabilityPolicy.TRANSIENT_LOCAL: "transient_local",
        DurabilityPolicy.VOLATILE: "volatile",
        DurabilityPolicy.SYSTEM_DEFAULT: "volatile",
    }.get(profile.durability, "best_available")
    return {"depth": profile.depth, "reliability": reliability, "durability": durability}
