"""Inert rows: statements a configuration makes true by construction.

A row is *inert* in a configuration when it cannot fail there whatever the ice does, so its pass is no
evidence; the scoreboard lists it apart and leaves it out of the tally. The flag is computed from the
configuration — the base scenario, the profile, a variant's keys and the statement's two design points —
in two ways:

- **Identity.** The two points resolve to the same run: the same scenario outside the model, and the same
  physics `Model` once the settings that do not enter it are set to their defaults (`UNUSED_SETTINGS`).
  Every metric is then bit-identical, the change is exactly 0, and the row is inert when a change of 0
  passes it (e.g. Table 8's "≤ 5 %" rows of BZ1/BZ2 when K_I comes from the load).
- **Cap.** The largest cusp cannot exceed the unbreakable area A_rotate(h) (Eq. 5, the only class that
  becomes a cusp, `failure.rotation`) times h, and in a field of hundreds of cusps the largest sits at that
  cap; its change between two thicknesses is then the cap's, (h₁/h₀)^1.75 − 1 for A_rotate = 13.5 h^¾, and
  the row is inert when that change passes it.

Both rest on a statement about the code (which setting is read where; that pieces reach the cap), written
here with its reason; tests/validation/test_inert.py checks each against the functions and on a run.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, replace
from typing import Any, Literal

from floebreak.validation.statements import Statement, verdict

STRESS_CRITERIA = ("tensile_stress", "flexural_stress")
# (mode, the settings that do not enter it, when, the reason): a setting is "unused" when the mode's check
# never reads it under the other settings (`failure.cracking.Cracking.criterion_check`,
# `mechanics.fracture.check_stress_sif`)
UNUSED_SETTINGS = (
    (
        "cracking",
        ("size_effect_law", "bz2_mode", "size_source"),
        lambda s: s.criterion not in STRESS_CRITERIA or s.stress_mode == "sif",
        'the size-effect law does not enter K_I from the load (stress_mode = "sif") nor the load criteria',
    ),
)
CAPPED_METRIC = "max_cusp_volume_m3"
CAP_TOLERANCE = 0.01  # the measured change of the largest cusp is within 1 % of the cap's (validation test)


@dataclass(frozen=True)
class Inert:
    """Why a row cannot fail in a configuration, and the value the reason predicts for it."""

    kind: Literal["identity", "cap"]
    reason: str
    predicted: float

    def holds(self, value: float) -> bool:
        """Whether a measured value agrees with the reason (the same run: a change of exactly 0; the cap: the
        cap's change within `CAP_TOLERANCE`). Where it does not, the reason is wrong for this run and the row
        is scored as any other (audit gap 7: an inert flag must not hide a failure)."""
        if self.kind == "identity":
            return value == 0.0
        return math.isfinite(value) and abs(value - self.predicted) <= CAP_TOLERANCE


@dataclass(frozen=True)
class PointRun:
    """What decides the runs of one design point: the scenario outside the model, the model with its unused
    settings at their defaults, and what the normalisation changed (for the reason)."""

    scenario: dict[str, Any]
    model: Any
    unused: tuple[str, ...]
    thickness_m: float | None
    cusp_volume_cap_m3: float | None


def normalised_model(model) -> tuple[Any, tuple[str, ...]]:
    """`model` with the settings of `UNUSED_SETTINGS` at their defaults; the reasons that applied."""
    modes = dict(model.failure.modes)
    reasons = []
    for name, keys, when, reason in UNUSED_SETTINGS:
        mode = modes.get(name)
        if mode is None or not when(mode.settings):
            continue
        defaults = type(mode.settings)()
        unused = {k: getattr(defaults, k) for k in keys}
        modes[name] = replace(mode, settings=replace(mode.settings, **unused))
        reasons.append(f"{name}.{'/'.join(keys)}: {reason}")
    return replace(model, failure=replace(model.failure, modes=modes)), tuple(reasons)


def point_run(base: dict[str, Any], profile: str, keys: dict[str, Any]) -> PointRun:
    """The `PointRun` of `base` with `profile` and the dotted `keys` (a variant's and a point's) applied."""
    from floebreak.app.run import build_model_for
    from floebreak.config.scenario import Scenario
    from floebreak.failure import get_mode, mode_names
    from floebreak.mechanics.classify import unbreakable_area_m2
    from floebreak.studies.design import set_dotted

    data = copy.deepcopy(base)
    data["profile"] = profile
    for key, value in keys.items():
        set_dotted(data, key, value)
    scenario = Scenario.from_dict(data).resolved()
    model, unused = normalised_model(build_model_for(scenario))
    rest = scenario.to_dict()
    rest.pop("failure", None)  # every [failure] key is a setting of the model
    model_ice = {"crushing_strength_pa", "contact_coefficient", "friction_coefficient", "youngs_modulus_pa",
                 "poisson_ratio"} | {k for n in mode_names() for k in get_mode(n).material}  # fmt: skip
    rest["ice"] = {k: v for k, v in rest.get("ice", {}).items() if k not in model_ice}
    h = scenario.ice.thickness_m  # None for a random thickness (thickness_range_m)
    cap = None
    if h is not None and model.classification.unbreakable_rule in ("thesis_1m_ell", "ell_squared"):
        cap = unbreakable_area_m2(h, model.classification) * h
    return PointRun(rest, model, unused, h, cap)


def inert_flag(st: Statement, runs: dict[str, PointRun]) -> Inert | None:
    """The `Inert` of a statement given the `PointRun` of every design point of the configuration, or None
    (levels, single floes and rows the configuration leaves open are not inert)."""
    if st.statistic != "change" or st.point not in runs or (st.against or "reference") not in runs:
        return None
    point, against = runs[st.point], runs[st.against or "reference"]
    if point.scenario == against.scenario and repr(point.model) == repr(against.model):
        if verdict(0.0, st.thesis_value, st.tolerance) != "pass":
            return None
        why = "; ".join(point.unused) or "no setting differs"
        return Inert("identity", f"`{st.point}` and `{st.against}` are the same run here ({why})", 0.0)
    if st.metric == CAPPED_METRIC and point.cusp_volume_cap_m3 and against.cusp_volume_cap_m3:
        predicted = point.cusp_volume_cap_m3 / against.cusp_volume_cap_m3 - 1.0
        if verdict(predicted, st.thesis_value, st.tolerance) != "pass":
            return None
        reason = (
            f"the largest cusp sits at the cap A_rotate(h)·h (Eq. 5: no larger piece becomes a cusp): "
            f"{against.cusp_volume_cap_m3:.2f} m³ at h = {against.thickness_m:g} m, "
            f"{point.cusp_volume_cap_m3:.2f} m³ at {point.thickness_m:g} m, "
            f"a change of {100 * predicted:+.1f} %"
        )
        return Inert("cap", reason, predicted)
    return None


def inert_flags(
    statements: tuple[Statement, ...], base: dict[str, Any], profile: str, overrides: dict[str, Any],
    points: dict[str, dict[str, Any]],
) -> dict[str, Inert]:  # fmt: skip
    """{statement id: `Inert`} of the inert statements of one configuration (`base` the scenario every run
    starts from, `overrides` a variant's keys, `points` the design points)."""
    runs = {name: point_run(base, profile, {**overrides, **keys}) for name, keys in points.items()}
    flags = {st.id: inert_flag(st, runs) for st in statements}
    return {key: flag for key, flag in flags.items() if flag is not None}
