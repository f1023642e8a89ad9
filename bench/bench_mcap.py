"""MCAP discovery speed: skillwright's Rust reader against the Python ``mcap`` library and
``rosbags`` on the same ~1 GB recording, with and without a summary section.

The recording is generated in a temporary folder at run time (50 topics, zstd chunks,
rosbag2 layout with metadata.yaml) and deleted afterwards. The "no summary" copy is the
same file cut right after its data section, as a recorder that was killed leaves it.
Timings are warm-cache (the file was just written), best of several runs.

    python bench/bench_mcap.py [--size-mb 1024] [--keep DIR]
"""

from __future__ import annotations

import argparse
import os
import shutil
import struct
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Callable
from pathlib import Path

SEPARATOR = "=" * 80
IMAGE_DEFINITION = "\n".join(
    [
        "std_msgs/Header header",
        "uint32 height",
        "uint32 width",
        "string encoding",
        "uint8 is_bigendian",
        "uint32 step",
        "uint8[] data",
        SEPARATOR,
        "MSG: std_msgs/Header",
        "builtin_interfaces/Time stamp",
        "string frame_id",
        SEPARATOR,
        "MSG: builtin_interfaces/Time",
        "int32 sec",
        "uint32 nanosec",
    ]
)
TWIST_DEFINITION = "\n".join(
    [
        "Vector3 linear",
        "Vector3 angular",
        SEPARATOR,
        "MSG: geometry_msgs/Vector3",
        "float64 x",
        "float64 y",
        "float64 z",
    ]
)
# (topic prefix, type, definition, payload bytes, rate Hz, how many topics)
TOPIC_GROUPS = [
    ("/camera", "sensor_msgs/msg/Image", IMAGE_DEFINITION, 200_000, 10, 5),
    ("/joint", "geometry_msgs/msg/Twist", TWIST_DEFINITION, 48, 100, 25),
    ("/status", "std_msgs/msg/String", "string data", 120, 20, 20),
]


def _topics() -> list[tuple[str, str, str, int, int]]:
    topics = []
    for prefix, type_name, definition, size, rate, count in TOPIC_GROUPS:
        for index in range(count):
            topics.append((f"{prefix}_{index}", type_name, definition, size, rate))
    return topics


def generate(folder: Path, size_mb: int) -> tuple[Path, int]:
    """Writes ``folder/bag_0.mcap`` (+ metadata.yaml) of about ``size_mb``; returns the
    file and its message count."""
    from mcap.writer import CompressionType, Writer

    topics = _topics()
    bytes_per_second = sum(size * rate for _, _, _, size, rate in topics)
    # Payloads are half fresh random bytes, half zeros: they compress about 2:1, like
    # real sensor data, and zstd cannot shortcut them by matching earlier messages.
    seconds = max(1, size_mb * 2_000_000 // bytes_per_second)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "bag_0.mcap"
    counts: Counter[str] = Counter()
    start_ns = 1_700_000_000_000_000_000
    with path.open("wb") as stream:
        writer = Writer(stream, compression=CompressionType.ZSTD, chunk_size=4 << 20)
        writer.start(profile="ros2", library="skillwright-bench")
        schema_ids: dict[str, int] = {}
        channels = []
        for topic, type_name, definition, size, rate in topics:
            if type_name not in schema_ids:
                schema_ids[type_name] = writer.register_schema(
                    name=type_name, encoding="ros2msg", data=definition.encode()
                )
            channel_id = writer.register_channel(
                topic=topic, message_encoding="cdr", schema_id=schema_ids[type_name]
            )
            channels.append((channel_id, topic, size, rate))
        for tick in range(seconds * 100):  # 10 ms steps
            now = start_ns + tick * 10_000_000
            for channel_id, topic, size, rate in channels:
                if tick % (100 // rate):
                    continue
                writer.add_message(
                    channel_id=channel_id,
                    log_time=now,
                    publish_time=now,
                    data=os.urandom(size // 2) + bytes(size - size // 2),
                    sequence=counts[topic],
                )
                counts[topic] += 1
        writer.finish()
    _write_metadata(folder, path, topics=topics, counts=counts, start_ns=start_ns, seconds=seconds)
    return path, sum(counts.values())


def _write_metadata(
    folder: Path,
    path: Path,
    *,
    topics: list[tuple[str, str, str, int, int]],
    counts: Counter[str],
    start_ns: int,
    seconds: int,
) -> None:
    lines = [
        "rosbag2_bagfile_information:",
        "  version: 8",
        "  storage_identifier: mcap",
        f"  duration: {{nanoseconds: {seconds * 1_000_000_000}}}",
        f"  starting_time: {{nanoseconds_since_epoch: {start_ns}}}",
        f"  message_count: {sum(counts.values())}",
        "  topics_with_message_count:",
    ]
    for topic, type_name, *_ in topics:
        lines += [
            "    - topic_metadata:",
            f"        name: {topic}",
            f"        type: {type_name}",
            "        serialization_format: cdr",
            '        offered_qos_profiles: ""',
            '        type_description_hash: ""',
            f"      message_count: {counts[topic]}",
        ]
    lines += [
        '  compression_format: ""',
        '  compression_mode: ""',
        "  relative_file_paths:",
        f"    - {path.name}",
        "  files:",
        f"    - path: {path.name}",
        f"      starting_time: {{nanoseconds_since_epoch: {start_ns}}}",
        f"      duration: {{nanoseconds: {seconds * 1_000_000_000}}}",
        f"      message_count: {sum(counts.values())}",
        "  custom_data: ~",
        '  ros_distro: ""',
    ]
    (folder / "metadata.yaml").write_text("\n".join(lines) + "\n")


def cut_after_data_section(source: Path, folder: Path) -> Path:
    """A copy of ``source`` ending where its summary would start (recorder killed)."""
    # The footer is the last record before the closing magic: opcode, length, then
    # summary_start as the first field of its body.
    with source.open("rb") as stream:
        stream.seek(-(8 + 20 + 9), os.SEEK_END)
        tail = stream.read(9 + 8)
    summary_start = struct.unpack_from("<Q", tail, 9)[0]
    if not summary_start:
        raise SystemExit("the generated file has no summary to cut off")
    folder.mkdir(parents=True, exist_ok=True)
    target = folder / source.name
    with source.open("rb") as src, target.open("wb") as dst:
        shutil.copyfileobj(src, dst, length=16 << 20)
        dst.truncate(summary_start)
    shutil.copy(source.parent / "metadata.yaml", folder / "metadata.yaml")
    return target


def best_of(runs: int, action: Callable[[], object]) -> tuple[float, object]:
    """Best wall time in seconds over ``runs`` and the last result."""
    times = []
    result: object = None
    for _ in range(runs):
        started = time.perf_counter()
        result = action()
        times.append(time.perf_counter() - started)
    return min(times), result


# --- the contenders --------------------------------------------------------------------


def ours(path: Path, mode: str) -> Callable[[], object]:
    from skillwright.core import read_mcap

    def run() -> object:
        result = read_mcap(path, mode)  # type: ignore[arg-type]
        return result.message_count, len(result.channels), result.method

    return run


def ours_inventory(folder: Path) -> Callable[[], object]:
    from skillwright.interfaces.sources.bag import discover_bag

    def run() -> object:
        return len(discover_bag(folder).interfaces)

    return run


def python_mcap_summary(path: Path) -> Callable[[], object]:
    from mcap.reader import make_reader

    def run() -> object:
        with path.open("rb") as stream:
            summary = make_reader(stream).get_summary()
        assert summary is not None
        assert summary.statistics is not None
        return summary.statistics.message_count, len(summary.channels)

    return run


def python_mcap_scan(path: Path) -> Callable[[], object]:
    """Python ``mcap`` streaming every record (chunks decompressed), counting messages."""
    from mcap.exceptions import McapError
    from mcap.records import Channel, Message
    from mcap.stream_reader import StreamReader

    def run() -> object:
        counts: Counter[int] = Counter()
        channels = 0
        with path.open("rb") as stream:
            try:
                for record in StreamReader(stream).records:
                    if isinstance(record, Message):
                        counts[record.channel_id] += 1
                    elif isinstance(record, Channel):
                        channels += 1
            except (McapError, EOFError):
                pass  # the cut-off end of a file without summary
        return sum(counts.values()), channels

    return run


def rosbags_open(folder: Path) -> Callable[[], object]:
    from rosbags.rosbag2 import Reader

    def run() -> object:
        with Reader(folder) as reader:
            return reader.message_count, len(reader.connections)

    return run


def measure(label: str, runs: int, action: Callable[[], object]) -> float | None:
    try:
        seconds, result = best_of(runs, action)
    except Exception as error:  # a contender failing is a result too
        print(f"  {label:<48} failed: {type(error).__name__}: {error}"[:160])
        return None
    print(f"  {label:<48} {seconds * 1000:10.1f} ms   {result}")
    return seconds


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size-mb", type=int, default=1024, help="recording size (MB)")
    parser.add_argument("--keep", type=Path, help="generate into (and keep) this folder")
    args = parser.parse_args()

    root = args.keep or Path(tempfile.mkdtemp(prefix="skillwright-bench-mcap-"))
    try:
        with_summary = root / "with_summary"
        started = time.perf_counter()
        bag, messages = generate(with_summary, args.size_mb)
        print(
            f"generated {bag} ({bag.stat().st_size / 1e6:.0f} MB, {messages} messages, "
            f"{len(_topics())} topics, zstd) in {time.perf_counter() - started:.1f} s"
        )
        cut = cut_after_data_section(bag, root / "no_summary")
        print(f"cut copy without summary: {cut} ({cut.stat().st_size / 1e6:.0f} MB)\n")

        print("with summary (discovery of schemas, channels, counts):")
        t_ours = measure("skillwright read_mcap auto (summary path)", 20, ours(bag, "auto"))
        t_inv = measure(
            "skillwright discover_bag (whole inventory)", 5, ours_inventory(with_summary)
        )
        t_py = measure("python mcap get_summary()", 5, python_mcap_summary(bag))
        t_rb = measure("rosbags Reader open", 5, rosbags_open(with_summary))

        print("\nwithout summary (recorder killed; records must be scanned):")
        s_ours = measure("skillwright read_mcap scan (index-assisted)", 3, ours(cut, "scan"))
        s_full = measure("skillwright read_mcap full (every chunk inflated)", 2, ours(cut, "full"))
        s_py = measure("python mcap StreamReader, every record", 1, python_mcap_scan(cut))
        s_rb = measure("rosbags Reader open", 1, rosbags_open(root / "no_summary"))

        def ratio(other: float | None, mine: float | None) -> str:
            return f"{other / mine:8.1f}x" if other and mine else "     n/a"

        print("\nsummary")
        print(f"  {'comparison':<62} {'ratio':>9}")
        rows = [
            ("summary path vs python mcap get_summary()", t_py, t_ours),
            ("summary path vs rosbags Reader open", t_rb, t_ours),
            ("scan path vs python mcap iterating records", s_py, s_ours),
            ("full scan (all chunks inflated) vs python mcap iterating records", s_py, s_full),
            ("scan path vs rosbags on the file without summary", s_rb, s_ours),
        ]
        for label, other, mine in rows:
            print(f"  {label:<62} {ratio(other, mine):>9}")
        print(
            f"\n  summary path: {t_ours * 1000 if t_ours else float('nan'):.2f} ms "
            f"(target <= 50 ms); whole inventory: {t_inv * 1000 if t_inv else float('nan'):.1f} ms"
        )
        if s_py and s_ours:
            print(f"  scan path speed-up over python mcap: {s_py / s_ours:.1f}x (target >= 10x)")
    finally:
        if args.keep is None:
            shutil.rmtree(root, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
