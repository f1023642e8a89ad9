"""Stage 6: checking a generated skill — static checks first."""
