"""Which mode handles a classified floe (thesis Alg. 2, §4.3, §4.4) — `floebreak.failure.dispatch`."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import ClassVar

from floebreak.failure import FailureModel, Outcome, resolve_failure
from floebreak.failure.base import Fate, NewPiece, no_failure
from floebreak.failure.bending import WITHIN_BREAKING_RADIUS


@dataclass(frozen=True)
class Scripted:
    """A stand-in mode that returns a fixed outcome and records nothing."""

    name: ClassVar[str] = "scripted"
    outcome: Outcome

    def evaluate(self, inp, ctx) -> Outcome:
        return self.outcome


CRACKED = Outcome("cracking", True, (NewPiece(None, Fate.FLOE),), reason="cracked")


def bending_input(make_input, kit):
    inp = make_input(kit.midbody_box(20.0, 40.0, 0.1))  # midbody: "shoulder" region
    return replace(inp, classification=replace(inp.classification, failure_class="bending"))


def test_a_floe_within_the_breaking_radius_goes_on_to_cracking(make_input, kit, context):
    model = FailureModel(
        bending=Scripted(no_failure("bending", WITHIN_BREAKING_RADIUS)),
        local_cracking=Scripted(no_failure("local_cracking", WITHIN_BREAKING_RADIUS)),
        cracking=Scripted(CRACKED),
    )
    assert resolve_failure(model, bending_input(make_input, kit), context) is CRACKED


def test_bending_that_merely_holds_does_not_fall_through_to_cracking(make_input, kit, context):
    holds = no_failure("local_cracking", "F_v <= P_f")
    model = FailureModel(bending=Scripted(holds), local_cracking=Scripted(holds), cracking=Scripted(CRACKED))
    assert resolve_failure(model, bending_input(make_input, kit), context) is holds
