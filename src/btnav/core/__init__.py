"""The bottom layer: geometry, frames, clock, errors, YAML and validation."""
