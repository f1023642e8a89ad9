"""``python -m skillwright`` runs the command line."""

from skillwright.cli import main

main()
