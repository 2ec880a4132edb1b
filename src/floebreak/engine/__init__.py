"""The stepping engine: the loop (`loop`), failure events between contact searches (`events`), the run's
records (`records`) and the ice motions behind one protocol (`motion`)."""
