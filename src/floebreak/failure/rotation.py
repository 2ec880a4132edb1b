"""Direct rotation (thesis §4.4): the floe is rotated out of the plane instead of breaking.

Two cases:
- unbreakable by size (classification "unbreakable", thesis Eq. 5): the piece in contact is pushed down
  and passes under the hull → **cusp**;
- rotated by position (a floe classified for cracking whose crack cannot start at the aft part of the bow,
  thesis §4.4 second case): the floe is turned aside and stays beside the hull → **flipped**.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from floebreak.failure.base import FailureContext, FailureInput, Fate, NewPiece, Outcome, failed
from floebreak.failure.registry import register_mode


@dataclass(frozen=True)
class DirectRotation:
    name: ClassVar[str] = "rotation"

    def evaluate(self, inp: FailureInput, ctx: FailureContext) -> Outcome:
        unbreakable = inp.classification.failure_class == "unbreakable"
        fate = Fate.CUSP if unbreakable else Fate.FLIPPED  # unbreakable by size, else rotated by position
        return failed(self.name, (NewPiece(inp.polygon, fate, inp.crack_count),))


register_mode(DirectRotation)
