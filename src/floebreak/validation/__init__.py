"""The thesis' statements, their scoring and the validation studies (`floebreak validate`,
docs/validation.md)."""
