"""Which interfaces are ROS 2 or tooling plumbing rather than part of the robot's task.

The rules are a plain table so that enrichment (and the user reading an inventory) can
see exactly why an interface was flagged. A rule matches on the interface kind and on
the name (last path segments) and/or the type; the first matching rule wins.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from skillwright.interfaces.inventory import InfrastructureFlag, InterfaceKind

__all__ = ["RULES", "InfrastructureRule", "classify"]


@dataclass(frozen=True)
class InfrastructureRule:
    """One row of the rule table."""

    rule: str
    """Stable identifier, recorded in the inventory."""
    kinds: frozenset[InterfaceKind]
    """Interface kinds the rule applies to."""
    reason: str
    """Why interfaces matching it are infrastructure."""
    name: re.Pattern[str] | None = None
    """Pattern the full interface name must match (``search``), if any."""
    type_name: re.Pattern[str] | None = None
    """Pattern the interface type must match (``fullmatch``), if any."""

    def matches(self, kind: InterfaceKind, name: str, type_name: str) -> bool:
        """Whether an interface of ``kind`` called ``name`` of ``type_name`` is covered."""
        if kind not in self.kinds:
            return False
        if self.name is not None and not self.name.search(name):
            return False
        return self.type_name is None or bool(self.type_name.fullmatch(type_name))


_TOPIC = frozenset[InterfaceKind]({"topic"})
_SERVICE = frozenset[InterfaceKind]({"service"})

RULES: tuple[InfrastructureRule, ...] = (
    InfrastructureRule(
        rule="rosout",
        kinds=_TOPIC,
        name=re.compile(r"^/rosout$"),
        reason="log output every ROS 2 node publishes; for debugging, not for control",
    ),
    InfrastructureRule(
        rule="parameter_events",
        kinds=_TOPIC,
        name=re.compile(r"(^|/)parameter_events$"),
        reason="notifications of parameter changes, published by every node",
    ),
    InfrastructureRule(
        rule="recorder_events",
        kinds=_TOPIC,
        name=re.compile(r"^/events/(write_split|read_split)$"),
        reason="rosbag2's own notifications about bag files being split or read",
    ),
    InfrastructureRule(
        rule="parameter_services",
        kinds=_SERVICE,
        name=re.compile(
            r"/(describe_parameters|get_parameters|get_parameter_types|list_parameters"
            r"|set_parameters|set_parameters_atomically)$"
        ),
        reason="parameter services every node offers; introspection and configuration",
    ),
    InfrastructureRule(
        rule="type_description_service",
        kinds=_SERVICE,
        name=re.compile(r"/get_type_description$"),
        reason="returns message type descriptions; introspection",
    ),
    InfrastructureRule(
        rule="lifecycle_transition_event",
        kinds=_TOPIC,
        type_name=re.compile(r"lifecycle_msgs/msg/TransitionEvent"),
        reason="lifecycle state-change notifications of a managed node",
    ),
    InfrastructureRule(
        rule="lifecycle_services",
        kinds=_SERVICE,
        type_name=re.compile(
            r"lifecycle_msgs/srv/(ChangeState|GetState|GetAvailableStates"
            r"|GetAvailableTransitions)"
        ),
        reason="lifecycle management of a managed node (configure, activate, ...)",
    ),
    InfrastructureRule(
        rule="logger_level_services",
        kinds=_SERVICE,
        name=re.compile(r"/(get_logger_levels|set_logger_levels)$"),
        reason="changes the verbosity of a node's logging",
    ),
)


def classify(kind: InterfaceKind, name: str, type_name: str) -> InfrastructureFlag | None:
    """The flag of the first rule that covers the interface, or ``None``."""
    for rule in RULES:
        if rule.matches(kind, name, type_name):
            return InfrastructureFlag(rule=rule.rule, reason=rule.reason)
    return None
