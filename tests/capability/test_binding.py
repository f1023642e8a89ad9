"""Binding a skill's annotations to its capability by name, by meaning, or as told."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from skillwright.capability import load_capability
from skillwright.capability.binding import Annotation, bind, targets
from skillwright.capability.model import Capability
from tests.conftest import SHARED, SHIPPED_CAPABILITIES

CAP2SKILL = SHARED / "data" / "cap2skill"


def _capability(stem: str) -> Capability:
    return load_capability(SHIPPED_CAPABILITIES / f"{stem}.ttl").capability


def _pairs(binding) -> dict[str, str]:  # type: ignore[no-untyped-def]
    return {b.annotation: b.target for b in binding.bound}


def test_the_capability_s_own_names_bind_by_name() -> None:
    capability = _capability("move-forward")
    annotations = [
        Annotation("inDistance", "input"),
        Annotation("in_linear_velocity", "input"),
        Annotation("outDistance", "output"),
    ]
    binding = bind(annotations, capability)
    assert _pairs(binding) == {
        "inDistance": "inDistance",
        "in_linear_velocity": "inLinearVelocity",
        "outDistance": "outDistance",
    }
    assert {b.how for b in binding.bound} == {"name"}
    assert binding.unbound == ["outLinearVelocity"]


def test_other_names_bind_by_the_quantity_unit_and_axis_they_speak_of() -> None:
    capability = _capability("move-to-point")
    names = {t.name for t in targets(capability)}
    assert {"inPositionX", "inPositionY", "inPositionZ"} <= names
    binding = bind(
        [
            Annotation("goal_z", "input", "Height of the goal position in metres."),
            Annotation("goal_x", "input", "The x coordinate of the goal position."),
            Annotation("goal_y", "input", "The y coordinate of the goal position."),
        ],
        capability,
    )
    assert _pairs(binding) == {
        "goal_x": "inPositionX",
        "goal_y": "inPositionY",
        "goal_z": "inPositionZ",
    }
    assert {b.how for b in binding.bound} == {"meaning"}


def test_a_parameter_binds_to_an_input_never_to_an_output() -> None:
    binding = bind(
        [Annotation("travelled", "input", "distance travelled")], _capability("move-forward")
    )
    assert _pairs(binding) == {"travelled": "inDistance"}


def test_what_the_words_cannot_settle_is_left_unbound_with_its_candidates() -> None:
    capability = _capability("collision-avoidance")
    binding = bind([Annotation("velocity", "input", "the speed to drive at")], capability)
    assert binding.bound == []
    assert binding.ambiguous["velocity"] == ["inLinearVelocityX", "inLinearVelocityY"]
    told = bind(
        [Annotation("velocity", "input", "the speed to drive at")],
        capability,
        explicit={"velocity": "inLinearVelocityX"},
    )
    assert _pairs(told) == {"velocity": "inLinearVelocityX"}
    assert told.bound[0].how == "explicit"


def test_an_annotation_that_means_nothing_of_the_capability_is_unknown() -> None:
    binding = bind(
        [Annotation("battery_level", "output", "charge in percent")], _capability("rotate")
    )
    assert binding.bound == []
    assert binding.unknown == ["battery_level"]


def _annotations(path: Path) -> list[Annotation]:
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if not isinstance(node, ast.FunctionDef):
            continue
        for decorator in node.decorator_list:
            if not (isinstance(decorator, ast.Call) and isinstance(decorator.func, ast.Name)):
                continue
            if decorator.func.id not in {"skill_parameter", "skill_output"}:
                continue
            words = {
                k.arg: k.value.value
                for k in decorator.keywords
                if isinstance(k.value, ast.Constant)
            }
            direction = "input" if decorator.func.id == "skill_parameter" else "output"
            found.append(
                Annotation(str(words["name"]), direction, str(words.get("description", "")))
            )
    return found


CORPUS = {
    "reference/move_forward": {
        "distance": "inDistance",
        "duration": "inTime",
        "traveled_distance": "outDistance",
        "time_needed": "outTime",
        "robot_velocity": "outVelocity",
    },
    "reference/rotate": {
        "target_degrees": "inDegree",
        "target_angular_speed": "inVelocity",
        "robot_orientation": "outDegree",
    },
    "reference/navigate_to_point": {
        "goal_position_x": "inPositionX",
        "goal_position_y": "inPositionY",
        "robot_position_x": "outPositionX",
        "robot_position_y": "outPositionY",
    },
    "reference/mapping": {
        "area_length_x": "inDistance_X",
        "area_length_y": "inDistance_Y",
        "generated_map": "outMap",
    },
    "gpt-4o/move_forward": {
        "desired_distance": "inDistance",
        "desired_time": "inTime",
        "elapsed_time": "outTime",
        "output_velocity": "outVelocity",
        "traveled_distance": "outDistance",
    },
}
"""What the paper's authors' skills and its method's mean by their annotations, read off the
skills' descriptions and code."""


@pytest.mark.parametrize("skill", sorted(CORPUS))
def test_the_paper_s_skills_bind_to_its_capability_models(skill: str) -> None:
    if not CAP2SKILL.is_dir():
        pytest.skip("../shared is not beside the repository")
    path = CAP2SKILL / "skill-implementations" / f"{skill}.py"
    stem = path.stem.replace("_", "-")
    capability = load_capability(CAP2SKILL / "capability-models" / f"{stem}.ttl").capability
    binding = bind(_annotations(path), capability)
    assert _pairs(binding) == CORPUS[skill]
    assert binding.ambiguous == {}
    assert binding.unknown == []


def test_the_paper_s_collision_avoidance_lacks_one_input_and_says_so() -> None:
    """The paper rates its annotations partial: one of the four inputs has no parameter."""
    if not CAP2SKILL.is_dir():
        pytest.skip("../shared is not beside the repository")
    path = CAP2SKILL / "skill-implementations" / "gpt-4o" / "collision_avoidance.py"
    capability = load_capability(
        CAP2SKILL / "capability-models" / "collision-avoidance.ttl"
    ).capability
    assert bind(_annotations(path), capability).unbound == ["inObstacleDistance"]
