"""The shipped MR-1 recording is exactly what its script makes."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.conftest import SHIPPED_CAPABILITIES

RECORDINGS = SHIPPED_CAPABILITIES / "recordings"


def test_make_recording_reproduces_the_shipped_bag_byte_for_byte(tmp_path: Path) -> None:
    subprocess.run(
        [sys.executable, str(RECORDINGS / "make_recording.py"), str(tmp_path / "mr1")],
        check=True,
        capture_output=True,
        timeout=300,
    )
    for name in ("mr1_0.mcap", "metadata.yaml"):
        made = (tmp_path / "mr1" / name).read_bytes()
        assert made == (RECORDINGS / "mr1" / name).read_bytes(), name
