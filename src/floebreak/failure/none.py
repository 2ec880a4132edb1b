"""The explicit "off" mode: the floe never fails this way (instead of `if enabled:` checks elsewhere)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from floebreak.failure.base import FailureContext, FailureInput, Outcome, no_failure


@dataclass(frozen=True)
class NoFailure:
    name: ClassVar[str] = "none"

    def evaluate(self, inp: FailureInput, ctx: FailureContext) -> Outcome:
        return no_failure(self.name, "mode disabled")
