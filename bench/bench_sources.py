"""Interface sources besides recordings: report import/export and the offline type store.

Alternatives named for comparison, measured in the same run:

* report import against plain ``json.loads`` of the same file, which is all the reference
  tool does (it keeps ``details`` as opaque text; we build field trees from it);
* report export against ``json.dumps`` of the parsed document (the text is re-rendered
  from our definitions, as ``ros2 interface show`` would print it);
* a type-store fill (parse + field trees) against calling rosbags directly (its stores
  cached, ``generate_msgdef`` only); the first fill, which loads the store, is shown too.

Run with ``make bench``; needs ``../shared`` beside the repository.
"""

from __future__ import annotations

import json
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared" / "data"
REPORT = SHARED / "cap2skill" / "interface-reports" / "ros2_system_report.json"
TYPES = [
    "geometry_msgs/msg/Twist",
    "nav_msgs/msg/Odometry",
    "sensor_msgs/msg/LaserScan",
    "sensor_msgs/msg/JointState",
    "tf2_msgs/msg/TFMessage",
    "trajectory_msgs/msg/JointTrajectory",
]


def timed(function: Callable[[], object], repeat: int) -> float:
    """Median wall time of ``repeat`` calls, in seconds."""
    samples = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        samples.append(time.perf_counter() - start)
    return statistics.median(samples)


def row(what: str, seconds: float, baseline: float | None = None) -> None:
    ratio = f"{seconds / baseline:8.1f}x" if baseline else f"{'':>9}"
    print(f"{what:60} {seconds * 1e3:9.2f} ms {ratio}")


def main() -> int:
    if not REPORT.is_file():
        print(f"skipped: {REPORT} not found")
        return 0
    from skillwright.interfaces.inventory import Interface
    from skillwright.interfaces.sources.report import read_report, report_text
    from skillwright.interfaces.typestore import TypeStore, _rosbags_store, fill_missing_definitions

    text = REPORT.read_text(encoding="utf-8")
    print(f"{'what':60} {'time':>12} {'ratio':>9}")
    loads = timed(lambda: json.loads(text), 20)
    row("json.loads of the raw report, 107 entries (alternative)", loads)
    row(
        "skillwright: report -> inventory (field trees)",
        timed(lambda: read_report(REPORT), 10),
        loads,
    )
    inventory = read_report(REPORT)
    document = json.loads(text)
    dumps = timed(lambda: json.dumps(document, indent=4), 20)
    row("json.dumps of the parsed report (alternative)", dumps)
    row("skillwright: inventory -> report text", timed(lambda: report_text(inventory), 10), dumps)

    def rosbags_direct() -> None:
        from rosbags.typesys import Stores, get_typestore

        store = get_typestore(Stores.ROS2_JAZZY)
        for name in TYPES:
            store.generate_msgdef(name, ros_version=2)

    def fill() -> None:
        fill_missing_definitions(
            [Interface(name=f"/t{i}", kind="topic", type_name=t) for i, t in enumerate(TYPES)]
        )

    _rosbags_store.cache_clear()
    start = time.perf_counter()
    fill()
    cold = time.perf_counter() - start
    direct = timed(rosbags_direct, 5)
    row(f"rosbags: get_typestore + generate_msgdef x{len(TYPES)} (alternative)", direct)
    # Not a like-for-like ratio: the first fill also imports rosbags and builds the store.
    row(f"skillwright: first fill of {len(TYPES)} (imports rosbags, loads the store)", cold)
    row(f"skillwright: fill {len(TYPES)} definitions, store loaded", timed(fill, 10), direct)
    assert TypeStore().text("std_msgs/msg/String") is not None
    return 0


if __name__ == "__main__":
    sys.exit(main())
