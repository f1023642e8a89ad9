"""Robot graphs written down from public sources, built into inventories for the labelled sets.

A robot file (``tests/retrieval/robots/*.yaml``) lists what the robot's ROS 2 graph offers, as
the sources it names show it: its nodes, and the topics, services and actions with their types.
The plumbing every ROS 2 node has is added here the way ``rclcpp`` and ``rclpy`` create it, so
the files stay readable and the graphs stay as large as real ones:

- every node offers the six parameter services (``describe_parameters``, ``get_parameters``,
  ``get_parameter_types``, ``list_parameters``, ``set_parameters``,
  ``set_parameters_atomically``), and from Jazzy on ``get_type_description``;
- a lifecycle node (``lifecycle: true``: Nav2's servers, the map server, AMCL) also offers
  ``change_state``, ``get_state``, ``get_available_states``, ``get_available_transitions`` and
  ``get_transition_graph`` and publishes ``transition_event``;
- the graph has ``/rosout`` and ``/parameter_events``.

Definitions come from the offline type stores where they have the type (standard messages);
the others (nav2_msgs, moveit_msgs, vendor packages) stay unknown, as they would for a source
that names types only. Infrastructure is flagged by the same rules as for any source.

A topic may be written ``{type: ..., publishers: n, subscribers: n}`` where the sources say
who is at either end, as a live graph would show it (the Stretch's /cmd_vel that nothing
reads).

A live graph also shows the fields of every type, Nav2's, MoveIt's and the vendors' included,
and those fields are words retrieval weighs (BackUp's ``distance_traveled``, MotionPlanRequest's
``max_velocity_scaling_factor``). ``robots/definitions/<package>.yaml`` holds the field lists of
the non-standard types the robots use, read from each package's sources for Humble and Jazzy
(fields only, no comments); ``robot_inventory(name, live=True)`` fills them in as a live graph
would have them, ``live=False`` leaves them unknown as a source naming types only does.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from pathlib import Path

import yaml

from skillwright.interfaces.infrastructure import classify
from skillwright.interfaces.inventory import (
    Endpoints,
    Interface,
    InterfaceKind,
    Inventory,
    MessageDefinition,
    Resource,
    Source,
)
from skillwright.interfaces.ros2msg import (
    Block,
    definition_from_text,
    parse_blocks,
    split_action,
    split_service,
)
from skillwright.interfaces.typestore import TypeStore, fill_missing_definitions, store_texts

ROBOTS = Path(__file__).resolve().parent / "robots"
DEFINITIONS = ROBOTS / "definitions"

_BEFORE_TYPE_DESCRIPTIONS = frozenset({"foxy", "galactic", "humble", "iron"})
"""Distributions whose nodes offer no ``get_type_description`` service."""

_PARAMETER_SERVICES = {
    "describe_parameters": "rcl_interfaces/srv/DescribeParameters",
    "get_parameters": "rcl_interfaces/srv/GetParameters",
    "get_parameter_types": "rcl_interfaces/srv/GetParameterTypes",
    "list_parameters": "rcl_interfaces/srv/ListParameters",
    "set_parameters": "rcl_interfaces/srv/SetParameters",
    "set_parameters_atomically": "rcl_interfaces/srv/SetParametersAtomically",
}
_LIFECYCLE_SERVICES = {
    "change_state": "lifecycle_msgs/srv/ChangeState",
    "get_state": "lifecycle_msgs/srv/GetState",
    "get_available_states": "lifecycle_msgs/srv/GetAvailableStates",
    "get_available_transitions": "lifecycle_msgs/srv/GetAvailableTransitions",
    "get_transition_graph": "lifecycle_msgs/srv/GetAvailableTransitions",
}


_PARTS = {"_Goal": 0, "_Result": 1, "_Feedback": 2, "_Request": 0, "_Response": 1}


@cache
def written_texts(distro: str) -> dict[str, str]:
    """The raw definitions of ``robots/definitions`` for a distribution (Humble's where a
    type has no text of its own for ``distro``), by full type name."""
    wanted = "jazzy" if distro not in _BEFORE_TYPE_DESCRIPTIONS else "humble"
    texts: dict[str, str] = {}
    for path in sorted(DEFINITIONS.glob("*.yaml")):
        for type_name, value in (yaml.safe_load(path.read_text(encoding="utf-8")) or {}).items():
            if isinstance(value, str):
                texts[type_name] = value
            elif wanted in value or "humble" in value:
                texts[type_name] = value.get(wanted, value.get("humble"))
            else:
                texts[type_name] = next(iter(value.values()))
    return texts


@cache
def _blocks(distro: str) -> dict[str, Block]:
    """Every message block known for ``distro``: the offline store's and the written ones."""
    blocks: dict[str, Block] = {}
    for type_name, text in {**store_texts(distro), **written_texts(distro)}.items():
        if "/msg/" in type_name:
            blocks[type_name] = parse_blocks(type_name, text)[0]
    return blocks


@dataclass(frozen=True)
class LiveStore(TypeStore):
    """The offline store, then ``robots/definitions``: the types a live graph would show."""

    def definition(self, type_name: str) -> MessageDefinition | None:
        found = super().definition(type_name)
        if found is not None:
            return found
        distro = self.distro or "humble"
        base, suffix = type_name, ""
        for part in _PARTS:
            if type_name.endswith(part):
                base, suffix = type_name.removesuffix(part), part
        text = written_texts(distro).get(base)
        if text is None:
            return None
        if suffix:
            split = split_action(text) if "/action/" in base else split_service(text)
            if split is None:
                raise ValueError(f"{base}: its written definition has no `---` parts")
            text = split[_PARTS[suffix]]
        definition = definition_from_text(type_name, text, extra_dependencies=_blocks(distro))
        # Retrieval reads two levels of fields: those of the packages written here must be
        # known (a vendor's own nested package, Spot's bosdyn_api_msgs, may stay unknown).
        top = definition.fields or ()
        shallow = [*top, *(f for parent in top for f in parent.fields)]
        written = {path.stem for path in DEFINITIONS.glob("*.yaml")}
        unresolved = [
            f.base_type
            for f in shallow
            if not f.resolved and f.base_type.split("/")[0] in written | {"std_msgs"}
        ]
        if unresolved:
            raise ValueError(f"{type_name} ({distro}): {unresolved}")
        return definition


@cache
def robot_inventory(name: str, live: bool = True) -> Inventory:
    """The inventory of ``robots/<name>.yaml``; ``live`` fills the fields of the types
    ``robots/definitions`` holds, as a live graph shows them."""
    path = ROBOTS / f"{name}.yaml"
    document = yaml.safe_load(path.read_text(encoding="utf-8"))
    distro = str(document["distro"])
    entries: dict[tuple[str, InterfaceKind], str] = {
        ("/rosout", "topic"): "rcl_interfaces/msg/Log",
        ("/parameter_events", "topic"): "rcl_interfaces/msg/ParameterEvent",
    }
    for node in document.get("nodes") or []:
        node_name, lifecycle = (node, False) if isinstance(node, str) else (node["name"], True)
        for service, type_name in _PARAMETER_SERVICES.items():
            entries[(f"{node_name}/{service}", "service")] = type_name
        if distro not in _BEFORE_TYPE_DESCRIPTIONS:
            entries[(f"{node_name}/get_type_description", "service")] = (
                "type_description_interfaces/srv/GetTypeDescription"
            )
        if lifecycle:
            for service, type_name in _LIFECYCLE_SERVICES.items():
                entries[(f"{node_name}/{service}", "service")] = type_name
            entries[(f"{node_name}/transition_event", "topic")] = (
                "lifecycle_msgs/msg/TransitionEvent"
            )
    counts: dict[tuple[str, InterfaceKind], Endpoints] = {}
    for section, kind in (("topics", "topic"), ("services", "service"), ("actions", "action")):
        for interface_name, entry in (document.get(section) or {}).items():
            key = (interface_name, kind)
            if isinstance(entry, dict):  # {type: ..., publishers: n, subscribers: n}
                entries[key] = entry.pop("type")  # type: ignore[index]
                counts[key] = Endpoints(**entry)  # type: ignore[index]
            else:
                entries[key] = entry  # type: ignore[index]
    interfaces = [
        Interface(
            name=interface_name,
            kind=kind,
            type_name=type_name,
            endpoints=counts.get((interface_name, kind)),
            infrastructure=classify(kind, interface_name, type_name),
        )
        for (interface_name, kind), type_name in sorted(
            entries.items(), key=lambda item: (item[0][1], item[0][0])
        )
    ]
    fill_missing_definitions(interfaces, distro, LiveStore(distro) if live else None)
    return Inventory(
        resource=Resource(name=document["robot"], description=document["description"]),
        sources=[Source(kind="report", location=str(path), ros_distro=distro)],
        interfaces=interfaces,
    )
