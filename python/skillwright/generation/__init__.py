"""Stage 5: write the skill — a deterministic skeleton, then behaviour from a local model."""
