"""The Textual TUI: ``skillwright tui [--workspace DIR]``.

A thin driver of the same engine the headless commands use. Headless modules never import
this package (or Textual); the app imports heavy libraries only inside its workers.
"""
