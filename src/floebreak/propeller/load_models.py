"""Which cusps load a propeller (pure): the transport rule ("hull": the transport model,
`floebreak.propeller.transport`, decides per cusp; "all": every cusp reaches, thesis §6.2), where a reaching
cusp meets the blade, the drive's rated torque and the out-of-range warnings. The per-cusp load models are
in `floebreak.propeller.loads`. docs/propeller.md §6–§8.
"""

from __future__ import annotations

import math

import numpy as np

from floebreak import constants as c
from floebreak.errors import InputError, require_range
from floebreak.propeller.engagement import engaged_interval
from floebreak.propeller.loads.milling import BladeGeometry
from floebreak.propeller.rates import RunExposure
from floebreak.propeller.spec import PropellerSpec
from floebreak.propeller.transport import (
    PATHS,
    CuspTransport,
    TransportSettings,
    transport_cusps,
)
from floebreak.ship.agulhas_ii import AGULHAS_II

TRANSPORTS = ("flow", "hull", "all")  # flow: `floebreak.propeller.flow_transport`
TRANSPORT_COLUMNS = ("bow_x_m", "centroid_x_m", "centroid_y_m", "area_m2", "thickness_m")
# the Agulhas II's rated power: rated torque P/(2π n) = 306.9 kN·m at 140 rpm
DEFAULT_RATED_POWER_W = float(AGULHAS_II.rated_power_w)
RATED_TORQUE_FACTOR = 2.0  # warn when a per-cusp torque exceeds this many times the rated torque
EXTRAPOLATION_FACTOR = 1.5  # warn when a rule-form x_max lies this far beyond the largest fitted load
# shaft lines of 1 or more than 2 propellers: evenly over ±5.5 m (the Agulhas II's ASSUMED offsets)


def check_choice(key: str, value: str, allowed: tuple[str, ...]) -> str:
    if value not in allowed:
        raise InputError(key, f"unknown value {value!r}", value=value, allowed=", ".join(allowed))
    return value


def drive_rated_torque_n_m(spec: PropellerSpec, rated_torque: float | None = None) -> float:
    """The drive's rated torque [N·m]: given, or the built-in Agulhas II line's rated power over
    2π × the spec's speed (4.5 MW at 140 rpm: 306.9 kN·m)."""
    if rated_torque is not None:
        return require_range("rated_torque_n_m", rated_torque, low=0.0, unit="N m")
    return DEFAULT_RATED_POWER_W / (2.0 * math.pi * spec.revolutions_per_s)


PLACEMENT_ENGAGED = "engaged interval from the transport"
PLACEMENT_TIP = "tip placement"


def engaged_intervals(
    transports: dict[str, tuple[np.ndarray, CuspTransport]], n_cusps: int, spec: PropellerSpec
) -> tuple[np.ndarray, np.ndarray]:
    """Per cusp (indices of `transports`, `transport_of_runs`) the blade's engaged interval (r_in, r_out)
    [m] in its cross-section at the propeller (`CuspTransport.cross_section_m`,
    `engagement.engaged_interval` on the spec's blade from r_hub to R); NaN for cusps that reach no
    propeller or whose run is not transported (tip placement). A reaching cusp whose cross-section misses
    the blade's annulus (inside the hub) engages with zero length at its nearest radius: it reaches and
    carries no load (docs/propeller.md §2). The transport's discs are the spec's
    (`TransportSettings.arrangement`)."""
    blade = BladeGeometry.from_spec(spec)
    hub, tip = blade.hub_radius_m, blade.radius_m
    inner, outer = np.full(n_cusps, math.nan), np.full(n_cusps, math.nan)
    for idx, t in transports.values():
        if t.cross_section_m is None:
            continue
        r_in, r_out = engaged_interval(*t.cross_section_m, hub, tip)
        y_lo, y_hi, z_lo, z_hi = t.cross_section_m
        nearest = np.clip(np.hypot(np.clip(0.0, y_lo, y_hi), np.clip(0.0, z_lo, z_hi)), hub, tip)
        missed = (t.propeller_index >= 0) & np.isnan(r_in)
        inner[idx] = np.where(missed, nearest, r_in)
        outer[idx] = np.where(missed, nearest, r_out)
    return inner, outer


def placement_text(places_on_blade: bool, modelled_runs: int, tip_runs: int) -> str | None:
    """How a load model that places loads on the blade (`LoadModel.places_on_blade`: the milling model)
    places each cusp (summary.json `load_model.placement`): the engaged interval for runs the transport
    moved, tip placement where no geometry is known (transport "all" or a fraction reaching override). None
    for other models."""
    if not places_on_blade:
        return None
    if not modelled_runs:
        return f"{PLACEMENT_TIP} (no cusp geometry at the disc with transport 'all' or a fraction override)"
    if tip_runs:
        return f"{PLACEMENT_ENGAGED}; {PLACEMENT_TIP} for the {tip_runs} run(s) with a fraction override"
    return PLACEMENT_ENGAGED


def transport_of_runs(
    columns: dict[str, np.ndarray],
    exposures: dict[str, RunExposure],
    runs,
    settings: TransportSettings = TransportSettings(),  # noqa: B008 - frozen dataclass, immutable default
    radius_m: float = PropellerSpec().radius_m,
) -> dict:
    """The transport (`transport_cusps`) of the cusps of each of `runs` at its run's speed and propeller
    count (3 m/s and 2 without an exposure), on discs of `radius_m` (the propeller spec's;
    `TransportSettings.arrangement`), with the hull and parameters of `settings`: run → (indices into
    `columns`, CuspTransport)."""
    missing = [k for k in TRANSPORT_COLUMNS if not np.all(np.isfinite(columns[k][_rows(columns, runs)]))]
    if missing:
        raise InputError(
            "cusps",
            f"the transport needs column(s) {', '.join(missing)} (cusps.parquet of a current run has them)",
            allowed="cusps with these columns, or transport 'all' / a fraction reaching",
        )
    out = {}
    for run in runs:
        idx = np.flatnonzero(columns["run_id"] == run)
        basis = exposures[run].basis if run in exposures else None
        speed = basis.speed_m_s if basis else c.SHIP_SPEED_IN_ICE_M_S
        n_prop = basis.n_propellers if basis else AGULHAS_II.propeller_count
        cols = {k: columns[k][idx] for k in TRANSPORT_COLUMNS}
        out[run] = (
            idx,
            transport_cusps(
                **cols,
                speed_m_s=speed,
                hull=settings.hull,
                arrangement=settings.arrangement(n_prop, radius_m),
                params=settings.params,
            ),
        )
    return out


def _rows(columns, runs) -> np.ndarray:
    return np.isin(columns["run_id"], list(runs))


def transport_summary(transports: dict[str, tuple[np.ndarray, CuspTransport]], n_cusps: int) -> dict:
    """Fractions reaching (all and per propeller) and the paths of the cusps that do not."""
    paths = dict.fromkeys(PATHS, 0)
    for _, t in transports.values():
        for k, v in t.path_counts().items():
            paths[k] += v
    n = sum(t.n_cusps for _, t in transports.values())
    sizes = {t.n_propellers for _, t in transports.values()}
    per_prop = []  # runs with different propeller counts (pooled with --pool) have no common list
    if n and len(sizes) == 1:
        per_prop = (sum(t.counts() for _, t in transports.values()) / n).tolist()
    return {
        "n_cusps": n,
        "n_reaching": int(paths["propeller"]),
        "fraction_reaching": paths["propeller"] / n if n else 0.0,
        "fraction_reaching_per_propeller": per_prop,
        "paths": paths,
        "n_cusps_not_transported": n_cusps - n,
    }


def torque_warnings(table_info: dict[str, dict], rated_torque: float, rule_max_torque: float | None) -> list:
    """A warning per pitch whose largest per-cusp |Q| exceeds `RATED_TORQUE_FACTOR` × the rated torque,
    and one where it exceeds the rule's Q_max (both in N·m; `table_info`'s ranges in kN·m)."""
    out = []
    for info in table_info.values():
        q_range = info.get("torque_range_knm")
        if q_range is None:
            continue
        top_knm = q_range[1]
        limit = RATED_TORQUE_FACTOR * rated_torque / 1e3
        if top_knm > limit:
            out.append(
                f"pitch {info['pitch_percent']:g} %: a per-cusp torque of {top_knm:.0f} kN·m exceeds "
                f"{RATED_TORQUE_FACTOR:g} × the rated torque ({rated_torque / 1e3:.1f} kN·m)"
            )
        if rule_max_torque is not None and top_knm > rule_max_torque / 1e3:
            out.append(
                f"pitch {info['pitch_percent']:g} %: a per-cusp torque of {top_knm:.0f} kN·m exceeds the "
                f"rule's Q_max ({rule_max_torque / 1e3:.0f} kN·m)"
            )
    return out


def force_warnings(table_info: dict[str, dict], backward_force: float, forward_force: float) -> list[str]:
    """A warning per pitch whose largest per-cusp blade force |F| exceeds the rule's backward force F_b,
    and one where it exceeds the forward force F_f (both in N; `table_info`'s ranges in kN). The per-cusp
    force is a magnitude (the FEM tables and `loads.milling.milling_loads` keep |F|), so both limits are
    checked."""
    out = []
    for info in table_info.values():
        f_range = info.get("force_range_kn")
        if f_range is None:
            continue
        top_kn = f_range[1]
        for name, limit in (("backward force F_b", backward_force), ("forward force F_f", forward_force)):
            if top_kn > limit / 1e3:
                out.append(
                    f"pitch {info['pitch_percent']:g} %: a per-cusp blade force of {top_kn:.0f} kN exceeds "
                    f"the rule's {name} ({limit / 1e3:.0f} kN)"
                )
    return out


def extrapolation_warnings(rule_form: dict | None) -> list[str]:
    """A warning for each rule-form x_max (per hour, over the profile, at the rule's N_ice) beyond
    `EXTRAPOLATION_FACTOR` × the largest load the fit was fitted to (`validity_range`)."""
    out = []
    for label, quantities in (rule_form or {}).items():
        if not (isinstance(quantities, dict) and label.startswith("p")):
            continue
        for quantity, entry in quantities.items():
            valid = entry.get("validity_range") if isinstance(entry, dict) else None
            if not valid:
                continue
            unit = "kN·m" if quantity == "torque_knm" else "kN"
            for key in ("x_max_per_hour", "x_max_lifetime", "x_max_at_rule_n_ice"):
                x = entry.get(key)
                if x is not None and x > EXTRAPOLATION_FACTOR * valid[1]:
                    out.append(
                        f"pitch {label[1:]} %, {quantity.split('_')[0]}: the rule-form {key} "
                        f"({x:.0f} {unit}) extrapolates {x / valid[1]:.1f} × beyond the largest fitted "
                        f"load (fitted {valid[0]:.0f}–{valid[1]:.0f} {unit})"
                    )
    return out


def override_warning(fractions: dict[str, float]) -> str:
    values = ", ".join(sorted({f"{f:g}" for f in fractions.values()}))
    return (
        f"fraction reaching {values} is an override (propeller.fraction_reaching / --fraction-reaching): "
        "every cusp loads the propellers with that weight; the transport model is not used"
    )
