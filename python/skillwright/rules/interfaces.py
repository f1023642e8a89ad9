"""SW2xx: the robot's interfaces as the skill uses them (names, kinds, types, fields).

Every topic, service and action a skill makes a handle for must exist on the robot with
the kind and type the code assumes, and every field and constant it touches must be one
the type's definition has: rclpy raises at the first wrong one, on the robot, mid-task.
The truth is the robot's inventory (a live graph or a recording) and the message
definitions it carries.
"""

from __future__ import annotations

from skillwright.rules.registry import Rule

__all__ = [
    "ARGUMENT_TYPE_MISMATCH",
    "DURATION_SECONDS_FIELD",
    "HEADING_NOT_ANGLE",
    "INTERFACE_KIND_MISMATCH",
    "INTERFACE_NAME_NOT_LITERAL",
    "INTERFACE_NOT_RETRIEVED",
    "INTERFACE_RETRIEVED_UNUSED",
    "INTERFACE_TYPE_MISMATCH",
    "MESSAGE_FIELD_NOT_NUMBER",
    "POSITIONAL_MESSAGE_FIELDS",
    "UNKNOWN_CONSTANT",
    "UNKNOWN_FIELD",
    "UNKNOWN_INTERFACE",
    "YAW_OF_MESSAGE",
]

_ROBOT = ("the robot", "ROS 2")

INTERFACE_NAME_NOT_LITERAL = Rule(
    "SW201",
    "interface-name-not-literal",
    group="grounding",
    stage="static",
    severity="warning",
    summary="create_publisher, create_subscription, create_client and ActionClient get their "
    "interface's name as a string literal.",
    why="A name worked out at run time cannot be checked against the robot before the skill "
    "runs; a wrong one shows only as silence (a topic nobody publishes) on the robot.",
    example="self.node.create_publisher(Twist, self.topic, 10)",
    data=("call",),
    grounds=_ROBOT,
)

UNKNOWN_INTERFACE = Rule(
    "SW202",
    "unknown-interface",
    group="grounding",
    stage="static",
    severity="error",
    summary="Every topic, service and action the skill makes a handle for exists on the robot.",
    why="A publisher on a topic nothing subscribes to moves nothing; a subscription to a "
    "topic nobody publishes waits forever; a client of a missing service or action never "
    "connects. ROS 2 reports none of these as an error.",
    example='self.node.create_publisher(Twist, "/cmd_vel_made_up", 10)',
    data=("kind", "name"),
    grounds=_ROBOT,
)

INTERFACE_KIND_MISMATCH = Rule(
    "SW203",
    "interface-kind-mismatch",
    group="grounding",
    stage="static",
    severity="error",
    summary="An interface is used as the kind it is on the robot (topic, service or action).",
    why="A service used as a topic (or an action as a service) is a different name on the "
    "wire (actions are services and topics under `<name>/_action/`): the handle finds nothing.",
    example='self.node.create_client(NavigateToPose, "/navigate_to_pose")  # an action',
    data=("name", "kind", "used_as"),
    grounds=_ROBOT,
)

INTERFACE_TYPE_MISMATCH = Rule(
    "SW204",
    "interface-type-mismatch",
    group="grounding",
    stage="static",
    severity="error",
    summary="A handle carries the type the robot's interface has.",
    why="DDS matches endpoints by name and type: a subscription of another type to the "
    "right topic never receives a message, and a publisher of another type is ignored.",
    example='self.node.create_subscription(Pose, "/odom", ...)  # /odom carries Odometry',
    data=("name", "type", "used_type"),
    grounds=_ROBOT,
)

UNKNOWN_FIELD = Rule(
    "SW205",
    "unknown-field",
    group="grounding",
    stage="static",
    severity="error",
    summary="Every field read or set on a message, request, goal, result or feedback is one "
    "its definition has.",
    why="rclpy's generated message classes have exactly their definition's fields (with "
    "__slots__): a made-up one raises AttributeError on the robot, often in a callback "
    "where it stops every later message.",
    example="msg.pose.position.x  # an Odometry holds pose.pose.position",
    fix="Puts the field the definition has where it is clear which one was meant (one level "
    "further down, a ROS 1 name, a singular of an array field); nothing else in the "
    "statement changes.",
    safety="safe",
    data=("type", "field", "fields", "meant"),
    grounds=("ROS 2", "rclpy"),
)

DURATION_SECONDS_FIELD = Rule(
    "SW206",
    "duration-seconds-field",
    group="grounding",
    stage="static",
    severity="error",
    summary="builtin_interfaces Duration and Time are made from their integer sec and "
    "nanosec fields.",
    why="The message classes have no `seconds` (that is rclpy.duration.Duration's keyword): "
    "Duration(seconds=2.0) raises TypeError where the skill builds its goal.",
    example="Duration(seconds=2.0)",
    fix="Splits the seconds into sec and nanosec of the same message.",
    safety="safe",
    data=("type",),
    grounds=("ROS 2", "rclpy"),
)

MESSAGE_FIELD_NOT_NUMBER = Rule(
    "SW207",
    "message-field-not-number",
    group="grounding",
    stage="static",
    severity="error",
    summary="A field that is a message is given a message, not a number.",
    why="Twist(linear=0.5) hands a float to a Vector3 field: rclpy's setter raises "
    "AssertionError (the field takes a Vector3), so the command is never built.",
    example="Twist(linear=0.5, angular=0.0)",
    fix="A zero command becomes Twist() (every field of it is zero); otherwise each number "
    "goes into the vector's x and z, which the fix has to assume.",
    safety="unsafe",
    data=("type", "field", "fields"),
    grounds=("ROS 2", "rclpy"),
)

POSITIONAL_MESSAGE_FIELDS = Rule(
    "SW208",
    "positional-message-fields",
    group="grounding",
    stage="static",
    severity="error",
    summary="A ROS 2 message is made with its fields as keywords.",
    why="rclpy's generated message classes take keyword arguments only: Vector3(0.0, 0.0, "
    "1.0) raises TypeError.",
    example="Vector3(0.0, 0.0, 1.0)",
    fix="Names each positional argument by the field in its place, in the definition's order.",
    safety="safe",
    data=("type", "fields"),
    grounds=("ROS 2", "rclpy"),
)

UNKNOWN_CONSTANT = Rule(
    "SW209",
    "unknown-constant",
    group="grounding",
    stage="static",
    severity="error",
    summary="An upper-case attribute of a message class is one of its definition's constants.",
    why="Message classes carry their definition's constants only (GoalStatus.STATUS_SUCCEEDED); "
    "a made-up one raises AttributeError.",
    example="Twist.MAX_SPEED",
    fix="Uses the skill's own constant of that meaning where it has one.",
    safety="unsafe",
    data=("type", "constant", "constants"),
    grounds=("ROS 2",),
)

YAW_OF_MESSAGE = Rule(
    "SW210",
    "yaw-of-message",
    group="grounding",
    stage="static",
    severity="error",
    summary="The skeleton's self._yaw() gets an orientation quaternion, not the message that "
    "holds one.",
    why="_yaw reads x, y, z and w of a quaternion; an Odometry, Pose or TransformStamped has "
    "none of them at its top and the call raises AttributeError.",
    example="self._yaw(self.odom_msg)",
    fix="Hands _yaw the message's orientation (pose.pose.orientation, transform.rotation, ...).",
    safety="safe",
    data=("argument", "type", "orientation"),
    grounds=("the skeleton", "ROS 2"),
)

HEADING_NOT_ANGLE = Rule(
    "SW211",
    "heading-not-angle",
    group="grounding",
    stage="static",
    severity="error",
    summary="The skeleton's self._pose_goal() gets the heading as an angle in radians.",
    why="_pose_goal turns the angle into the goal's quaternion; given a quaternion or a "
    "message it raises TypeError, or sends the robot facing the wrong way.",
    example="self._pose_goal('map', x, y, transform.transform.rotation)",
    fix="Hands it self._yaw() of the orientation.",
    safety="safe",
    data=("argument",),
    grounds=("the skeleton", "ROS 2"),
)

ARGUMENT_TYPE_MISMATCH = Rule(
    "SW212",
    "argument-type-mismatch",
    group="grounding",
    stage="static",
    severity="error",
    summary="publish, call_async, send_goal_async and the skeleton's goal helpers get a "
    "message of the type their handle carries.",
    why="rclpy checks the type when it serialises: publishing a PoseStamped on a Twist "
    "publisher, or sending it as a NavigateToPose goal, raises TypeError.",
    example="self.navigate_client.send_goal_async(pose_stamped)",
    fix="Wraps the message in the expected one when exactly one of its fields has its type "
    "(NavigateToPose.Goal(pose=...)), or sends it on the handle that carries its type.",
    safety="unsafe",
    data=("call", "expected", "given"),
    grounds=("rclpy", "the robot"),
)

INTERFACE_RETRIEVED_UNUSED = Rule(
    "SW213",
    "interface-retrieved-unused",
    group="interfaces",
    stage="static",
    severity="warning",
    summary="Every interface retrieval chose for the capability is used.",
    why="Retrieval picked it because the capability seems to need it; a skill that never "
    "uses it may be missing part of the behaviour (a stop on the velocity command, say).",
    example="# /cmd_vel retrieved, no publisher made for it",
    data=("name",),
    grounds=("retrieval",),
)

INTERFACE_NOT_RETRIEVED = Rule(
    "SW214",
    "interface-not-retrieved",
    group="interfaces",
    stage="static",
    severity="warning",
    summary="Every interface the skill uses was retrieved for the capability.",
    why="An interface retrieval did not choose may be a twin of the right one (another "
    "robot's velocity command, a second scanner); the engineer should confirm it.",
    example='self.node.create_publisher(Twist, "/arm/cmd_vel", 10)',
    data=("name",),
    grounds=("retrieval",),
)
