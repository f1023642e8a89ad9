"""Widgets the panes share: the streaming code view."""
