"""Names nothing defines: unimported classes, attributes never set, rclpy calls that do not exist."""

from __future__ import annotations

import pytest

from skillwright.capability import Capability
from skillwright.rules.api import UNKNOWN_API_ATTRIBUTE
from skillwright.rules.finding import Finding
from skillwright.spec import SkillSpec
from skillwright.validation.model import CheckReport
from skillwright.validation.static import check_skill
from tests.validation.test_static import CATALOG, GOOD


def _check(source: str, inputs: tuple[Capability, SkillSpec]) -> CheckReport:
    capability, spec = inputs
    return check_skill(source, capability=capability, spec=spec, catalog=CATALOG)


def stopping_with(statements: str) -> str:
    """The good skill with ``statements`` first in its stopping state."""
    halt = '        """Halt the base."""\n'
    return GOOD.replace(halt, halt + statements, 1)


def with_method(method: str, statements: str) -> str:
    """The good skill with ``method`` (class indentation, ending in ``@execute``) before its
    execute state, and ``statements`` before the execute's stop."""
    stop = "        self.cmd_vel_publisher.publish(Twist())\n        self.out_distance"
    return GOOD.replace("    @execute\n", method, 1).replace(stop, statements + stop, 1)


def _names(source: str, inputs: tuple[Capability, SkillSpec]) -> list[Finding]:
    """The findings of the names check."""
    return [f for f in _check(source, inputs).findings if f.check == "names"]


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        (
            "command = Twist()",
            "command = Twist(linear=Vector3(x=speed))",
            "Vector3 is not defined: import it",
        ),
        (
            "command.linear.x = speed",
            "command.linear.x = velocity",
            "velocity is not defined: no statement of this method assigns it before it is read",
        ),
        (
            'self.node.get_logger().info(f"{self.in_distance}',
            'self.logger.info(f"{self.in_distance}',
            "self.logger is never set in this class; log with self.node.get_logger()",
        ),
        (
            "while self.odom_msg is None and time.time() < deadline:",
            "while self.odom_mgs is None and time.time() < deadline:",
            "self.odom_mgs is never set in this class; did you mean self.odom_msg?",
        ),
        (
            "            time.sleep(0.05)\n\n    @execute",
            "            self.odom_subscription.wait_for_message(timeout_sec=0.05)\n\n    @execute",
            "self.odom_subscription is a Subscription, which has no 'wait_for_message' in rclpy; "
            "its callback keeps the latest message in self.odom_msg: wait for the first one with "
            'self._wait_until(lambda: self.odom_msg is not None, 2.0, "odom_msg")',
        ),
        (
            "self.cmd_vel_publisher.publish(command)",
            "self.cmd_vel_publisher.send(command)",
            "self.cmd_vel_publisher is a Publisher, which has no 'send' in rclpy",
        ),
        (
            'self.node.get_logger().info(f"{self.in_distance}',
            'self.node.get_logger().write(f"{self.in_distance}',
            "is the logger, which has no 'write' in rclpy",
        ),
        (
            'self.node.get_logger().info(f"{self.in_distance}',
            'self.node.info(f"{self.in_distance}',
            "self.node is the node (rclpy Node), which has no 'info' in rclpy; info belongs to "
            "the logger: self.node.get_logger().info(...)",
        ),
        (
            "    def _travelled(self) -> float:",
            "    def _travelled(self, p: Odometry.Pose = None) -> float:",
            "Odometry.Pose does not exist",
        ),
    ],
    ids=[
        "unimported class",
        "unassigned variable",
        "logger on the skill",
        "misspelt attribute",
        "subscription method",
        "publisher method",
        "logger method",
        "logger method on the node",
        "nested message class",
    ],
)
def test_names_nothing_defines_are_errors_located_at_their_use(
    move_forward: tuple[Capability, SkillSpec], old: str, new: str, expected: str
) -> None:
    assert old in GOOD
    source = GOOD.replace(old, new, 1)
    found = _names(source, move_forward)
    assert any(expected in f.message for f in found), found
    finding = next(f for f in found if expected in f.message)
    assert finding.severity == "error"
    changed = next(line.strip() for line in new.splitlines() if line.strip() not in old)
    assert changed[:20] in source.splitlines()[finding.line - 1]


@pytest.mark.parametrize(
    ("statement", "unknown"),
    [
        # rclpy's Node has it, and so has the sandbox's stand-in
        ("self.node.remove_on_set_parameters_callback(print)", []),
        ("self.node.get_publishers_info_by_topic('/odom')", []),
        ("self.node.get_subscriptions_info_by_topic('/cmd_vel')", []),
        # rclpy's Node has no such method, nor has the stand-in
        ("self.node.get_publishers_by_topic('/odom')", ["get_publishers_by_topic"]),
    ],
)
def test_the_node_api_the_checks_accept_is_the_sandboxs(
    move_forward: tuple[Capability, SkillSpec], statement: str, unknown: list[str]
) -> None:
    source = stopping_with(f"        {statement}\n")
    found = [f for f in _names(source, move_forward) if f.code == UNKNOWN_API_ATTRIBUTE.code]
    assert [f.data["attribute"] for f in found] == unknown


def test_a_message_asked_of_a_subscription_is_waited_for_once_and_taken_from_the_callback(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # What the eval's MR-1 get-distance answer did: wait, guard, then keep the message.
    source = GOOD.replace(
        "        self.start_x = self.odom_msg.pose.pose.position.x\n",
        "        self.odom_subscription.wait_for_messages(timeout_sec=2.0)\n"
        "        if not self.odom_subscription.get_last_message():\n"
        '            raise RuntimeError("no odometry within 2 s")\n'
        "        odom = self.odom_subscription.get_last_message()\n"
        "        self.start_x = odom.pose.pose.position.x\n",
        1,
    )
    found = [f for f in _names(source, move_forward) if "Subscription" in f.message]
    wait = 'self._wait_until(lambda: self.odom_msg is not None, 2.0, "odom_msg")'
    # The first asks for the wait; the guard and the second ask are then left out, and the
    # message is taken from where the callback keeps it.
    assert [f.replacement for f in found] == [wait, "", "odom = self.odom_msg"]


def _logged(source: str, more: str) -> str:
    """``source`` with ``more`` added to what completing logs."""
    return source.replace(
        '{self.out_distance} m done")', f'{{self.out_distance}} m done{more}")', 1
    )


def test_a_local_variable_other_methods_read_from_the_skill_is_found_where_it_is_made(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "        command = Twist()\n",
        "        command = Twist()\n        timer = self.node.create_timer(0.05, self._travelled)\n",
        1,
    ).replace(
        '        """Halt the base."""\n',
        '        """Halt the base."""\n        self.timer.cancel()\n',
        1,
    )
    found = _names(source, move_forward)
    assert [f.message for f in found] == [
        "timer is a local variable of execute, but stopping read self.timer: "
        "assign it as self.timer = ... here"
    ]
    assert "timer = self.node.create_timer" in source.splitlines()[found[0].line - 1]
    # the fix keeps the value on the skill where it is made
    assert found[0].replacement == (
        "timer = self.node.create_timer(0.05, self._travelled)\nself.timer = timer"
    )


def test_a_local_variable_of_another_method_is_found_where_it_is_used(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = _logged(GOOD, " at {speed} m/s")
    found = _names(source, move_forward)
    assert [f.message for f in found] == [
        "speed is a local variable of execute and does not exist here: use what execute "
        "stored on the skill (it keeps self.start_x, self.start_y, self.out_distance, "
        "self.out_linear_velocity), or get the value again here"
    ]
    assert "m done at {speed}" in source.splitlines()[found[0].line - 1]
    # the fix reads it from the skill; the next check has execute keep it there
    assert found[0].replacement == (
        "self.node.get_logger().info(f'{self.in_distance} m asked, {self.out_distance} m done "
        "at {self.speed} m/s')"
    )


def test_locals_of_another_method_in_one_statement_are_all_read_from_the_skill_at_once(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = _logged(GOOD, " at {speed}, {command}")
    found = _names(source, move_forward)
    assert [f.message.split(" and ")[0] for f in found] == [
        "speed is a local variable of execute",
        "command is a local variable of execute",
    ]
    fix = (
        "self.node.get_logger().info(f'{self.in_distance} m asked, {self.out_distance} m done "
        "at {self.speed}, {self.command}')"
    )
    assert [f.replacement for f in found] == [fix, fix]


TRY = "        try:\n            scale = float(self.in_distance)\n        except ValueError:\n            raise\n"
BRANCH = "        scale = 1.0\n        if self.in_distance > 2.0:\n            scale = 0.5\n"


@pytest.mark.parametrize(
    ("made", "in_loop", "where", "fix"),
    [
        # made in a try block: kept right after it is made
        (TRY, "", "scale = float(self.in_distance)", "scale = float(self.in_distance)"),
        # updated by a loop: kept on every pass
        ("        scale = 1.0\n", "            scale = scale * 0.9\n", "scale = scale * 0.9", ""),
        # changed in a branch: kept after the branch, whichever ran
        (BRANCH, "", "if self.in_distance > 2.0:", "if self.in_distance > 2.0:\n    scale = 0.5"),
    ],
)
def test_a_local_is_kept_on_the_skill_where_its_method_is_done_changing_it(
    move_forward: tuple[Capability, SkillSpec], made: str, in_loop: str, where: str, fix: str
) -> None:
    publish = "            self.cmd_vel_publisher.publish(command)\n"
    source = GOOD.replace("        command = Twist()\n", f"        command = Twist()\n{made}", 1)
    source = _logged(source.replace(publish, publish + in_loop, 1), ", {self.scale}")
    found = _names(source, move_forward)
    assert [f.message for f in found] == [
        "scale is a local variable of execute, but completing read self.scale: "
        "assign it as self.scale = ... here"
    ]
    assert source.splitlines()[found[0].line - 1].strip() == where
    assert found[0].replacement == f"{fix or where}\nself.scale = scale"


def test_an_invented_attribute_with_no_close_name_points_to_the_latest_messages(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        '{self.out_distance} m done")',
        '{self.out_distance} m done, {self.measured_speed_now} m/s")',
        1,
    )
    found = _names(source, move_forward)
    assert [f.message for f in found] == [
        "self.measured_speed_now is never set in this class; the latest messages are in "
        "self.odom_msg (Odometry): read the field from there"
    ]


def test_an_attribute_close_to_a_method_name_suggests_calling_the_method(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = _logged(GOOD, ", {self._travelled_m}")
    found = _names(source, move_forward)
    assert [f.message for f in found] == [
        "self._travelled_m is never set in this class; did you mean the method "
        "self._travelled(...)?"
    ]


HALT = (
    "    def _halt(self) -> None:\n"
    '        """Commands zero velocity; returns once published."""\n'
    "        self.cmd_vel_publisher.publish(Twist())\n\n"
    "    @execute\n"
)


def test_the_value_of_a_method_that_returns_nothing_is_an_error_at_its_use(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    stop = "        self.cmd_vel_publisher.publish(Twist())\n        self.out_distance"
    source = GOOD.replace("    @execute\n", HALT, 1).replace(
        stop,
        "        halted = self._halt()\n"
        "        if not halted:\n"
        "            self._halt()\n"
        "        later = lambda: self._halt()\n"
        "        later()\n"
        "        self.out_distance",
        1,
    )
    found = _names(source, move_forward)
    assert [(f.message, f.replacement) for f in found] == [
        (
            f"self._halt() returns nothing (its definition, line {_line(source, 'def _halt')}, "
            "says -> None) (Commands zero velocity), so its value is always None: call it as a "
            "statement of its own",
            "self._halt()",
        )
    ]
    assert found[0].line == _line(source, "halted = self._halt()")


def _line(source: str, text: str) -> int:
    return next(n for n, line in enumerate(source.splitlines(), 1) if text in line)


def test_the_good_skill_uses_no_undefined_name(move_forward: tuple[Capability, SkillSpec]) -> None:
    assert not _names(GOOD, move_forward)


def test_pyskillup_decorators_builtins_and_locals_are_known(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)",
        "        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)\n"
        "        values = [round(v, 2) for v in (speed, 1.0)]\n"
        "        for index, value in enumerate(values):\n"
        "            self.node.get_logger().debug(f'{index}: {value}')",
    )
    assert not _names(source, move_forward)


def test_a_goal_handle_method_asked_of_the_action_client_gets_the_goal_handle_statement(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = stopping_with(
        '        self.nav_client = ActionClient(self.node, NavigateToPose, "/navigate_to_pose")\n'
        "        self.nav_client.cancel_goal_async()\n"
    )
    found = [f.message for f in _names(source, move_forward)]
    assert (
        "self.nav_client is an ActionClient, which has no 'cancel_goal_async' in rclpy; it "
        "belongs to the goal handle that sending the goal gives: self.goal_handle = "
        'self._result_of(self.nav_client.send_goal_async(goal), 5.0, "goal acceptance"), then '
        "self.goal_handle.get_result_async() or self.goal_handle.cancel_goal_async()"
    ) in found


def test_an_invented_constant_is_named_with_the_constants_the_skeleton_has(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace("self.LINEAR_VELOCITY_MAX)", "self.SPEED_LIMIT)", 1)
    assert [f.message for f in _names(source, move_forward)] == [
        "self.SPEED_LIMIT is never set in this class; the skeleton's constants (the "
        "resource's requirements) are self.LINEAR_VELOCITY_MAX and none is SPEED_LIMIT: use one "
        "of them, or leave the limit out"
    ]


def _without_constants(source: str) -> str:
    """``source`` without the skeleton's class constants, as for a capability that states no
    resource requirements."""
    return "".join(
        line for line in source.splitlines(keepends=True) if "LINEAR_VELOCITY_MAX =" not in line
    )


@pytest.mark.parametrize(
    ("reads", "replacement"),
    [
        # a clamp to the made-up limit goes
        (
            "        speed = abs(self.in_linear_velocity)\n"
            "        if speed > self.LINEAR_VELOCITY_MAX:\n"
            "            speed = self.LINEAR_VELOCITY_MAX\n",
            "",
        ),
        (
            "        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)\n",
            "speed = abs(self.in_linear_velocity)",
        ),
        # what the limit would stand for otherwise is the model's to say
        ("        speed = self.LINEAR_VELOCITY_MAX / 2\n", None),
        (
            "        speed = abs(self.in_linear_velocity)\n"
            "        if speed > self.LINEAR_VELOCITY_MAX:\n"
            "            raise ValueError('too fast')\n",
            None,
        ),
    ],
)
def test_a_made_up_limit_the_capability_does_not_state_is_left_out_where_that_is_plain(
    move_forward: tuple[Capability, SkillSpec], reads: str, replacement: str | None
) -> None:
    source = _without_constants(GOOD).replace(
        "        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)\n", reads
    )
    (found,) = _names(source, move_forward)
    assert found.replacement == replacement


def test_a_constant_read_where_the_capability_states_no_limits_says_so(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # The idiom of the worked examples, copied for a capability without resource requirements.
    source = _without_constants(GOOD)
    assert [f.message for f in _names(source, move_forward)] == [
        "self.LINEAR_VELOCITY_MAX is never set in this class; the capability states no limits, "
        "so the skeleton defines no constants: leave the limit out (a value made up for "
        "LINEAR_VELOCITY_MAX is one nobody gave), and work with the inputs and the messages"
    ]


@pytest.mark.parametrize("written", ["in_max_speed", "IN_MAX_SPEED"])
def test_an_input_the_capability_does_not_have_is_named_with_the_inputs_it_has(
    move_forward: tuple[Capability, SkillSpec], written: str
) -> None:
    source = GOOD.replace(
        "speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)",
        f"speed = min(abs(self.in_linear_velocity), self.{written})",
        1,
    )
    assert [f.message for f in _names(source, move_forward)] == [
        f"self.{written} is never set in this class; the capability's inputs are "
        "self.in_distance, self.in_linear_velocity and none gives max_speed: give it a value in "
        "a local variable of this method (max_speed = ...)"
    ]


@pytest.mark.parametrize(
    ("handle", "words"),
    [("tf_listener", "a tf2 TransformListener"), ("tf_buffer", "a tf2 Buffer")],
)
def test_a_transform_listener_or_buffer_torn_down_is_a_call_left_out(
    move_forward: tuple[Capability, SkillSpec], handle: str, words: str
) -> None:
    # rclpy's tf2 Buffer has no destroy(): a skill of the evaluation failed its cleanup on it.
    source = stopping_with(
        "        self.tf_buffer = Buffer()\n"
        "        self.tf_listener = TransformListener(self.tf_buffer, self.node)\n"
        f"        self.{handle}.destroy()\n"
    )
    (found,) = [f for f in _names(source, move_forward) if "destroy" in f.message]
    assert found.message == (
        f"self.{handle} is {words}, which has no 'destroy' in rclpy; it needs "
        "no teardown of its own: leave the call out"
    )
    assert found.replacement == ""


def test_a_tf2_buffer_asked_for_what_it_has_is_not_a_finding(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = stopping_with(
        "        self.tf_buffer = Buffer()\n"
        "        if self.tf_buffer.can_transform('odom', 'base_link', Time()):\n"
        "            self.tf_buffer.lookup_transform('odom', 'base_link', Time())\n"
        "        self.tf_buffer.lookup_frame('odom')\n"
    )
    found = [f.message for f in _names(source, move_forward) if "tf_buffer" in f.message]
    assert found == [
        "self.tf_buffer is a tf2 Buffer, which has no 'lookup_frame' in rclpy; did you mean "
        "lookup_transform?"
    ]


@pytest.mark.parametrize("helper", [True, False], ids=["skeleton-helper", "no-helper"])
def test_cancelling_all_goals_of_an_action_client_is_the_skeletons_cancel_helper(
    move_forward: tuple[Capability, SkillSpec], helper: bool
) -> None:
    source = stopping_with(
        '        self.nav_client = ActionClient(self.node, NavigateToPose, "/navigate_to_pose")\n'
        "        self.nav_client.cancel_all_goals()\n"
    )
    if helper:
        source = source.replace(
            "    @stopping\n",
            "    def _cancel_nav_goal(self, timeout: float) -> None:\n"
            '        """Cancel the goal sent."""\n\n'
            "    @stopping\n",
            1,
        )
    (found,) = [f for f in _names(source, move_forward) if "cancel_all_goals" in f.message]
    if helper:
        assert found.message.endswith(
            "; the skeleton's self._cancel_nav_goal(timeout) cancels the goal this client sent"
        )
        assert found.replacement == "self._cancel_nav_goal(5.0)"
    else:
        assert found.replacement is None


def test_a_local_variable_that_hides_a_standard_module_is_renamed_in_every_statement(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = stopping_with(
        "        time = 0.5\n"
        "        if time > 0.2:\n"
        "            time = 0.2\n"
        "        time.sleep(time)\n"
    )
    found = _names(source, move_forward)
    lines = source.splitlines()
    assert [(lines[f.line - 1].strip(), f.replacement) for f in found] == [
        ("time = 0.5", "time_value = 0.5"),
        ("if time > 0.2:", "if time_value > 0.2:\n    time_value = 0.2"),
        ("time.sleep(time)", "time.sleep(time_value)"),
    ]
    assert all("renamed to time_value" in f.message for f in found)


def test_a_hidden_module_in_a_statement_that_cannot_be_replaced_whole_is_only_named(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = stopping_with(
        "        time = 0.5\n        for _ in range(2):\n            time.sleep(time)\n"
    )
    found = _names(source, move_forward)
    assert [(f.message, f.replacement) for f in found] == [
        (
            "time is the module time, which stopping also uses; a local variable of that "
            "name hides it in the whole method: name the variable differently",
            None,
        )
    ]
    assert source.splitlines()[found[0].line - 1].strip() == "time = 0.5"


@pytest.mark.parametrize(
    ("statements", "flagged", "replacement"),
    [
        (  # ev71: the local was renamed in one statement and not in the loop
            "        time_value = 0.5\n"
            "        start = time.monotonic()\n"
            "        while time.monotonic() - start < time:\n"
            "            time.sleep(0.05)\n",
            "while time.monotonic() - start < time:",
            "while time.monotonic() - start < time_value:\n    time.sleep(0.05)",
        ),
        (  # no local stands for it, an attribute of its name does
            "        self.in_time = 0.5\n"
            "        if time.monotonic() > time * 2:\n"
            "            pass\n",
            "if time.monotonic() > time * 2:",
            "if time.monotonic() > self.in_time * 2:\n    pass",
        ),
        (  # nothing to tell what was meant
            "        self.out_distance = -math\n",
            "self.out_distance = -math",
            None,
        ),
    ],
)
def test_a_module_used_as_a_number_is_found(
    move_forward: tuple[Capability, SkillSpec],
    statements: str,
    flagged: str,
    replacement: str | None,
) -> None:
    source = stopping_with(statements)
    found = [f for f in _names(source, move_forward) if "as a number" in f.message]
    assert [(source.splitlines()[f.line - 1].strip(), f.replacement) for f in found] == [
        (flagged, replacement)
    ]
    assert "raises TypeError when it runs" in found[0].message


def test_a_module_level_function_parameter_is_not_an_undefined_name(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "\n\n@skill(",
        "\n\ndef _wrap(angle: float) -> float:\n    return math.atan2(math.sin(angle), "
        "math.cos(angle))\n\n\n@skill(",
        1,
    )
    assert "def _wrap(angle" in source
    assert not _names(source, move_forward)


def test_a_made_up_class_for_a_geometry_field_comes_with_the_statement_using_its_type(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace("command = Twist()", "command = Twist(linear=Twist.Linear(x=0.1))", 1)
    found = _names(source, move_forward)
    assert [(f.message, f.replacement) for f in found] == [
        (
            "Twist.Linear does not exist: message classes have no classes for their fields; "
            "linear is a Vector3: use Vector3(...)",
            "command = Twist(linear=Vector3(x=0.1))",
        )
    ]


def test_a_made_up_class_with_no_known_type_gets_no_replacement(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace("command = Twist()", "command = Twist(linear=Twist.Velocity(x=0.1))", 1)
    found = _names(source, move_forward)
    assert [f.replacement for f in found] == [None]
    assert "use the field's own type" in found[0].message


@pytest.mark.parametrize(
    ("guard", "replacement"),
    [
        (
            "        if self.cmd_vel_publisher.is_alive():\n"
            "            self.cmd_vel_publisher.publish(Twist())\n",
            "self.cmd_vel_publisher.publish(Twist())",
        ),
        (
            "        if not self.cmd_vel_publisher.is_alive():\n"
            '            raise RuntimeError("no publisher")\n'
            "        self.cmd_vel_publisher.publish(Twist())\n",
            "",
        ),
    ],
    ids=["guards work", "guards nothing"],
)
def test_a_guard_on_a_publisher_method_that_does_not_exist_comes_to_what_it_guards(
    move_forward: tuple[Capability, SkillSpec], guard: str, replacement: str
) -> None:
    source = GOOD.replace(
        '        """Halt the base."""\n        self.cmd_vel_publisher.publish(Twist())\n',
        '        """Halt the base."""\n' + guard,
        1,
    )
    found = _names(source, move_forward)
    assert [f.replacement for f in found] == [replacement]
    assert "a publisher is ready from create_publisher until it is destroyed" in found[0].message


def test_a_method_of_the_node_or_logger_called_elsewhere_comes_with_its_statement_fixed(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace("self.node.get_logger().info(f", "self.node.info(f", 1)
    (found,) = _names(source, move_forward)
    assert found.replacement is not None
    assert found.replacement.startswith("self.node.get_logger().info(f")
    source = GOOD.replace(
        '        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)\n',
        '        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)\n'
        "        self.tf_listener = TransformListener(Buffer(), self.node)\n"
        "        self.started = self.tf_listener.get_clock().now()\n",
        1,
    )
    found = [f for f in _names(source, move_forward) if "self.tf_listener is" in f.message]
    assert [(f.message, f.replacement) for f in found] == [
        (
            "self.tf_listener is a tf2 TransformListener, which has no 'get_clock' in rclpy; "
            "get_clock belongs to the node: self.node.get_clock(...)",
            "self.started = self.node.get_clock().now()",
        )
    ]


@pytest.mark.parametrize(
    ("call", "expected"),
    [
        ("self._travelled(1.0)", "too many positional arguments"),
        ("self._travelled(limit=1.0)", "got an unexpected keyword argument 'limit'"),
    ],
)
def test_a_helper_that_does_not_take_what_its_call_gives_is_found_at_its_definition(
    move_forward: tuple[Capability, SkillSpec], call: str, expected: str
) -> None:
    source = stopping_with(f"        {call}\n")
    [finding] = _names(source, move_forward)
    lines = source.splitlines()
    assert lines[finding.line - 1].strip().startswith("def _travelled(self)")
    called_at = next(n for n, line in enumerate(lines, start=1) if call in line)
    assert f"_travelled() does not take what its call at line {called_at} gives" in (
        finding.message
    )
    assert expected in finding.message


def test_a_documented_method_called_wrongly_is_found_at_the_call(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    helper = (
        "    def _stop(self, timeout):\n"
        '        """Stops the base."""\n'
        "        self.cmd_vel_publisher.publish(Twist())\n\n"
        "    @stopping\n"
    )
    source = stopping_with("        self._stop()\n").replace("    @stopping\n", helper, 1)
    [finding] = _names(source, move_forward)
    assert source.splitlines()[finding.line - 1].strip() == "self._stop()"
    assert "missing a required argument: 'timeout'" in finding.message
    # the timeout is all it leaves out: the fix gives it the helpers' two seconds
    assert finding.replacement == "self._stop(2.0)"


def test_a_documented_helper_missing_more_than_its_timeout_gets_no_fix(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    helper = (
        "    def _look(self, target, source, timeout):\n"
        '        """Looks a transform up."""\n'
        "        return target, source, timeout\n\n"
        "    @stopping\n"
    )
    source = stopping_with(
        '        self.seen = self._look("map")\n        self.both = self._look("map", "base")[0]\n'
    ).replace("    @stopping\n", helper, 1)
    found = {f.line: f.replacement for f in _names(source, move_forward)}
    lines = source.splitlines()
    assert {lines[line - 1].strip(): fix for line, fix in found.items()} == {
        'self.seen = self._look("map")': None,
        'self.both = self._look("map", "base")[0]': "self.both = self._look('map', 'base', 2.0)[0]",
    }


def test_a_helper_missing_the_parameter_its_call_gives_is_found_and_defaults_count(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    helper = (
        "    def _within(self, threshold, timeout):\n"
        "        return threshold < timeout\n\n"
        "    def _near(self, threshold, timeout=1.0):\n"
        "        return threshold < timeout\n\n"
        "    @stopping\n"
    )
    source = stopping_with(
        "        self._within(0.05)\n        self._near(0.05)\n        self._near(*[0.05])\n"
    ).replace("    @stopping\n", helper, 1)
    messages = [f.message for f in _names(source, move_forward)]
    assert len(messages) == 1
    assert messages[0].startswith("_within(threshold, timeout) does not take what its call")
    assert "missing a required argument: 'timeout'" in messages[0]


@pytest.mark.parametrize(
    ("statements", "replacement"),
    [
        (
            "        elapsed = self.node.get_clock().now().seconds()\n",
            "elapsed = (self.node.get_clock().now().nanoseconds / 1e9)",
        ),
        (
            "        self.begun = self.node.get_clock().now()\n        elapsed = self.begun.sec\n",
            "elapsed = (self.begun.nanoseconds / 1e9)",
        ),
    ],
)
def test_the_seconds_of_an_rclpy_time_are_its_nanoseconds_over_1e9(
    move_forward: tuple[Capability, SkillSpec], statements: str, replacement: str
) -> None:
    [finding] = _names(stopping_with(statements), move_forward)
    assert "is an rclpy Time, which has no" in finding.message
    assert "nanoseconds / 1e9" in finding.message
    assert finding.replacement == replacement


def test_a_datetime_now_is_no_rclpy_time(move_forward: tuple[Capability, SkillSpec]) -> None:
    statements = (
        "        self.begun = datetime.datetime.now()\n        elapsed = self.begun.second\n"
    )
    source = "import datetime\n" + stopping_with(statements)
    assert _names(source, move_forward) == []


def test_an_attribute_only_ever_set_to_none_but_read_as_an_object_is_found(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = stopping_with("        self.start = None\n        x = self.start.x\n")
    [finding] = _names(source, move_forward)
    assert source.splitlines()[finding.line - 1].strip() == "x = self.start.x"
    assert "self.start is only ever set to None" in finding.message


@pytest.mark.parametrize(
    "statements",
    [
        "        self.start = None\n        if self.start is not None:\n            x = self.start.x\n",
        "        self.start = None\n        self.start = self.odom_msg.pose.pose.position\n"
        "        x = self.start.x\n",
        "        self.start = None\n        self.start, other = (1, 2)\n        x = self.start.real\n",
    ],
)
def test_an_attribute_set_to_something_or_tested_first_is_fine(
    move_forward: tuple[Capability, SkillSpec], statements: str
) -> None:
    assert _names(stopping_with(statements), move_forward) == []


def test_the_renamed_variable_takes_a_name_the_method_does_not_use(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = stopping_with(
        "        time_value = 1\n        time = 0.5 + time_value\n        time.sleep(time)\n"
    )
    replacements = [f.replacement for f in _names(source, move_forward)]
    assert replacements == ["time_value2 = 0.5 + time_value", "time.sleep(time_value2)"]


GOAL_HELPERS = (
    "    def _send_dock_goal(self, goal, timeout: float) -> None:\n"
    '        """Sends goal to /dock and waits until the server accepts it."""\n'
    "        self.dock_result_future = None\n\n"
    '    def _dock_result(self, timeout: float) -> "Dock.Result":\n'
    '        """Waits for the result of the goal sent with self._send_dock_goal."""\n'
    "        return self.dock_result_future.result().result\n\n"
    "    @execute\n"
)


@pytest.mark.parametrize("read", [True, False])
def test_a_goal_sends_value_used_as_its_result_is_fixed_to_a_wait_for_the_result(
    move_forward: tuple[Capability, SkillSpec], read: bool
) -> None:
    use = "        self.node.get_logger().info(f'{result}')\n" if read else ""
    source = GOOD.replace("    @execute\n", GOAL_HELPERS, 1).replace(
        "        self.cmd_vel_publisher.publish(Twist())\n        self.out_distance",
        f"        result = self._send_dock_goal(None, 5.0)\n{use}"
        "        self.cmd_vel_publisher.publish(Twist())\n        self.out_distance",
        1,
    )
    [found] = [f for f in _names(source, move_forward) if "returns nothing" in f.message]
    if read:
        assert found.message.endswith(
            "call it as a statement of its own, then wait for the result: "
            "result = self._dock_result(60.0)"
        )
        assert found.replacement == (
            "self._send_dock_goal(None, 5.0)\nresult = self._dock_result(60.0)"
        )
    else:
        assert found.message.endswith("call it as a statement of its own")
        assert found.replacement == "self._send_dock_goal(None, 5.0)"


WAIT = (
    "    def _wait_until(self, condition, timeout: float, what: str) -> None:\n"
    '        """Waits until condition() is true; raises RuntimeError after timeout."""\n'
    "        deadline = time.monotonic() + timeout\n"
    "        while not condition():\n"
    "            if time.monotonic() > deadline:\n"
    '                raise RuntimeError(f"no {what} within {timeout:g} s")\n'
    "            time.sleep(0.02)\n\n"
    "    @execute\n"
)


@pytest.mark.parametrize(
    ("test", "kept"),
    [
        ("if self._wait_until(lambda: self.odom_msg is not None, 0.5, 'odom'):", "body"),
        ("if not self._wait_until(lambda: self.odom_msg is not None, 0.5, 'odom'):", "else"),
    ],
)
def test_a_wait_that_raises_used_as_an_if_test_is_called_and_its_branch_kept(
    move_forward: tuple[Capability, SkillSpec], test: str, kept: str
) -> None:
    # MR-1 set-velocity in ev53: `if self._wait_until(...):` around the outputs and a return.
    source = with_method(
        WAIT,
        f"        {test}\n"
        "            self.out_linear_velocity = 1.0\n"
        "        else:\n"
        "            self.out_linear_velocity = 2.0\n",
    )
    [found] = [f for f in _names(source, move_forward) if "returns nothing" in f.message]
    assert found.line == _line(source, "self._wait_until(lambda")
    branch = "else branch" if kept == "else" else "body"
    assert found.message.endswith(
        "It raises when it fails, so once it returns, what it waits for has happened: the fix "
        f"calls it and goes on with the {branch} of this `if`"
    )
    value = "2.0" if kept == "else" else "1.0"
    assert found.replacement == (
        "self._wait_until(lambda: self.odom_msg is not None, 0.5, 'odom')\n"
        f"self.out_linear_velocity = {value}"
    )


def test_a_helper_that_never_raises_used_as_an_if_test_gets_no_fix(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # _halt returns nothing and cannot fail: which branch was meant is not known.
    source = with_method(
        HALT, "        if self._halt():\n            self.out_linear_velocity = 1.0\n"
    )
    [found] = [f for f in _names(source, move_forward) if "returns nothing" in f.message]
    assert found.replacement is None
    assert "It raises" not in found.message


def test_an_attribute_named_with_an_underscore_too_many_is_renamed(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # ev70 MR-1 mapping: self._map_saver_save_map_client for the skeleton's handle
    source = stopping_with("        self._cmd_vel_publisher.publish(Twist())\n")
    (found,) = [f for f in _names(source, move_forward) if "_cmd_vel_publisher" in f.message]
    assert found.message.endswith("did you mean self.cmd_vel_publisher?")
    assert found.replacement == "self.cmd_vel_publisher.publish(Twist())"
    other = stopping_with("        self.cmd_vel_pub.publish(Twist())\n")
    (found,) = [f for f in _names(other, move_forward) if "cmd_vel_pub " in f.message]
    assert found.replacement is None


@pytest.mark.parametrize(
    ("ros1", "ros2"),
    [
        (  # the MR-1 move-to-point of the evaluation at d678df9
            "timeout = rospy.Duration(0.0)",
            "timeout = rclpy.duration.Duration(seconds=0.0)",
        ),
        ("stamp = rospy.Time(0)", "stamp = rclpy.time.Time()"),
        ("stamp = rospy.Time.now()", "stamp = self.node.get_clock().now()"),
        ("rospy.sleep(0.5)", "time.sleep(0.5)"),
        ("rospy.logwarn('halting')", "self.node.get_logger().warning('halting')"),
        (
            "running = not rospy.is_shutdown() and rospy.get_time() > 0",
            "running = rclpy.ok() and time.time() > 0",
        ),
        ("rate = rospy.Rate(10)", None),  # no plain counterpart: named only
        ("timeout = rospy.Duration(1.0) + rospy.Rate(10).sleep_dur", None),
    ],
)
def test_rospy_is_named_as_ros_1_with_the_rclpy_statement_where_there_is_one(
    move_forward: tuple[Capability, SkillSpec], ros1: str, ros2: str | None
) -> None:
    source = stopping_with(f"        {ros1}\n")
    [finding] = [f for f in _names(source, move_forward) if "rospy" in f.message]
    assert source.splitlines()[finding.line - 1].strip() == ros1
    assert finding.message.startswith("rospy is ROS 1's client library")
    assert finding.replacement == ros2
    if ros2 is None:
        assert "rclpy.duration.Duration(seconds=...)" in finding.message or (
            "rospy.Duration(1.0) is rclpy.duration.Duration(seconds=1.0)" in finding.message
        )


def test_a_method_replaced_by_its_value_is_kept_in_a_local(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # the MR-1 collision avoidance of the evaluation at 3ec2321:
    # self._closest_reading = self._closest_reading(self.scan_msg), then a call: TypeError
    source = stopping_with("        self._travelled = self._travelled()\n")
    [finding] = [f for f in _names(source, move_forward) if "is a method" in f.message]
    assert source.splitlines()[finding.line - 1].strip() == "self._travelled = self._travelled()"
    assert finding.replacement == "travelled = self._travelled()"
    assert "every later self._travelled(...) raises TypeError" in finding.message


@pytest.mark.parametrize(
    ("statements", "replacement"),
    [
        # the MR-1 get-position of the evaluation at cf9631a
        (
            "        self.node.get_logger().info(\n"
            '            f"heading: {self.in_distance:.2f}, timestamp: {self._stamp:.2f}"\n'
            "        )\n",
            "self.node.get_logger().info(f'heading: {self.in_distance:.2f}')",
        ),
        (
            '        print(f"took {self._elapsed} s")\n',
            "print(f'')",
        ),
    ],
)
def test_a_log_line_reading_an_attribute_nothing_sets_loses_that_field(
    move_forward: tuple[Capability, SkillSpec], statements: str, replacement: str
) -> None:
    [finding] = _names(stopping_with(statements), move_forward)
    assert "is never set in this class" in finding.message
    assert finding.replacement == replacement


def test_an_attribute_nothing_sets_outside_a_log_line_gets_no_such_fix(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    [finding] = _names(stopping_with("        self.out_distance = self._stamp\n"), move_forward)
    assert "self._stamp is never set in this class" in finding.message
    assert finding.replacement is None


RESULT_OF = (
    "    def _result_of(self, future, timeout: float, what: str):\n"
    '        """Waits for ``future``."""\n'
    "        return future.result()\n"
    "\n"
    "    @execute\n"
)


@pytest.mark.parametrize("helper", [True, False], ids=["skeleton-helper", "no-helper"])
def test_a_timeout_handed_to_call_async_moves_to_the_wait_for_the_response(
    move_forward: tuple[Capability, SkillSpec], helper: bool
) -> None:
    # The MR-1 mapping of the evaluation: a TypeError in its run.
    statements = (
        '        self.saver = self.node.create_client(SaveMap, "/map_saver/save_map")\n'
        "        self.saved = self.saver.call_async(SaveMap.Request(), 5.0)\n"
    )
    source = (
        with_method(RESULT_OF, statements) if helper else with_method("    @execute\n", statements)
    )
    (found,) = [f for f in _names(source, move_forward) if "call_async" in f.message]
    assert found.message == (
        "self.saver.call_async(request) takes the request only, not 5.0: it gives a future at "
        "once; wait for the response with self._result_of(self.saver.call_async(request), 5.0, "
        '"the response")'
    )
    assert found.replacement == (
        "self.saved = self._result_of(self.saver.call_async(SaveMap.Request()), 5.0, "
        "'the response')"
        if helper
        else None
    )


@pytest.mark.parametrize(
    ("call", "expected"),
    [
        ("self.nav.send_goal_async(goal)", None),
        ("self.nav.send_goal_async(goal, feedback_callback=self._on_feedback)", None),
        ("self.nav.wait_for_server(timeout_sec=5.0)", None),
        (
            "self.nav.send_goal_async(goal, 5.0)",
            "self.nav.send_goal_async() takes the goal and a feedback callback, not a timeout "
            "(5.0): send the goal with self.nav.send_goal_async(goal) and wait for the goal "
            "handle with self._result_of(future, timeout, what)",
        ),
        (
            "self.nav.wait_for_server(5.0, 1.0)",
            "self.nav.wait_for_server(timeout_sec=None) does not take these arguments (too many "
            "positional arguments)",
        ),
        (
            "self.cmd_vel_publisher.publish(Twist(), 10)",
            "self.cmd_vel_publisher.publish(msg) does not take these arguments (too many "
            "positional arguments)",
        ),
    ],
)
def test_calls_of_rclpy_handles_are_held_to_what_rclpy_takes(
    move_forward: tuple[Capability, SkillSpec], call: str, expected: str | None
) -> None:
    source = with_method(
        '    def _on_feedback(self, message) -> None:\n        """Feedback."""\n\n    @execute\n',
        '        self.nav = ActionClient(self.node, NavigateToPose, "/navigate_to_pose")\n'
        "        goal = NavigateToPose.Goal()\n"
        f"        {call}\n",
    )
    found = [f.message for f in _names(source, move_forward) if " take" in f.message]
    assert found == ([] if expected is None else [expected])


@pytest.mark.parametrize(
    ("statement", "replacement"),
    [
        ('if not self.saved.done():\n            raise RuntimeError("not saved")', ""),
        ("answer = self.saved.result()", "answer = self.saved"),
        ("answer = self.saved.result", None),
    ],
    ids=["done-guard", "result-call", "result-field"],
)
def test_a_future_asked_of_what_result_of_waited_for_is_the_response_itself(
    move_forward: tuple[Capability, SkillSpec], statement: str, replacement: str | None
) -> None:
    # The MR-1 mapping of the evaluation, once its call_async(request, 5.0) was fixed.
    source = with_method(
        RESULT_OF,
        '        self.saver = self.node.create_client(SaveMap, "/map_saver/save_map")\n'
        '        self.saved = self._result_of(self.saver.call_async(SaveMap.Request()), 5.0, "r")\n'
        f"        {statement}\n",
    )
    found = [f for f in _names(source, move_forward) if "holds what" in f.message]
    if replacement is None:  # a result's field named result is no future's method
        assert found == []
        return
    (finding,) = found
    assert finding.message.startswith(
        "self.saved holds what self._result_of(...) waited for at line "
    )
    assert finding.replacement == replacement
