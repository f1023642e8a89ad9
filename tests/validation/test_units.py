"""Angles in degrees and radians mixed up (check ``units``), on the paper's capabilities
(angles in degrees) and the MR-1's (radians)."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.capability.model import Capability
from skillwright.capability.reader import load_capability
from skillwright.validation.units import check_angle_units
from tests.validation.test_facts import facts_of
from tests.validation.test_loops import skill_facts

REPO = Path(__file__).resolve().parents[2]

HEAD = """class S:
    def _yaw(self) -> float:
        q = self.odom_msg.pose.pose.orientation
        return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))

"""


@pytest.fixture(scope="module")
def degrees(shared_data: Path) -> dict[str, Capability]:
    """The paper's capabilities: bearings and headings in degrees."""
    folder = shared_data / "cap2skill" / "capability-models"
    return {
        name: load_capability(folder / f"{name}.ttl").capability
        for name in ("rotate", "get-distance-to-nearest-object", "move-forward")
    }


@pytest.fixture(scope="module")
def radians() -> Capability:
    return load_capability(REPO / "capabilities" / "get-distance-to-nearest-object.ttl").capability


def _units(capability: Capability, method: str) -> list:
    return check_angle_units(skill_facts(HEAD, method, capability))


@pytest.mark.parametrize(
    ("body", "fix"),
    [
        (  # ev46-ev56: a bearing from the scan, in radians, reported as degrees
            "self.out_degree = scan.angle_min + scan.angle_increment * scan.ranges.index(d)",
            "self.out_degree = math.degrees(scan.angle_min + scan.angle_increment * "
            "scan.ranges.index(d))",
        ),
        (  # through a local variable
            "bearing = scan.angle_min + i * scan.angle_increment\nself.out_degree = bearing",
            "self.out_degree = math.degrees(bearing)",
        ),
        (  # ev31: a helper's yaw reported as degrees
            "self.out_degree = self._yaw()",
            "self.out_degree = math.degrees(self._yaw())",
        ),
        (  # the skeleton's nearest-reading helper gives its bearing in radians
            "distance, bearing = self._closest_reading(self.scan_msg)\nself.out_degree = bearing",
            "self.out_degree = math.degrees(bearing)",
        ),
        (
            "self.out_degree = self._closest_reading(self.scan_msg)[1]",
            "self.out_degree = math.degrees(self._closest_reading(self.scan_msg)[1])",
        ),
        (  # the helper's tuple kept whole, of both scanners of a split view, then indexed
            "closest = self._closest_reading(self.scan_msg, self.scan2_msg)\n"
            "self.out_distance = closest[0]\nself.out_degree = closest[1]",
            "self.out_degree = math.degrees(closest[1])",
        ),
    ],
)
def test_radians_stored_in_an_output_in_degrees_are_converted(
    degrees: dict[str, Capability], body: str, fix: str
) -> None:
    method = "def execute(self) -> None:\n" + "\n".join("    " + line for line in body.splitlines())
    [finding] = _units(degrees["get-distance-to-nearest-object"], method)
    assert (finding.check, finding.severity) == ("units", "error")
    assert "self.out_degree is in degrees" in finding.message
    assert "radians" in finding.message
    assert finding.replacement == fix


def test_degrees_and_radians_in_one_sum_are_put_in_the_capabilitys_unit(
    degrees: dict[str, Capability],
) -> None:
    # ev46-ev56 rotate: a target in degrees from the yaw in radians, then a loop comparing them
    method = """
    def execute(self) -> None:
        last_angle = self._yaw()
        self.out_degree = (self.in_degree + last_angle) % 360
        while abs(last_angle - self.out_degree) > 0.05:
            time.sleep(0.05)
            last_angle = self._yaw()
    """
    findings = _units(degrees["rotate"], method)
    assert [f.replacement for f in findings] == [
        "self.out_degree = (self.in_degree + math.degrees(last_angle)) % 360",
        "while abs(math.degrees(last_angle) - self.out_degree) > 0.05:\n"
        "    time.sleep(0.05)\n"
        "    last_angle = self._yaw()",
    ]
    assert "mixes degrees and radians" in findings[0].message
    assert "_yaw() returns radians" in findings[0].message


def test_a_quaternion_component_is_not_an_angle(degrees: dict[str, Capability]) -> None:
    # ev38-ev43: the rotation's z reported as the bearing in degrees
    method = """
    def execute(self) -> None:
        transform = self._transform("map", "base_link", 1.0)
        self.out_degree = transform.transform.rotation.z
    """
    [finding] = _units(degrees["get-distance-to-nearest-object"], method)
    assert "quaternion component" in finding.message
    assert "math.atan2" in finding.message
    assert finding.replacement is None


@pytest.mark.parametrize(
    ("body", "fix"),
    [
        (  # ev71 cap2skill collision avoidance: the old index formula fed the helper's range
            "self.out_degree = math.degrees(self.scan_msg.angle_min + "
            "self.scan_msg.angle_increment * self._closest_reading(self.scan_msg)[0])",
            "self.out_degree = math.degrees(self._closest_reading(self.scan_msg)[1])",
        ),
        (  # the same left in radians: the bearing replaces the formula, then is converted
            "self.out_degree = self.scan_msg.angle_min + "
            "self._closest_reading(self.scan_msg)[0] * self.scan_msg.angle_increment",
            "self.out_degree = math.degrees(self._closest_reading(self.scan_msg)[1])",
        ),
        (  # without the start angle
            "angle = self.scan_msg.angle_increment * self._closest_reading(self.scan_msg)[0]\n"
            "self.out_degree = math.degrees(angle)",
            "angle = self._closest_reading(self.scan_msg)[1]",
        ),
        (  # through a local: said, not fixed
            "distance, bearing = self._closest_reading(self.scan_msg)\n"
            "self.out_degree = math.degrees(self.scan_msg.angle_increment * distance)",
            None,
        ),
    ],
)
def test_an_angle_times_the_nearest_distance_is_no_bearing(
    degrees: dict[str, Capability], body: str, fix: str | None
) -> None:
    method = "def execute(self) -> None:\n" + "\n".join("    " + line for line in body.splitlines())
    [finding] = _units(degrees["get-distance-to-nearest-object"], method)
    assert "multiplies an angle by a distance" in finding.message
    assert "not the index of a reading" in finding.message
    assert finding.replacement == fix
    if fix is None:
        assert "self._closest_reading(scan)[1]" in finding.message


def test_a_distance_stored_as_an_angle_is_found(degrees: dict[str, Capability]) -> None:
    method = """
    def execute(self) -> None:
        self.out_degree = self._closest_reading(self.scan_msg)[0]
    """
    [finding] = _units(degrees["get-distance-to-nearest-object"], method)
    assert "self.out_degree is an angle in degrees" in finding.message
    assert "is a distance in metres" in finding.message
    assert finding.replacement is None


@pytest.mark.parametrize(
    "body",
    [
        "self.out_degree = math.degrees(scan.angle_min + i * scan.angle_increment)",
        "self.out_degree = (scan.angle_min + i * scan.angle_increment) * 180 / math.pi",
        "self.out_degree = self._yaw() * 57.29578",
        "target = math.radians(self.in_degree) + self._yaw()\nwhile abs(self._yaw() - target) > 0.01:\n    pass",
        "self.out_degree = i * 360 / len(scan.ranges)",  # no evident unit: nothing guessed
        "self.out_degree = (self.in_degree + 90) % 360",
        "self.out_distance = min(scan.ranges)",
        "distance, bearing = self._closest_reading(self.scan_msg)\n"
        "self.out_distance = distance\nself.out_degree = math.degrees(bearing)",
        "self.out_distance = self._closest_reading(self.scan_msg)[0]",
        "distance, bearing = self._closest_reading(self.scan_msg)\n"
        "if distance < 0.5 and abs(bearing) < 0.3:\n    pass",
        "self.out_distance = self._closest_reading(self.scan_msg)[0] * 1.0",
        "self.out_distance, bearing = self._closest_reading(self.scan_msg)\n"
        "self.out_degree = math.degrees(bearing)",
    ],
)
def test_consistent_or_unknown_units_are_left_alone(
    degrees: dict[str, Capability], body: str
) -> None:
    method = "def execute(self) -> None:\n" + "\n".join("    " + line for line in body.splitlines())
    assert (
        _units(degrees["get-distance-to-nearest-object"], method)
        + _units(degrees["rotate"], method)
        == []
    )


@pytest.mark.parametrize(
    ("body", "fix", "said"),
    [
        (  # the evaluation at d678df9, cap2skill get-distance: distance and bearing swapped
            "self.out_degree, self.out_distance = "
            "self._closest_reading(self.scan_msg, self.scan2_msg)",
            "self.out_distance, bearing = self._closest_reading(self.scan_msg, self.scan2_msg)\n"
            "self.out_degree = math.degrees(bearing)",
            "self.out_degree is an angle in degrees",
        ),
        (  # the right order, but the bearing kept in radians
            "self.out_distance, self.out_degree = self._closest_reading(self.scan_msg)",
            "self.out_distance, bearing = self._closest_reading(self.scan_msg)\n"
            "self.out_degree = math.degrees(bearing)",
            "self.out_degree is in degrees",
        ),
    ],
)
def test_the_helpers_tuple_unpacked_into_outputs_puts_the_bearing_in_the_angle(
    degrees: dict[str, Capability], body: str, fix: str, said: str
) -> None:
    method = "def execute(self) -> None:\n    " + body
    [finding] = _units(degrees["get-distance-to-nearest-object"], method)
    assert said in finding.message
    assert finding.replacement == fix


def test_the_swapped_tuple_into_an_output_in_radians_only_swaps(radians: Capability) -> None:
    method = """
    def execute(self) -> None:
        self.out_angle, self.out_distance = self._closest_reading(self.scan_msg)
    """
    [finding] = _units(radians, method)
    assert finding.replacement == (
        "self.out_distance, self.out_angle = self._closest_reading(self.scan_msg)"
    )


def test_degrees_stored_in_an_output_in_radians_are_converted(radians: Capability) -> None:
    method = """
    def execute(self) -> None:
        self.out_angle = math.degrees(scan.angle_min + i * scan.angle_increment)
    """
    [finding] = _units(radians, method)
    assert finding.replacement == (
        "self.out_angle = math.radians(math.degrees(scan.angle_min + i * scan.angle_increment))"
    )


def test_a_capability_without_angles_is_not_checked(degrees: dict[str, Capability]) -> None:
    method = """
    def execute(self) -> None:
        x = self._yaw() + math.degrees(1.0)
    """
    assert _units(degrees["move-forward"], method) == []


@pytest.mark.parametrize(
    "skill", sorted((REPO / "capabilities" / "skills").glob("*.py")), ids=lambda p: p.stem
)
def test_the_shipped_skills_pass(skill: Path) -> None:
    model = REPO / "capabilities" / f"{skill.stem.replace('_', '-')}.ttl"
    capability = load_capability(model).capability
    assert check_angle_units(facts_of(skill.read_text(), capability=capability)) == []
