"""Nav2-style params files: loading, schemas and checks."""
