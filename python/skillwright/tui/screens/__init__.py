"""The tabs of the main screen (panes) and the modal screens (help, open a path)."""
