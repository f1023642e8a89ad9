"""The inventory model: JSON round trip, strict fields, and the checked-in JSON schema."""

from __future__ import annotations

import json

import pytest
from pydantic import ValidationError

from skillwright.interfaces.inventory import (
    SCHEMA_PATH,
    Interface,
    Inventory,
    Resource,
    schema_text,
)


def test_checked_in_json_schema_matches_the_model() -> None:
    assert SCHEMA_PATH.read_text(encoding="utf-8") == schema_text(), (
        "inventory.schema.json is out of date: run "
        "`python -m skillwright.interfaces.inventory` and commit the result"
    )


def test_inventory_round_trips_through_json() -> None:
    inventory = Inventory(
        resource=Resource(name="robot"),
        interfaces=[Interface(name="/cmd_vel", kind="topic", type_name="geometry_msgs/msg/Twist")],
    )
    again = Inventory.model_validate_json(inventory.model_dump_json())
    assert again == inventory
    assert json.loads(inventory.model_dump_json())["schema_version"] == 1


def test_unknown_fields_and_versions_are_rejected() -> None:
    with pytest.raises(ValidationError):
        Inventory.model_validate({"resource": {"name": "r"}, "surprise": 1})
    with pytest.raises(ValidationError):
        Inventory.model_validate({"resource": {"name": "r"}, "schema_version": 2})


def test_interface_lookup_by_name_and_kind() -> None:
    inventory = Inventory(
        resource=Resource(name="robot"),
        interfaces=[
            Interface(name="/x", kind="topic", type_name="a/msg/B"),
            Interface(name="/x", kind="service", type_name="a/srv/C"),
        ],
    )
    assert inventory.interface("/x", "service").type_name == "a/srv/C"
    with pytest.raises(KeyError):
        inventory.interface("/y")
