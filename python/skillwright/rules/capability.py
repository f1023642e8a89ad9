"""SW5xx: the capability's inputs and outputs, as the skill's code uses them.

A capability (CaSk/CSS) says what a skill takes (inputs with units and ranges) and what it
reports (outputs, some asserted to equal an input or a measured quantity). pySkillUp sets
each input on the attribute its ``@skill_parameter`` getter returns and reads each output
through its ``@skill_output`` getter once the skill completed; the code in between must use
the one and set the other.
"""

from __future__ import annotations

from skillwright.rules.registry import Rule

__all__ = [
    "CONSTANT_FOR_INPUT",
    "INPUT_COPIED_UNUSED",
    "INPUT_NEVER_READ",
    "INPUT_ONLY_VALIDATED",
    "INPUT_OVERWRITTEN",
    "OUTPUT_CONSTANT",
    "OUTPUT_NEVER_SET",
]

_CAPABILITY = ("the capability", "pySkillUp")

CONSTANT_FOR_INPUT = Rule(
    "SW501",
    "constant-for-input",
    group="constants",
    stage="static",
    severity="error",
    summary="No number named like a capability input stands in for it.",
    why="`target_distance = 1.0` where the capability takes inDistance drives a metre "
    "whatever the client asked for; the robot ignores its request. Zero, the "
    "specification's own numbers and the resource's limits from the capability model are "
    "not flagged.",
    example="self.desired_distance = 1.0",
    data=("input", "name", "value"),
    grounds=_CAPABILITY,
)

INPUT_OVERWRITTEN = Rule(
    "SW502",
    "input-overwritten",
    group="inputs",
    stage="static",
    severity="error",
    summary="No state assigns the attribute that holds a capability input.",
    why="The client sets the input before execute; a state that overwrites it changes the "
    "request, and a second run of the skill (or a getter read afterwards) sees the "
    "changed value.",
    example="self.in_distance = abs(self.in_distance)",
    fix="Keeps the method's arithmetic on a local copy of the input.",
    safety="unsafe",
    data=("input", "attribute", "local"),
    grounds=_CAPABILITY,
)

INPUT_COPIED_UNUSED = Rule(
    "SW503",
    "input-copied-unused",
    group="inputs",
    stage="static",
    severity="error",
    summary="An input copied into a local is used through that local.",
    why="The copy is made and nothing reads it: the skill behaves the same whatever the "
    "client asks.",
    example="distance = self.in_distance  # and distance is never read",
    data=("input", "attribute", "method", "local"),
    grounds=_CAPABILITY,
)

INPUT_ONLY_VALIDATED = Rule(
    "SW504",
    "input-only-validated",
    group="inputs",
    stage="static",
    severity="error",
    summary="An input does more than decide whether to refuse the request.",
    why="Checking that a speed is positive and then driving at a fixed speed accepts the "
    "request and ignores it.",
    example="if self.in_velocity <= 0: raise ValueError(...)  # and nothing else reads it",
    data=("input", "attribute", "method"),
    grounds=_CAPABILITY,
)

INPUT_NEVER_READ = Rule(
    "SW505",
    "input-never-read",
    group="inputs",
    stage="static",
    severity="error",
    summary="Every input's attribute is read by some method (its own getter aside).",
    why="An input nothing reads is ignored: the robot does the same whatever the client "
    "asks, usually with a hard-coded value in its place.",
    example="# in_distance is set by pySkillUp and read by no state",
    data=("input", "attribute"),
    grounds=_CAPABILITY,
)

OUTPUT_NEVER_SET = Rule(
    "SW506",
    "output-never-set",
    group="outputs",
    stage="static",
    severity="error",
    summary="Every output's attribute is assigned by some method (__init__ aside).",
    why="pySkillUp reports what the output getter returns after completing; unset, that is "
    "whatever __init__ put there, whatever the robot did.",
    example="# out_distance is set in __init__ and nowhere else",
    data=("output", "attribute", "scans"),
    grounds=_CAPABILITY,
)

OUTPUT_CONSTANT = Rule(
    "SW507",
    "output-constant",
    group="outputs",
    stage="static",
    severity="error",
    summary="An output the capability measures is stored as a measured value, not only literals.",
    why="An output such as a reached distance or a heading is what the robot measured; a "
    "skill that stores 0.0 reports a fixed number whatever happened, and the capability's "
    "assurance (outDistance = inDistance) is then false on the robot.",
    example="self.out_distance = 0.0",
    fix="Stores the value the method worked out (or the skeleton's closest reading) instead "
    "of the literal.",
    safety="unsafe",
    data=("output", "attribute", "values", "scans"),
    grounds=_CAPABILITY,
)
