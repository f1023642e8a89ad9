"""The model's behaviour goes into the skeleton; the skeleton's structure always stays."""

from __future__ import annotations

import ast
import textwrap

import pytest

from skillwright.generation.examples import few_shot_examples
from skillwright.generation.merge import merge_into_skeleton
from skillwright.generation.model import Skeleton
from skillwright.generation.skeleton import build_skeleton
from tests.generation.test_skeleton import CMD_VEL, ODOM, shipped

STATES = ["starting", "execute", "completing", "stopping", "resetting"]


@pytest.fixture(scope="module")
def skeleton() -> Skeleton:
    capability, spec = shipped("set-velocity")
    assert list(spec.states) == STATES
    return build_skeleton(capability, spec, [CMD_VEL, ODOM])


def merge(skeleton: Skeleton, model_code: str):  # type: ignore[no-untyped-def]
    return merge_into_skeleton(skeleton.code, skeleton.class_name, STATES, model_code)


def method(code: str, name: str) -> ast.FunctionDef:
    tree = ast.parse(code)
    cls = next(n for n in tree.body if isinstance(n, ast.ClassDef))
    return next(n for n in cls.body if isinstance(n, ast.FunctionDef) and n.name == name)


def test_merging_the_skeleton_into_itself_changes_nothing(skeleton: Skeleton) -> None:
    merged = merge(skeleton, skeleton.code)
    assert merged is not None
    assert merged.code == skeleton.code
    assert merged.written == ()
    assert merged.missing == tuple(STATES)


def test_a_complete_skill_contributes_every_state_its_helpers_and_imports(
    skeleton: Skeleton,
) -> None:
    example = next(e for e in few_shot_examples() if e.code_path.stem == "set_velocity")
    merged = merge_into_skeleton(
        skeleton.code, skeleton.class_name, STATES, example.code, author="model-x"
    )
    assert merged is not None
    assert "Behaviour: written by model-x" in merged.code
    assert merged.written == tuple(STATES)
    assert merged.missing == ()
    assert {"helper _clip", "helper _publish_zero", "import time"} <= set(merged.added)
    assert "attribute self.command_timer" in merged.added
    assert "NotImplementedError" not in merged.code
    assert "self._clip(self.in_linear_velocity" in ast.unparse(method(merged.code, "execute"))


def test_the_skeleton_decorator_class_name_and_getters_survive_a_model_that_changed_them(
    skeleton: Skeleton,
) -> None:
    model = textwrap.dedent(
        """
        @skill(skill_iri="http://example.org/guessed", capability_iri="http://x")
        class Renamed(ROS2Skill):
            @skill_parameter(is_required=True, name="speed", description="made up")
            def get_speed(self) -> float:
                return 1.0

            @execute
            def execute(self) -> None:
                self.out_linear_velocity = 0.5

            @holding
            def holding(self) -> None:
                self.node.get_logger().info("holding")
        """
    )
    merged = merge(skeleton, model)
    assert merged is not None
    assert "http://example.org/guessed" not in merged.code
    assert f"class {skeleton.class_name}(ROS2Skill)" in merged.code
    assert 'name="speed"' not in merged.code
    assert merged.written == ("execute",)
    assert any(item.startswith("state holding") for item in merged.left_out)
    assert any(item.startswith("getter get_speed") for item in merged.left_out)
    assert "def holding" not in merged.code


def test_handles_the_model_forgot_to_create_are_kept_in_front_of_its_code(
    skeleton: Skeleton,
) -> None:
    model = textwrap.dedent(
        """
        class SetVelocitySkill(ROS2Skill):
            @starting
            def starting(self) -> None:
                self.node.get_logger().info("starting")
        """
    )
    merged = merge(skeleton, model)
    assert merged is not None
    body = method(merged.code, "starting").body
    created = [ast.unparse(s) for s in body if "create_" in ast.unparse(s)]
    assert len(created) == 2
    assert "get_logger" in ast.unparse(body[-1])


def test_a_state_the_model_left_as_a_placeholder_counts_as_missing(skeleton: Skeleton) -> None:
    model = textwrap.dedent(
        """
        class SetVelocitySkill(ROS2Skill):
            @execute
            def execute(self) -> None:
                \"\"\"Does it.\"\"\"
                pass

            @stopping
            def stopping(self) -> None:
                ...
        """
    )
    merged = merge(skeleton, model)
    assert merged is not None
    assert "execute" in merged.missing
    assert "stopping" in merged.missing
    assert "NotImplementedError" in ast.unparse(method(merged.code, "execute"))


def test_module_level_helpers_and_new_attributes_are_taken(skeleton: Skeleton) -> None:
    model = textwrap.dedent(
        """
        import math

        def clamp(value, limit):
            return max(-limit, min(limit, value))

        class SetVelocitySkill(ROS2Skill):
            def __init__(self) -> None:
                super().__init__("set_velocity")
                self.in_linear_velocity = 3.0
                self.started_at = None

            @execute
            def execute(self) -> None:
                self.out_linear_velocity = clamp(self.in_linear_velocity, math.inf)
        """
    )
    merged = merge(skeleton, model)
    assert merged is not None
    assert "import math" in merged.code
    assert "def clamp(value, limit):" in merged.code
    init = ast.unparse(method(merged.code, "__init__"))
    assert "self.started_at = None" in init
    assert "self.in_linear_velocity = 3.0" not in init
    assert "self.in_linear_velocity: float = 0.0" in init


def test_code_that_does_not_parse_cannot_be_merged(skeleton: Skeleton) -> None:
    assert merge(skeleton, "class A(:\n    pass\n") is None


def test_code_without_a_skill_class_cannot_be_merged(skeleton: Skeleton) -> None:
    assert merge(skeleton, "import rclpy\nprint('hello')\n") is None
