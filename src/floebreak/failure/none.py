"""The explicit "off" mode: the floe never fails this way (instead of `if enabled:` checks elsewhere).

It passes the floe on, so the dispatch policy's next mode decides (a policy of ``["none"]`` alone leaves the
floe intact).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from floebreak.failure.base import FailureContext, FailureInput, Outcome, pass_on
from floebreak.failure.registry import register_mode


@dataclass(frozen=True)
class NoFailure:
    name: ClassVar[str] = "none"

    def evaluate(self, inp: FailureInput, ctx: FailureContext) -> Outcome:
        return pass_on(self.name)


register_mode(NoFailure)
