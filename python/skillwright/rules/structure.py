"""SW1xx: the pySkillUp structure of a skill (the @skill class, its annotations and states).

pySkillUp turns a class into a skill by its decorators: ``@skill(...)`` on a ``ROS2Skill``
subclass names the skill, its capability and module by IRI and its interface; each input
is a ``@skill_parameter`` getter, each output a ``@skill_output`` getter; each PackML state
it runs is a method decorated with the state's name. A skill that gets these wrong is not
found, not bound to its capability, or runs states that do nothing.
"""

from __future__ import annotations

from skillwright.rules.registry import Rule

__all__ = [
    "ABORT_SWALLOWED",
    "ANNOTATION_AMBIGUOUS",
    "ANNOTATION_MATCHES_NOTHING",
    "EMPTY_STATE",
    "ERROR_SWALLOWED",
    "LEFTOVER_MARKER",
    "NOT_IMPLEMENTED",
    "NOT_ROS2SKILL",
    "NO_SKILL_CLASS",
    "PARAMETER_UNANNOTATED",
    "SKILL_INTERFACE_MISMATCH",
    "SKILL_IRI_MISMATCH",
    "SKILL_IRI_MISSING",
    "STATE_MISSING",
    "STATE_NOT_SPECIFIED",
    "SYNTAX_ERROR",
]

_SKILL = ("pySkillUp",)

SYNTAX_ERROR = Rule(
    "SW101",
    "syntax-error",
    group="syntax",
    stage="static",
    severity="error",
    summary="The file parses as Python.",
    why="A skill that does not parse is never loaded: the robot's skill server refuses it "
    "at start-up, and every other check needs the parsed file.",
    example="def execute(self)\n    pass",
    data=("detail",),
    grounds=("Python",),
)

NO_SKILL_CLASS = Rule(
    "SW102",
    "no-skill-class",
    group="annotations",
    stage="static",
    severity="error",
    summary="The file has a class decorated with @skill(...).",
    why="pySkillUp registers a skill by its @skill decorator; without one the file offers "
    "no skill, whatever its methods do.",
    example="class MoveForward(ROS2Skill):  # no @skill(...)",
    grounds=_SKILL,
)

SKILL_IRI_MISMATCH = Rule(
    "SW103",
    "skill-iri-mismatch",
    group="annotations",
    stage="static",
    severity="error",
    summary="@skill names the capability's IRI as capability_iri and its resource's IRI as "
    "module_iri.",
    why="The skill registry binds a skill to the capability it implements by these IRIs; a "
    "missing or different one leaves the capability without a skill or binds the wrong one.",
    example='@skill(capability_iri="urn:x:other", ...)',
    data=("key", "expected", "given"),
    grounds=(*_SKILL, "the capability"),
)

SKILL_IRI_MISSING = Rule(
    "SW104",
    "skill-iri-missing",
    group="annotations",
    stage="static",
    severity="error",
    summary="@skill gives the skill its own IRI (skill_iri, a string).",
    why="pySkillUp describes the skill in its ontology under skill_iri; without it the "
    "skill cannot be found or invoked through its interface.",
    example='@skill(capability_iri="...", module_iri="...")  # no skill_iri',
    grounds=_SKILL,
)

SKILL_INTERFACE_MISMATCH = Rule(
    "SW105",
    "skill-interface-mismatch",
    group="annotations",
    stage="static",
    severity="error",
    summary="@skill's skill_interface is the one the specification names (REST, OPC_UA, MQTT).",
    why="The skill interface decides how the plant's orchestrator reaches the skill; another "
    "one leaves it unreachable from where it is called.",
    example="@skill(skill_interface=SkillInterface.MQTT, ...)  # the spec says REST",
    data=("expected",),
    grounds=_SKILL,
)

NOT_ROS2SKILL = Rule(
    "SW106",
    "not-ros2skill",
    group="annotations",
    stage="static",
    severity="error",
    summary="The @skill class derives from ROS2Skill.",
    why="ROS2Skill gives the skill its rclpy node and the state machine pySkillUp drives; "
    "without it the states have no node to create handles on.",
    example="@skill(...)\nclass MoveForward:",
    data=("class",),
    grounds=_SKILL,
)

PARAMETER_UNANNOTATED = Rule(
    "SW107",
    "parameter-unannotated",
    group="annotations",
    stage="static",
    severity="error",
    summary="Each input of the capability has a @skill_parameter getter and each output a "
    "@skill_output getter (a composite parameter may have one per component).",
    why="pySkillUp sets inputs and reads outputs only through these getters: an input without "
    "one cannot be given, an output without one is never reported.",
    example="# the capability has inDistance, the class no @skill_parameter for it",
    data=("decorator", "parameter", "missing"),
    grounds=(*_SKILL, "the capability"),
)

ANNOTATION_MATCHES_NOTHING = Rule(
    "SW108",
    "annotation-matches-nothing",
    group="annotations",
    stage="static",
    severity="warning",
    summary="Every @skill_parameter and @skill_output names an input or output of the capability.",
    why="A getter for a parameter the capability does not have is offered to the client but "
    "means nothing to the capability; usually a misspelt name.",
    example='@skill_parameter(name="inDistanse")',
    data=("decorator", "name"),
    grounds=(*_SKILL, "the capability"),
)

STATE_MISSING = Rule(
    "SW109",
    "state-missing",
    group="annotations",
    stage="static",
    severity="error",
    summary="Every state the specification describes has a method decorated with it.",
    why="pySkillUp runs the decorated state methods only; a state the specification asks for "
    "and the class lacks simply does not happen (no stop on Stop, nothing on execute).",
    example="# the spec describes stopping; no @stopping method",
    data=("state",),
    grounds=(*_SKILL, "the specification"),
)

STATE_NOT_SPECIFIED = Rule(
    "SW110",
    "state-not-specified",
    group="annotations",
    stage="static",
    severity="warning",
    summary="A state method the specification does not describe (a halting one aside).",
    why="Behaviour the specification does not ask for runs on the robot unreviewed; a "
    "stopping or aborting state that halts the robot is welcome and not flagged.",
    example="@holding\ndef holding(self): ...  # the spec has no holding",
    data=("state",),
    grounds=(*_SKILL, "the specification"),
)

EMPTY_STATE = Rule(
    "SW111",
    "empty-state",
    group="placeholders",
    stage="static",
    severity="error",
    summary="A state method does more than pass or ... .",
    why="An empty state is a placeholder: the robot does nothing where the specification "
    "asks for behaviour, and the skill reports success.",
    example="@execute\ndef execute(self):\n    pass",
    data=("state",),
    grounds=_SKILL,
)

NOT_IMPLEMENTED = Rule(
    "SW112",
    "not-implemented",
    group="placeholders",
    stage="static",
    severity="error",
    summary="The skill does not raise NotImplementedError.",
    why="NotImplementedError marks behaviour still to be written; on the robot the state "
    "aborts the skill the first time it runs.",
    example="raise NotImplementedError",
    grounds=("Python",),
)

LEFTOVER_MARKER = Rule(
    "SW113",
    "leftover-marker",
    group="placeholders",
    stage="static",
    severity="warning",
    summary="No TODO, FIXME or XXX marker is left in a comment.",
    why="A marker says the author knew something was missing; a reviewer should see it "
    "before the skill reaches the robot.",
    example="# TODO: stop the base",
    data=("marker",),
    grounds=("Python",),
)

ABORT_SWALLOWED = Rule(
    "SW114",
    "abort-swallowed",
    group="failures",
    stage="static",
    severity="error",
    summary="Where the specification says a state aborts, no handler catches the error and "
    "carries on.",
    why="pySkillUp aborts a skill when a state raises; a handler that logs and goes on ends "
    "the state as if it had succeeded, so the operator sees a completed skill that failed.",
    example="try:\n    self._wait_until(...)\nexcept RuntimeError:\n    self.node.get_logger()"
    ".error('no odometry')",
    data=("state", "caught"),
    grounds=(*_SKILL, "the specification"),
)

ERROR_SWALLOWED = Rule(
    "SW115",
    "error-swallowed",
    group="failures",
    stage="static",
    severity="warning",
    summary="A handler in a state that is not a halting one catches an error and carries on.",
    why="The skill goes on after something failed; sometimes right, often the failure the "
    "operator should have been told about (pySkillUp aborts on a raised error).",
    example="except Exception:\n    pass",
    data=("state", "caught"),
    grounds=_SKILL,
)

ANNOTATION_AMBIGUOUS = Rule(
    "SW116",
    "annotation-ambiguous",
    group="annotations",
    stage="static",
    severity="warning",
    summary="A @skill_parameter or @skill_output named otherwise than the capability's input "
    "or output means one of them unambiguously (by the quantity, unit and axis its name and "
    "description speak of).",
    why="pySkillUp does not ask for the capability's names, so the skill is bound to its "
    "capability by what each annotation means; one that could mean two inputs (a 'velocity' "
    "where the capability has inVelocityX and inVelocityY) is given neither.",
    example="@skill_parameter(name='velocity', description='how fast')",
    data=("decorator", "name", "candidates"),
    grounds=(*_SKILL, "the capability"),
)
