"""A state that gives up sooner than its specification allows."""

from __future__ import annotations

import pytest

from skillwright.rules.finding import Finding
from skillwright.spec.model import SkillSpec
from skillwright.validation.grace import check_grace, stated_seconds
from tests.validation.test_facts import facts_of


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            "Check that SLAM publishes the map; abort if any is missing after 5 s. Record it.",
            (5.0, "abort if any is missing after 5 s."),
        ),
        (
            "Create the client and wait at most 5 s for the server; abort otherwise.",
            (5.0, "Create the client and wait at most 5 s for the server;"),
        ),
        ("Wait for the next scan, at most 2 s, and abort if none arrives.", (2.0, None)),
        ("Drive forward for 10 s, then stop.", None),
        ("If the speed has not settled after 5 s, publish zero and abort.", None),
        ("Wait at most 2 s for odometry. Wait at most 5 s for the server.", None),
    ],
)
def test_the_seconds_a_state_gives_its_interfaces_are_read_from_one_sentence(
    text: str, expected: tuple[float, str | None] | None
) -> None:
    found = stated_seconds(text)
    if expected is None or expected[1] is None:
        assert (found and found[0]) == (expected and expected[0])
    else:
        assert found == expected


SKILL = '''
class Skill:
    def _wait_until(self, condition, timeout: float, what: str) -> None:
        """Waits."""
    @starting
    def starting(self) -> None:
        self.client = ActionClient(self.node, NavigateToPose, "/navigate_to_pose")
        self._wait_until(lambda: self.map_msg is not None, {map_wait}, "map")
        self._wait_until(lambda: self.ready, 1.0, "ready")
        if not self.client.wait_for_server(timeout_sec={server_wait}):
            raise RuntimeError("no server")
'''


def _grace(map_wait: float, server_wait: float, text: str) -> list[Finding]:
    source = SKILL.format(map_wait=map_wait, server_wait=server_wait)
    spec = SkillSpec(
        name="skill", description="", skill_interface="REST", states={"starting": text}
    )
    return check_grace(facts_of(source, spec=spec))


def test_waits_for_a_first_message_or_a_server_shorter_than_the_spec_are_lengthened() -> None:
    found = _grace(2.0, 1.0, "Abort if the map or Nav2 is missing after 5 s.")
    assert [(f.line, f.check, f.severity) for f in found] == [
        (8, "waits", "error"),
        (10, "waits", "error"),
    ]
    assert found[0].message == (
        'starting gives up after 2 s where its specification allows 5 s ("Abort if the map or '
        'Nav2 is missing after 5 s."): a robot that answers later is refused; wait 5 s'
    )
    assert found[0].replacement == "self._wait_until(lambda: self.map_msg is not None, 5.0, 'map')"
    assert found[1].replacement is not None
    assert "wait_for_server(timeout_sec=5.0)" in found[1].replacement


@pytest.mark.parametrize(
    ("map_wait", "server_wait", "text"),
    [
        (5.0, 10.0, "Abort if the map or Nav2 is missing after 5 s."),
        (2.0, 1.0, "Subscribe to the map and create the client."),
        (2.0, 1.0, "Abort if the map is missing after 5 s, or Nav2 after 8 s."),
    ],
    ids=["long-enough", "no-seconds-stated", "two-numbers"],
)
def test_waits_the_spec_does_not_bound_are_left_alone(
    map_wait: float, server_wait: float, text: str
) -> None:
    assert _grace(map_wait, server_wait, text) == []
