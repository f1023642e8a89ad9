"""run_skill: the shipped MR-1 skills run clean; inputs, scenarios, progress and cancel."""

from __future__ import annotations

import math
import threading
from pathlib import Path

import pytest

from skillwright.errors import GenerationCancelledError, InvalidArgumentError
from skillwright.interfaces.inventory import Inventory
from skillwright.runtime import sandbox
from skillwright.runtime.report import RunProgress, RunReport
from skillwright.runtime.run import run_skill
from skillwright.runtime.sandbox import SandboxProcess
from skillwright.runtime.scenario import ActionScript, load_scenario
from tests.runtime.conftest import SKILLS, quick, skill_path

SHIPPED = sorted(p for p in SKILLS.glob("*.py"))


def test_the_nine_mr1_capabilities_have_a_skill_and_a_scenario() -> None:
    specs = sorted(
        p.name.removesuffix(".spec.yaml").replace("-", "_")
        for p in SKILLS.parent.glob("*.spec.yaml")
    )
    assert [p.stem for p in SHIPPED] == specs
    assert all(p.with_suffix(".scenario.yaml").is_file() for p in SHIPPED)


@pytest.mark.parametrize("skill", SHIPPED, ids=lambda p: p.stem)
def test_shipped_skill_runs_clean(skill: Path, mr1_inventory: Inventory) -> None:
    scenario = load_scenario(skill.with_suffix(".scenario.yaml"))

    report = run_skill(skill, mr1_inventory, scenario=scenario)

    assert report.findings == []
    normal = report.trace.episodes[0]
    ran = [(s.name, s.outcome) for s in normal.states if s.outcome != "absent"]
    assert ran == [(name, "done") for name in ("starting", "execute", "completing", "resetting")]
    for episode in report.trace.episodes[1:]:
        assert episode.name == "stop"
        assert ("execute", "interrupted", "stop") in [
            (s.name, s.outcome, s.detail) for s in episode.states
        ]


def _outputs(name: str, inventory: Inventory) -> dict[str, float]:
    skill = skill_path(name)
    scenario = load_scenario(skill.with_suffix(".scenario.yaml")).model_copy(
        update={"stop_run": "never"}
    )
    report = run_skill(skill, inventory, scenario=scenario)
    assert report.passed, report.findings
    return report.trace.episodes[0].outputs


def test_move_forward_covers_the_distance_within_the_capability_tolerance(
    mr1_inventory: Inventory,
) -> None:
    outputs = _outputs("move_forward", mr1_inventory)
    assert abs(outputs["outDistance"] - 0.5) <= 0.02
    assert outputs["outLinearVelocity"] == pytest.approx(0.0, abs=0.01)


def test_rotate_reaches_the_heading_a_quarter_turn_away(mr1_inventory: Inventory) -> None:
    outputs = _outputs("rotate", mr1_inventory)
    assert outputs["outHeading"] == pytest.approx(math.pi / 2, abs=0.02)


def test_move_to_point_reports_where_the_arm_went(mr1_inventory: Inventory) -> None:
    outputs = _outputs("move_to_point", mr1_inventory)
    assert (
        outputs["outPositionX"],
        outputs["outPositionY"],
        outputs["outPositionZ"],
    ) == pytest.approx((0.5, 0.1, 0.4), abs=0.01)


def test_run_reports_progress_of_every_state(mr1_inventory: Inventory) -> None:
    seen: list[RunProgress] = []

    run_skill(skill_path("get_position"), mr1_inventory, scenario=quick(), on_progress=seen.append)

    events = [(p.event, p.state) for p in seen]
    assert events[0] == ("episode-start", None)
    assert ("state-end", "execute") in events
    assert events[-1] == ("episode-end", None)


def test_a_rejected_goal_meets_a_scenario_that_expects_an_abort(mr1_inventory: Inventory) -> None:
    scenario = quick(
        inputs={"inPositionX": 1.0, "inPositionY": 0.0},
        actions={"/navigate_to_pose": ActionScript(accept=False)},
        expect="abort",
    )

    report = run_skill(skill_path("navigate_to_point"), mr1_inventory, scenario=scenario)

    assert report.findings == []
    outcomes = {s.name: s.outcome for s in report.trace.episodes[0].states}
    assert outcomes["execute"] == "raised"
    assert any(
        e["kind"] == "goal_response" and e["accepted"] is False
        for e in report.trace.episodes[0].events
    )


def test_a_skill_that_completes_where_the_scenario_expects_an_abort_is_reported(
    mr1_inventory: Inventory,
) -> None:
    report = run_skill(skill_path("get_position"), mr1_inventory, scenario=quick(expect="abort"))

    assert [f.check for f in report.findings] == ["run.expectation"]


def test_missing_inputs_are_an_error_naming_them(mr1_inventory: Inventory) -> None:
    with pytest.raises(InvalidArgumentError, match="inDistance, inLinearVelocity"):
        run_skill(skill_path("move_forward"), mr1_inventory, scenario=quick())


def test_unknown_inputs_are_an_error_naming_the_skills_inputs(mr1_inventory: Inventory) -> None:
    with pytest.raises(InvalidArgumentError, match=r"no input 'inSpeed'.*inDistance"):
        run_skill(
            skill_path("move_forward"), mr1_inventory, inputs={"inSpeed": 1.0}, scenario=quick()
        )


def test_a_scenario_naming_an_interface_the_robot_lacks_is_an_error(
    mr1_inventory: Inventory,
) -> None:
    scenario = quick(actions={"/navigate": ActionScript()})
    with pytest.raises(InvalidArgumentError, match="action /navigate"):
        run_skill(skill_path("get_position"), mr1_inventory, scenario=scenario)


def test_a_file_without_a_skill_is_a_finding_not_a_run(
    mr1_inventory: Inventory, tmp_path: Path
) -> None:
    path = tmp_path / "broken.py"
    path.write_text("def execute(:\n", encoding="utf-8")

    report = run_skill(path, mr1_inventory)

    assert [(f.check, f.line) for f in report.findings] == [("run.syntax", 1)]
    assert report.trace.episodes == []


def test_cancelling_kills_the_run_and_leaves_nothing(
    mr1_inventory: Inventory, monkeypatch: pytest.MonkeyPatch
) -> None:
    cancel = threading.Event()
    children: list[SandboxProcess] = []
    real_fork = sandbox.ForkServer.fork

    def fork(server: sandbox.ForkServer) -> SandboxProcess:
        children.append(real_fork(server))
        return children[-1]

    def on_progress(progress: RunProgress) -> None:
        if progress.event == "state-start" and progress.state == "execute":
            cancel.set()

    monkeypatch.setattr(sandbox.ForkServer, "fork", fork)
    with pytest.raises(GenerationCancelledError):
        run_skill(
            skill_path("navigate_to_point"),
            mr1_inventory,
            inputs={"inPositionX": 2.0, "inPositionY": 1.0},
            world="kinematic",
            scenario=quick(),
            on_progress=on_progress,
            cancel=cancel,
        )
    assert children, "the run started a child"
    for child in children:  # the run's own and the spare booted for its Stop run
        assert child.exit_status is not None
        assert not child.running()
        assert not child.temp.exists()
        assert child.server is not None
        assert not child.server.alive(), "the run's own pool ends its fork server"


@pytest.mark.parametrize("hooked", [False, True], ids=["plain", "own-setattr"])
def test_inputs_never_read_are_found_whatever_the_class_does_with_attributes(
    mr1_inventory: Inventory, hooked: bool
) -> None:
    skill = skill_path("move_forward")
    source = skill.read_text(encoding="utf-8")
    if hooked:
        source = source.replace(
            "    def __init__(self) -> None:",
            "    def __setattr__(self, name, value) -> None:\n"
            "        super().__setattr__(name, value)\n\n"
            "    def __init__(self) -> None:",
        )
    hard_coded = source.replace("speed = abs(self.in_linear_velocity)", "speed = 0.3")
    scenario = load_scenario(skill.with_suffix(".scenario.yaml")).model_copy(
        update={"stop_run": "never"}
    )

    faithful = run_skill(skill, mr1_inventory, source=source, scenario=scenario)
    careless = run_skill(skill, mr1_inventory, source=hard_coded, scenario=scenario)

    assert faithful.findings == []
    assert [f.check for f in careless.findings] == ["run.input"]
    assert "inLinearVelocity" in careless.findings[0].message
    assert careless.trace.episodes[0].outputs["outDistance"] > 0.4


def _run_edited(tmp_path: Path, inventory: Inventory, text: str, **options: object) -> RunReport:
    """``text`` (an edit of the shipped move forward) run as move_forward.py."""
    skill = tmp_path / "move_forward.py"
    skill.write_text(text, encoding="utf-8")
    return run_skill(
        skill,
        inventory,
        inputs={"inDistance": 0.3, "inLinearVelocity": 0.3},
        world="kinematic",
        **options,  # type: ignore[arg-type]
    )


def _renamed(tmp_path: Path) -> Path:
    """The shipped move forward with its parameters and outputs named as its author liked."""
    text = (SKILLS / "move_forward.py").read_text(encoding="utf-8")
    for old, new in (
        (
            'name="inDistance", description="Distance to drive. Unit: m."',
            'name="how_far", description="How far to drive forward, in metres."',
        ),
        ('name="inLinearVelocity"', 'name="speed"'),
        ('name="outDistance"', 'name="travelled_distance"'),
    ):
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "move_forward.py"
    path.write_text(text, encoding="utf-8")
    return path


def test_inputs_by_the_capability_s_names_reach_the_parameters_bound_to_them(
    tmp_path: Path, mr1_inventory: Inventory
) -> None:
    from skillwright.capability import load_capability
    from tests.conftest import SHIPPED_CAPABILITIES

    capability = load_capability(SHIPPED_CAPABILITIES / "move-forward.ttl").capability
    skill = _renamed(tmp_path)
    inputs = {"inDistance": 0.3, "inLinearVelocity": 0.3}
    with pytest.raises(InvalidArgumentError, match="give the capability with --capability"):
        run_skill(skill, mr1_inventory, inputs=inputs, world="kinematic")
    report = run_skill(
        skill,
        mr1_inventory,
        inputs=inputs,
        world="kinematic",
        capability=capability,
        bindings={"speed": "inLinearVelocity"},
    )
    assert report.passed, report.findings
    assert report.trace.binding == {
        "inDistance": "how_far",
        "inLinearVelocity": "speed",
        "outDistance": "travelled_distance",
        "outLinearVelocity": "outLinearVelocity",
    }
    assert report.trace.inputs == {"how_far": 0.3, "speed": 0.3}
    travelled = report.trace.episodes[0].outputs["travelled_distance"]
    assert abs(travelled - 0.3) < 0.05


def test_an_input_that_reaches_no_parameter_is_a_finding_not_bad_input(
    tmp_path: Path, mr1_inventory: Inventory
) -> None:
    from skillwright.capability import load_capability
    from tests.conftest import SHIPPED_CAPABILITIES

    capability = load_capability(SHIPPED_CAPABILITIES / "move-forward.ttl").capability
    skill = _renamed(tmp_path)
    text = skill.read_text(encoding="utf-8")
    text = text.replace('name="speed", description="Requested speed. Unit: m/s."', 'name="knob"')
    skill.write_text(text, encoding="utf-8")
    report = run_skill(
        skill,
        mr1_inventory,
        inputs={"inDistance": 0.3, "inLinearVelocity": 0.3},
        world="kinematic",
        capability=capability,
    )
    [unbound] = [f for f in report.findings if f.code == "SW630"]
    assert unbound.data == {"input": "inLinearVelocity", "candidates": []}
    assert "none of its parameters (how_far, knob) means it" in unbound.message


def test_tf2_s_buffer_transform_moves_a_stamped_point_as_the_lookup_says(
    tmp_path: Path, mr1_inventory: Inventory
) -> None:
    """Buffer.transform with tf2_geometry_msgs, as real tf2 has them: the robot's origin put
    in the map is where the lookup of the map -> base_link transform says it is."""
    from skillwright.capability import load_capability
    from skillwright.spec import load_spec
    from skillwright.validation.catalog import catalog_from_inventory
    from skillwright.validation.static import check_skill
    from tests.conftest import SHIPPED_CAPABILITIES

    text = (SKILLS / "get_position.py").read_text(encoding="utf-8")
    imports = "from tf2_ros import Buffer, TransformException, TransformListener\n"
    stored = (
        "        self.out_position_x = translation.x\n        self.out_position_y = translation.y\n"
    )
    assert imports in text
    assert stored in text
    text = text.replace(
        imports,
        imports
        + "import tf2_geometry_msgs  # noqa: F401\nfrom geometry_msgs.msg import PointStamped\n",
    ).replace(
        stored,
        "        origin = PointStamped()\n"
        "        origin.header.frame_id = self.BASE_FRAME\n"
        "        moved = self.tf_buffer.transform(origin, self.MAP_FRAME, Duration(seconds=2.0))\n"
        "        assert moved.header.frame_id == self.MAP_FRAME\n"
        "        self.out_position_x = moved.point.x\n"
        "        self.out_position_y = moved.point.y\n",
    )
    skill = tmp_path / "get_position.py"
    skill.write_text(text, encoding="utf-8")
    capability = load_capability(SHIPPED_CAPABILITIES / "get-position.ttl").capability
    spec = load_spec(SHIPPED_CAPABILITIES / "get-position.spec.yaml")
    static = check_skill(
        text, capability=capability, spec=spec, catalog=catalog_from_inventory(mr1_inventory)
    )
    assert [f for f in static.findings if f.severity == "error"] == []
    scenario = load_scenario(SKILLS / "get_position.scenario.yaml")
    moved = run_skill(skill, mr1_inventory, scenario=scenario)
    looked_up = run_skill(SKILLS / "get_position.py", mr1_inventory, scenario=scenario)
    assert moved.passed, moved.findings
    for name in ("outPositionX", "outPositionY"):
        assert moved.trace.episodes[0].outputs[name] == pytest.approx(
            looked_up.trace.episodes[0].outputs[name], abs=1e-9
        )


def test_an_input_is_set_where_its_getter_reads_it(
    tmp_path: Path, mr1_inventory: Inventory
) -> None:
    """A getter that returns a field of what __init__ made (``return self.request.x``) gets
    its input there, not written over the whole object."""
    text = (SKILLS / "move_forward.py").read_text(encoding="utf-8")
    text = text.replace(
        "        self.in_distance: float = 0.0\n",
        "        self.request = Twist()\n",
    ).replace("        return self.in_distance\n", "        return self.request.linear.x\n")
    text = text.replace("self.in_distance", "self.request.linear.x")
    report = _run_edited(tmp_path, mr1_inventory, text)
    assert report.passed, report.findings
    assert abs(report.trace.episodes[0].outputs["outDistance"] - 0.3) < 0.05


@pytest.mark.parametrize(
    ("command", "after"),
    [("stop", ["stopping", "resetting"]), ("abort", ["aborting", "clearing", "resetting"])],
)
def test_a_state_asks_pyskillups_state_machine_for_stop_or_abort(
    tmp_path: Path, mr1_inventory: Inventory, command: str, after: list[str]
) -> None:
    """``self.state_machine.stop()`` in execute (as the paper authors' collision avoidance
    does) takes the run to stopping once execute returns; ``abort()`` to aborting."""
    text = (SKILLS / "move_forward.py").read_text(encoding="utf-8")
    start = "        position = self.odom_msg.pose.pose.position\n        self.start_position"
    assert start in text
    text = text.replace(start, f"        self.state_machine.{command}()\n        return\n{start}")
    report = _run_edited(tmp_path, mr1_inventory, text)
    ran = [s.name for s in report.trace.episodes[0].states]
    assert ran == ["starting", "execute", *after]  # the skill has no aborting: it is absent


@pytest.mark.parametrize("isolated", [True, False], ids=["sandbox", "unisolated"])
def test_a_skill_may_compute_with_numpy(
    tmp_path: Path, mr1_inventory: Inventory, isolated: bool
) -> None:
    """numpy is one of the packages a skill may import (the paper's gpt-4o skills do): it
    is imported in the sandbox, with its native code, while ``import ctypes`` stays refused."""
    text = (SKILLS / "move_forward.py").read_text(encoding="utf-8")
    stored = "        self.out_distance = self._travelled()\n"
    assert stored in text
    text = text.replace(
        stored,
        "        import numpy\n        self.out_distance = float(numpy.hypot(*numpy.array([0.3, 0.4])))\n",
    )
    report = _run_edited(tmp_path, mr1_inventory, text, isolated=isolated)
    assert report.passed, report.findings
    assert report.trace.episodes[0].outputs["outDistance"] == pytest.approx(0.5)


def test_tf_transformations_turns_a_quaternion_into_roll_pitch_and_yaw(
    tmp_path: Path, mr1_inventory: Inventory
) -> None:
    """The package ROS 2 skills take a heading with (the paper authors' rotate does)."""
    text = (SKILLS / "move_forward.py").read_text(encoding="utf-8")
    stored = "        self.out_distance = self._travelled()\n"
    text = text.replace(
        stored,
        "        from tf_transformations import euler_from_quaternion, quaternion_from_euler\n"
        "        q = quaternion_from_euler(0.1, -0.2, 2.5)\n"
        "        roll, pitch, yaw = euler_from_quaternion(q)\n"
        "        self.out_distance = yaw + 10 * pitch + 100 * roll\n",
    )
    report = _run_edited(tmp_path, mr1_inventory, text)
    assert report.passed, report.findings
    assert report.trace.episodes[0].outputs["outDistance"] == pytest.approx(2.5 - 2.0 + 10.0)


def test_a_value_of_the_wrong_type_names_the_field_its_type_and_the_value_s(
    tmp_path: Path, mr1_inventory: Inventory
) -> None:
    """rosidl's own words, then the field's message type and path, its type and the type
    of what the skill gave it (a str where a float64 is)."""
    text = (SKILLS / "move_forward.py").read_text(encoding="utf-8")
    old = "command.linear.x = min(speed, max(braking, self.FINAL_SPEED))"
    assert old in text
    skill = tmp_path / "move_forward.py"
    skill.write_text(text.replace(old, 'command.linear.x = "fast"'), encoding="utf-8")
    report = run_skill(
        skill,
        mr1_inventory,
        inputs={"inDistance": 0.3, "inLinearVelocity": 0.2},
        world="kinematic",
    )
    [field] = [f for f in report.findings if f.code == "SW604"]
    assert field.message == (
        "execute raised InvalidFieldValue: The 'x' field must be of type 'float' "
        "(geometry_msgs/msg/Vector3.x is float64; the value given is a str)"
    )
    assert field.data == {
        "field": "geometry_msgs/msg/Vector3.x",
        "expected": "float64",
        "given": "str",
    }
    assert not [f for f in report.findings if f.code == "SW614"]


_TIMER_OUTPUT = """
from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface


@skill(skill_interface=SkillInterface.REST, skill_iri="urn:s", module_iri="urn:m",
       capability_iri="urn:c", description="a test skill")
class Subject(ROS2Skill):
    def __init__(self) -> None:
        super().__init__("subject")
        self.out_ticks = 0
        self.timer = None

    @skill_output(is_required=True, name="outTicks", description="Ticks so far.")
    def get_out_ticks(self) -> int:
        return self.out_ticks

    @execute
    def execute(self) -> None:
        self.timer = self.node.create_timer(100.0, self.on_timer)

    def on_timer(self) -> None:
        self.out_ticks += 1

    @resetting
    def resetting(self) -> None:
        self.timer.cancel()
"""


def test_an_output_a_callback_sets_counts_as_set_though_it_did_not_fire(
    tmp_path: Path, mr1_inventory: Inventory
) -> None:
    skill = tmp_path / "subject.py"
    skill.write_text(_TIMER_OUTPUT, encoding="utf-8")
    report = run_skill(skill, mr1_inventory, world="none")
    assert [f.code for f in report.findings if f.code == "SW620"] == []
    unset = tmp_path / "unset.py"
    unset.write_text(_TIMER_OUTPUT.replace("self.out_ticks += 1", "pass"), encoding="utf-8")
    report = run_skill(unset, mr1_inventory, world="none")
    assert [f.code for f in report.findings if f.code == "SW620"] == ["SW620"]
