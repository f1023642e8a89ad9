"""Types of the simulated graph: the inventory's first, then the standard store."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.interfaces.inventory import Inventory
from skillwright.interfaces.load import discover_path
from skillwright.interfaces.ros2msg import BUILTIN_TYPES
from skillwright.runtime.typesys import TypeRegistry, is_zero_motion


@pytest.fixture(scope="module")
def registry(mr1_inventory: Inventory) -> TypeRegistry:
    return TypeRegistry(mr1_inventory)


def test_messages_of_the_inventory_and_their_nested_types_are_known(registry: TypeRegistry) -> None:
    twist = registry.describe("geometry_msgs/msg/Twist")
    assert twist["ok"]
    assert [f[0] for f in twist["fields"]] == ["linear", "angular"]
    assert registry.describe("geometry_msgs/msg/Vector3")["ok"]


def test_services_and_actions_are_described_by_their_parts(registry: TypeRegistry) -> None:
    assert registry.describe("nav2_msgs/srv/SaveMap")["parts"] == {
        "Request": "nav2_msgs/srv/SaveMap_Request",
        "Response": "nav2_msgs/srv/SaveMap_Response",
    }
    parts = registry.describe("nav2_msgs/action/NavigateToPose")["parts"]
    assert set(parts) == {"Goal", "Result", "Feedback"}


def test_standard_types_outside_the_inventory_come_from_the_store_with_constants(
    registry: TypeRegistry,
) -> None:
    status = registry.describe("action_msgs/msg/GoalStatus")
    assert status["ok"]
    assert ["STATUS_SUCCEEDED", 4] in status["constants"]
    assert registry.has_package("std_msgs")


def test_an_unknown_type_is_refused_with_a_reason(registry: TypeRegistry) -> None:
    answer = registry.describe("nav2_msgs/action/DockRobot")
    assert not answer["ok"]
    assert "the robot has no type nav2_msgs/action/DockRobot" in answer["error"]
    assert not registry.has_package("acme_msgs")


def test_defaults_fill_every_field(registry: TypeRegistry) -> None:
    odom = registry.default("nav_msgs/msg/Odometry")
    assert odom["header"] == {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": ""}
    assert odom["pose"]["covariance"] == [0.0] * 36
    assert odom["twist"]["twist"]["angular"] == {"x": 0.0, "y": 0.0, "z": 0.0}


def test_a_type_is_described_with_every_type_it_is_made_of(registry: TypeRegistry) -> None:
    action = registry.describe_with_nested("moveit_msgs/action/MoveGroup")
    nested = action["nested"]
    assert {"moveit_msgs/action/MoveGroup_Goal", "moveit_msgs/msg/MotionPlanRequest"} <= set(nested)
    assert "std_msgs/msg/Header" in nested
    assert all(answer["ok"] for answer in nested.values())
    for answer in nested.values():
        for spec in answer.get("fields", []):
            assert spec[1] in nested or spec[1] in BUILTIN_TYPES, spec
    assert "nested" not in registry.describe_with_nested("std_msgs/msg/String")
    assert registry.describe_with_nested("acme_msgs/msg/Nothing")["ok"] is False


def test_packages_are_those_of_known_types(registry: TypeRegistry) -> None:
    packages = registry.packages()
    assert {"geometry_msgs", "nav2_msgs", "moveit_msgs", "std_msgs"} <= set(packages)
    assert "rclpy" not in packages
    assert all(registry.has_package(p) for p in packages)


def test_conform_fills_missing_fields_and_turns_integers_into_floats(
    registry: TypeRegistry,
) -> None:
    twist = registry.conform("geometry_msgs/msg/Twist", {"linear": {"x": 1}})
    assert twist == {
        "linear": {"x": 1.0, "y": 0.0, "z": 0.0},
        "angular": {"x": 0.0, "y": 0.0, "z": 0.0},
    }
    assert isinstance(twist["linear"]["x"], float)


@pytest.mark.parametrize(
    ("value", "problem"),
    [
        ({"linear": {"w": 1.0}}, "Vector3 has no field 'w'"),
        ({"linear": {"x": "fast"}}, "expected a number"),
        ({"linear": [1.0]}, "expected a geometry_msgs/msg/Vector3 message"),
        ([], "expected a geometry_msgs/msg/Twist message"),
    ],
)
def test_conform_names_the_field_that_does_not_fit(
    registry: TypeRegistry, value: object, problem: str
) -> None:
    with pytest.raises(ValueError, match=problem):
        registry.conform("geometry_msgs/msg/Twist", value)


def test_conform_checks_array_sizes(registry: TypeRegistry) -> None:
    with pytest.raises(ValueError, match=r"covariance: expected 36 elements, got 2"):
        registry.conform("geometry_msgs/msg/PoseWithCovariance", {"covariance": [0.0, 1.0]})


def test_conform_takes_a_large_array_whole_and_still_names_a_bad_element(
    registry: TypeRegistry,
) -> None:
    cells = [-1, 0, 100] * 40_000
    grid = registry.conform("nav_msgs/msg/OccupancyGrid", {"data": cells})
    assert grid["data"] == cells
    assert grid["data"] is not cells
    scan = registry.conform("sensor_msgs/msg/LaserScan", {"ranges": [1, 2.5, float("inf")]})
    assert scan["ranges"] == [1.0, 2.5, float("inf")]
    assert all(isinstance(r, float) for r in scan["ranges"])
    with pytest.raises(ValueError, match=r"data\[5\]: expected an integer \(int8\), got bool"):
        registry.conform("nav_msgs/msg/OccupancyGrid", {"data": [0, 0, 0, 0, 0, True]})
    with pytest.raises(ValueError, match=r"ranges\[1\]: expected a number \(float32\), got str"):
        registry.conform("sensor_msgs/msg/LaserScan", {"ranges": [1.0, "far"]})


@pytest.mark.parametrize(
    ("message", "zero"),
    [
        (
            {"linear": {"x": 0.0, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.0}},
            True,
        ),
        (
            {"linear": {"x": 0.0, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.2}},
            False,
        ),
        ({"header": {"stamp": {"sec": 5, "nanosec": 1}}, "twist": {"linear": {"x": 0.0}}}, True),
    ],
)
def test_zero_motion_means_every_velocity_is_zero(message: dict[str, object], zero: bool) -> None:
    assert is_zero_motion(message) is zero


_SLAM_NAV2 = Path(__file__).resolve().parents[1] / "fixtures" / "slam_nav2_report.json"


@pytest.fixture(scope="module")
def slam_nav2() -> Inventory:
    return discover_path(_SLAM_NAV2)


@pytest.fixture(scope="module")
def base_only(slam_nav2: Inventory) -> TypeRegistry:
    """The paper robot without its SLAM Toolbox and Nav2 interfaces."""
    kept = [
        i
        for i in slam_nav2.interfaces
        if not i.name.startswith(("/slam_toolbox/", "/navigate_to_pose"))
    ]
    return TypeRegistry(slam_nav2.model_copy(update={"interfaces": kept}))


def test_a_core_service_is_standard_without_the_inventory_defining_it(
    base_only: TypeRegistry,
) -> None:
    answer = base_only.describe("nav_msgs/srv/GetMap")
    assert answer["ok"], answer
    assert answer["parts"] == {
        "Request": "nav_msgs/srv/GetMap_Request",
        "Response": "nav_msgs/srv/GetMap_Response",
    }
    grid = base_only.default("nav_msgs/srv/GetMap_Response")["map"]
    assert set(grid) == {"header", "info", "data"}
    assert base_only.describe("std_srvs/srv/SetBool")["ok"]
    assert base_only.describe("action_msgs/srv/CancelGoal")["ok"]


@pytest.mark.parametrize("name", ["nav2_msgs/action/NavigateToPose", "slam_toolbox/srv/SaveMap"])
def test_navigation_stack_types_are_not_standard(base_only: TypeRegistry, name: str) -> None:
    answer = base_only.describe(name)
    assert not answer["ok"]
    assert answer["error"] == (
        f"the robot has no type {name}: it is not among its interfaces' definitions nor a "
        "standard ROS 2 Jazzy type"
    )


@pytest.mark.parametrize(
    ("name", "parts"),
    [
        ("nav2_msgs/action/NavigateToPose", {"Goal", "Result", "Feedback"}),
        ("slam_toolbox/srv/SaveMap", {"Request", "Response"}),
        ("slam_toolbox/srv/SerializePoseGraph", {"Request", "Response"}),
    ],
)
def test_the_slam_nav2_inventory_defines_its_navigation_stack_types(
    slam_nav2: Inventory, name: str, parts: set[str]
) -> None:
    registry = TypeRegistry(slam_nav2)
    answer = registry.describe(name)
    assert answer["ok"], answer
    assert set(answer["parts"]) == parts
    goal = registry.message("nav2_msgs/action/NavigateToPose_Goal")
    assert goal is not None
    assert [f.name for f in goal.fields] == ["pose", "behavior_tree"]
    result = registry.message("slam_toolbox/srv/SaveMap_Response")
    assert result is not None
    assert ("RESULT_SUCCESS", 0) in result.constants
