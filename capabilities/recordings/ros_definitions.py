"""ROS 2 (Jazzy) interface definitions used by make_recording.py.

Field lists (types, names, constants, defaults, array bounds) follow the ROS 2 Jazzy
releases of the packages named below; the layout and the few comments are our own.
Keys are full interface names: ``pkg/msg/Name``, ``pkg/srv/Name`` (request ``---``
response) and ``pkg/action/Name`` (goal ``---`` result ``---`` feedback).  Inside a
definition, types of the same package are written bare (``Pose``), other packages as
``pkg/Name``, exactly like the .msg/.srv/.action files do, so rosbag2's dependency
resolution works on this text unchanged.
"""

from __future__ import annotations

_ARRAY, _BSEQ, _USEQ = 48, 96, 144
_FIELD_TYPE_BASE = [
    "NESTED_TYPE", "INT8", "UINT8", "INT16", "UINT16", "INT32", "UINT32", "INT64",
    "UINT64", "FLOAT", "DOUBLE", "LONG_DOUBLE", "CHAR", "WCHAR", "BOOLEAN", "BYTE",
    "STRING", "WSTRING", "FIXED_STRING", "FIXED_WSTRING", "BOUNDED_STRING",
    "BOUNDED_WSTRING",
]


def _field_type_constants() -> str:
    lines = ["uint8 FIELD_TYPE_NOT_SET=0"]
    for suffix, offset in (("", 0), ("_ARRAY", _ARRAY), ("_BOUNDED_SEQUENCE", _BSEQ),
                           ("_UNBOUNDED_SEQUENCE", _USEQ)):
        for number, base in enumerate(_FIELD_TYPE_BASE, start=1):
            lines.append(f"uint8 FIELD_TYPE_{base}{suffix}={number + offset}")
    return "\n".join(lines)


DEFINITIONS: dict[str, str] = {
    # ------------------------------------------------------------ builtin_interfaces
    "builtin_interfaces/msg/Time": """\
# ROS time: seconds and nanoseconds since the epoch
int32 sec
uint32 nanosec
""",
    "builtin_interfaces/msg/Duration": """\
# Time span: seconds and nanoseconds
int32 sec
uint32 nanosec
""",
    # ------------------------------------------------------------ std_msgs
    "std_msgs/msg/Header": """\
# Time stamp and coordinate frame of stamped data
builtin_interfaces/Time stamp
string frame_id
""",
    "std_msgs/msg/String": "string data\n",
    "std_msgs/msg/Empty": "",
    "std_msgs/msg/ColorRGBA": "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n",
    # ------------------------------------------------------------ geometry_msgs
    "geometry_msgs/msg/Vector3": "float64 x\nfloat64 y\nfloat64 z\n",
    "geometry_msgs/msg/Point": "float64 x\nfloat64 y\nfloat64 z\n",
    "geometry_msgs/msg/Point32": "float32 x\nfloat32 y\nfloat32 z\n",
    "geometry_msgs/msg/Quaternion": "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n",
    "geometry_msgs/msg/Pose": "Point position\nQuaternion orientation\n",
    "geometry_msgs/msg/PoseStamped": "std_msgs/Header header\nPose pose\n",
    "geometry_msgs/msg/PoseWithCovariance": """\
Pose pose
# Row-major 6x6 covariance of (x, y, z, rot x, rot y, rot z)
float64[36] covariance
""",
    "geometry_msgs/msg/PoseWithCovarianceStamped": "std_msgs/Header header\nPoseWithCovariance pose\n",
    "geometry_msgs/msg/Twist": "Vector3 linear\nVector3 angular\n",
    "geometry_msgs/msg/TwistWithCovariance": "Twist twist\nfloat64[36] covariance\n",
    "geometry_msgs/msg/Accel": "Vector3 linear\nVector3 angular\n",
    "geometry_msgs/msg/Wrench": "Vector3 force\nVector3 torque\n",
    "geometry_msgs/msg/Transform": "Vector3 translation\nQuaternion rotation\n",
    "geometry_msgs/msg/TransformStamped": """\
std_msgs/Header header
string child_frame_id
Transform transform
""",
    "geometry_msgs/msg/Polygon": "Point32[] points\n",
    "geometry_msgs/msg/PolygonStamped": "std_msgs/Header header\nPolygon polygon\n",
    # ------------------------------------------------------------ nav_msgs
    "nav_msgs/msg/Odometry": """\
std_msgs/Header header
string child_frame_id
geometry_msgs/PoseWithCovariance pose
geometry_msgs/TwistWithCovariance twist
""",
    "nav_msgs/msg/MapMetaData": """\
builtin_interfaces/Time map_load_time
float32 resolution
uint32 width
uint32 height
geometry_msgs/Pose origin
""",
    "nav_msgs/msg/OccupancyGrid": """\
std_msgs/Header header
MapMetaData info
# Row-major cells, probabilities in [0, 100], -1 unknown
int8[] data
""",
    "nav_msgs/msg/Path": "std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n",
    # ------------------------------------------------------------ sensor_msgs
    "sensor_msgs/msg/LaserScan": """\
std_msgs/Header header
float32 angle_min
float32 angle_max
float32 angle_increment
float32 time_increment
float32 scan_time
float32 range_min
float32 range_max
float32[] ranges
float32[] intensities
""",
    "sensor_msgs/msg/Imu": """\
std_msgs/Header header
geometry_msgs/Quaternion orientation
float64[9] orientation_covariance
geometry_msgs/Vector3 angular_velocity
float64[9] angular_velocity_covariance
geometry_msgs/Vector3 linear_acceleration
float64[9] linear_acceleration_covariance
""",
    "sensor_msgs/msg/JointState": """\
std_msgs/Header header
string[] name
float64[] position
float64[] velocity
float64[] effort
""",
    "sensor_msgs/msg/MultiDOFJointState": """\
std_msgs/Header header
string[] joint_names
geometry_msgs/Transform[] transforms
geometry_msgs/Twist[] twist
geometry_msgs/Wrench[] wrench
""",
    "sensor_msgs/msg/BatteryState": """\
uint8 POWER_SUPPLY_STATUS_UNKNOWN=0
uint8 POWER_SUPPLY_STATUS_CHARGING=1
uint8 POWER_SUPPLY_STATUS_DISCHARGING=2
uint8 POWER_SUPPLY_STATUS_NOT_CHARGING=3
uint8 POWER_SUPPLY_STATUS_FULL=4
uint8 POWER_SUPPLY_HEALTH_UNKNOWN=0
uint8 POWER_SUPPLY_HEALTH_GOOD=1
uint8 POWER_SUPPLY_HEALTH_OVERHEAT=2
uint8 POWER_SUPPLY_HEALTH_DEAD=3
uint8 POWER_SUPPLY_HEALTH_OVERVOLTAGE=4
uint8 POWER_SUPPLY_HEALTH_UNSPEC_FAILURE=5
uint8 POWER_SUPPLY_HEALTH_COLD=6
uint8 POWER_SUPPLY_HEALTH_WATCHDOG_TIMER_EXPIRE=7
uint8 POWER_SUPPLY_HEALTH_SAFETY_TIMER_EXPIRE=8
uint8 POWER_SUPPLY_TECHNOLOGY_UNKNOWN=0
uint8 POWER_SUPPLY_TECHNOLOGY_NIMH=1
uint8 POWER_SUPPLY_TECHNOLOGY_LION=2
uint8 POWER_SUPPLY_TECHNOLOGY_LIPO=3
uint8 POWER_SUPPLY_TECHNOLOGY_LIFE=4
uint8 POWER_SUPPLY_TECHNOLOGY_NICD=5
uint8 POWER_SUPPLY_TECHNOLOGY_LIMN=6
uint8 POWER_SUPPLY_TECHNOLOGY_TERNARY=7
uint8 POWER_SUPPLY_TECHNOLOGY_VRLA=8

std_msgs/Header header
float32 voltage
float32 temperature
float32 current
float32 charge
float32 capacity
float32 design_capacity
float32 percentage
uint8 power_supply_status
uint8 power_supply_health
uint8 power_supply_technology
bool present
float32[] cell_voltage
float32[] cell_temperature
string location
string serial_number
""",
    # ------------------------------------------------------------ tf2_msgs / rosgraph_msgs
    "tf2_msgs/msg/TFMessage": "geometry_msgs/TransformStamped[] transforms\n",
    "rosgraph_msgs/msg/Clock": "builtin_interfaces/Time clock\n",
    # ------------------------------------------------------------ diagnostic_msgs
    "diagnostic_msgs/msg/KeyValue": "string key\nstring value\n",
    "diagnostic_msgs/msg/DiagnosticStatus": """\
byte OK=0
byte WARN=1
byte ERROR=2
byte STALE=3
byte level
string name
string message
string hardware_id
KeyValue[] values
""",
    "diagnostic_msgs/msg/DiagnosticArray": "std_msgs/Header header\nDiagnosticStatus[] status\n",
    # ------------------------------------------------------------ rcl_interfaces
    "rcl_interfaces/msg/Log": """\
uint8 DEBUG=10
uint8 INFO=20
uint8 WARN=30
uint8 ERROR=40
uint8 FATAL=50
builtin_interfaces/Time stamp
uint8 level
string name
string msg
string file
string function
uint32 line
""",
    "rcl_interfaces/msg/ParameterValue": """\
# type is one of the ParameterType constants; only the matching *_value is valid
uint8 type
bool bool_value
int64 integer_value
float64 double_value
string string_value
byte[] byte_array_value
bool[] bool_array_value
int64[] integer_array_value
float64[] double_array_value
string[] string_array_value
""",
    "rcl_interfaces/msg/Parameter": "string name\nParameterValue value\n",
    "rcl_interfaces/msg/ParameterEvent": """\
builtin_interfaces/Time stamp
string node
Parameter[] new_parameters
Parameter[] changed_parameters
Parameter[] deleted_parameters
""",
    "rcl_interfaces/msg/FloatingPointRange": "float64 from_value\nfloat64 to_value\nfloat64 step\n",
    "rcl_interfaces/msg/IntegerRange": "int64 from_value\nint64 to_value\nuint64 step\n",
    "rcl_interfaces/msg/ParameterDescriptor": """\
string name
uint8 type
string description
string additional_constraints
bool read_only false
bool dynamic_typing false
FloatingPointRange[<=1] floating_point_range
IntegerRange[<=1] integer_range
""",
    "rcl_interfaces/msg/SetParametersResult": "bool successful\nstring reason\n",
    "rcl_interfaces/msg/ListParametersResult": "string[] names\nstring[] prefixes\n",
    "rcl_interfaces/srv/DescribeParameters": "string[] names\n---\nParameterDescriptor[] descriptors\n",
    "rcl_interfaces/srv/GetParameters": "string[] names\n---\nParameterValue[] values\n",
    "rcl_interfaces/srv/GetParameterTypes": "string[] names\n---\nuint8[] types\n",
    "rcl_interfaces/srv/ListParameters": """\
uint64 DEPTH_RECURSIVE=0
string[] prefixes
uint64 depth
---
ListParametersResult result
""",
    "rcl_interfaces/srv/SetParameters": "Parameter[] parameters\n---\nSetParametersResult[] results\n",
    "rcl_interfaces/srv/SetParametersAtomically": "Parameter[] parameters\n---\nSetParametersResult result\n",
    # ------------------------------------------------------------ type_description_interfaces
    "type_description_interfaces/msg/FieldType": _field_type_constants() + """
uint8 type_id 0
uint64 capacity
uint64 string_capacity
string<=255 nested_type_name
""",
    "type_description_interfaces/msg/Field": """\
string name
FieldType type
string default_value
""",
    "type_description_interfaces/msg/IndividualTypeDescription": "string<=255 type_name\nField[] fields\n",
    "type_description_interfaces/msg/TypeDescription": """\
IndividualTypeDescription type_description
IndividualTypeDescription[] referenced_type_descriptions
""",
    "type_description_interfaces/msg/TypeSource": """\
string type_name
string encoding
string raw_file_contents
""",
    "type_description_interfaces/msg/KeyValue": "string key\nstring value\n",
    "type_description_interfaces/srv/GetTypeDescription": """\
string type_name
string type_hash
bool include_type_sources true
---
bool successful
string failure_reason
TypeDescription type_description
TypeSource[] type_sources
KeyValue[] extra_information
""",
    # ------------------------------------------------------------ lifecycle_msgs
    "lifecycle_msgs/msg/State": """\
uint8 PRIMARY_STATE_UNKNOWN=0
uint8 PRIMARY_STATE_UNCONFIGURED=1
uint8 PRIMARY_STATE_INACTIVE=2
uint8 PRIMARY_STATE_ACTIVE=3
uint8 PRIMARY_STATE_FINALIZED=4
uint8 TRANSITION_STATE_CONFIGURING=10
uint8 TRANSITION_STATE_CLEANINGUP=11
uint8 TRANSITION_STATE_SHUTTINGDOWN=12
uint8 TRANSITION_STATE_ACTIVATING=13
uint8 TRANSITION_STATE_DEACTIVATING=14
uint8 TRANSITION_STATE_ERRORPROCESSING=15
uint8 id
string label
""",
    "lifecycle_msgs/msg/Transition": """\
uint8 TRANSITION_CREATE=0
uint8 TRANSITION_CONFIGURE=1
uint8 TRANSITION_CLEANUP=2
uint8 TRANSITION_ACTIVATE=3
uint8 TRANSITION_DEACTIVATE=4
uint8 TRANSITION_UNCONFIGURED_SHUTDOWN=5
uint8 TRANSITION_INACTIVE_SHUTDOWN=6
uint8 TRANSITION_ACTIVE_SHUTDOWN=7
uint8 TRANSITION_DESTROY=8
uint8 TRANSITION_ON_CONFIGURE_SUCCESS=10
uint8 TRANSITION_ON_CONFIGURE_FAILURE=11
uint8 TRANSITION_ON_CONFIGURE_ERROR=12
uint8 TRANSITION_ON_CLEANUP_SUCCESS=20
uint8 TRANSITION_ON_CLEANUP_FAILURE=21
uint8 TRANSITION_ON_CLEANUP_ERROR=22
uint8 TRANSITION_ON_ACTIVATE_SUCCESS=30
uint8 TRANSITION_ON_ACTIVATE_FAILURE=31
uint8 TRANSITION_ON_ACTIVATE_ERROR=32
uint8 TRANSITION_ON_DEACTIVATE_SUCCESS=40
uint8 TRANSITION_ON_DEACTIVATE_FAILURE=41
uint8 TRANSITION_ON_DEACTIVATE_ERROR=42
uint8 TRANSITION_ON_SHUTDOWN_SUCCESS=50
uint8 TRANSITION_ON_SHUTDOWN_FAILURE=51
uint8 TRANSITION_ON_SHUTDOWN_ERROR=52
uint8 TRANSITION_ON_ERROR_SUCCESS=60
uint8 TRANSITION_ON_ERROR_FAILURE=61
uint8 TRANSITION_ON_ERROR_ERROR=62
uint8 TRANSITION_CALLBACK_SUCCESS=97
uint8 TRANSITION_CALLBACK_FAILURE=98
uint8 TRANSITION_CALLBACK_ERROR=99
uint8 id
string label
""",
    "lifecycle_msgs/msg/TransitionEvent": """\
uint64 timestamp
Transition transition
State start_state
State goal_state
""",
    "lifecycle_msgs/srv/ChangeState": "Transition transition\n---\nbool success\n",
    "lifecycle_msgs/srv/GetState": "---\nState current_state\n",
    # ------------------------------------------------------------ bond / rosbag2_interfaces
    "bond/msg/Status": """\
std_msgs/Header header
string id
string instance_id
bool active
float32 heartbeat_timeout
float32 heartbeat_period
""",
    "rosbag2_interfaces/msg/WriteSplitEvent": """\
string closed_file
string opened_file
string node_name
""",
    # ------------------------------------------------------------ service_msgs / actions
    "service_msgs/msg/ServiceEventInfo": """\
uint8 REQUEST_SENT=0
uint8 REQUEST_RECEIVED=1
uint8 RESPONSE_SENT=2
uint8 RESPONSE_RECEIVED=3
uint8 event_type
builtin_interfaces/Time stamp
char[16] client_gid
int64 sequence_number
""",
    "unique_identifier_msgs/msg/UUID": "uint8[16] uuid\n",
    "action_msgs/msg/GoalInfo": "unique_identifier_msgs/UUID goal_id\nbuiltin_interfaces/Time stamp\n",
    "action_msgs/msg/GoalStatus": """\
int8 STATUS_UNKNOWN=0
int8 STATUS_ACCEPTED=1
int8 STATUS_EXECUTING=2
int8 STATUS_CANCELING=3
int8 STATUS_SUCCEEDED=4
int8 STATUS_CANCELED=5
int8 STATUS_ABORTED=6
GoalInfo goal_info
int8 status
""",
    "action_msgs/msg/GoalStatusArray": "GoalStatus[] status_list\n",
    "action_msgs/srv/CancelGoal": """\
GoalInfo goal_info
---
int8 ERROR_NONE=0
int8 ERROR_REJECTED=1
int8 ERROR_UNKNOWN_GOAL_ID=2
int8 ERROR_GOAL_TERMINATED=3
int8 return_code
GoalInfo[] goals_canceling
""",
    # ------------------------------------------------------------ nav2_msgs (Jazzy)
    "nav2_msgs/action/NavigateToPose": """\
#goal definition
geometry_msgs/PoseStamped pose
string behavior_tree
---
#result definition
uint16 NONE=0
uint16 UNKNOWN=9000
uint16 FAILED_TO_LOAD_BEHAVIOR_TREE=9001
uint16 TF_ERROR=9002
uint16 error_code
string error_msg
---
#feedback definition
geometry_msgs/PoseStamped current_pose
builtin_interfaces/Duration navigation_time
builtin_interfaces/Duration estimated_time_remaining
int16 number_of_recoveries
float32 distance_remaining
""",
    "nav2_msgs/action/NavigateThroughPoses": """\
#goal definition
geometry_msgs/PoseStamped[] poses
string behavior_tree
---
#result definition
uint16 NONE=0
uint16 UNKNOWN=9000
uint16 FAILED_TO_LOAD_BEHAVIOR_TREE=9001
uint16 TF_ERROR=9002
uint16 error_code
string error_msg
---
#feedback definition
geometry_msgs/PoseStamped current_pose
builtin_interfaces/Duration navigation_time
builtin_interfaces/Duration estimated_time_remaining
int16 number_of_recoveries
float32 distance_remaining
int16 number_of_poses_remaining
""",
    "nav2_msgs/action/ComputePathToPose": """\
#goal definition
geometry_msgs/PoseStamped goal
geometry_msgs/PoseStamped start
string planner_id
bool use_start # false: start at the robot's current pose
---
#result definition
uint16 NONE=0
uint16 UNKNOWN=200
uint16 INVALID_PLANNER=201
uint16 TF_ERROR=202
uint16 START_OUTSIDE_MAP=203
uint16 GOAL_OUTSIDE_MAP=204
uint16 START_OCCUPIED=205
uint16 GOAL_OCCUPIED=206
uint16 TIMEOUT=207
uint16 NO_VALID_PATH=208
nav_msgs/Path path
builtin_interfaces/Duration planning_time
uint16 error_code
string error_msg
---
#feedback definition
""",
    "nav2_msgs/action/FollowPath": """\
#goal definition
nav_msgs/Path path
string controller_id
string goal_checker_id
---
#result definition
uint16 NONE=0
uint16 UNKNOWN=100
uint16 INVALID_CONTROLLER=101
uint16 TF_ERROR=102
uint16 INVALID_PATH=103
uint16 PATIENCE_EXCEEDED=104
uint16 FAILED_TO_MAKE_PROGRESS=105
uint16 NO_VALID_CONTROL=106
uint16 CONTROLLER_TIMED_OUT=107
std_msgs/Empty result
uint16 error_code
string error_msg
---
#feedback definition
float32 distance_to_goal
float32 speed
""",
    "nav2_msgs/action/Spin": """\
#goal definition
float32 target_yaw
builtin_interfaces/Duration time_allowance
bool disable_collision_checks
---
#result definition
uint16 NONE=0
uint16 UNKNOWN=700
uint16 TIMEOUT=701
uint16 TF_ERROR=702
uint16 COLLISION_AHEAD=703
builtin_interfaces/Duration total_elapsed_time
uint16 error_code
string error_msg
---
#feedback definition
float32 angular_distance_traveled
""",
    "nav2_msgs/action/BackUp": """\
#goal definition
geometry_msgs/Point target
float32 speed
builtin_interfaces/Duration time_allowance
bool disable_collision_checks
---
#result definition
uint16 NONE=0
uint16 UNKNOWN=710
uint16 TIMEOUT=711
uint16 TF_ERROR=712
uint16 INVALID_INPUT=713
uint16 COLLISION_AHEAD=714
builtin_interfaces/Duration total_elapsed_time
uint16 error_code
string error_msg
---
#feedback definition
float32 distance_traveled
""",
    "nav2_msgs/srv/SaveMap": """\
# URL of the map to write, without extension
string map_topic
string map_url
# png, pgm or bmp
string image_format
# trinary, scale or raw
string map_mode
float32 free_thresh
float32 occupied_thresh
---
bool result
""",
    "nav2_msgs/srv/ClearEntireCostmap": "std_msgs/Empty request\n---\nstd_msgs/Empty response\n",
    # ------------------------------------------------------------ slam_toolbox
    "slam_toolbox/srv/SaveMap": """\
std_msgs/String name
---
uint8 RESULT_SUCCESS=0
uint8 RESULT_NO_MAP_RECEIEVD=1
uint8 RESULT_UNDEFINED_FAILURE=255
uint8 result
""",
    "slam_toolbox/srv/SerializePoseGraph": """\
string filename
---
uint8 RESULT_SUCCESS=0
uint8 RESULT_UNDEFINED_FAILURE=255
uint8 result
""",
    # ------------------------------------------------------------ trajectory_msgs
    "trajectory_msgs/msg/JointTrajectoryPoint": """\
float64[] positions
float64[] velocities
float64[] accelerations
float64[] effort
builtin_interfaces/Duration time_from_start
""",
    "trajectory_msgs/msg/JointTrajectory": """\
std_msgs/Header header
string[] joint_names
JointTrajectoryPoint[] points
""",
    "trajectory_msgs/msg/MultiDOFJointTrajectoryPoint": """\
geometry_msgs/Transform[] transforms
geometry_msgs/Twist[] velocities
geometry_msgs/Twist[] accelerations
builtin_interfaces/Duration time_from_start
""",
    "trajectory_msgs/msg/MultiDOFJointTrajectory": """\
std_msgs/Header header
string[] joint_names
MultiDOFJointTrajectoryPoint[] points
""",
    # ------------------------------------------------------------ control_msgs (Jazzy)
    "control_msgs/msg/JointTolerance": """\
string name
float64 position
float64 velocity
float64 acceleration
""",
    "control_msgs/msg/JointComponentTolerance": """\
uint16 X_AXIS=1
uint16 Y_AXIS=2
uint16 Z_AXIS=3
uint16 TRANSLATION=4
uint16 ROTATION=5
string joint_name
uint16 component
float64 position
float64 velocity
float64 acceleration
""",
    "control_msgs/msg/GripperCommand": "float64 position\nfloat64 max_effort\n",
    "control_msgs/action/FollowJointTrajectory": """\
trajectory_msgs/JointTrajectory trajectory
trajectory_msgs/MultiDOFJointTrajectory multi_dof_trajectory
JointTolerance[] path_tolerance
JointComponentTolerance[] component_path_tolerance
JointTolerance[] goal_tolerance
JointComponentTolerance[] component_goal_tolerance
builtin_interfaces/Duration goal_time_tolerance
---
int32 error_code
int32 SUCCESSFUL=0
int32 INVALID_GOAL=-1
int32 INVALID_JOINTS=-2
int32 OLD_HEADER_TIMESTAMP=-3
int32 PATH_TOLERANCE_VIOLATED=-4
int32 GOAL_TOLERANCE_VIOLATED=-5
string error_string
---
std_msgs/Header header
string[] joint_names
trajectory_msgs/JointTrajectoryPoint desired
trajectory_msgs/JointTrajectoryPoint actual
trajectory_msgs/JointTrajectoryPoint error
string[] multi_dof_joint_names
trajectory_msgs/MultiDOFJointTrajectoryPoint multi_dof_desired
trajectory_msgs/MultiDOFJointTrajectoryPoint multi_dof_actual
trajectory_msgs/MultiDOFJointTrajectoryPoint multi_dof_error
""",
    "control_msgs/action/GripperCommand": """\
GripperCommand command
---
float64 position
float64 effort
bool stalled
bool reached_goal
---
float64 position
float64 effort
bool stalled
bool reached_goal
""",
    # ------------------------------------------------------------ controller_manager_msgs (Jazzy)
    "controller_manager_msgs/msg/ChainConnection": "string name\nstring[] reference_interfaces\n",
    "controller_manager_msgs/msg/ControllerState": """\
string name
string state
string type
string[] claimed_interfaces
string[] required_command_interfaces
string[] required_state_interfaces
bool is_chainable
bool is_chained
string[] reference_interfaces
ChainConnection[] chain_connections
""",
    "controller_manager_msgs/srv/ListControllers": "---\nControllerState[] controller\n",
    "controller_manager_msgs/srv/SwitchController": """\
int32 BEST_EFFORT=1
int32 STRICT=2
string[] activate_controllers
string[] deactivate_controllers
int32 strictness
bool activate_asap
builtin_interfaces/Duration timeout
---
bool ok
""",
    # ------------------------------------------------------------ shape_msgs / object_recognition / octomap
    "shape_msgs/msg/SolidPrimitive": """\
uint8 BOX=1
uint8 SPHERE=2
uint8 CYLINDER=3
uint8 CONE=4
uint8 PRISM=5
uint8 type
float64[<=3] dimensions
uint8 BOX_X=0
uint8 BOX_Y=1
uint8 BOX_Z=2
uint8 SPHERE_RADIUS=0
uint8 CYLINDER_HEIGHT=0
uint8 CYLINDER_RADIUS=1
uint8 CONE_HEIGHT=0
uint8 CONE_RADIUS=1
uint8 PRISM_HEIGHT=0
geometry_msgs/Polygon polygon
""",
    "shape_msgs/msg/MeshTriangle": "uint32[3] vertex_indices\n",
    "shape_msgs/msg/Mesh": "MeshTriangle[] triangles\ngeometry_msgs/Point[] vertices\n",
    "shape_msgs/msg/Plane": "# ax + by + cz + d = 0\nfloat64[4] coef\n",
    "object_recognition_msgs/msg/ObjectType": "string key\nstring db\n",
    "octomap_msgs/msg/Octomap": """\
std_msgs/Header header
bool binary
string id
float64 resolution
int8[] data
""",
    "octomap_msgs/msg/OctomapWithPose": """\
std_msgs/Header header
geometry_msgs/Pose origin
octomap_msgs/Octomap octomap
""",
    # ------------------------------------------------------------ moveit_msgs (Jazzy)
    "moveit_msgs/msg/MoveItErrorCodes": """\
int32 val
int32 SUCCESS=1
int32 UNDEFINED=0
int32 FAILURE=99999
int32 PLANNING_FAILED=-1
int32 INVALID_MOTION_PLAN=-2
int32 MOTION_PLAN_INVALIDATED_BY_ENVIRONMENT_CHANGE=-3
int32 CONTROL_FAILED=-4
int32 UNABLE_TO_AQUIRE_SENSOR_DATA=-5
int32 TIMED_OUT=-6
int32 PREEMPTED=-7
int32 START_STATE_IN_COLLISION=-10
int32 START_STATE_VIOLATES_PATH_CONSTRAINTS=-11
int32 START_STATE_INVALID=-26
int32 GOAL_IN_COLLISION=-12
int32 GOAL_VIOLATES_PATH_CONSTRAINTS=-13
int32 GOAL_CONSTRAINTS_VIOLATED=-14
int32 GOAL_STATE_INVALID=-27
int32 UNRECOGNIZED_GOAL_TYPE=-28
int32 INVALID_GROUP_NAME=-15
int32 INVALID_GOAL_CONSTRAINTS=-16
int32 INVALID_ROBOT_STATE=-17
int32 INVALID_LINK_NAME=-18
int32 INVALID_OBJECT_NAME=-19
int32 FRAME_TRANSFORM_FAILURE=-21
int32 COLLISION_CHECKING_UNAVAILABLE=-22
int32 ROBOT_STATE_STALE=-23
int32 SENSOR_INFO_STALE=-24
int32 COMMUNICATION_FAILURE=-25
int32 CRASH=-29
int32 ABORT=-30
int32 NO_IK_SOLUTION=-31
string message
string source
""",
    "moveit_msgs/msg/CollisionObject": """\
std_msgs/Header header
geometry_msgs/Pose pose
string id
object_recognition_msgs/ObjectType type
shape_msgs/SolidPrimitive[] primitives
geometry_msgs/Pose[] primitive_poses
shape_msgs/Mesh[] meshes
geometry_msgs/Pose[] mesh_poses
shape_msgs/Plane[] planes
geometry_msgs/Pose[] plane_poses
string[] subframe_names
geometry_msgs/Pose[] subframe_poses
byte ADD=0
byte REMOVE=1
byte APPEND=2
byte MOVE=3
byte operation
""",
    "moveit_msgs/msg/AttachedCollisionObject": """\
string link_name
CollisionObject object
string[] touch_links
trajectory_msgs/JointTrajectory detach_posture
float64 weight
""",
    "moveit_msgs/msg/RobotState": """\
sensor_msgs/JointState joint_state
sensor_msgs/MultiDOFJointState multi_dof_joint_state
AttachedCollisionObject[] attached_collision_objects
bool is_diff
""",
    "moveit_msgs/msg/WorkspaceParameters": """\
std_msgs/Header header
geometry_msgs/Vector3 min_corner
geometry_msgs/Vector3 max_corner
""",
    "moveit_msgs/msg/JointConstraint": """\
string joint_name
float64 position
float64 tolerance_above
float64 tolerance_below
float64 weight
""",
    "moveit_msgs/msg/BoundingVolume": """\
shape_msgs/SolidPrimitive[] primitives
geometry_msgs/Pose[] primitive_poses
shape_msgs/Mesh[] meshes
geometry_msgs/Pose[] mesh_poses
""",
    "moveit_msgs/msg/PositionConstraint": """\
std_msgs/Header header
string link_name
geometry_msgs/Vector3 target_point_offset
BoundingVolume constraint_region
float64 weight
""",
    "moveit_msgs/msg/OrientationConstraint": """\
std_msgs/Header header
geometry_msgs/Quaternion orientation
string link_name
float64 absolute_x_axis_tolerance
float64 absolute_y_axis_tolerance
float64 absolute_z_axis_tolerance
uint8 parameterization
uint8 XYZ_EULER_ANGLES=0
uint8 ROTATION_VECTOR=1
float64 weight
""",
    "moveit_msgs/msg/VisibilityConstraint": """\
float64 target_radius
geometry_msgs/PoseStamped target_pose
int32 cone_sides
geometry_msgs/PoseStamped sensor_pose
float64 max_view_angle
float64 max_range_angle
uint8 SENSOR_Z=0
uint8 SENSOR_Y=1
uint8 SENSOR_X=2
uint8 sensor_view_direction
float64 weight
""",
    "moveit_msgs/msg/Constraints": """\
string name
JointConstraint[] joint_constraints
PositionConstraint[] position_constraints
OrientationConstraint[] orientation_constraints
VisibilityConstraint[] visibility_constraints
""",
    "moveit_msgs/msg/TrajectoryConstraints": "Constraints[] constraints\n",
    "moveit_msgs/msg/CartesianPoint": """\
geometry_msgs/Pose pose
geometry_msgs/Twist velocity
geometry_msgs/Accel acceleration
""",
    "moveit_msgs/msg/CartesianTrajectoryPoint": """\
CartesianPoint point
builtin_interfaces/Duration time_from_start
""",
    "moveit_msgs/msg/CartesianTrajectory": """\
std_msgs/Header header
string tracked_frame
CartesianTrajectoryPoint[] points
""",
    "moveit_msgs/msg/GenericTrajectory": """\
std_msgs/Header header
trajectory_msgs/JointTrajectory[] joint_trajectory
CartesianTrajectory[] cartesian_trajectory
""",
    "moveit_msgs/msg/MotionPlanRequest": """\
WorkspaceParameters workspace_parameters
RobotState start_state
Constraints[] goal_constraints
Constraints path_constraints
TrajectoryConstraints trajectory_constraints
GenericTrajectory[] reference_trajectories
string pipeline_id
string planner_id
string group_name
int32 num_planning_attempts
float64 allowed_planning_time
float64 max_velocity_scaling_factor
float64 max_acceleration_scaling_factor
string cartesian_speed_limited_link
float64 max_cartesian_speed
""",
    "moveit_msgs/msg/AllowedCollisionEntry": "bool[] enabled\n",
    "moveit_msgs/msg/AllowedCollisionMatrix": """\
string[] entry_names
AllowedCollisionEntry[] entry_values
string[] default_entry_names
bool[] default_entry_values
""",
    "moveit_msgs/msg/LinkPadding": "string link_name\nfloat64 padding\n",
    "moveit_msgs/msg/LinkScale": "string link_name\nfloat64 scale\n",
    "moveit_msgs/msg/ObjectColor": "string id\nstd_msgs/ColorRGBA color\n",
    "moveit_msgs/msg/PlanningSceneWorld": """\
CollisionObject[] collision_objects
octomap_msgs/OctomapWithPose octomap
""",
    "moveit_msgs/msg/PlanningScene": """\
string name
RobotState robot_state
string robot_model_name
geometry_msgs/TransformStamped[] fixed_frame_transforms
AllowedCollisionMatrix allowed_collision_matrix
LinkPadding[] link_padding
LinkScale[] link_scale
ObjectColor[] object_colors
PlanningSceneWorld world
bool is_diff
""",
    "moveit_msgs/msg/PlanningOptions": """\
PlanningScene planning_scene_diff
bool plan_only
bool look_around
int32 look_around_attempts
float64 max_safe_execution_cost
bool replan
int32 replan_attempts
float64 replan_delay
""",
    "moveit_msgs/msg/RobotTrajectory": """\
trajectory_msgs/JointTrajectory joint_trajectory
trajectory_msgs/MultiDOFJointTrajectory multi_dof_joint_trajectory
""",
    "moveit_msgs/msg/PositionIKRequest": """\
string group_name
moveit_msgs/RobotState robot_state
moveit_msgs/Constraints constraints
bool avoid_collisions
string ik_link_name
geometry_msgs/PoseStamped pose_stamped
string[] ik_link_names
geometry_msgs/PoseStamped[] pose_stamped_vector
builtin_interfaces/Duration timeout
""",
    "moveit_msgs/action/MoveGroup": """\
# Motion planning request, and how to plan and execute it
MotionPlanRequest request
PlanningOptions planning_options
---
MoveItErrorCodes error_code
moveit_msgs/RobotState trajectory_start
moveit_msgs/RobotTrajectory planned_trajectory
moveit_msgs/RobotTrajectory executed_trajectory
float64 planning_time
---
string state
""",
    "moveit_msgs/action/ExecuteTrajectory": """\
RobotTrajectory trajectory
string[] controller_names
---
MoveItErrorCodes error_code
---
string state
""",
    "moveit_msgs/srv/GetPositionIK": """\
PositionIKRequest ik_request
---
RobotState solution
MoveItErrorCodes error_code
""",
    "moveit_msgs/srv/GetPositionFK": """\
std_msgs/Header header
string[] fk_link_names
RobotState robot_state
---
geometry_msgs/PoseStamped[] pose_stamped
string[] fk_link_names
MoveItErrorCodes error_code
""",
}
