"""Single-floe validation matrix (thesis §5.2, Fig. 14, Figs. 15–16).

One circular floe at each of five positions relative to the bow's start position:

- a: ahead of the port shoulder, b: ahead of the port bow between tip and shoulder,
- c: ahead of the starboard shoulder, d: ahead of the starboard bow between tip and shoulder,
- e: midship, straight ahead of the stem,

for diameters d ∈ {10, 20, 30} m and thicknesses h ∈ {0.8, 1.0, 1.2} m. The thesis shows the positions only in
a figure; we place the floe centres at y = ±B/2 (shoulders), y = ±B/4 (between) and y = 0, and d/2 + 1 m ahead
of the stem, so every floe starts free of the bow; the bow then runs until its shoulder has passed the floe.
The thesis observes the fan-shaped pattern of model tests (Puntigliano; Ettema et al.): cusps along the bow,
flipped pieces near the shoulders.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from floebreak.engine.loop import Model, SimulationParams, SimulationResult, simulate
from floebreak.ice.field import FloeField, circle_polygons

POSITIONS = ("a", "b", "c", "d", "e")
POSITION_NAMES = {
    "a": "port shoulder",
    "b": "port, between tip and shoulder",
    "c": "starboard shoulder",
    "d": "starboard, between tip and shoulder",
    "e": "midship ahead",
}
DIAMETERS_M = (10.0, 20.0, 30.0)
THICKNESSES_M = (0.8, 1.0, 1.2)
START_GAP_M = 1.0  # free water between the stem and the floe at the start


@dataclass(frozen=True)
class SingleFloeCase:
    position: str
    diameter_m: float
    thickness_m: float


def floe_centre_m(position: str, diameter_m: float, half_breadth_m: float) -> tuple[float, float]:
    """Centre of the floe for a Fig. 14 position (bow frame at the start: stem tip at the origin)."""
    y = {
        "a": half_breadth_m,
        "b": half_breadth_m / 2,
        "c": -half_breadth_m,
        "d": -half_breadth_m / 2,
        "e": 0.0,
    }
    return diameter_m / 2.0 + START_GAP_M, y[position]


def single_floe_field(case: SingleFloeCase, half_breadth_m: float) -> FloeField:
    x, y = floe_centre_m(case.position, case.diameter_m, half_breadth_m)
    r = case.diameter_m / 2.0
    polygon = circle_polygons(np.array([[x, y]]), np.array([r]), 64)
    return FloeField(
        polygon,
        np.array([case.thickness_m]),
        np.array([case.diameter_m]),
        np.array([0]),
        (x - r, y - r, x + r, y + r),
        metadata={"single_floe": {"position": case.position, "diameter_m": case.diameter_m}},
    )


def run_case(case: SingleFloeCase, bow, model: Model, step_m: float = 0.25) -> SimulationResult:
    """Run the bow through one single floe until the bow shoulder has passed it."""
    field = single_floe_field(case, float(bow.half_breadth_m))
    x_end = field.domain_m[2] + float(bow.length_bow_m) + 2.0
    return simulate(field, bow, model, SimulationParams(step_m=step_m, x_end_m=x_end))


def case_row(case: SingleFloeCase, result: SimulationResult) -> dict[str, float | int | str]:
    return {
        "position": case.position,
        "position_name": POSITION_NAMES[case.position],
        "diameter_m": case.diameter_m,
        "thickness_m": case.thickness_m,
        "n_cusps": int(result.mask("cusp").sum()),
        "n_flipped": int(result.mask("flipped").sum()),
        "n_remaining": int(result.mask("remaining").sum()),
        "cusp_area_m2": result.area_m2("cusp"),
        "flipped_area_m2": result.area_m2("flipped"),
        "remaining_area_m2": result.area_m2("remaining"),
        "area_balance_rel_error": result.area_balance_rel_error,
    }


def write_single_floe_matrix(out_dir: Path, overwrite: bool = False, profile: str = "default") -> Path:
    """Run all 45 cases; write `cases.csv`, `cases.md` and one pattern grid per diameter into `out_dir`."""
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from floebreak.config.profiles import build_model
    from floebreak.io.atomic import atomic_directory
    from floebreak.io.figures import save_figure
    from floebreak.io.writers import rows_to_columns, write_csv
    from floebreak.plotting.common import CUSP_COLOUR, FLIPPED_COLOUR, UNTOUCHED_COLOUR
    from floebreak.plotting.pattern import plot_breaking_pattern
    from floebreak.ship.hulls import get_hull

    model = build_model(profile)
    rows = []
    with atomic_directory(out_dir, overwrite=overwrite, field="out") as temp:
        for diameter in DIAMETERS_M:
            figure = Figure(figsize=(4.0 * len(POSITIONS), 2.7 * len(THICKNESSES_M)), constrained_layout=True)
            axes = figure.subplots(len(THICKNESSES_M), len(POSITIONS))
            for i, thickness in enumerate(THICKNESSES_M):
                bow = get_hull("agulhas_ii", ice_thickness_m=thickness)
                for j, position in enumerate(POSITIONS):
                    case = SingleFloeCase(position, diameter, thickness)
                    result = run_case(case, bow, model)
                    row = case_row(case, result)
                    rows.append(row)
                    plot_breaking_pattern(
                        result,
                        ax=axes[i, j],
                        title=f"{position}) d = {diameter:g} m, h = {thickness:g} m: "
                        f"{row['n_cusps']} cusps, {row['n_flipped']} flipped",
                        bow_at_end=False,  # the end position lies far aft of the floe
                        legend=False,
                    )
                    axes[i, j].title.set_fontsize("small")
            figure.legend(
                handles=[
                    Patch(facecolor=UNTOUCHED_COLOUR, label="ice in the field"),
                    Patch(facecolor=FLIPPED_COLOUR, label="flipped"),
                    Patch(facecolor=CUSP_COLOUR, label="cusps"),
                    Line2D([], [], color="k", ls="--", label="bow at the start (upper / lower waterline)"),
                ],
                loc="outside lower center",
                ncols=4,
            )
            figure.suptitle(
                f"Single floes of d = {diameter:g} m at the positions of thesis Fig. 14 (profile {profile}); "
                "pieces drawn where they were made"
            )
            save_figure(figure, temp / f"pattern_d{int(diameter)}m.png")
        write_csv(temp / "cases.csv", rows_to_columns(rows))
        lines = ["| position | d [m] | h [m] | cusps | flipped | remaining |", "|---|---|---|---|---|---|"]
        lines += [
            f"| {r['position']}) {r['position_name']} | {r['diameter_m']:g} | {r['thickness_m']:g} | "
            f"{r['n_cusps']} | {r['n_flipped']} | {r['n_remaining']} |"
            for r in rows
        ]
        (temp / "cases.md").write_text("\n".join(lines) + "\n", encoding="utf-8")
    return Path(out_dir)
