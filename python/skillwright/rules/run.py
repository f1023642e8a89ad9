"""SW6xx: what the run in the sandbox shows (the skill's states against the simulated graph).

The run drives the skill as pySkillUp does (inputs on the attributes their getters return,
starting, execute, completing, resetting; aborting on a raise; stopping on a Stop) against
every topic, service and action of the robot, with ROS 2's QoS matching, and watches what
it does in virtual time. What these rules report happened; the line is the skill's line
that did it (or the last one the run heard of).
"""

from __future__ import annotations

from skillwright.rules.registry import Rule

__all__ = [
    "RUN_ACTION_UNKNOWN",
    "RUN_BLOCKED",
    "RUN_BUSY",
    "RUN_COMMAND_STILL_MOVING",
    "RUN_CPU",
    "RUN_EXCEPTION",
    "RUN_EXPECTATION",
    "RUN_FIELD",
    "RUN_GOAL_LEFT_ACTIVE",
    "RUN_IMPORT",
    "RUN_INPUT_GETTER",
    "RUN_INPUT_UNBOUND",
    "RUN_INPUT_UNREAD",
    "RUN_MEMORY",
    "RUN_NO_DATA",
    "RUN_OUTPUT_UNSET",
    "RUN_PROCESS_DIED",
    "RUN_PROTOCOL",
    "RUN_QOS",
    "RUN_SANDBOX",
    "RUN_SERVICE_UNKNOWN",
    "RUN_SHORT_WAIT",
    "RUN_STRUCTURE",
    "RUN_SYNTAX",
    "RUN_SYS_EXIT",
    "RUN_THREAD",
    "RUN_TIMEOUT",
    "RUN_TOPIC_UNKNOWN",
    "RUN_TYPE",
    "WORLD_REPORT",
]

_RUN = ("pySkillUp", "rclpy", "the robot")

RUN_SYNTAX = Rule(
    "SW601",
    "run-syntax",
    group="run.syntax",
    stage="run",
    severity="error",
    summary="The skill's file compiles in the sandbox's interpreter.",
    why="The robot's interpreter refuses a file that does not compile; nothing of it runs.",
    example="def execute(self)",
    grounds=("Python",),
)

RUN_STRUCTURE = Rule(
    "SW602",
    "run-structure",
    group="run.structure",
    stage="run",
    severity="error",
    summary="The file holds one @skill class that pySkillUp can make.",
    why="pySkillUp instantiates the decorated ROS2Skill class; a file without one, or whose "
    "class cannot be made, offers no skill.",
    example="# no @skill class, or __init__ raising",
    grounds=("pySkillUp",),
)

RUN_IMPORT = Rule(
    "SW603",
    "run-import",
    group="run.import",
    stage="run",
    severity="error",
    summary="Every module and message type the skill imports exists on the robot.",
    why="An interface package the robot lacks (or a type it does not define) makes the import "
    "fail when pySkillUp loads the skill.",
    example="from nav2_msgs.action import MadeUp",
    data=("module",),
    grounds=("ROS 2", "the robot"),
)

RUN_FIELD = Rule(
    "SW604",
    "run-field",
    group="run.field",
    stage="run",
    severity="error",
    summary="Every message field the skill touches exists, and gets a value of its type.",
    why="rclpy's generated classes refuse an unknown field (AttributeError) and a value of the "
    "wrong type (an int where a float64 is: AssertionError) when the line runs.",
    example="twist.linear.x = 1  # an int",
    data=("field", "expected", "given"),
    grounds=("rclpy",),
)

RUN_EXCEPTION = Rule(
    "SW605",
    "run-exception",
    group="run.exception",
    stage="run",
    severity="error",
    summary="No state (or callback) raises.",
    why="pySkillUp aborts the skill when a state raises; an exception in a subscription's "
    "callback stops that callback for good on a real executor. The finding stands at the "
    "skill's line that raised, with the calls that led there.",
    example="raise RuntimeError('the motion was not finished within 2 s')",
    data=("state", "type", "detail", "seconds", "action", "under_way", "frame", "frames"),
    grounds=_RUN,
)

RUN_SANDBOX = Rule(
    "SW606",
    "run-sandbox",
    group="run.sandbox",
    stage="run",
    severity="error",
    summary="The skill does nothing a skill has no business doing: start programs, load native "
    "code, open network sockets, signal other processes, write or read outside its scratch "
    "folder, end its process.",
    why="On the robot such code reaches far beyond the skill; the sandbox refuses it in the "
    "kernel whatever the skill does, and reports it here at its line.",
    example="os.system('rm -rf ~')",
    grounds=("the sandbox",),
)

RUN_MEMORY = Rule(
    "SW607",
    "run-memory",
    group="run.memory",
    stage="run",
    severity="error",
    summary="The skill stays within the sandbox's memory limit.",
    why="A skill that allocates without bound takes the robot computer's memory from its "
    "drivers and planners.",
    example="readings = [0.0] * 10**10",
    data=("limit_mb",),
    grounds=("the sandbox",),
)

RUN_SYS_EXIT = Rule(
    "SW608",
    "run-sys-exit",
    group="run.exit",
    stage="run",
    severity="error",
    summary="The skill does not end its process (sys.exit).",
    why="pySkillUp runs many skills in one process; ending it takes every skill and the "
    "skill server down. Raise an exception to abort.",
    example="sys.exit(1)",
    grounds=("pySkillUp",),
)

RUN_PROCESS_DIED = Rule(
    "SW609",
    "run-process-died",
    group="run.exit",
    stage="run",
    severity="error",
    summary="The skill's process does not die under it (a signal, os._exit, a crash, a limit).",
    why="A skill process that dies leaves the robot with whatever it last commanded; the "
    "finding says what the resource use shows of the cause.",
    example="os.kill(os.getpid(), signal.SIGKILL)",
    data=("status", "state"),
    grounds=("the sandbox",),
)

RUN_TIMEOUT = Rule(
    "SW610",
    "run-timeout",
    group="run.timeout",
    stage="run",
    severity="error",
    summary="Every state returns within its deadline, and the whole run within its wall time.",
    why="A state that never returns blocks pySkillUp's state machine: the skill can be neither "
    "completed nor stopped cleanly.",
    example="while True:\n    time.sleep(0.1)",
    data=("state", "seconds"),
    grounds=("pySkillUp",),
)

RUN_BUSY = Rule(
    "SW611",
    "run-busy",
    group="run.busy",
    stage="run",
    severity="error",
    summary="No state runs for long without waiting (sleeping, spinning or on a future).",
    why="A loop that never waits burns a core on the robot and keeps the executor's callbacks "
    "from running, so what it waits for never arrives.",
    example="while self.odom_msg.pose.pose.position.x < 1.0:\n    pass",
    data=("state", "seconds"),
    grounds=("rclpy",),
)

RUN_BLOCKED = Rule(
    "SW612",
    "run-blocked",
    group="run.blocked",
    stage="run",
    severity="error",
    summary="No state waits in a way time cannot pass for (a lock, input(), a raw socket).",
    why="Such a wait hangs the skill on the robot as well; waits belong to time.sleep, "
    "rclpy.spin_once or a future.",
    example="input('press enter')",
    data=("state", "seconds"),
    grounds=("rclpy",),
)

RUN_CPU = Rule(
    "SW613",
    "run-cpu",
    group="run.cpu",
    stage="run",
    severity="error",
    summary="The skill stays within the sandbox's CPU-time limit.",
    why="A skill that computes for minutes starves the robot's controllers on a shared computer.",
    example="sum(range(10**12))",
    data=("state",),
    grounds=("the sandbox",),
)

RUN_PROTOCOL = Rule(
    "SW614",
    "run-protocol",
    group="run.protocol",
    stage="run",
    severity="error",
    summary="The sandboxed process keeps to the runtime's protocol.",
    why="Garbage on the runtime's socket means the skill wrote to a descriptor it does not "
    "own or replaced the runtime's modules; nothing after it can be trusted.",
    example="os.write(3, b'garbage')",
    grounds=("the sandbox",),
)

RUN_TOPIC_UNKNOWN = Rule(
    "SW615",
    "run-topic-unknown",
    group="run.topic",
    stage="run",
    severity="error",
    summary="Every topic the skill publishes or subscribes to is on the robot.",
    why="A publisher on a topic nothing subscribes to moves nothing; a subscription to a "
    "topic nobody publishes waits forever. ROS 2 reports neither.",
    example='self.node.create_publisher(Twist, "/cmd_vel_made_up", 10)',
    data=("name",),
    grounds=("the robot",),
)

RUN_SERVICE_UNKNOWN = Rule(
    "SW628",
    "run-service-unknown",
    group="run.service",
    stage="run",
    severity="error",
    summary="Every service the skill makes a client of is on the robot.",
    why="A client of a missing service never becomes ready: wait_for_service times out and "
    "call_async's future never completes.",
    example='self.node.create_client(Trigger, "/made_up")',
    data=("name",),
    grounds=("the robot",),
)

RUN_ACTION_UNKNOWN = Rule(
    "SW629",
    "run-action-unknown",
    group="run.action",
    stage="run",
    severity="error",
    summary="Every action the skill makes a client of is on the robot.",
    why="An action client of a missing server never connects: wait_for_server times out and "
    "a goal is never accepted.",
    example='ActionClient(self.node, NavigateToPose, "/navigate_made_up")',
    data=("name",),
    grounds=("the robot",),
)

RUN_TYPE = Rule(
    "SW616",
    "run-type",
    group="run.type",
    stage="run",
    severity="error",
    summary="Every handle carries the type its interface has on the robot.",
    why="DDS matches endpoints by name and type: a handle of another type never connects.",
    example='self.node.create_subscription(Pose, "/odom", ...)',
    data=("name", "type", "used_type"),
    grounds=("ROS 2", "the robot"),
)

RUN_QOS = Rule(
    "SW617",
    "run-qos",
    group="run.qos",
    stage="run",
    severity="error",
    summary="A subscription's QoS is compatible with what the robot publishes.",
    why="ROS 2 delivers nothing across incompatible QoS: a reliable subscription to a "
    "best-effort scan, or a transient-local one to a volatile topic, receives no message "
    "and reports no error.",
    example='self.node.create_subscription(LaserScan, "/scan", cb, 10)  # /scan is best effort',
    data=("name",),
    grounds=("ROS 2",),
)

RUN_INPUT_GETTER = Rule(
    "SW618",
    "run-input-getter",
    group="run.input",
    stage="run",
    severity="error",
    summary="An input's getter returns an attribute of the skill (`return self.<name>`).",
    why="pySkillUp sets an input on the attribute its getter returns; a getter that computes "
    "its value cannot be set, and the skill runs with whatever it computes.",
    example='@skill_parameter(name="inDistance")\ndef distance(self) -> float:\n    return 1.0',
    data=("input", "getter"),
    grounds=("pySkillUp",),
)

RUN_INPUT_UNREAD = Rule(
    "SW619",
    "run-input-unread",
    group="run.input",
    stage="run",
    severity="error",
    summary="Every input given to the run is read by some state.",
    why="An input no state reads changes nothing the robot does.",
    example="# in_distance set, never read during the run",
    data=("input", "attribute"),
    grounds=("pySkillUp", "the capability"),
)

RUN_OUTPUT_UNSET = Rule(
    "SW620",
    "run-output-unset",
    group="run.output",
    stage="run",
    severity="error",
    summary="Every output is assigned by some state during a completed run.",
    why="pySkillUp reports the output getter's value after completing: unset, it is whatever "
    "__init__ put there.",
    example="# out_distance never assigned in the run",
    data=("output", "attribute"),
    grounds=("pySkillUp", "the capability"),
)

RUN_NO_DATA = Rule(
    "SW621",
    "run-no-data",
    group="run.no_data",
    stage="run",
    severity="warning",
    summary="Something arrives on every topic the skill subscribes to during the run.",
    why="A subscription to a topic nobody publishes (in this recording, or on the robot) "
    "gives the skill nothing to act on.",
    example='self.node.create_subscription(Odometry, "/odom_filtered", ...)',
    data=("name",),
    grounds=("the robot",),
)

RUN_GOAL_LEFT_ACTIVE = Rule(
    "SW622",
    "run-goal-left-active",
    group="run.motion",
    stage="run",
    severity="error",
    summary="No action goal the skill sent is still active after stopping, aborting, "
    "resetting or the end of the run.",
    why="A navigation or arm goal left active goes on moving the robot after the skill ended; "
    "cancel it where the skill stops.",
    example="# stopping publishes a zero Twist but never cancels the NavigateToPose goal",
    data=("action", "state"),
    grounds=("rclpy", "ROS 2"),
)

RUN_COMMAND_STILL_MOVING = Rule(
    "SW623",
    "run-command-still-moving",
    group="run.motion",
    stage="run",
    severity="error",
    summary="The last velocity command is a stop after stopping, aborting, resetting and at "
    "the end of the run.",
    why="A base holds a latched or repeated command: a skill that ends without a zero "
    "velocity leaves the robot driving.",
    example="# aborting publishes nothing after execute drove at 0.3 m/s",
    data=("topic", "state"),
    grounds=("ROS 2",),
)

RUN_THREAD = Rule(
    "SW624",
    "run-thread",
    group="run.thread",
    stage="run",
    severity="error",
    summary="No thread the skill started is still running after resetting.",
    why="A thread left running outlives the skill in pySkillUp's process and goes on doing "
    "what it did (commanding the base, holding handles).",
    example="threading.Thread(target=self._drive_forever).start()",
    data=("thread",),
    grounds=("pySkillUp",),
)

RUN_EXPECTATION = Rule(
    "SW625",
    "run-expectation",
    group="run.expectation",
    stage="run",
    severity="error",
    summary="The skill ends as its scenario expects (aborts where the scenario's interfaces fail).",
    why="A scenario that makes Nav2 reject the goal expects the skill to abort; one that "
    "completes reports success for a task that did not happen.",
    example="# the goal was rejected and execute returned normally",
    data=("expected",),
    grounds=("the scenario",),
)

RUN_SHORT_WAIT = Rule(
    "SW626",
    "run-short-wait",
    group="run.short_wait",
    stage="run",
    severity="error",
    summary="A wait that gave up gets past, run again with longer: its timeout was too short "
    "for the motion.",
    why="A timeout shorter than the motion takes aborts the skill on a robot that is doing "
    "what it was told; the finding carries the time the state took, measured.",
    example="self._wait_until(lambda: reached(), 2.0, 'the goal')  # the drive takes 3.4 s",
    fix="Sets the wait's timeout to three times the measured time, rounded up.",
    safety="unsafe",
    data=("seconds", "timeout", "took"),
    grounds=("the run",),
)

WORLD_REPORT = Rule(
    "SW627",
    "world-report",
    group="world",
    stage="run",
    severity="error",
    summary="What a world plug-in reports of the skill's effect on it (a collision, an "
    "unreachable pose).",
    why="A world simulates the robot's surroundings; what it reports happened to the "
    "simulated robot because of the skill.",
    example="# a world plug-in's host.report('collision', ...)",
    data=("check",),
    grounds=("the world plug-in",),
)

RUN_INPUT_UNBOUND = Rule(
    "SW630",
    "run-input-unbound",
    group="run.binding",
    stage="run",
    severity="warning",
    summary="Every input the scenario gives by its capability name reaches a parameter of the "
    "skill: one of that name, one whose name and description mean it, or one --bind names.",
    why="pySkillUp sets a skill's inputs by the names its @skill_parameter decorators give; "
    "a capability input no parameter stands for is never given to the skill, which then runs "
    "with what its __init__ put there. The skill still executes with the parameters it "
    "declares, so the run warns and goes on: the missing or ambiguous annotation is the "
    "static checks' finding (SW107 parameter-unannotated, SW116 annotation-ambiguous), and "
    "an ignored input shows in the behaviour its oracles judge.",
    example="@skill_parameter(name='speed', description='how fast')  # inVelocityX or inVelocityY?",
    data=("input", "candidates"),
    grounds=("pySkillUp", "the capability"),
)
