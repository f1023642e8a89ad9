"""Stand-in of ``pyskillup.decorator_check``."""
