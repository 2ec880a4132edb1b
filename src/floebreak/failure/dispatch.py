"""Which failure mode handles a classified floe: the dispatch policy (thesis §3.2, Alg. 2, §4.3, §4.4).

A policy names, per failure class (Alg. 2) and bow region, the modes to try in order: a mode that returns
`Status.FAILED` or `Status.INTACT` ends the list, one that returns `Status.PASS_ON` hands the floe to the
next; a floe that every mode passed on stays intact. The default policy (the thesis gives no rule; a
documented choice, docs/model.md §10):

- "unbreakable" → `rotation` (a cusp);
- "bending" → `bending` at the stem region, `local_cracking` at the shoulder region (the thesis' breaking
  patterns show local cracking on bent floes near the bow side and shoulder, §4.3, Figs. 15–16); a floe that
  lies wholly within the breaking radius (no bending line crosses it) is passed on to `cracking` (it is not
  pushed under whole — cusps are the unbreakable pieces, thesis §3.2; the thesis profile rotates it whole
  instead, `profiles.THESIS_POLICY`, docs/model.md §11);
- "cracking" → `cracking`; at the shoulder, a floe in which no crack starts is passed on to `rotation`:
  rotated aside by its position → flipped (thesis §4.4, second case; `flip_uncracked_at_shoulder`).

The stem/shoulder boundary is a fraction of the stem-to-shoulder length (`shoulder_region_start`); the
thesis gives no number, so it is a documented parameter.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import get_args

from floebreak.errors import InputError, require_range
from floebreak.failure.base import BowRegion, FailureContext, FailureInput, FailureMode, Outcome, Status
from floebreak.failure.none import NoFailure
from floebreak.failure.rotation import DirectRotation
from floebreak.mechanics.classify import FailureClass

FAILURE_CLASSES: tuple[str, ...] = get_args(FailureClass)
BOW_REGIONS: tuple[str, ...] = get_args(BowRegion)

# policy: failure class → bow region → mode names, tried in order
Policy = Mapping[str, Mapping[str, Sequence[str]]]
# as stated (a scenario's [failure.policy]): a class's regions, or one list for both
StatedPolicy = Mapping[str, Mapping[str, Sequence[str]] | Sequence[str]]


def default_policy(flip_uncracked_at_shoulder: bool = True) -> dict[str, dict[str, tuple[str, ...]]]:
    """The default policy of the module docstring (without the shoulder's rotation if not flipping)."""
    flip = ("rotation",) if flip_uncracked_at_shoulder else ()
    return {
        "unbreakable": {"stem": ("rotation",), "shoulder": ("rotation",)},
        "bending": {"stem": ("bending", "cracking"), "shoulder": ("local_cracking", "cracking", *flip)},
        "cracking": {"stem": ("cracking",), "shoulder": ("cracking", *flip)},
    }


def normalise_policy(
    stated: StatedPolicy | None, modes: Sequence[str] | None = None
) -> dict[str, dict[str, tuple[str, ...]]]:
    """`stated` as failure class → bow region → modes, a class's one list standing for both regions: the one
    reading of a policy's shape (the scenario's ``[failure.policy]``, a profile's policy, `complete_policy`).

    An unknown class or region, a class or region naming no mode, a value that is not a list of names and,
    when `modes` is given, a name not in `modes` raise an InputError naming the key as stated
    (``failure.policy.<class>`` for one list, ``failure.policy.<class>.<region>`` for a region's).
    """
    result: dict[str, dict[str, tuple[str, ...]]] = {}
    for failure_class, value in (stated or {}).items():
        if failure_class not in FAILURE_CLASSES:
            raise InputError(
                f"failure.policy.{failure_class}", "unknown failure class", allowed=", ".join(FAILURE_CLASSES)
            )
        per_region = isinstance(value, Mapping)
        regions = value if per_region else dict.fromkeys(BOW_REGIONS, value)
        for region, names in regions.items():
            key = f"failure.policy.{failure_class}" + (f".{region}" if per_region else "")
            if region not in BOW_REGIONS:
                raise InputError(key, "unknown bow region", allowed=", ".join(BOW_REGIONS))
            if isinstance(names, str) or not isinstance(names, Sequence):
                raise InputError(key, "must be a list of mode names", value=names)
            if not names:
                raise InputError(key, "names no mode", allowed="one or more of " + ", ".join(modes or ()))
            for name in names:
                if modes is not None and name not in modes:
                    raise InputError(key, f"unknown failure mode {name!r}", allowed=", ".join(modes))
        result[failure_class] = {region: tuple(names) for region, names in regions.items()}
    return result


def complete_policy(
    *stated: StatedPolicy | None, flip_uncracked_at_shoulder: bool = True, modes: Sequence[str] | None = None
) -> Policy:
    """The default policy with each of `stated` (`normalise_policy`, names checked against `modes` when
    given) laid over it in turn, per failure class and bow region: what a policy leaves out keeps the
    default (or an earlier layer's, e.g. a profile's under the scenario's)."""
    policy = default_policy(flip_uncracked_at_shoulder)
    for layer in stated:
        for failure_class, regions in normalise_policy(layer, modes).items():
            policy[failure_class] = {**policy.get(failure_class, {}), **regions}
    return policy


# without a profile (`Model()`): unbreakable floes rotate, nothing breaks (tests, rotation-only runs)
_NO_BREAKING = complete_policy(
    {
        "bending": {"stem": ("none",), "shoulder": ("none",)},
        "cracking": {"stem": ("none",), "shoulder": ("none", "rotation")},
    }
)


@dataclass(frozen=True, eq=False)
class FailureModel:
    """The failure modes of a run (by name) and the dispatch policy that names them."""

    modes: Mapping[str, FailureMode] = field(
        default_factory=lambda: {"rotation": DirectRotation(), "none": NoFailure()}
    )
    policy: Policy = field(default_factory=lambda: _NO_BREAKING)
    shoulder_region_start: float = 0.5  # fraction of the stem→shoulder length where the "shoulder" begins

    def __post_init__(self) -> None:
        require_range(
            "failure.shoulder_region_start", self.shoulder_region_start, low=0.0, high=1.0, low_inclusive=True
        )
        check_policy(self.policy, tuple(self.modes))


def check_policy(policy: Policy, modes: Sequence[str]) -> None:
    """InputError naming ``failure.policy.<class>[.<region>]`` unless `policy` names one or more of `modes`
    for every failure class and bow region (`normalise_policy`, then every class and region present)."""
    normalise_policy(policy, modes)
    for failure_class in FAILURE_CLASSES:
        regions = policy.get(failure_class)
        if regions is None:
            raise InputError(f"failure.policy.{failure_class}", "missing", allowed=", ".join(FAILURE_CLASSES))
        for region in BOW_REGIONS:
            if not regions.get(region):
                key = f"failure.policy.{failure_class}.{region}"
                raise InputError(key, "names no mode", allowed="one or more of " + ", ".join(modes))


def bow_region(centre_x_m: float, bow_length_m: float, shoulder_region_start: float) -> BowRegion:
    """ "stem" or "shoulder" for a contact centre at bow-frame x (stem tip at x = 0, shoulder at −L_b)."""
    fraction = -centre_x_m / bow_length_m if bow_length_m > 0 else 0.0
    return "shoulder" if fraction >= shoulder_region_start else "stem"


def resolve_failure(model: FailureModel, inp: FailureInput, ctx: FailureContext) -> Outcome:
    """Try the policy's modes for the floe's class and region in order; the first outcome that is not
    `Status.PASS_ON` decides (or the last mode's, if every mode passed the floe on)."""
    for name in model.policy[inp.classification.failure_class][inp.region]:
        outcome = model.modes[name].evaluate(inp, ctx)
        if outcome.status is not Status.PASS_ON:
            return outcome
    return outcome
