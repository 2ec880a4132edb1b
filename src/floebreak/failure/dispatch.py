"""Which failure mode handles a classified floe (thesis §3.2, Alg. 2, §4.3, §4.4).

- "unbreakable" → direct rotation (a cusp);
- "bending" → bending at the stem region; local cracking at the bow side and shoulder (the thesis'
  breaking patterns show local cracking on bent floes near the bow side and shoulder, §4.3, Figs. 15–16);
- a floe of the "bending" class that lies wholly within the breaking radius (no bending line crosses
  it) cannot bend there: it is treated like the "cracking" class below (it is not pushed under whole —
  cusps are the unbreakable pieces, thesis §3.2);
- "cracking" → global cracking; if no crack starts while the contact lies in the shoulder region, the
  floe is rotated aside by its position → flipped (thesis §4.4, second case).

The stem/shoulder boundary is a fraction of the stem-to-shoulder length (`shoulder_region_start`); the
thesis gives no number, so it is a documented parameter.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from floebreak.errors import require_range
from floebreak.failure.base import BowRegion, FailureContext, FailureInput, FailureMode, Outcome
from floebreak.failure.bending import WITHIN_BREAKING_RADIUS
from floebreak.failure.none import NoFailure
from floebreak.failure.rotation import DirectRotation


@dataclass(frozen=True)
class FailureModel:
    """The failure modes of a run and the dispatch settings."""

    bending: FailureMode = NoFailure()
    cracking: FailureMode = NoFailure()
    local_cracking: FailureMode = NoFailure()
    rotation: FailureMode = DirectRotation()
    shoulder_region_start: float = 0.5  # fraction of the stem→shoulder length where the "shoulder" begins
    flip_uncracked_at_shoulder: bool = True

    def __post_init__(self) -> None:
        require_range(
            "failure.shoulder_region_start", self.shoulder_region_start, low=0.0, high=1.0, low_inclusive=True
        )


def bow_region(centre_x_m: float, bow_length_m: float, shoulder_region_start: float) -> BowRegion:
    """ "stem" or "shoulder" for a contact centre at bow-frame x (stem tip at x = 0, shoulder at −L_b)."""
    fraction = -centre_x_m / bow_length_m if bow_length_m > 0 else 0.0
    return "shoulder" if fraction >= shoulder_region_start else "stem"


def resolve_failure(model: FailureModel, inp: FailureInput, ctx: FailureContext) -> Outcome:
    """Apply the dispatch policy above and return the outcome of the chosen mode."""
    failure_class = inp.classification.failure_class
    if failure_class == "unbreakable":
        return model.rotation.evaluate(inp, ctx)
    if failure_class == "bending":
        local = inp.region == "shoulder" and not isinstance(model.local_cracking, NoFailure)
        bent = (model.local_cracking if local else model.bending).evaluate(inp, ctx)
        if bent.failed or bent.reason != WITHIN_BREAKING_RADIUS:
            return bent
    outcome = model.cracking.evaluate(inp, ctx)
    if not outcome.failed and inp.region == "shoulder" and model.flip_uncracked_at_shoulder:
        flipped = model.rotation.evaluate(inp, ctx)
        return replace(flipped, reason=f"no crack at the shoulder ({outcome.reason}); rotated by position")
    return outcome
