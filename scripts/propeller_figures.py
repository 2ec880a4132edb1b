"""The headline figures of a `floebreak propeller` output directory (docs/propeller.md §10, choice 5).

    python scripts/propeller_figures.py OUT [OUT ...]

OUT as written by `floebreak propeller RUN --out OUT --shaft-line agulhas_ii --speed-m-s 3 --polar-class PC5
--hours-in-ice-per-year 1000 --years 25`. Prints per OUT: cusps and cusps reaching a propeller, the
per-cusp |Q| and |F| at the largest pitch over the reaching cusps (min / median / max), impacts per cusp,
the PC5 lifetime maximum over Q_max and blade impacts per hour on one blade (as the `PC5.*` rows of
`floebreak validate thesis`, `studies.chain_statements`), and, with OUT/shaft, case 1's Q_peak and the
drive's minimum rpm.
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import numpy as np

from floebreak.validation.chain_statements import blade_load_rate, lifetime_max_ratio


def _columns(path: Path) -> dict[str, np.ndarray]:
    with path.open() as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return {k: np.array([r[k] for r in rows]) for k in rows[0]}


def _numbers(values: np.ndarray) -> np.ndarray:
    return np.array([float(v) if v not in ("", "nan") else np.nan for v in values])


def figures(out: Path) -> dict[str, object]:
    summary = json.loads((out / "summary.json").read_text())
    cols = _columns(out / "cusp_loads.csv")
    label = max(
        (k[len("torque_knm_") :] for k in cols if k.startswith("torque_knm_")), key=lambda s: float(s[1:])
    )
    reach = np.char.lower(cols["reaches_propeller"].astype(str)) == "true"
    q = np.abs(_numbers(cols[f"torque_knm_{label}"]))[reach]
    f = np.abs(_numbers(cols[f"force_kn_{label}"]))[reach]
    impacts = _numbers(cols[f"n_impacts_{label}"])
    weight = _numbers(cols["loads_per_propeller"])
    fit = summary["rule_form"][label]["torque_knm"]
    q_max = summary["ice_class"]["max_torque_nm"] / 1e3
    blades = summary["propeller"]["blades"]
    rate = blade_load_rate(weight, impacts, blades, summary["rates"]["hours_in_ice"])
    out_figures = {
        "placement": summary["load_model"].get("placement", "tip placement"),
        "cusps": int(reach.size),
        "reaching": int(reach.sum()),
        "torque_knm min/median/max": tuple(round(float(x), 1) for x in (q.min(), np.median(q), q.max())),
        "force_kn min/max": (round(float(f.min()), 1), round(float(f.max()), 1)),
        "impacts per reaching cusp (mean)": round(float(impacts[reach].mean()), 2),
        "PC5 lifetime max / Q_max": round(lifetime_max_ratio(q, q_max, fit.get("x_max_lifetime")), 3),
        "impacts per hour per blade": round(rate),
        "rule impacts per hour": round(
            summary["rule_form"]["rule_n_ice"] / summary["rule_form"]["operating_profile"]["hours"]
        ),
    }
    shaft = out / "shaft" / "summary.json"
    if shaft.is_file():
        s = json.loads(shaft.read_text())
        out_figures["shaft case 1 Q_peak [kN·m]"] = round(s["q_peak_knm"]["1"]["q_peak_knm"], 1)
        if "drive" in s:
            out_figures["shaft case 1 min rpm"] = round(s["drive"]["cases"]["1"]["min_rpm"], 1)
    return out_figures


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, nargs="+")
    for out in parser.parse_args().out:
        print(out)
        for key, value in figures(out).items():
            print(f"  {key}: {value}")


if __name__ == "__main__":
    main()
