"""Piece sizes against the unbreakable area A_rotate over the ice thickness (docs/validation.md, "What Table 7
itself says about the two rows").

Usage:  python scripts/piece_sizes.py [--profile thesis] [--n-fields 16] [--first-seed 200] [--set KEY=VALUE]

Runs the reference configuration on fields of the thesis' size (`studies.field_size.thesis_scenario`) at
h = 0.8, 1.0 and 1.2 m, seeds first-seed … first-seed + n − 1, in this process, and prints per thickness the
Table 7 columns per field, Ā_cusp / A_rotate and the mean flipped piece / A_rotate (A_rotate = 1 m · 13.5 h^¾,
thesis Eq. 5), then the flipped pieces per field by their size in A_rotate and by the mode that made them
(the mode that broke their parent; "whole" for a floe flipped as it was). The thesis' Table 7 gives
Ā_cusp / A_rotate = 0.602 / 0.603 / 0.603 and mean flipped piece / A_rotate = 2.08 / 2.17 / 2.15.
"""

from __future__ import annotations

import argparse
from collections import defaultdict

import numpy as np

import floebreak
from floebreak.ice.material import characteristic_length_lu_m
from floebreak.studies.field_size import thesis_scenario

THICKNESSES_M = (0.8, 1.0, 1.2)
FLIP_BINS = (0.0, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, np.inf)  # in A_rotate


def _field_rows(profile: str, thickness_m: float, seeds: range, sets: list[str]):
    """Per seed: (n_cusp, n_flip, A_cusp, A_flip) and the flipped pieces' (area, source mode)."""
    rows, flips = [], []
    for seed in seeds:
        keys = [f'profile="{profile}"', f"seed={seed}", f"ice.thickness_m={thickness_m}", *sets]
        simulation = floebreak.run(thesis_scenario(keys)).simulation
        area, parent = simulation.piece_area_m2, simulation.parent_piece_id
        cusp, flipped = simulation.mask("cusp"), simulation.mask("flipped")
        rows.append((cusp.sum(), flipped.sum(), area[cusp].sum(), area[flipped].sum()))
        for i in np.flatnonzero(flipped):
            flips.append((area[i], simulation.ended_by[parent[i]] if parent[i] >= 0 else "whole"))
    return np.array(rows, dtype=float), flips


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="thesis", choices=("default", "thesis"))
    parser.add_argument("--n-fields", type=int, default=16)
    parser.add_argument("--first-seed", type=int, default=200)
    parser.add_argument("--set", dest="sets", action="append", default=[], help="scenario override KEY=VALUE")
    options = parser.parse_args()
    seeds = range(options.first_seed, options.first_seed + options.n_fields)
    edges = ", ".join(f"{e:g}" for e in FLIP_BINS[:-1])
    for thickness_m in THICKNESSES_M:
        a_rotate_m2 = 1.0 * float(characteristic_length_lu_m(thickness_m))
        rows, flips = _field_rows(options.profile, thickness_m, seeds, options.sets)
        n_cusp, n_flip, a_cusp, a_flip = rows.mean(axis=0)
        cusp_ratio, flip_ratio = a_cusp / n_cusp / a_rotate_m2, a_flip / n_flip / a_rotate_m2
        print(
            f"h = {thickness_m} m (A_rotate {a_rotate_m2:.2f} m²): n_cusp {n_cusp:.1f}, n_flip {n_flip:.1f}, "
            f"A_cusp {a_cusp:.0f} m², A_flip {a_flip:.0f} m² per field; Ā_cusp / A_rotate {cusp_ratio:.3f}, "
            f"mean flipped / A_rotate {flip_ratio:.2f}"
        )
        by_source: dict[str, np.ndarray] = defaultdict(lambda: np.zeros(len(FLIP_BINS) - 1))
        for area_m2, source in flips:
            by_source[source] += np.histogram([area_m2 / a_rotate_m2], FLIP_BINS)[0] / len(seeds)
        print(f"  flipped per field by size [A_rotate], bins from {edges}, ∞:")
        for source, counts in sorted(by_source.items()):
            print(f"    {source:<15}", " ".join(f"{c:5.1f}" for c in counts))


if __name__ == "__main__":
    main()
