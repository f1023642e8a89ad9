"""Uniform interface descriptions, and the deterministic ``rules`` engine that writes them.

Every interface gets the same five parts, whichever engine wrote them: what it is for,
which module of the resource it belongs to, the tasks it serves, who uses it, and its key
fields. The parts are joined into one paragraph for embedding, so retrieval compares like
with like. The rules engine needs no model: it reads the ROS 2 type (the strongest
signal), then the name, then the package, and falls back to a plain account of the
kind, type and fields. It never claims more than those give: a rule states what the
standard type means by its definition and ROS convention, and names the node only as the
interface's name spells it.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

from skillwright.interfaces.inventory import Description

__all__ = ["MODULES", "Description", "Role", "control_role", "describe_by_rules"]

MODULES = (
    "base motion",
    "localisation",
    "perception",
    "mapping",
    "navigation",
    "manipulation",
    "controller management",
    "simulation",
    "diagnostics",
    "system",
    "other",
)
"""Modules of a resource an interface can belong to."""

Role = Literal["command", "sense", "plan", "manage"]
"""How a control interface serves the resource: it commands it, senses it or its
surroundings, plans or executes a task for it, or selects how it is commanded."""

_ANY = "tsa"


@dataclass(frozen=True)
class _Rule:
    kinds: str  # letters t, s, a for topic, service, action
    type_pattern: str  # fullmatch on the type name
    # may use {name}, {what} (the name as words), {node} and {controller} (from the
    # interface's namespace, e.g. "node joint_trajectory_controller", else "its node")
    purpose: str
    module: str
    tasks: tuple[str, ...]
    used_by: tuple[str, ...]
    name_pattern: str | None = None  # search on the interface name
    role: Role | None = None  # for control interfaces: see Role


_RULES: tuple[_Rule, ...] = (
    # ------------------------------------------------------------------ base motion
    _Rule(
        "t",
        r"geometry_msgs/msg/Twist(Stamped)?",
        "Commands the base's linear and angular velocity (forward, sideways, turning).",
        "base motion",
        ("drive forward", "rotate in place", "set velocity", "stop the base", "avoid collisions"),
        ("navigation controller", "teleoperation", "skills"),
        r"cmd|command",
        role="command",
    ),
    _Rule(
        "t",
        r"geometry_msgs/msg/Twist(Stamped)?",
        "Carries a velocity (linear and angular) of {what}.",
        "base motion",
        ("monitor velocity",),
        ("motion controllers",),
        role="sense",
    ),
    # ------------------------------------------------------------------ localisation
    _Rule(
        "t",
        r"nav_msgs/msg/Odometry",
        "Reports the base's estimated pose and velocity from odometry, "
        "relative to where it started.",
        "localisation",
        (
            "measure travelled distance",
            "measure velocity",
            "track position and heading",
            "close the loop of motion commands",
        ),
        ("base driver", "localisation", "navigation"),
        role="sense",
    ),
    _Rule(
        "t",
        r"sensor_msgs/msg/Imu",
        "Orientation, angular velocity and linear acceleration from an inertial unit.",
        "localisation",
        ("estimate orientation and turning rate", "sensor fusion"),
        ("IMU driver", "state estimation"),
        role="sense",
    ),
    _Rule(
        "t",
        r"geometry_msgs/msg/PoseWithCovarianceStamped",
        "Sets the robot's initial pose estimate for localisation.",
        "localisation",
        ("initialise localisation",),
        ("operators", "RViz"),
        r"initial",
        role="command",
    ),
    _Rule(
        "t",
        r"geometry_msgs/msg/PoseWithCovarianceStamped",
        "The robot's estimated pose in the map frame, with its uncertainty.",
        "localisation",
        ("get the current position and heading in the map", "check localisation quality"),
        ("SLAM", "AMCL", "navigation"),
        role="sense",
    ),
    _Rule(
        "t",
        r"tf2_msgs/msg/TFMessage",
        "Fixed transforms between the robot's frames (sensor mounts, links that do not "
        "move), published once and kept for late subscribers.",
        "localisation",
        ("convert sensor data into the robot's frame", "complete tf lookups"),
        ("robot state publisher", "every node using tf2"),
        r"tf_static$",
        role="sense",
    ),
    _Rule(
        "t",
        r"tf2_msgs/msg/TFMessage",
        "Transforms between the robot's coordinate frames (map, odom, base_link, sensors, "
        "arm links).",
        "localisation",
        ("look up the robot's pose in the map", "convert positions between frames"),
        ("robot state publisher", "localisation", "every node using tf2"),
        role="sense",
    ),
    # ------------------------------------------------------------------ perception
    _Rule(
        "t",
        r"sensor_msgs/msg/LaserScan",
        "2-D range measurements around the robot from a laser scanner.",
        "perception",
        (
            "detect obstacles",
            "find the nearest object and its bearing",
            "mapping",
            "localisation",
            "collision avoidance",
        ),
        ("lidar driver", "SLAM", "costmaps"),
        role="sense",
    ),
    _Rule(
        "t",
        r"sensor_msgs/msg/PointCloud2",
        "3-D points measured around the robot (depth camera or 3-D lidar).",
        "perception",
        ("detect obstacles", "perceive objects", "mapping"),
        ("sensor driver", "costmaps"),
        role="sense",
    ),
    _Rule(
        "t",
        r"sensor_msgs/msg/(Image|CompressedImage)",
        "Camera images.",
        "perception",
        ("detect objects", "inspect the scene"),
        ("camera driver", "perception nodes"),
        role="sense",
    ),
    _Rule(
        "t",
        r"sensor_msgs/msg/CameraInfo",
        "Calibration of a camera (intrinsics, distortion).",
        "perception",
        ("project between image and 3-D",),
        ("camera driver",),
        role="sense",
    ),
    _Rule(
        "t",
        r"sensor_msgs/msg/Range",
        "One distance measurement from a range sensor (ultrasonic or infrared).",
        "perception",
        ("detect close obstacles",),
        ("sensor driver", "costmaps"),
        role="sense",
    ),
    # ------------------------------------------------------------------ diagnostics
    _Rule(
        "t",
        r"sensor_msgs/msg/BatteryState",
        "State of charge and health of the battery.",
        "diagnostics",
        ("monitor battery", "decide when to recharge"),
        ("power driver",),
        role="sense",
    ),
    _Rule(
        "t",
        r"diagnostic_msgs/msg/DiagnosticArray",
        "Health reports of the robot's hardware and software components.",
        "diagnostics",
        ("monitor component health",),
        ("drivers", "diagnostic aggregator"),
        role="sense",
    ),
    # ------------------------------------------------------------------ joints and arms
    _Rule(
        "t",
        r"sensor_msgs/msg/JointState",
        "Positions, velocities and efforts of the robot's joints.",
        "manipulation",
        ("read arm configuration", "monitor joint motion", "compute forward kinematics"),
        ("joint state broadcaster", "robot state publisher", "motion planning"),
        role="sense",
    ),
    _Rule(
        "t",
        r"control_msgs/msg/DynamicJointState",
        "Every state interface value of the robot's joints (position, velocity, effort and "
        "any others the hardware reports), as ros2_control reads them.",
        "controller management",
        ("monitor joints", "read hardware-specific joint values"),
        ("joint state broadcaster", "monitoring tools"),
        role="sense",
    ),
    _Rule(
        "t",
        r"trajectory_msgs/msg/JointTrajectory",
        "Commands a joint trajectory (timed waypoints of joint positions and velocities) to "
        "{controller}, without feedback.",
        "manipulation",
        ("move the arm along joint waypoints", "send a joint configuration"),
        ("motion planning", "teleoperation", "skills"),
        role="command",
    ),
    _Rule(
        "t",
        r"control_msgs/msg/JointTrajectoryControllerState",
        "State of {controller}, a joint trajectory controller: reference, feedback and "
        "error of every joint it drives.",
        "manipulation",
        ("monitor how closely the joints follow the trajectory", "detect tracking errors"),
        ("monitoring tools", "skills"),
        role="sense",
    ),
    _Rule(
        "s",
        r"control_msgs/srv/QueryTrajectoryState",
        "Samples the trajectory that {controller} is executing at a given time: joint "
        "positions, velocities and accelerations.",
        "manipulation",
        ("check where the joints will be at a time", "verify trajectory execution"),
        ("skills", "monitoring tools"),
        role="sense",
    ),
    _Rule(
        "a",
        r"control_msgs/action/FollowJointTrajectory",
        "Makes {controller} follow a joint trajectory within tolerances, reporting "
        "progress and the final error.",
        "manipulation",
        ("move the arm along joint waypoints", "move joints to a configuration"),
        ("MoveIt", "skills"),
        role="command",
    ),
    _Rule(
        "a",
        r"control_msgs/action/GripperCommand",
        "Opens or closes the gripper to a position with a maximum effort.",
        "manipulation",
        ("grasp", "release"),
        ("skills",),
        role="command",
    ),
    _Rule(
        "a",
        r"moveit_msgs/action/MoveGroup",
        "Plans and executes a motion of the arm to a goal (pose or joint values) with MoveIt.",
        "manipulation",
        ("move the arm to a point", "reach a pose"),
        ("skills", "operators"),
        role="plan",
    ),
    _Rule(
        "a",
        r"moveit_msgs/action/ExecuteTrajectory",
        "Executes a planned arm trajectory.",
        "manipulation",
        ("execute a planned motion",),
        ("MoveIt clients",),
        role="command",
    ),
    _Rule(
        "s",
        r"moveit_msgs/srv/GetPositionIK",
        "Computes joint values that put the arm's end effector at a pose (inverse kinematics).",
        "manipulation",
        ("reach a point", "check reachability"),
        ("MoveIt clients",),
        role="plan",
    ),
    _Rule(
        "s",
        r"moveit_msgs/srv/GetPositionFK",
        "Computes link poses from joint values (forward kinematics).",
        "manipulation",
        ("get the end effector position",),
        ("MoveIt clients",),
        role="plan",
    ),
    _Rule(
        "s",
        r"moveit_msgs/srv/GetMotionPlan",
        "Plans an arm motion without executing it.",
        "manipulation",
        ("plan arm motion",),
        ("MoveIt clients",),
        role="plan",
    ),
    # ------------------------------------------------------------------ mapping
    _Rule(
        "t",
        r"nav_msgs/msg/OccupancyGrid",
        "A costmap: the grid of obstacle costs the navigation stack plans around.",
        "navigation",
        ("plan collision-free paths", "check free space"),
        ("Nav2 costmaps",),
        r"costmap",
        role="sense",
    ),
    _Rule(
        "t",
        r"nav_msgs/msg/OccupancyGrid",
        "The occupancy grid map of the environment (free, occupied, unknown cells).",
        "mapping",
        ("build and save a map", "localise in the map", "plan paths"),
        ("SLAM", "map server", "navigation"),
        role="sense",
    ),
    _Rule(
        "t",
        r"nav_msgs/msg/MapMetaData",
        "Size, resolution and origin of the current map.",
        "mapping",
        ("convert between map cells and coordinates", "follow the map's growth"),
        ("SLAM", "map server"),
        role="sense",
    ),
    _Rule(
        "s",
        r"nav_msgs/srv/GetMap",
        "Returns the current occupancy grid map.",
        "mapping",
        ("read the map once",),
        ("map server", "skills"),
        role="sense",
    ),
    _Rule(
        "s",
        r"(nav2_msgs/srv/SaveMap|slam_toolbox/srv/SaveMap)",
        "Saves the current map to files.",
        "mapping",
        ("save the map",),
        ("operators", "skills"),
        role="command",
    ),
    _Rule(
        "s",
        r"slam_toolbox/srv/SerializePoseGraph",
        "Saves SLAM's pose graph so mapping can continue later.",
        "mapping",
        ("store mapping session",),
        ("operators",),
        role="command",
    ),
    _Rule(
        "s",
        r"nav2_msgs/srv/LoadMap",
        "Loads a saved map into the map server.",
        "mapping",
        ("load a map",),
        ("operators",),
        role="command",
    ),
    # ------------------------------------------------------------------ navigation
    _Rule(
        "t",
        r"nav_msgs/msg/Path",
        "A path as a sequence of poses, e.g. the plan the navigation stack follows.",
        "navigation",
        ("show or follow the planned path",),
        ("planner", "controller"),
        role="plan",
    ),
    _Rule(
        "t",
        r"geometry_msgs/msg/PoseStamped",
        "A goal pose for the navigation stack to drive to.",
        "navigation",
        ("send the robot to a pose",),
        ("RViz", "operators"),
        r"goal",
        role="command",
    ),
    _Rule(
        "t",
        r"geometry_msgs/msg/PoseStamped",
        "A pose in a named frame: {what}.",
        "localisation",
        ("read a pose",),
        ("nodes",),
        role="sense",
    ),
    _Rule(
        "t",
        r"geometry_msgs/msg/PolygonStamped",
        "The outline of the robot's footprint as the costmap uses it.",
        "navigation",
        ("check clearance around the robot",),
        ("Nav2 costmaps",),
        r"footprint",
        role="sense",
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/NavigateToPose",
        "Drives the robot to a goal pose, planning and following a collision-free path.",
        "navigation",
        ("navigate to a point", "move to a goal position", "go to a pose"),
        ("skills", "behaviour trees", "operators"),
        role="plan",
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/NavigateThroughPoses",
        "Drives the robot through a sequence of poses, avoiding obstacles.",
        "navigation",
        ("follow waypoints", "patrol"),
        ("skills", "behaviour trees"),
        role="plan",
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/ComputePathToPose",
        "Plans a collision-free path from the current pose to a goal pose.",
        "navigation",
        ("plan a path",),
        ("behaviour trees",),
        role="plan",
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/FollowPath",
        "Makes the controller follow a given path.",
        "navigation",
        ("follow a path",),
        ("behaviour trees",),
        role="plan",
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/Spin",
        "Rotates the base in place by a given angle (Nav2 behaviour).",
        "navigation",
        ("rotate by an angle",),
        ("behaviour trees", "recoveries"),
        role="command",
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/BackUp",
        "Drives the base straight backwards by a distance (Nav2 behaviour).",
        "navigation",
        ("back up",),
        ("behaviour trees", "recoveries"),
        role="command",
    ),
    _Rule(
        "a",
        r"nav2_msgs/action/DriveOnHeading",
        "Drives the base straight along its heading for a distance (Nav2 behaviour).",
        "navigation",
        ("drive forward a distance",),
        ("behaviour trees",),
        role="command",
    ),
    _Rule(
        "s",
        r"nav2_msgs/srv/ClearEntireCostmap",
        "Clears the obstacles a costmap has accumulated.",
        "navigation",
        ("recover from stale obstacles",),
        ("recoveries",),
        role="command",
    ),
    # ------------------------------------------------------------------ ros2_control
    _Rule(
        "s",
        r"controller_manager_msgs/srv/ListControllers",
        "Lists the ros2_control controllers with their type, state (active, inactive) and "
        "the command interfaces they claim.",
        "controller management",
        ("check that a controller is active before commanding through it",),
        ("skills", "controller spawner", "ros2 control CLI"),
        role="manage",
    ),
    _Rule(
        "s",
        r"controller_manager_msgs/srv/SwitchController",
        "Activates and deactivates ros2_control controllers in one step, e.g. to hand joints "
        "from one controller to another.",
        "controller management",
        ("activate the controller a skill commands through", "switch between control modes"),
        ("skills", "controller spawner", "ros2 control CLI"),
        role="manage",
    ),
    _Rule(
        "s",
        r"controller_manager_msgs/srv/LoadController",
        "Loads a controller plugin into the controller manager under a name.",
        "controller management",
        ("bring up controllers",),
        ("controller spawner", "launch files", "ros2 control CLI"),
    ),
    _Rule(
        "s",
        r"controller_manager_msgs/srv/UnloadController",
        "Unloads a controller from the controller manager.",
        "controller management",
        ("shut controllers down",),
        ("controller spawner", "ros2 control CLI"),
    ),
    _Rule(
        "s",
        r"controller_manager_msgs/srv/ConfigureController",
        "Configures a loaded controller (its lifecycle configure transition).",
        "controller management",
        ("bring up controllers",),
        ("controller spawner", "ros2 control CLI"),
    ),
    _Rule(
        "s",
        r"controller_manager_msgs/srv/ReloadControllerLibraries",
        "Reloads the controller plugin libraries, optionally unloading running controllers first.",
        "controller management",
        ("pick up rebuilt controller plugins",),
        ("developers", "ros2 control CLI"),
    ),
    _Rule(
        "s",
        r"controller_manager_msgs/srv/ListControllerTypes",
        "Lists the controller types the controller manager can load.",
        "controller management",
        ("introspection",),
        ("ros2 control CLI",),
    ),
    _Rule(
        "s",
        r"controller_manager_msgs/srv/ListHardwareComponents",
        "Lists the hardware components (systems, actuators, sensors) the controller manager "
        "drives, with their lifecycle state.",
        "controller management",
        ("introspection", "check hardware state"),
        ("ros2 control CLI",),
    ),
    _Rule(
        "s",
        r"controller_manager_msgs/srv/ListHardwareInterfaces",
        "Lists the command and state interfaces of the hardware, and whether each is "
        "available and claimed by a controller.",
        "controller management",
        ("introspection",),
        ("ros2 control CLI",),
    ),
    _Rule(
        "s",
        r"controller_manager_msgs/srv/SetHardwareComponentState",
        "Moves a hardware component to another lifecycle state (configure, activate, deactivate).",
        "controller management",
        ("bring hardware up or down",),
        ("operators", "ros2 control CLI"),
    ),
    _Rule(
        "s",
        r"controller_manager_msgs/srv/\w+",
        "Manages ros2_control controllers and hardware ({what}).",
        "controller management",
        ("switch or inspect controllers",),
        ("operators", "launch tooling"),
    ),
    # ------------------------------------------------------------------ simulation
    _Rule(
        "s",
        r"gazebo_msgs/srv/ApplyJointEffort",
        "Applies an effort (force or torque) to a joint of a simulated model for a given "
        "time (Gazebo).",
        "simulation",
        ("disturb a simulated joint", "test controllers in simulation"),
        ("test scripts", "simulation tooling"),
    ),
    _Rule(
        "s",
        r"gazebo_msgs/srv/ApplyLinkWrench",
        "Applies a force and torque to a link of a simulated model for a given time (Gazebo).",
        "simulation",
        ("push a simulated body", "test controllers in simulation"),
        ("test scripts", "simulation tooling"),
    ),
    _Rule(
        "s",
        r"gazebo_msgs/srv/JointRequest",
        "Removes the efforts applied to a joint of a simulated model (Gazebo).",
        "simulation",
        ("end a simulated disturbance",),
        ("test scripts", "simulation tooling"),
    ),
    _Rule(
        "s",
        r"gazebo_msgs/srv/LinkRequest",
        "Removes the wrenches applied to a link of a simulated model (Gazebo).",
        "simulation",
        ("end a simulated disturbance",),
        ("test scripts", "simulation tooling"),
    ),
    _Rule(
        "s",
        r"gazebo_msgs/srv/SpawnEntity",
        "Adds a model (URDF or SDF) to the simulated world at a given pose (Gazebo).",
        "simulation",
        ("set up a simulated scene", "spawn the robot"),
        ("launch files", "test scripts"),
    ),
    _Rule(
        "s",
        r"gazebo_msgs/srv/DeleteEntity",
        "Removes a model from the simulated world (Gazebo).",
        "simulation",
        ("clean up a simulated scene",),
        ("test scripts",),
    ),
    _Rule(
        "s",
        r"gazebo_msgs/srv/GetModelList",
        "Lists the models in the simulated world (Gazebo).",
        "simulation",
        ("inspect the simulated scene",),
        ("test scripts",),
    ),
    _Rule(
        "s",
        r"gazebo_msgs/srv/\w+",
        "Simulator service ({what}).",
        "simulation",
        ("manipulate the simulation",),
        ("simulation tooling",),
    ),
    _Rule(
        "s",
        r"std_srvs/srv/Empty",
        "Pauses the simulator's physics; simulated time stops.",
        "simulation",
        ("freeze the simulation",),
        ("operators", "test scripts"),
        r"/pause_physics$",
    ),
    _Rule(
        "s",
        r"std_srvs/srv/Empty",
        "Resumes the simulator's physics after a pause.",
        "simulation",
        ("continue the simulation",),
        ("operators", "test scripts"),
        r"/unpause_physics$",
    ),
    _Rule(
        "s",
        r"std_srvs/srv/Empty",
        "Resets the whole simulation: model poses and the simulated time.",
        "simulation",
        ("restart an experiment",),
        ("operators", "test scripts"),
        r"/reset_simulation$",
    ),
    _Rule(
        "s",
        r"std_srvs/srv/Empty",
        "Resets the poses of the simulated models, keeping the simulated time.",
        "simulation",
        ("restart an experiment",),
        ("operators", "test scripts"),
        r"/reset_world$",
    ),
    _Rule(
        "t",
        r"gazebo_msgs/msg/PerformanceMetrics",
        "The simulator's real-time factor and the update rates of its simulated sensors.",
        "simulation",
        ("check that the simulation keeps up with real time",),
        ("Gazebo", "developers"),
    ),
    _Rule(
        "t",
        r"gazebo_msgs/msg/(ModelStates|LinkStates)",
        "The simulator's true poses and velocities of every model or link (Gazebo).",
        "simulation",
        ("compare estimates with ground truth",),
        ("test scripts", "developers"),
    ),
    _Rule(
        "t",
        r"gazebo_msgs/msg/\w+",
        "Simulator topic ({what}).",
        "simulation",
        ("observe the simulation",),
        ("simulation tooling",),
    ),
    # ------------------------------------------------------------------ generic services
    _Rule(
        "s",
        r"std_srvs/srv/Empty",
        "Triggers {what} (no arguments, no result).",
        "other",
        (),
        ("operators",),
    ),
    _Rule(
        "s",
        r"std_srvs/srv/Trigger",
        "Triggers {what}; answers whether it succeeded, with a message.",
        "other",
        (),
        ("operators",),
    ),
    _Rule(
        "s",
        r"std_srvs/srv/SetBool",
        "Switches {what} on or off; answers whether it succeeded, with a message.",
        "other",
        (),
        ("operators",),
    ),
    # ------------------------------------------------------------------ ROS 2 plumbing
    _Rule(
        "t",
        r"std_msgs/msg/String",
        "The robot's URDF model (links, joints, limits) as XML text.",
        "system",
        ("read the robot model",),
        ("robot state publisher", "motion planning"),
        r"robot_description$",
    ),
    _Rule(
        "t",
        r"std_msgs/msg/String",
        "The robot's semantic description for MoveIt (SRDF: planning groups, end effectors).",
        "system",
        ("read planning groups",),
        ("MoveIt",),
        r"robot_description_semantic$",
    ),
    _Rule(
        "t",
        r"rcl_interfaces/msg/Log",
        "Log messages of all nodes.",
        "system",
        ("debugging",),
        ("every node",),
    ),
    _Rule(
        "t",
        r"rcl_interfaces/msg/ParameterEvent",
        "Notifications of parameters declared, changed or deleted on any node.",
        "system",
        ("introspection",),
        ("every node",),
    ),
    _Rule(
        "t",
        r"rosgraph_msgs/msg/Clock",
        "Simulated or played-back time, which nodes use instead of the wall clock.",
        "system",
        ("time keeping in simulation and bag playback",),
        ("simulator", "bag player", "nodes with use_sim_time"),
    ),
    _Rule(
        "t",
        r"bond/msg/Status",
        "Heartbeats between a lifecycle manager and the nodes it supervises.",
        "system",
        ("detect crashed nodes",),
        ("Nav2 lifecycle manager",),
    ),
    _Rule(
        "t",
        r"rosbag2_interfaces/msg/\w+",
        "Notices from a bag recorder or player ({what}).",
        "system",
        ("recording",),
        ("rosbag2",),
    ),
    _Rule(
        "t",
        r"lifecycle_msgs/msg/TransitionEvent",
        "Lifecycle state changes of {node} (e.g. inactive to active).",
        "system",
        ("follow bring-up",),
        ("lifecycle manager", "monitoring tools"),
    ),
    _Rule(
        "s",
        r"lifecycle_msgs/srv/ChangeState",
        "Triggers a lifecycle transition of {node} (configure, activate, deactivate, "
        "cleanup, shutdown).",
        "system",
        ("bring nodes up and down",),
        ("lifecycle manager",),
    ),
    _Rule(
        "s",
        r"lifecycle_msgs/srv/GetState",
        "Returns the lifecycle state of {node}.",
        "system",
        ("check bring-up",),
        ("lifecycle manager",),
    ),
    _Rule(
        "s",
        r"lifecycle_msgs/srv/\w+",
        "Lists the lifecycle states or transitions of {node}.",
        "system",
        ("introspection",),
        ("lifecycle manager",),
    ),
    _Rule(
        "s",
        r"nav2_msgs/srv/ManageLifecycleNodes",
        "Starts, pauses, resumes or resets the lifecycle nodes of {node} as a group.",
        "system",
        ("bring the navigation stack up and down",),
        ("operators", "launch files"),
    ),
    _Rule(
        "s",
        r"rcl_interfaces/srv/DescribeParameters",
        "Describes parameters of {node}: type, allowed range, whether read-only.",
        "system",
        ("configuration", "introspection"),
        ("ros2 param CLI", "rqt"),
    ),
    _Rule(
        "s",
        r"rcl_interfaces/srv/GetParameterTypes",
        "Returns the types of parameters of {node}.",
        "system",
        ("introspection",),
        ("ros2 param CLI", "rqt"),
    ),
    _Rule(
        "s",
        r"rcl_interfaces/srv/GetParameters",
        "Returns the values of parameters of {node}.",
        "system",
        ("configuration", "introspection"),
        ("ros2 param CLI", "rqt"),
    ),
    _Rule(
        "s",
        r"rcl_interfaces/srv/ListParameters",
        "Lists the parameter names of {node}.",
        "system",
        ("introspection",),
        ("ros2 param CLI", "rqt"),
    ),
    _Rule(
        "s",
        r"rcl_interfaces/srv/SetParameters",
        "Sets parameters of {node}, each on its own.",
        "system",
        ("configuration", "tuning"),
        ("ros2 param CLI", "rqt"),
    ),
    _Rule(
        "s",
        r"rcl_interfaces/srv/SetParametersAtomically",
        "Sets several parameters of {node} together: all or none.",
        "system",
        ("configuration", "tuning"),
        ("ros2 param CLI", "rqt"),
    ),
    _Rule(
        "s",
        r"rcl_interfaces/srv/(Get|Set)LoggerLevels",
        "Reads or sets the log levels of {node}'s loggers.",
        "system",
        ("debugging",),
        ("ros2 CLI", "rqt"),
    ),
    _Rule(
        "s",
        r"rcl_interfaces/srv/\w+",
        "Reads or changes a node's parameters ({what}).",
        "system",
        ("configuration", "introspection"),
        ("tooling",),
    ),
    _Rule(
        "s",
        r"type_description_interfaces/srv/GetTypeDescription",
        "Returns the full description of a message type {node} uses.",
        "system",
        ("introspection",),
        ("tooling",),
    ),
    _Rule(
        "t",
        r"visualization_msgs/msg/\w+",
        "Markers for RViz ({what}).",
        "diagnostics",
        ("visualise",),
        ("RViz",),
    ),
)

_PACKAGE_MODULES = {
    "nav2_msgs": "navigation",
    "nav_msgs": "navigation",
    "moveit_msgs": "manipulation",
    "control_msgs": "manipulation",
    "trajectory_msgs": "manipulation",
    "sensor_msgs": "perception",
    "geometry_msgs": "base motion",
    "tf2_msgs": "localisation",
    "slam_toolbox": "mapping",
    "gazebo_msgs": "simulation",
    "ros_gz_interfaces": "simulation",
    "controller_manager_msgs": "controller management",
    "diagnostic_msgs": "diagnostics",
    "rcl_interfaces": "system",
    "lifecycle_msgs": "system",
    "type_description_interfaces": "system",
    "composition_interfaces": "system",
    "rosbag2_interfaces": "system",
}

_KEY_FIELDS = 8


def _what(name: str) -> str:
    words = re.split(r"[/_]+", name.strip("/"))
    return " ".join(w for w in words if w) or name


def _owner(name: str) -> str | None:
    """The namespace an interface lives in (``/arm_controller/state`` -> ``arm_controller``).

    By ROS convention a node's own services and topics sit under the node's name, so this
    is the node (or controller) the interface belongs to when the name has a namespace.
    """
    head, _, _ = name.strip("/").rpartition("/")
    return head or None


def _match(kind: str, name: str, type_name: str) -> _Rule | None:
    for rule in _RULES:
        if kind[:1] not in rule.kinds:
            continue
        if not re.fullmatch(rule.type_pattern, type_name):
            continue
        if rule.name_pattern is None or re.search(rule.name_pattern, name) is not None:
            return rule
    return None


def _telling(path: str) -> bool:
    # A std_msgs/Header (stamp, frame_id) heads most messages and the sec/nanosec halves
    # of a time say nothing about what an interface is for; the other fields do.
    parts = path.split(".")
    return "header" not in parts and parts[-1] not in {"sec", "nanosec"}


def _key_fields(field_paths: Sequence[str]) -> list[str]:
    # Top-level fields first: `pose` and `twist` of an Odometry tell more than the
    # parts of the first one.
    telling = [p for p in field_paths if _telling(p)]
    return sorted(telling, key=lambda p: p.count("."))[:_KEY_FIELDS]


def control_role(kind: str, name: str, type_name: str) -> Role | None:
    """How the rule for this interface says it serves the resource, if a rule says so."""
    rule = _match(kind, name, type_name)
    return rule.role if rule is not None else None


def describe_by_rules(
    kind: str, name: str, type_name: str, field_paths: Sequence[str] = ()
) -> Description:
    """A description from the interface's kind, name, type and field paths alone."""
    key_fields = _key_fields(field_paths)
    rule = _match(kind, name, type_name)
    if rule is not None:
        owner = _owner(name)
        return Description(
            purpose=rule.purpose.format(
                name=name,
                what=_what(name),
                node=f"node {owner}" if owner else "its node",
                controller=f"the controller {owner}" if owner else "its controller",
            ),
            module=rule.module,
            tasks=list(rule.tasks),
            used_by=list(rule.used_by),
            key_fields=key_fields,
            engine="rules",
        )
    package = type_name.split("/", 1)[0]
    short_type = type_name.rsplit("/", 1)[-1]
    verb = {"topic": "Topic", "service": "Service", "action": "Action"}.get(kind, kind)
    purpose = f"{verb} {name} ({short_type}): {_what(name)}."
    return Description(
        purpose=purpose,
        module=_PACKAGE_MODULES.get(package, "other"),
        tasks=[],
        used_by=[],
        key_fields=key_fields,
        engine="rules",
    )
