"""Driving an engine over an inventory: descriptions, verdicts, cache, progress and cancel."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest

from skillwright.interfaces.enrich import (
    EnrichmentCache,
    Outcome,
    RulesEngine,
    content_hash,
    default_cache,
    enrich,
    trimmed_definition,
)
from skillwright.interfaces.inventory import (
    Description,
    Interface,
    Inventory,
    MessageDefinition,
    MessageField,
    Relevance,
    Resource,
)


def _field(
    name: str, type_name: str = "float64", fields: list[MessageField] | None = None
) -> MessageField:
    base = type_name.rstrip("[]")
    return MessageField(
        name=name,
        type=type_name,
        base_type=base,
        builtin="/" not in base,
        fields=fields or [],
    )


def _twist() -> MessageDefinition:
    vector = [_field("x"), _field("y"), _field("z")]
    return MessageDefinition(
        type_name="geometry_msgs/msg/Twist",
        encoding="ros2msg",
        raw="Vector3 linear\nVector3 angular\n" + "=" * 80 + "\nMSG: geometry_msgs/Vector3\n"
        "float64 x\nfloat64 y\nfloat64 z\n",
        fields=[
            _field("linear", "geometry_msgs/msg/Vector3", vector),
            _field("angular", "geometry_msgs/msg/Vector3", vector),
        ],
    )


def small_inventory() -> Inventory:
    return Inventory(
        resource=Resource(name="test robot"),
        interfaces=[
            Interface(
                name="/cmd_vel",
                kind="topic",
                type_name="geometry_msgs/msg/Twist",
                definitions={"message": _twist()},
            ),
            Interface(name="/rosout", kind="topic", type_name="rcl_interfaces/msg/Log"),
            Interface(
                name="/teleop/set_parameters",
                kind="service",
                type_name="rcl_interfaces/srv/SetParameters",
            ),
        ],
    )


def test_rules_engine_fills_every_description_and_verdict() -> None:
    inventory = small_inventory()
    report = enrich(inventory, RulesEngine())
    described = report.inventory
    assert all(i.description is not None for i in described.interfaces)
    assert all(i.relevance is not None for i in described.interfaces)
    cmd_vel = described.interface("/cmd_vel")
    assert cmd_vel.description is not None
    assert cmd_vel.description.engine == "rules"
    assert cmd_vel.description.key_fields == [
        "linear",
        "angular",
        "linear.x",
        "linear.y",
        "linear.z",
        "angular.x",
        "angular.y",
        "angular.z",
    ]
    assert (report.described, report.cached, report.control, report.infrastructure) == (3, 0, 1, 2)
    assert report.notes == []
    assert inventory.interfaces[0].description is None  # the input is left as it was


def test_progress_is_reported_after_each_interface() -> None:
    calls: list[tuple[int, int, str]] = []
    enrich(small_inventory(), RulesEngine(), progress=lambda *a: calls.append(a))
    assert calls == [
        (1, 3, "/cmd_vel"),
        (2, 3, "/rosout"),
        (3, 3, "/teleop/set_parameters"),
    ]


def test_a_set_cancel_event_stops_between_interfaces() -> None:
    cancel = threading.Event()

    def stop_after_first(done: int, _total: int, _name: str) -> None:
        if done == 1:
            cancel.set()

    report = enrich(small_inventory(), RulesEngine(), progress=stop_after_first, cancel=cancel)
    assert report.cancelled
    assert report.described == 1
    assert [i.relevance is not None for i in report.inventory.interfaces] == [True, False, False]


def test_report_descriptions_are_kept_unless_replacing_is_asked_for() -> None:
    inventory = small_inventory()
    written = Description(purpose="From the report.", module="base motion", engine="report")
    inventory.interfaces[0].description = written
    report = enrich(inventory, RulesEngine())
    kept = report.inventory.interface("/cmd_vel")
    assert kept.description == written
    assert kept.relevance is not None
    assert report.kept == 1
    replaced = enrich(inventory, RulesEngine(), replace_source_descriptions=True)
    description = replaced.inventory.interface("/cmd_vel").description
    assert description is not None
    assert description.engine == "rules"
    assert replaced.kept == 0


class _CountingEngine:
    """A caching engine that records what it was asked (a stand-in for the LLM engine)."""

    name = "counting"

    def __init__(self) -> None:
        self.asked: list[str] = []

    def cache_key(self, interface: Interface) -> str:
        return content_hash(interface)

    def from_cache(self, interface: Interface, answer: str) -> Outcome | None:
        if answer == "stale":
            return None
        return self._outcome(interface, answer)

    def _outcome(self, interface: Interface, answer: str) -> Outcome:
        return Outcome(
            description=Description(purpose=answer, module="other", engine=self.name),
            relevance=Relevance(relevant=True, category="control", reason="r", engine=self.name),
            answer=answer,
        )

    def run(self, interface: Interface, cancel: threading.Event | None) -> Outcome:
        self.asked.append(interface.name)
        return self._outcome(interface, f"answer for {interface.name}")


def test_cached_answers_are_not_asked_for_again(tmp_path: Path) -> None:
    cache = EnrichmentCache(tmp_path / "enrich.sqlite")
    engine = _CountingEngine()
    first = enrich(small_inventory(), engine, cache=cache)
    assert (first.described, first.cached) == (3, 0)
    second = enrich(small_inventory(), engine, cache=cache)
    assert (second.described, second.cached) == (0, 3)
    assert engine.asked == ["/cmd_vel", "/rosout", "/teleop/set_parameters"]
    assert second.inventory == first.inventory
    assert len(cache) == 3


def test_a_changed_interface_is_asked_for_again(tmp_path: Path) -> None:
    cache = EnrichmentCache(tmp_path / "enrich.sqlite")
    engine = _CountingEngine()
    enrich(small_inventory(), engine, cache=cache)
    changed = small_inventory()
    changed.interfaces[1].type_name = "rcl_interfaces/msg/LogV2"
    report = enrich(changed, engine, cache=cache)
    assert (report.described, report.cached) == (1, 2)
    assert engine.asked[-1] == "/rosout"


def test_a_cached_answer_that_no_longer_validates_is_asked_for_again(tmp_path: Path) -> None:
    cache = EnrichmentCache(tmp_path / "enrich.sqlite")
    engine = _CountingEngine()
    inventory = small_inventory()
    cache.put(content_hash(inventory.interfaces[0]), "counting", "stale")
    report = enrich(inventory, engine, cache=cache)
    assert (report.described, report.cached) == (3, 0)


def test_content_hash_ignores_enrichment_and_traffic() -> None:
    plain = small_inventory().interfaces[0]
    enriched = enrich(small_inventory(), RulesEngine()).inventory.interfaces[0]
    assert content_hash(plain) == content_hash(enriched)
    other = plain.model_copy(update={"name": "/cmd_vel_nav"})
    assert content_hash(other) != content_hash(plain)


def test_the_default_cache_lives_in_the_cache_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("SKILLWRIGHT_CACHE_DIR", str(tmp_path / "c"))
    assert default_cache().path == tmp_path / "c" / "enrich.sqlite"


def test_an_unusable_cache_file_is_named_in_the_error(tmp_path: Path) -> None:
    from skillwright.errors import InputFileError

    broken = tmp_path / "enrich.sqlite"
    broken.write_bytes(b"this is not a database, it is much longer than a header" * 20)
    with pytest.raises(InputFileError, match=r"enrich\.sqlite.*delete the file"):
        EnrichmentCache(broken).get("key")


def test_trimmed_definition_keeps_the_main_block_without_comments() -> None:
    interface = small_inventory().interfaces[0]
    assert trimmed_definition(interface) == "[message]\nVector3 linear\nVector3 angular"


def test_trimmed_definition_keeps_one_level_of_expanded_fields_and_orders_roles() -> None:
    expanded = "# goal\nJointTrajectory trajectory\n\tHeader header\n\t\tTime stamp\n"
    interface = Interface(
        name="/follow",
        kind="action",
        type_name="control_msgs/action/FollowJointTrajectory",
        definitions={
            "feedback": MessageDefinition(type_name="x", encoding="ros2msg", raw="float64 error"),
            "goal": MessageDefinition(type_name="x", encoding="unknown", raw=expanded),
            "binary": MessageDefinition(type_name="x", encoding="protobuf", raw="AAEC"),
        },
    )
    assert trimmed_definition(interface) == (
        "[goal]\nJointTrajectory trajectory\n\tHeader header\n[feedback]\nfloat64 error"
    )


def test_trimmed_definition_is_bounded() -> None:
    raw = "\n".join(f"float64 field_{i}" for i in range(500))
    interface = Interface(
        name="/big",
        kind="topic",
        type_name="acme/msg/Big",
        definitions={
            "message": MessageDefinition(type_name="acme/msg/Big", encoding="ros2msg", raw=raw)
        },
    )
    text = trimmed_definition(interface)
    assert len(text.splitlines()) <= 26
    assert text.endswith("\t...")
    assert trimmed_definition(Interface(name="/x", kind="topic", type_name="a/msg/B")) == (
        "(no definition available)"
    )
