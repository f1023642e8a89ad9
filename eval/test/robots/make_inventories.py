"""Writes the test split's robot inventories from the labelled robot graphs of the retrieval
tests.

``tests/retrieval/robots/<robot>.yaml`` describes the ROS 2 graph of the TurtleBot 4, the TIAGo
and the MMO-700 as public sources show it; ``tests.retrieval.robots.robot_inventory`` builds an
inventory from it the way a live graph would list it (every node's parameter services, the
lifecycle services, message definitions of the types a live graph shows). This script saves
those inventories beside it as ``<robot>.json``, in the format ``skillwright discover -o``
writes and ``--interfaces`` reads, so that the evaluation reads a project-owned copy and does
not depend on the tests' code. The source location is kept relative to the repository, so
the files do not depend on where it was checked out.

    python eval/test/robots/make_inventories.py

A test (tests/eval/test_test_split.py) checks that the saved files are what this script
writes.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
ROBOTS = ("tb4", "tiago", "mmo700nav")


def inventory_text(robot: str) -> str:
    """The saved form of one robot's inventory: compact JSON, fields left at their defaults
    left out (the reader fills them in), the schema version kept, a final newline."""
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    from tests.retrieval.robots import robot_inventory

    inventory = robot_inventory(robot)
    for source in inventory.sources:
        source.location = Path(source.location).resolve().relative_to(ROOT).as_posix()
    document = {
        "schema_version": inventory.schema_version,
        **inventory.model_dump(mode="json", exclude_defaults=True),
    }
    return json.dumps(document, separators=(",", ":"), sort_keys=True) + "\n"


def main() -> int:
    for robot in ROBOTS:
        target = HERE / f"{robot}.json"
        target.write_text(inventory_text(robot), encoding="utf-8")
        print(f"wrote {target.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
