"""SW4xx: behaviour a skill's code shows before it runs (waits, loops, motion, units, frames).

rclpy delivers messages in callbacks, on the executor's thread, while the skill's state
waits; a base driver stops when its velocity command is not repeated; tf2 gives the
transform from a source frame into a target frame; LaserScan and every yaw are in radians;
measured numbers carry noise. Code that ignores one of these runs, and does the wrong thing
on the robot: these rules read it from the code.
"""

from __future__ import annotations

from skillwright.rules.registry import Rule

__all__ = [
    "BEARING_OFFSET_TWICE",
    "BUILT_NOT_SENT",
    "CLOCK_COMPARED_WITH_DURATION",
    "EXACT_EQUALITY",
    "FILTERED_INDEX",
    "FIRST_MESSAGE_GUARD",
    "FIRST_MESSAGE_READ",
    "LOOP_NEVER_SLEEPS",
    "MIXED_ANGLE_UNITS",
    "NO_MOTION_COMMANDED",
    "ONE_SHOT_COMMAND_LOOP",
    "ONE_SHOT_COMMAND_SLEEP",
    "READ_RIGHT_AFTER_COMMAND",
    "SCANNER_UNREAD",
    "STALE_LOOP",
    "STALE_READING",
    "STOP_IN_WAIT_LOOP",
    "TRANSFORM_REVERSED",
    "UNMOVED_LOOP",
    "WAIT_SHORTER_THAN_SPEC",
    "ZERO_TIMEOUT",
]

_EXECUTOR = ("rclpy",)

CLOCK_COMPARED_WITH_DURATION = Rule(
    "SW401",
    "clock-compared-with-duration",
    group="waits",
    stage="static",
    severity="error",
    summary="A clock's reading is compared with a deadline, not with a duration.",
    why="time.monotonic() counts seconds from an arbitrary start (the machine's boot): "
    "`time.monotonic() < 5.0` is decided at once, so the wait ends at once or never.",
    example="while time.monotonic() < 5.0:",
    fix="Takes a deadline where the wait begins and compares the clock with it.",
    safety="unsafe",
    data=("comparison", "clock", "seconds"),
    grounds=("Python",),
)

LOOP_NEVER_SLEEPS = Rule(
    "SW402",
    "loop-never-sleeps",
    group="waits",
    stage="static",
    severity="error",
    summary="A loop that waits for the robot (the clock, a callback's message, a future) "
    "sleeps or spins in every pass.",
    why="A busy loop spins a core, publishes as fast as Python can and, on a single-threaded "
    "executor, keeps the very callbacks it waits for from running.",
    example="while self.odom_msg.pose.pose.position.x < target:\n    pass",
    fix="Adds time.sleep(0.05) at the end of the loop's body.",
    safety="unsafe",
    data=("method", "waits_for"),
    grounds=_EXECUTOR,
)

FIRST_MESSAGE_GUARD = Rule(
    "SW403",
    "first-message-guard",
    group="waits",
    stage="static",
    severity="error",
    summary="A state that gives up when a subscription's latest message is None waits for "
    "the first message first.",
    why="The skeleton keeps a subscription's latest message in self.X_msg, None until the "
    "first one arrives; pySkillUp runs a state right after the one that subscribed, so the "
    "guard gives up on a robot that is fine.",
    example="if self.odom_msg is None:\n    raise RuntimeError('no odometry')",
    fix="Puts the skeleton's wait for the first message in the guard's place.",
    safety="unsafe",
    data=("attribute", "state"),
    grounds=("the skeleton", "rclpy"),
)

FIRST_MESSAGE_READ = Rule(
    "SW404",
    "first-message-read",
    group="waits",
    stage="static",
    severity="error",
    summary="A state reads a latest message's fields only after something waited for it.",
    why="Until the first message arrives self.X_msg is None, and reading its fields raises "
    "AttributeError.",
    example="x = self.odom_msg.pose.pose.position.x  # first thing in execute",
    fix="Puts the wait for the message before the statement.",
    safety="unsafe",
    data=("attributes", "state"),
    grounds=("the skeleton", "rclpy"),
)

READ_RIGHT_AFTER_COMMAND = Rule(
    "SW405",
    "read-right-after-command",
    group="waits",
    stage="static",
    severity="error",
    summary="A state does not give up on a reading taken the moment after it commanded the robot.",
    why="The latest message came in before the command: the robot has had no time to answer "
    "it, so the test fails on a robot that is fine.",
    example="self.cmd_vel_publisher.publish(cmd)\nif abs(self.odom_msg.twist.twist.linear.x - "
    "v) > 0.05: raise ...",
    fix="Waits until the condition holds instead of testing it once.",
    safety="unsafe",
    data=("attribute", "condition"),
    grounds=("rclpy",),
)

WAIT_SHORTER_THAN_SPEC = Rule(
    "SW406",
    "wait-shorter-than-spec",
    group="waits",
    stage="static",
    severity="error",
    summary="A wait for an interface to show up allows at least the seconds its state's "
    "specification gives.",
    why="The specification says how long the robot's interfaces may take ('abort if any is "
    "missing after 5 s'); a shorter wait gives up on a robot that is only slower (SLAM "
    "Toolbox publishes its map every 5 s by default).",
    example="self._wait_until(lambda: self.map_msg is not None, 2.0, 'the map')  # spec: 5 s",
    fix="Gives the wait the stated seconds.",
    safety="unsafe",
    data=("state", "seconds", "stated"),
    grounds=("the specification",),
)

ZERO_TIMEOUT = Rule(
    "SW407",
    "zero-timeout",
    group="waits",
    stage="static",
    severity="error",
    summary="A skeleton helper's wait gets a timeout above zero.",
    why="_wait_until, _transform, _result_of and the goal helpers give up after their "
    "timeout: with 0 they give up before the first message can come (tf2's 'latest' stamp "
    "is a different argument).",
    example='self._transform("map", "base_link", 0.0)',
    fix="Gives the wait the skeleton's own two seconds.",
    safety="unsafe",
    data=("helper",),
    grounds=("the skeleton", "tf2"),
)

NO_MOTION_COMMANDED = Rule(
    "SW408",
    "no-motion-commanded",
    group="motion",
    stage="static",
    severity="error",
    summary="A skill whose capability takes a speed commands a non-zero velocity or sends a "
    "goal somewhere.",
    why="A velocity input means the robot moves; a skill that only sleeps and stops reports "
    "success with the robot where it was.",
    example="time.sleep(self.in_time)\nself._stop_base()",
    data=("speeds", "publishers"),
    grounds=("the capability", "ROS 2"),
)

UNMOVED_LOOP = Rule(
    "SW409",
    "unmoved-loop",
    group="motion",
    stage="static",
    severity="error",
    summary="A loop that waits for the robot to move follows a motion command.",
    why="With no velocity published and no goal sent the reading never changes, and the "
    "loop runs until the state gives up.",
    example="while self._yaw(...) < target:\n    time.sleep(0.05)  # nothing turns the robot",
    data=("state", "test"),
    grounds=("ROS 2",),
)

ONE_SHOT_COMMAND_SLEEP = Rule(
    "SW410",
    "one-shot-command-sleep",
    group="motion",
    stage="static",
    severity="error",
    summary="A velocity command is repeated while the robot should keep moving, not published "
    "once and slept on.",
    why="Base drivers stop when the command is not repeated within their timeout (half a "
    "second for ros2_control's diff_drive_controller): publish-then-sleep moves the robot "
    "for half a second at most.",
    example="self.cmd_vel_publisher.publish(cmd)\ntime.sleep(3.0)",
    fix="Publishes the command every 0.05 s until the time is up.",
    safety="unsafe",
    data=("handle", "seconds"),
    grounds=("ros2_control", "ROS 2"),
)

ONE_SHOT_COMMAND_LOOP = Rule(
    "SW411",
    "one-shot-command-loop",
    group="motion",
    stage="static",
    severity="error",
    summary="A loop that waits for the robot to move repeats the velocity command it relies on.",
    why="The command published once before the loop lapses after the driver's timeout: the "
    "robot halts and what the loop waits for never comes.",
    example="self.cmd_vel_publisher.publish(cmd)\nwhile travelled < distance:\n    "
    "time.sleep(0.05)",
    fix="Publishes the command again at the start of every pass.",
    safety="unsafe",
    data=("handle",),
    grounds=("ros2_control", "ROS 2"),
)

STOP_IN_WAIT_LOOP = Rule(
    "SW412",
    "stop-in-wait-loop",
    group="stops",
    stage="static",
    severity="error",
    summary="A loop that waits for the robot to move does not stop it on every pass.",
    why="A zero Twist published inside the wait halts the base after the first pass: the "
    "awaited heading or distance never comes.",
    example="while not reached:\n    self.cmd_vel_publisher.publish(Twist())",
    fix="Publishes the command the loop relies on instead of the stop.",
    safety="unsafe",
    data=("handle",),
    grounds=("ROS 2",),
)

STALE_LOOP = Rule(
    "SW413",
    "stale-loop",
    group="stale",
    stage="static",
    severity="error",
    summary="A loop's exit test reads something the loop changes (or a callback may).",
    why="A condition on locals nothing in the loop assigns is decided once: the loop ends "
    "only by raising.",
    example="last = self._yaw(...)\nwhile abs(last - target) > 0.05:\n    time.sleep(0.05)",
    fix="Repeats the readings the test comes from at the start of each pass.",
    safety="unsafe",
    data=("test", "names"),
    grounds=("Python",),
)

STALE_READING = Rule(
    "SW414",
    "stale-reading",
    group="stale",
    stage="static",
    severity="error",
    summary="A `while True` loop that leaves on values worked out from a reading takes the "
    "reading again each pass.",
    why="The values the break tests are worked out once, before the loop: the test gives the "
    "same answer on every pass.",
    example="remaining = target - self._yaw(...)\nwhile True:\n    if remaining < 0.05: break",
    fix="Repeats the readings at the end of the loop.",
    safety="unsafe",
    data=("names",),
    grounds=("Python",),
)

MIXED_ANGLE_UNITS = Rule(
    "SW415",
    "mixed-angle-units",
    group="units",
    stage="static",
    severity="error",
    summary="Degrees and radians are not mixed: a capability's angle in degrees is converted "
    "from the radians LaserScan, math.atan2 and every yaw give.",
    why="LaserScan's angles, atan2 and a quaternion's yaw are radians (REP 103); an output in "
    "degrees stored from them reports 3.07 for 176 degrees.",
    example="self.out_degree = scan.angle_min + index * scan.angle_increment",
    fix="Converts with math.degrees or math.radians where the unit differs.",
    safety="unsafe",
    data=("reasons",),
    grounds=("REP 103", "the capability"),
)

BUILT_NOT_SENT = Rule(
    "SW416",
    "built-not-sent",
    group="unsent",
    stage="static",
    severity="error",
    summary="A command, goal or request the skill builds is sent.",
    why="A Twist filled in and never published moves nothing; a goal never sent is never "
    "pursued; the state then waits for what cannot happen.",
    example="cmd = Twist()\ncmd.linear.x = 0.3  # never published",
    fix="Publishes the message once it is complete, where the class has one publisher of its type.",
    safety="unsafe",
    data=("name", "kind", "handles"),
    grounds=("rclpy",),
)

FILTERED_INDEX = Rule(
    "SW417",
    "filtered-index",
    group="positions",
    stage="static",
    severity="error",
    summary="A position found in a filtered copy of a list is not used as a position in the "
    "original.",
    why="`valid = [r for r in ranges if finite(r)]; i = valid.index(min(valid))` counts only "
    "kept readings: angle_min + i * angle_increment is another reading's bearing.",
    example="i = valid.index(min(valid))\nangle = scan.angle_min + i * scan.angle_increment",
    fix="Takes the position in the original list.",
    safety="unsafe",
    data=("name", "source"),
    grounds=("ROS 2",),
)

BEARING_OFFSET_TWICE = Rule(
    "SW418",
    "bearing-offset-twice",
    group="bearings",
    stage="static",
    severity="error",
    summary="The skeleton's closest-reading bearing is not offset by the scan's angle_min again.",
    why="_closest_reading(scan) gives the bearing counted from the scanner's x axis already "
    "(angle_min + index * angle_increment): subtracting angle_min once more reports every "
    "bearing off by it (pi on a scanner that starts at -pi).",
    example="angle = reading[1] - self.scan_msg.angle_min",
    fix="Uses the bearing as it is.",
    safety="safe",
    data=("expression",),
    grounds=("the skeleton", "ROS 2"),
)

TRANSFORM_REVERSED = Rule(
    "SW419",
    "transform-reversed",
    group="frames",
    stage="static",
    severity="error",
    summary="The robot's pose is asked of tf with the world frame as the target and the base "
    "frame as the source.",
    why="tf2's lookup_transform(target, source) gives the transform taking source into "
    "target: asked (base_link, map) it is the map's origin seen from the robot, the robot's "
    "position only while it stands at the origin.",
    example='self._transform("base_link", "map", 2.0).transform.translation.x',
    fix="Swaps the frames.",
    safety="safe",
    data=("target", "source"),
    grounds=("tf2",),
)

SCANNER_UNREAD = Rule(
    "SW420",
    "scanner-unread",
    group="views",
    stage="static",
    severity="error",
    summary="Every scanner of a split view the skill subscribes to is read.",
    why="Two scanners on opposite corners each see half around: reading one misses an "
    "obstacle only the other sees.",
    example="# scan2_msg kept by its callback, read by nothing",
    fix="Hands the second scan to the same closest-reading call, which gives the closer "
    "reading of both.",
    safety="unsafe",
    data=("attribute", "interface"),
    grounds=("the robot",),
)

EXACT_EQUALITY = Rule(
    "SW421",
    "exact-equality",
    group="equality",
    stage="static",
    severity="error",
    summary="A measured value is compared with a tolerance, not with == or != (an error where "
    "the comparison decides when a loop ends, a warning elsewhere).",
    why="Odometry, scans and transforms are noisy floats: a reached velocity is 0.2994 or "
    "0.3008, never exactly the 0.3 asked for, so the loop never ends or the test never holds.",
    example="while velocity == self.odom_msg.twist.twist.linear.x:",
    fix="Compares the difference with a tolerance.",
    safety="unsafe",
    data=("reading", "other"),
    grounds=("ROS 2",),
)
