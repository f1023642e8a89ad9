"""Stand-in of pySkillUp: the decorators and the ROS 2 skill base class skills use."""
