"""Stand-in of ``pyskillup.decorators``."""
