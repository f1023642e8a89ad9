"""Pipeline stage 2 (and the model stage 3 fills): the robot's ROS 2 interfaces.

:mod:`~skillwright.interfaces.inventory` defines the inventory document;
:mod:`~skillwright.interfaces.sources` holds the sources that produce it (recordings,
reference-tool reports, the live graph); :mod:`~skillwright.interfaces.ros2msg` parses
message definitions, :mod:`~skillwright.interfaces.typestore` fills in standard ones a
source only names, and :mod:`~skillwright.interfaces.infrastructure` flags ROS 2
plumbing. ``commands`` has the ``skillwright discover`` command.
"""
