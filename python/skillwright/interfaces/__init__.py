"""Pipeline stages 2 and 3: the robot's ROS 2 interfaces, described and judged.

:mod:`~skillwright.interfaces.inventory` defines the inventory document;
:mod:`~skillwright.interfaces.sources` holds the sources that produce it (recordings,
reference-tool reports, the live graph); :mod:`~skillwright.interfaces.ros2msg` parses
message definitions, :mod:`~skillwright.interfaces.typestore` fills in standard ones a
source only names, and :mod:`~skillwright.interfaces.infrastructure` flags ROS 2
plumbing. Stage 3: :mod:`~skillwright.interfaces.description` (uniform descriptions, rules
engine), :mod:`~skillwright.interfaces.relevance` (control or infrastructure) and
:mod:`~skillwright.interfaces.enrich` (both engines, the LLM one cached). ``commands`` has
``skillwright discover``, ``inventory_commands`` ``skillwright inventory``.
"""
