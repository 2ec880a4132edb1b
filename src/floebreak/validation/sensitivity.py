"""What the results depend on: one-at-a-time elasticities and numerical convergence.

`floebreak validate sensitivity`: every physical and numerical input x is moved to x(1 − δ) and x(1 + δ)
around the reference configuration, on the same fields; the elasticity of an output y is, per field,

    e = ln(y₊ / y₋) / ln((1 + δ) / (1 − δ))      (central difference of d ln y / d ln x),

reported as mean ± standard error over the fields (thesis Fig. 25 generalised). Categorical inputs
(size-effect law, crack criterion) give the paired relative change y / y_ref − 1 instead.

`floebreak validate convergence`: the outputs at x_step 0.5 / 0.25 / 0.125 / 0.0625 m and at the wedge
angle φ 10 / 5 / 2.5°, each as the paired relative difference to the finest setting; a setting is
converged when it and every finer one are within 2 % of the finest for every output.
"""

from __future__ import annotations

import math
from typing import Any

from floebreak.config.scenario import Scenario
from floebreak.studies.design import StudySpec
from floebreak.validation.statements import mean_se, paired_relative_change
from floebreak.validation.validate import Config, _sweep

OUTPUTS = (
    ("mean_cusp_volume_m3", "V̄_cusp"),
    ("mean_cusp_area_m2", "Ā_cusp"),
    ("n_cusps", "n_cusp"),
    ("n_flipped", "n_flip"),
    ("cusp_area_m2", "A_cusp^tot"),
    ("flipped_area_m2", "A_flip^tot"),
)
CONTINUOUS_INPUTS = (  # (label, scenario key)
    ("h", "ice.thickness_m"),
    ("K_Ic", "ice.fracture_toughness_pa_sqrt_m"),
    ("σ_c", "ice.crushing_strength_pa"),
    ("σ_f", "ice.flexural_strength_pa"),
    ("μ", "ice.friction_coefficient"),
    ("E", "ice.youngs_modulus_pa"),
    ("ν", "ice.poisson_ratio"),
    ("k_c", "ice.contact_coefficient"),
    ("x_step", "ship.step_m"),
    ("φ", "failure.bending.wedge_angle_deg"),
    ("α_nextcrack", "failure.cracking.next_crack_angle_deg"),
    # the dispatch's own choice (docs/model.md §10: the thesis gives no number for where the shoulder begins)
    ("shoulder start", "failure.shoulder_region_start"),
)
CATEGORICAL_INPUTS = (
    ("SEL = BZ1", {"failure.cracking.size_effect_law": "BZ1"}),
    ("SEL = BZ2", {"failure.cracking.size_effect_law": "BZ2"}),
    ("criterion = point load", {"failure.cracking.criterion": "point_load"}),
    ("criterion = line load", {"failure.cracking.criterion": "line_load"}),
    ("criterion = flexural stress", {"failure.cracking.criterion": "flexural_stress"}),
)
NOT_EXPOSED = (
    (
        "dist_bow_max",
        "SimulationParams.dist_bow_max_m (candidate search distance, thesis §3.2): elasticity 0 by "
        "construction — it only pre-selects the pieces whose contact is evaluated on the hull "
        "(tests/test_simulation.py::test_the_candidate_search_distance_changes_no_result); no scenario key",
    ),
)
STEPS_M = (0.5, 0.25, 0.125, 0.0625)
WEDGE_ANGLES_DEG = (10.0, 5.0, 2.5)
CONVERGED_REL = 0.02


def reference_value(scenario: Scenario, key: str) -> float:
    """The value the run uses for the dotted scenario `key`: a failure-mode setting from the model the
    scenario builds (its profile's value unless the scenario sets one), any other key from the resolved
    scenario."""
    from floebreak.app.run import build_model_for
    from floebreak.config.scenario import FLAT_FAILURE_KEYS

    section, _, name = key.partition(".")
    if section == "failure":
        failure = build_model_for(scenario).failure
        if name == "shoulder_region_start":  # a setting of the dispatch, not of a mode
            return float(failure.shoulder_region_start)
        mode, setting = FLAT_FAILURE_KEYS.get(name, tuple(name.split(".", 1)))
        return float(getattr(failure.modes[mode].settings, setting))
    node: Any = scenario.to_dict()
    for part in key.split("."):
        node = node[part]
    return float(node)


def sensitivity_points(base: dict[str, Any], delta: float) -> dict[str, dict[str, Any]]:
    """Design points: the reference, each continuous input at (1 ∓ δ) × its reference value, each
    categorical alternative."""
    resolved = Scenario.from_dict(base).resolved()
    points: dict[str, dict[str, Any]] = {"reference": {}}
    for label, key in CONTINUOUS_INPUTS:
        x = reference_value(resolved, key)
        points[f"{label}-"] = {key: x * (1.0 - delta)}
        points[f"{label}+"] = {key: x * (1.0 + delta)}
    for label, keys in CATEGORICAL_INPUTS:
        points[label] = dict(keys)
    return points


def elasticity(minus: dict[int, float], plus: dict[int, float], delta: float) -> tuple[float, float, int]:
    """Mean ± standard error over the common fields of ln(y₊/y₋) / ln((1 + δ)/(1 − δ))."""
    span = math.log((1.0 + delta) / (1.0 - delta))
    values = [
        math.log(plus[i] / minus[i]) / span
        for i in sorted(set(minus) & set(plus))
        if minus[i] and plus[i] and minus[i] > 0 and plus[i] > 0
    ]
    return mean_se(values)


def sensitivity_rows(data: dict[str, dict[int, dict[str, float]]], delta: float) -> list[dict[str, Any]]:
    """One row per input: per output the elasticity (continuous) or paired relative change (categorical)."""

    def series(point: str, key: str) -> dict[int, float]:
        return {i: m.get(key, math.nan) for i, m in data.get(point, {}).items()}

    rows = []
    for label, key in CONTINUOUS_INPUTS:
        row: dict[str, Any] = {"input": label, "key": key, "kind": "elasticity"}
        for out_key, _ in OUTPUTS:
            mean, se, n = elasticity(series(f"{label}-", out_key), series(f"{label}+", out_key), delta)
            row.update({f"{out_key}_value": mean, f"{out_key}_se": se, "n_fields": n})
        rows.append(row)
    for label, keys in CATEGORICAL_INPUTS:
        row = {
            "input": label,
            "key": ", ".join(f"{k}={v}" for k, v in keys.items()),
            "kind": "relative change",
        }
        for out_key, _ in OUTPUTS:
            mean, se, n = paired_relative_change(series(label, out_key), series("reference", out_key))
            row.update({f"{out_key}_value": mean, f"{out_key}_se": se, "n_fields": n})
        rows.append(row)
    for label, reason in NOT_EXPOSED:
        rows.append({"input": label, "key": "", "kind": f"not exposed: {reason}"})
    return rows


def convergence_points(steps_m=STEPS_M, angles_deg=WEDGE_ANGLES_DEG) -> dict[str, dict[str, Any]]:
    points = {f"step {s:g}": {"ship.step_m": float(s)} for s in steps_m}
    points.update({f"phi {a:g}": {"failure.bending.wedge_angle_deg": float(a)} for a in angles_deg})
    return points


def convergence_table(
    data: dict[str, dict[int, dict[str, float]]], steps_m=STEPS_M, angles_deg=WEDGE_ANGLES_DEG
) -> dict[str, dict[float, dict[str, Any]]]:
    """{parameter: {value: {output: paired relative difference to the finest value, …_se, …_mean}}}."""
    table: dict[str, dict[float, dict[str, Any]]] = {}
    for parameter, values, prefix in (("x_step [m]", steps_m, "step"), ("φ [deg]", angles_deg, "phi")):
        finest = f"{prefix} {min(values):g}"
        table[parameter] = {}
        for value in values:
            entry: dict[str, Any] = {}
            for key, _ in OUTPUTS:
                series = {i: m.get(key, math.nan) for i, m in data.get(f"{prefix} {value:g}", {}).items()}
                ref = {i: m.get(key, math.nan) for i, m in data.get(finest, {}).items()}
                entry[key], entry[f"{key}_se"], _ = paired_relative_change(series, ref)
                entry[f"{key}_mean"] = mean_se(series.values())[0]
            table[parameter][float(value)] = entry
    return table


def converged_from(by_value: dict[float, dict[str, Any]], tolerance: float = CONVERGED_REL) -> float | None:
    """The coarsest value from which this and every finer value are within `tolerance` of the finest, for
    every output (None: not even the second finest is)."""
    coarsest = None
    for value in sorted(by_value):  # finest first
        if all(
            abs(by_value[value][key]) <= tolerance
            for key, _ in OUTPUTS
            if math.isfinite(by_value[value][key])
        ):
            coarsest = value
        else:
            break
    return coarsest if coarsest is not None and coarsest != min(by_value) else None


def one_config_spec(
    name: str, config: Config, base: dict, points: dict, n_fields: int, seed: int
) -> StudySpec:
    sweeps = [_sweep(config, point, keys) for point, keys in points.items()]
    return StudySpec(
        name=name, root_seed=seed, n_fields=n_fields, common_fields=True, base=base, sweeps=sweeps
    )
