"""SW3xx: the rclpy, tf2 and skeleton-helper API as a skill calls it, and its own names.

rclpy's handles (node, publisher, subscription, client, action client, timer, clock, time,
duration, future, goal handle) and tf2's Buffer have the attributes and signatures their
libraries give them; the skeleton's helpers (``_wait_until``, ``_transform``, ``_result_of``,
the goal helpers) have theirs. A made-up attribute, a call with the wrong arguments or a
name nothing defines raises on the robot, mid-task; these rules read the API instead.
"""

from __future__ import annotations

from skillwright.rules.registry import Rule

__all__ = [
    "ATTRIBUTE_NEVER_SET",
    "ATTRIBUTE_ONLY_NONE",
    "FEEDBACK_CALLBACK_NOT_TIMEOUT",
    "FUTURE_METHOD_ON_RESULT",
    "GOAL_RESULT_WITHOUT_SEND",
    "HANDLE_MADE_TWICE",
    "HELPER_CALL_MISMATCH",
    "LOCAL_HIDES_MODULE",
    "LOCAL_READ_AS_ATTRIBUTE",
    "METHOD_CALL_MISMATCH",
    "METHOD_OVERWRITTEN",
    "MODULE_AS_NUMBER",
    "MODULE_SHADOWED",
    "NESTED_MESSAGE_CLASS",
    "NONE_RESULT_USED",
    "RCLPY_CALL_ARGUMENTS",
    "ROS1_API",
    "TIMER_NEVER_CANCELLED",
    "TIMER_NOT_KEPT",
    "UNDEFINED_NAME",
    "UNKNOWN_API_ATTRIBUTE",
]

_RCLPY = ("rclpy",)

GOAL_RESULT_WITHOUT_SEND = Rule(
    "SW301",
    "goal-result-without-send",
    group="names",
    stage="static",
    severity="error",
    summary="A goal's result is waited for only where the skill sends that goal.",
    why="The skeleton's self._X_result() waits on the goal handle self._send_X_goal() "
    "returned; without the send there is no goal and the wait can only time out.",
    example="result = self._navigate_result(30.0)  # _send_navigate_goal is never called",
    data=("helper", "send"),
    grounds=("the skeleton", "rclpy"),
)

HANDLE_MADE_TWICE = Rule(
    "SW302",
    "handle-made-twice",
    group="handles",
    stage="static",
    severity="error",
    summary="A handle kept on the skill is made in one state only.",
    why="rclpy keeps every publisher, subscription and client a node made until it is "
    "destroyed: making it again leaks the first, and a second subscription runs its "
    "callback twice for every message.",
    example="self.odom_sub = self.node.create_subscription(...)  # in starting and in execute",
    fix="Removes the second making; the state uses the handle made first.",
    safety="unsafe",
    data=("attribute", "first"),
    grounds=_RCLPY,
)

TIMER_NEVER_CANCELLED = Rule(
    "SW303",
    "timer-never-cancelled",
    group="handles",
    stage="static",
    severity="error",
    summary="A timer kept on the skill is cancelled somewhere.",
    why="An rclpy timer fires until cancelled or destroyed: one that commands motion goes on "
    "commanding it after the skill stopped.",
    example="self.timer = self.node.create_timer(0.1, self._drive)  # never cancelled",
    data=("timer",),
    grounds=_RCLPY,
)

TIMER_NOT_KEPT = Rule(
    "SW304",
    "timer-not-kept",
    group="handles",
    stage="static",
    severity="error",
    summary="A timer is kept on the skill, so that something can cancel it.",
    why="A timer held only by a local variable (or by nothing) still fires: rclpy's node "
    "keeps it, and nothing can cancel it once the method returned.",
    example="self.node.create_timer(0.1, self._drive)",
    fix="Keeps the timer as an attribute of the skill.",
    safety="unsafe",
    data=("attribute",),
    grounds=_RCLPY,
)

ROS1_API = Rule(
    "SW310",
    "ros1-api",
    group="names",
    stage="static",
    severity="error",
    summary="The skill uses ROS 2 (rclpy), not ROS 1's rospy.",
    why="rospy does not exist on a ROS 2 robot; its calls have rclpy equivalents on the "
    "skill's node.",
    example="rospy.loginfo('done')",
    fix="Writes the rclpy equivalent on the skill's node where there is one.",
    safety="unsafe",
    data=("name",),
    grounds=_RCLPY,
)

UNDEFINED_NAME = Rule(
    "SW311",
    "undefined-name",
    group="names",
    stage="static",
    severity="error",
    summary="Every name the skill reads is defined: imported, assigned, a builtin or one of "
    "pySkillUp's.",
    why="An undefined name raises NameError when the line runs, on the robot.",
    example="msg = Twist()  # Twist never imported",
    fix="Reads the name from the skill (self.name) where another method of it keeps a local "
    "of that name.",
    safety="unsafe",
    data=("name",),
    grounds=("Python", "pySkillUp"),
)

LOCAL_READ_AS_ATTRIBUTE = Rule(
    "SW312",
    "local-read-as-attribute",
    group="names",
    stage="static",
    severity="error",
    summary="What one method keeps in a local variable, others do not read from the skill.",
    why="self.name is never set when only a local called name exists: the reading method "
    "raises AttributeError.",
    example="# execute: remaining = ...; completing: self.remaining",
    fix="Keeps the local on the skill once the method is done changing it.",
    safety="unsafe",
    data=("name", "method"),
    grounds=("Python",),
)

ATTRIBUTE_NEVER_SET = Rule(
    "SW313",
    "attribute-never-set",
    group="names",
    stage="static",
    severity="error",
    summary="Every attribute the skill reads from self is set in the class (or given by "
    "ROS2Skill, or a method of it).",
    why="A made-up attribute raises AttributeError where it is read, on the robot; often a "
    "misspelling of the handle or message the class does keep.",
    example="self.velocity_publisher.publish(cmd)  # the class keeps self.cmd_vel_publisher",
    fix="Uses the attribute it evidently means (the underscored one the class sets), or "
    "leaves out a made-up limit or a made-up field of a log line.",
    safety="unsafe",
    data=("attribute", "candidates"),
    grounds=("Python", "pySkillUp"),
)

ATTRIBUTE_ONLY_NONE = Rule(
    "SW314",
    "attribute-only-none",
    group="names",
    stage="static",
    severity="error",
    summary="An attribute whose fields or methods the skill uses is set to something other "
    "than None somewhere.",
    why="Set only to None, every use of its fields raises AttributeError when it runs.",
    example="self.goal_handle = None  # and later self.goal_handle.cancel_goal_async()",
    data=("attribute",),
    grounds=("Python",),
)

UNKNOWN_API_ATTRIBUTE = Rule(
    "SW315",
    "unknown-api-attribute",
    group="names",
    stage="static",
    severity="error",
    summary="An attribute of an rclpy handle or a tf2 Buffer is one that API has.",
    why="rclpy's Publisher, Subscription, Client, ActionClient, Timer, Clock, Time, "
    "Duration, Future and goal handles, and tf2's Buffer, have a fixed API; a made-up "
    "method (publisher.is_ready(), Buffer.destroy(), time.seconds) raises AttributeError.",
    example="self.tf_buffer.destroy()",
    fix="Writes what the API offers for it: nanoseconds / 1e9 for seconds, the handle's "
    "own teardown, the skeleton's wait for a latest message; or leaves the call out.",
    safety="unsafe",
    data=("receiver", "kind", "attribute"),
    grounds=("rclpy", "tf2"),
)

NESTED_MESSAGE_CLASS = Rule(
    "SW316",
    "nested-message-class",
    group="names",
    stage="static",
    severity="error",
    summary="A message's field types are imported from their own packages, not reached as "
    "classes of the message.",
    why="Generated message classes hold no classes for their fields: Twist.Vector3 raises "
    "AttributeError; Vector3 comes from geometry_msgs.msg.",
    example="Twist.Vector3(x=0.5)",
    fix="Uses the field's own message class where the field is known.",
    safety="safe",
    data=("owner", "name"),
    grounds=("ROS 2",),
)

LOCAL_HIDES_MODULE = Rule(
    "SW317",
    "local-hides-module",
    group="names",
    stage="static",
    severity="error",
    summary="No local variable takes the name of a module the method also uses.",
    why="Python makes a name local to the whole function once it is assigned anywhere in it: "
    "`time = ...` after `time.sleep(...)` makes the sleep raise UnboundLocalError.",
    example="time.sleep(0.1)\ntime = self.node.get_clock().now()",
    fix="Renames the local variable.",
    safety="safe",
    data=("module", "method", "local"),
    grounds=("Python",),
)

MODULE_SHADOWED = Rule(
    "SW318",
    "module-shadowed",
    group="names",
    stage="static",
    severity="error",
    summary="A module used in a method is not also assigned as a local there.",
    why="The assignment makes the module's name local in the whole method: every use of the "
    "module in it raises UnboundLocalError.",
    example="math = abs(x)\nmath.pi",
    data=("module", "method"),
    grounds=("Python",),
)

MODULE_AS_NUMBER = Rule(
    "SW319",
    "module-as-number",
    group="names",
    stage="static",
    severity="error",
    summary="A module is not used as a number in arithmetic or comparison.",
    why="`time - start` with `time` the module raises TypeError when it runs.",
    example="elapsed = time - self.start",
    fix="Uses the value the method evidently meant (its local of a similar name).",
    safety="unsafe",
    data=("module",),
    grounds=("Python",),
)

NONE_RESULT_USED = Rule(
    "SW320",
    "none-result-used",
    group="names",
    stage="static",
    severity="error",
    summary="The value of a skill method that returns nothing is not used.",
    why="A method annotated -> None always gives None: storing or testing it is a mistake, "
    "and a guard on it is always false.",
    example="ok = self._stop_base()\nif not ok: raise ...",
    fix="Calls the method as a statement of its own (and waits for the result where it "
    "sent a goal).",
    safety="unsafe",
    data=("method",),
    grounds=("Python", "the skeleton"),
)

HELPER_CALL_MISMATCH = Rule(
    "SW321",
    "helper-call-mismatch",
    group="names",
    stage="static",
    severity="error",
    summary="A method of the skill is defined to take what its calls give it.",
    why="A call with arguments the definition does not take raises TypeError when it runs.",
    example="def _drive(self): ...\nself._drive(0.5)",
    data=("method", "signature"),
    grounds=("Python",),
)

METHOD_CALL_MISMATCH = Rule(
    "SW322",
    "method-call-mismatch",
    group="names",
    stage="static",
    severity="error",
    summary="A call of a skill method or skeleton helper gives what its definition takes.",
    why="The skeleton's helpers have fixed signatures (_transform(target, source, timeout), "
    "_result_of(future, timeout, what)); other arguments raise TypeError.",
    example='self._transform("map", "base_link", 2.0, True)',
    fix="Gives a helper's wait that was called without its timeout the skeleton's two seconds.",
    safety="unsafe",
    data=("method", "signature"),
    grounds=("the skeleton",),
)

FUTURE_METHOD_ON_RESULT = Rule(
    "SW323",
    "future-method-on-result",
    group="names",
    stage="static",
    severity="error",
    summary="What self._result_of(...) returned is used as the response or result it is, not "
    "as a future.",
    why="_result_of waits for the future and returns its result: .done() or .result() on "
    "that raises AttributeError.",
    example="response = self._result_of(future, 5.0, 'the map')\nif not response.done(): ...",
    fix="Leaves out a guard that only raises, and reads the value itself for .result().",
    safety="safe",
    data=("name",),
    grounds=("the skeleton", "rclpy"),
)

RCLPY_CALL_ARGUMENTS = Rule(
    "SW324",
    "rclpy-call-arguments",
    group="names",
    stage="static",
    severity="error",
    summary="Calls of rclpy handles give what rclpy's signatures take (call_async, call, "
    "wait_for_service, send_goal_async, send_goal, wait_for_server, publish).",
    why="rclpy raises TypeError for other arguments: call_async(request, 5.0) is a common "
    "one, as a future has no timeout.",
    example="self.client.call_async(request, 5.0)",
    fix="Moves a timeout handed to call_async into the skeleton's wait for the response.",
    safety="unsafe",
    data=("handle", "method"),
    grounds=_RCLPY,
)

FEEDBACK_CALLBACK_NOT_TIMEOUT = Rule(
    "SW325",
    "feedback-callback-not-timeout",
    group="names",
    stage="static",
    severity="error",
    summary="send_goal_async gets a callable as its feedback callback, not a number.",
    why="The second argument of ActionClient.send_goal_async is feedback_callback; a number "
    "there is called with every feedback and raises TypeError in the executor.",
    example="self.client.send_goal_async(goal, 30.0)",
    data=("handle", "method", "argument"),
    grounds=_RCLPY,
)

METHOD_OVERWRITTEN = Rule(
    "SW326",
    "method-overwritten",
    group="names",
    stage="static",
    severity="error",
    summary="No assignment replaces a method of the skill with a value.",
    why="After `self._closest_reading = self._closest_reading(scan)` every later call of it "
    "raises TypeError (a tuple is not callable).",
    example="self._closest_reading = self._closest_reading(self.scan_msg)",
    fix="Keeps the value in a local of the method's name.",
    safety="safe",
    data=("method", "local"),
    grounds=("Python",),
)
