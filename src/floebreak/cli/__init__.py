"""The command line (`floebreak`): one module per command group, options defined once (`options`)."""

from floebreak.cli.main import app, main

__all__ = ["app", "main"]
