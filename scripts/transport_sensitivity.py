"""Loads per hour per propeller from the cusp transport model, and how they move with each parameter.

    python scripts/transport_sensitivity.py RUN_DIR/cusps.parquet [--transit-m 385] [--speed-m-s 3]

Prints the markdown table of docs/model.md ("Cusp transport under the hull"): for the default Agulhas II
hull, arrangement and parameters, and for each parameter varied alone, the fraction of the cusps reaching
each propeller and the loads per hour on each (cusps reaching / (transit / speed)).
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np
import pyarrow.parquet as pq

from floebreak.propeller.transport import (
    HullUnderwater,
    Propeller,
    PropellerArrangement,
    TransportParameters,
    loads_per_hour,
    transport_cusp_table,
)

HULL, ARRANGEMENT, PARAMS = HullUnderwater(), PropellerArrangement(), TransportParameters()


def _arrangement(offset_m=5.5, diameter_m=4.3, shaft_depth_m=5.25, tip_clearance_m=0.86):
    props = tuple(Propeller(s * offset_m, diameter_m, shaft_depth_m) for s in (1.0, -1.0))
    return PropellerArrangement(props, tip_clearance_m)


# (parameter, values, builder value → keyword arguments of transport_cusp_table)
VARIATIONS = [
    ("slip_factor s", [0.5, 0.75, 1.0], lambda v: {"params": replace(PARAMS, slip_factor=v)}),
    ("drag_coefficient C_D", [0.8, 1.17, 2.0], lambda v: {"params": replace(PARAMS, drag_coefficient=v)}),
    ("lateral_spread_m [m]", [0.0, 1.0, 2.0], lambda v: {"params": replace(PARAMS, lateral_spread_m=v)}),
    (
        "shoulder_cusps_submerge",
        [False, True],
        lambda v: {"params": replace(PARAMS, shoulder_cusps_submerge=v)},
    ),
    (
        "shoulder_region_start",
        [0.3, 0.5, 0.7],
        lambda v: {"params": replace(PARAMS, shoulder_region_start=v)},
    ),
    ("bilge_radius_m [m]", [1.0, 2.5, 4.0], lambda v: {"hull": replace(HULL, bilge_radius_m=v)}),
    ("run_length_m [m]", [8.0, 15.0, 30.0], lambda v: {"hull": replace(HULL, run_length_m=v)}),
    ("tip_clearance_m [m]", [0.43, 0.86, 1.29], lambda v: {"arrangement": _arrangement(tip_clearance_m=v)}),
    ("shaft offset ±y_s [m]", [4.5, 5.5, 6.5], lambda v: {"arrangement": _arrangement(offset_m=v)}),
    ("shaft depth z_s [m]", [4.75, 5.0, 5.25], lambda v: {"arrangement": _arrangement(shaft_depth_m=v)}),
    ("diameter D [m]", [3.8, 4.3, 4.8], lambda v: {"arrangement": _arrangement(diameter_m=v)}),
    (
        "propeller plane L_p [m]",
        [105.0, 115.0, 125.0],
        lambda v: {"hull": replace(HULL, propeller_plane_aft_of_stem_m=v)},
    ),
    ("ship speed v [m/s]", [2.0, 3.0, 5.0], lambda v: {"speed_m_s": v}),
]


def _row(name, value, cusps, transit_m, speed_m_s, kw):
    speed = kw.get("speed_m_s", speed_m_s)
    rng = np.random.default_rng(0)
    result = transport_cusp_table(cusps, rng=rng, **{"speed_m_s": speed_m_s, **kw})
    rates = loads_per_hour(result.counts(), transit_m, speed)
    fractions = " / ".join(f"{f:.3f}" for f in result.fractions())
    per_hour = " / ".join(f"{r:,.0f}" for r in rates)
    travel = (result.arrival_time_s - cusps["bow_x_m"] / speed)[result.propeller_index >= 0]
    delay = f"{travel.mean():.1f}" if travel.size else "–"
    return f"| {name} | {value} | {fractions} | {per_hour} | {delay} |"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cusps", help="a run directory's cusps.parquet")
    parser.add_argument("--transit-m", type=float, default=385.0)
    parser.add_argument("--speed-m-s", type=float, default=3.0)
    args = parser.parse_args()
    table = pq.read_table(args.cusps).to_pydict()
    cusps = {key: np.asarray(value) for key, value in table.items() if key != "geometry"}
    n = len(cusps["bow_x_m"])
    every = loads_per_hour(n / 2, args.transit_m, args.speed_m_s)
    head = f"{n} cusps over {args.transit_m:g} m at {args.speed_m_s:g} m/s; every cusp reaching"
    print(f"{head}, shared by two propellers: {every:,.0f} loads per hour per propeller\n")
    print("| parameter | value | fraction reaching (port / starboard) | loads per hour (port / starboard) "
          "| mean travel time [s] |")  # fmt: skip
    print("|---|---|---|---|---|")
    print(_row("default", "–", cusps, args.transit_m, args.speed_m_s, {}))
    for name, values, build in VARIATIONS:
        for value in values:
            print(_row(name, value, cusps, args.transit_m, args.speed_m_s, build(value)))


if __name__ == "__main__":
    main()
