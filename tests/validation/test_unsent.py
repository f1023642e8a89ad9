"""A message, goal or request a method builds must leave it whole."""

from __future__ import annotations

import pytest

from skillwright.rules.finding import Finding
from skillwright.validation.unsent import check_unsent
from tests.validation.test_loops import skill_facts

STARTING = """class Skill:
    def starting(self):
        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)
        self.navigate_to_pose_client = ActionClient(self.node, NavigateToPose, "/navigate_to_pose")
        self.save_map_client = self.node.create_client(srv_type=SaveMap, srv_name="/save_map")

"""


def _unsent(method: str, starting: str = STARTING) -> list[Finding]:
    return check_unsent(skill_facts(starting, method))


def test_a_velocity_command_whose_fields_are_set_and_read_but_never_published() -> None:
    # MR-1 set-velocity, ev56-ev59: the base never moved and the wait for it gave up
    [finding] = _unsent(
        """
        def execute(self):
            linear = min(abs(self.in_linear_velocity), 0.8)
            command = Twist()
            command.linear.x = linear
            command.angular.z = self.in_angular_velocity
            self._wait_until(lambda: self._twist_within(0.05), 0.5, "odometry twist")
            if not self._twist_within(0.05):
                command.linear.x = 0.0
            self.out_linear_velocity = command.linear.x
        """
    )
    assert finding.check == "unsent"
    assert finding.severity == "error"
    assert finding.message.startswith(
        "command, a Twist message built on line 9, is never sent: nothing publishes it"
    )
    assert "publish it with self.cmd_vel_publisher.publish(command) once it is complete" in (
        finding.message
    )
    # published once complete: after the last field it sets, before the branch that
    # touches it again
    assert finding.line == 11
    assert finding.replacement == (
        "command.angular.z = self.in_angular_velocity\nself.cmd_vel_publisher.publish(command)"
    )


def test_a_zero_command_in_a_state_that_stops_is_published_where_it_is_built() -> None:
    [finding] = _unsent(
        """
        def stopping(self):
            command = Twist()
            self.node.get_logger().info("stopping")
        """
    )
    assert finding.line == 8
    assert finding.replacement == "command = Twist()\nself.cmd_vel_publisher.publish(command)"


def test_a_command_whose_fields_a_loop_sets_gets_no_fix() -> None:
    # publishing the empty command before the loop would not move the robot either
    [finding] = _unsent(
        """
        def execute(self):
            command = Twist()
            while self._travelled() < self.in_distance:
                command.linear.x = 0.2
                time.sleep(0.05)
        """
    )
    assert finding.message.endswith("publish it with self.cmd_vel_publisher")
    assert finding.replacement is None


@pytest.mark.parametrize(
    "use",
    [
        "self.cmd_vel_publisher.publish(command)",
        "self._hold(command)",
        "self.last_command = command",
        "self.timer = self.node.create_timer(0.05, lambda: self.cmd_vel_publisher.publish(command))",
        "return command",
        "commands = [command]",
    ],
    ids=["published", "passed to a helper", "kept", "published by a timer", "returned", "listed"],
)
def test_a_command_that_leaves_the_method_whole_is_not_flagged(use: str) -> None:
    assert not _unsent(
        f"""
        def execute(self):
            command = Twist()
            command.linear.x = self.in_velocity
            {use}
        """
    )


def test_a_left_over_command_beside_one_that_is_published_is_dead_code_only() -> None:
    assert not _unsent(
        """
        def execute(self):
            command = Twist()
            command.linear.x = self.in_velocity
            self.cmd_vel_publisher.publish(Twist(linear=Vector3(x=self.in_velocity)))
        """
    )


def test_a_message_the_class_does_not_publish_is_only_a_record() -> None:
    # a PoseStamped kept to read fields from is not a command anybody waits for
    assert not _unsent(
        """
        def execute(self):
            target = PoseStamped()
            target.pose.position.x = self.in_x
            self.out_x = target.pose.position.x
        """
    )


def test_a_goal_built_and_never_sent_names_the_action_client() -> None:
    [finding] = _unsent(
        """
        def execute(self):
            goal = NavigateToPose.Goal()
            goal.pose.pose.position.x = self.in_x
            self._wait_until(lambda: self.arrived, 60.0, "arrival")
        """
    )
    assert finding.message.startswith("goal, a NavigateToPose.Goal built on line 8")
    assert finding.message.endswith("send it with self.navigate_to_pose_client")
    assert finding.line == 8
    assert finding.replacement is None


def test_a_request_built_and_never_sent_names_the_service_client() -> None:
    [finding] = _unsent(
        """
        def completing(self):
            request = SaveMap.Request()
            request.map_url = self.in_map_name
        """
    )
    assert "calls the service with it" in finding.message
    assert finding.message.endswith("call self.save_map_client with it")
    assert finding.replacement is None


def test_with_two_publishers_of_the_type_the_model_chooses() -> None:
    starting = STARTING.replace(
        "        self.navigate",
        '        self.arm_publisher = self.node.create_publisher(Twist, "/arm/cmd_vel", 10)\n'
        "        self.navigate",
    )
    [finding] = _unsent(
        """
        def execute(self):
            command = Twist()
            command.linear.x = self.in_velocity
        """,
        starting,
    )
    assert finding.message.endswith("publish it with self.cmd_vel_publisher or self.arm_publisher")
    assert finding.replacement is None


def test_each_name_is_reported_once() -> None:
    findings = _unsent(
        """
        def execute(self):
            command = Twist()
            command.linear.x = self.in_velocity
            command = Twist()
        """
    )
    assert len(findings) == 1
