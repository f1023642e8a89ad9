"""SW7xx: the simulation's verdicts (the skill in MuJoCo, judged on the world's ground truth).

Each scenario of the capability runs the skill against the MR-1 in MuJoCo; oracles derived
from the capability model and the resource judge the run on what the simulator knows (the
robot's true pose, its contacts) as well as on what the skill reported. One rule per
family of oracle; a finding's data names the scenario, the run, the oracle and its values.
"""

from __future__ import annotations

from skillwright.rules.registry import Rule

__all__ = ["SIM_FAMILIES", "simulation_rule"]

_DATA = ("scenario", "episode", "oracle", "check", "measured", "tolerance", "time", "state")
_SIM = ("the capability", "the simulation")

SIM_OUTCOME = Rule(
    "SW701",
    "sim-outcome",
    group="behaviour.outcome",
    stage="simulation",
    severity="error",
    summary="The skill ends as the scenario expects (completes, or aborts where it must).",
    why="A skill that completes a task its scenario makes impossible (a rejected goal, an "
    "input outside the capability's range) tells the plant something false.",
    example="# the scenario expects an abort; the skill completed",
    data=_DATA,
    grounds=_SIM,
)

SIM_PRECONDITION = Rule(
    "SW702",
    "sim-precondition",
    group="behaviour.precondition",
    stage="simulation",
    severity="error",
    summary="The scenario's inputs satisfy the capability's preconditions, or the skill "
    "refuses them.",
    why="A capability's precondition (inVelocity <= the resource's limit) says which requests "
    "are valid; a skill must not carry out one that violates it.",
    example="# inVelocity 2.0 where the capability allows 0.8; the skill drove",
    data=_DATA,
    grounds=_SIM,
)

SIM_CONSTRAINT = Rule(
    "SW703",
    "sim-constraint",
    group="behaviour.constraint",
    stage="simulation",
    severity="error",
    summary="The capability's constraints hold on what the skill reported (its outputs "
    "against its inputs).",
    why="The capability asserts relations between inputs and outputs (outDistance = "
    "inDistance); reported outputs that break them are a false report to the plant.",
    example="# outDistance 0.0 reported for inDistance 1.0",
    data=_DATA,
    grounds=_SIM,
)

SIM_TRUTH = Rule(
    "SW704",
    "sim-truth",
    group="behaviour.truth",
    stage="simulation",
    severity="error",
    summary="The capability's constraints hold on what the robot really did (the simulator's "
    "ground truth).",
    why="A skill can report the requested distance and have driven another; the world's true "
    "pose says what happened.",
    example="# reported 1.0 m, the base moved 0.6 m",
    data=_DATA,
    grounds=_SIM,
)

SIM_OUTPUT = Rule(
    "SW705",
    "sim-output",
    group="behaviour.output",
    stage="simulation",
    severity="error",
    summary="Each output agrees with the quantity it names, measured in the world (a "
    "position, a heading, a distance, a saved map).",
    why="An output is what the robot measured; one that disagrees with the world misleads "
    "whatever uses it next.",
    example="# outHeading 0.0 reported, the robot faces 1.57 rad",
    data=_DATA,
    grounds=_SIM,
)

SIM_REQUIREMENT = Rule(
    "SW706",
    "sim-requirement",
    group="behaviour.requirement",
    stage="simulation",
    severity="error",
    summary="What the capability requires of the run happens (it drives where it should, it "
    "saves the map it is asked to).",
    why="A capability with an effect is fulfilled only when the effect happened in the world.",
    example="# the mapping skill never called the map saver",
    data=_DATA,
    grounds=_SIM,
)

SIM_LIMIT = Rule(
    "SW707",
    "sim-limit",
    group="behaviour.limit",
    stage="simulation",
    severity="error",
    summary="The robot stays within the resource's limits (speed, turn rate) throughout.",
    why="The capability model states the resource's limits; commanding beyond them is unsafe "
    "on the real machine.",
    example="# 1.2 m/s commanded where the MR-1 allows 0.8",
    data=_DATA,
    grounds=_SIM,
)

SIM_CONTACT = Rule(
    "SW708",
    "sim-contact",
    group="behaviour.contact",
    stage="simulation",
    severity="error",
    summary="The robot touches nothing it should not.",
    why="A collision in the simulation is a collision on the shop floor.",
    example="# the base hit the shelf at t = 4.2 s",
    data=_DATA,
    grounds=_SIM,
)

SIM_REST = Rule(
    "SW709",
    "sim-rest",
    group="behaviour.rest",
    stage="simulation",
    severity="error",
    summary="The robot is at rest when the skill says it is done, stopped or aborted.",
    why="A skill that ends with the base still moving hands the next skill a moving robot.",
    example="# completing returned at 0.3 m/s",
    data=_DATA,
    grounds=_SIM,
)

SIM_FAMILIES = {
    "outcome": SIM_OUTCOME,
    "precondition": SIM_PRECONDITION,
    "constraint": SIM_CONSTRAINT,
    "truth": SIM_TRUTH,
    "output": SIM_OUTPUT,
    "requirement": SIM_REQUIREMENT,
    "limit": SIM_LIMIT,
    "contact": SIM_CONTACT,
    "rest": SIM_REST,
}
"""The rule of each family of oracle (``Verdict.kind``)."""


def simulation_rule(kind: str) -> Rule:
    """The rule of the oracles of family ``kind``."""
    return SIM_FAMILIES[kind]
