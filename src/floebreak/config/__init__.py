"""The scenario (pydantic models, TOML) and the profiles, resolved into the typed settings of the computing
packages (docs/architecture.md)."""
