"""Cusp tables (read by `floebreak.output.run_files.load_cusps`): validation, bounding-box volume classes,
kinetic
energy.

Volume classes and class means follow thesis §6.1.1 / Alg. 1 / Fig. 26: cuboidal bounding box of each cusp
(shorter side l_min, longer side l_max in the plane, thickness h), box volume l_max·l_min·h, classes
(0, 5], (5, 8], (8, 11], (11, 14] m³ by default; per class the means of l_max, l_min, h and the box volume
(the structure of thesis Tables 10/11). Kinetic energy: thesis Eqs. 27–28.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
import pyarrow as pa

from floebreak.constants import ICE_DENSITY_KG_M3
from floebreak.errors import InputError

# the columns of a cusps table (a run directory's cusps.parquet)
REQUIRED_COLUMNS = ("volume_m3", "bbox_length_m", "bbox_width_m", "thickness_m", "area_m2")
# the bow at the cusp's making (transit order) and the centroid (the transport model); NaN if absent
OPTIONAL_COLUMNS = ("bow_x_m", "centroid_x_m", "centroid_y_m")

DEFAULT_CLASS_EDGES_M3 = (5.0, 8.0, 11.0, 14.0)


def cusp_columns(cusps: pa.Table | Mapping[str, Sequence], field: str = "cusps") -> dict[str, np.ndarray]:
    """Validated float arrays of the required columns plus ``run_id`` (default "run") and the optional
    ``bow_x_m``, ``centroid_x_m``, ``centroid_y_m`` (NaN where absent; finite or NaN)."""
    if isinstance(cusps, pa.Table):
        names = cusps.column_names

        def get(c):
            return cusps.column(c).to_numpy(zero_copy_only=False)
    elif isinstance(cusps, Mapping):
        names = list(cusps)

        def get(c):
            return np.asarray(cusps[c])
    else:
        raise InputError(
            field, f"unsupported type {type(cusps).__name__}", allowed="a pyarrow.Table or a dict of arrays"
        )
    missing = [c for c in REQUIRED_COLUMNS if c not in names]
    if missing:
        raise InputError(
            field, f"missing column(s) {', '.join(missing)}", allowed=", ".join(REQUIRED_COLUMNS)
        )
    out: dict[str, np.ndarray] = {}
    n = None
    for c in REQUIRED_COLUMNS:
        try:
            values = np.asarray(get(c), dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise InputError(field, f"column {c!r} is not numeric") from None
        bad = np.flatnonzero(~np.isfinite(values) | (values < 0.0))
        if bad.size:
            raise InputError(
                field,
                f"column {c!r}, row {bad[0]}: {values[bad[0]]!r}",
                value=float(values[bad[0]]),
                allowed="finite values >= 0",
            )
        if n is not None and values.size != n:
            raise InputError(field, f"column {c!r} has {values.size} rows, expected {n}")
        n = values.size
        out[c] = values
    run_id = (
        np.asarray(get("run_id"), dtype=object).reshape(-1)
        if "run_id" in names
        else np.full(n, "run", object)
    )
    if run_id.size != n:
        raise InputError(field, f"column 'run_id' has {run_id.size} rows, expected {n}")
    out["run_id"] = run_id.astype(str).astype(object)
    for c in OPTIONAL_COLUMNS:
        out[c] = np.full(n, np.nan)
        if c in names:
            try:
                out[c] = np.asarray(get(c), dtype=float).reshape(-1)
            except (TypeError, ValueError):
                raise InputError(field, f"column {c!r} is not numeric") from None
            if out[c].size != n or np.isinf(out[c]).any():
                raise InputError(field, f"column {c!r} needs one finite (or NaN) value per cusp")
    return out


def box_dimensions(length_m, width_m, thickness_m) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(longer side, shorter side, box volume l_max·l_min·h) (thesis Alg. 1, Fig. 26)."""
    length_m, width_m, thickness_m = (np.asarray(a, dtype=float) for a in (length_m, width_m, thickness_m))
    longer = np.maximum(length_m, width_m)
    shorter = np.minimum(length_m, width_m)
    return longer, shorter, longer * shorter * thickness_m


def check_class_edges(edges_m3) -> np.ndarray:
    edges = np.asarray(edges_m3, dtype=float).reshape(-1)
    if edges.size < 1 or not np.all(np.isfinite(edges)) or edges[0] <= 0.0 or np.any(np.diff(edges) <= 0.0):
        raise InputError(
            "volume_class_edges_m3",
            f"{edges.tolist()} is not strictly increasing and > 0",
            value=edges.tolist(),
            allowed="increasing positive upper class edges, e.g. 5, 8, 11, 14",
        )
    return edges


def volume_class(volume_m3, edges_m3=DEFAULT_CLASS_EDGES_M3) -> np.ndarray:
    """Class index i with edges[i−1] < V ≤ edges[i] (edges[−1] = 0); −1 above the last edge or at V = 0."""
    edges = check_class_edges(edges_m3)
    v = np.asarray(volume_m3, dtype=float)
    index = np.searchsorted(edges, v, side="left")
    return np.where((v > 0.0) & (index < edges.size), index, -1)


def class_means(
    longer_m, shorter_m, thickness_m, box_volume_m3, edges_m3=DEFAULT_CLASS_EDGES_M3
) -> dict[str, np.ndarray]:
    """Per volume class: count and mean box volume, longer side, shorter side, thickness (thesis Alg. 1).

    Empty classes have NaN means. Classification is by box volume, as in Alg. 1.
    """
    edges = check_class_edges(edges_m3)
    cls = volume_class(box_volume_m3, edges)
    out = {
        "class_index": np.arange(edges.size),
        "lower_m3": np.concatenate([[0.0], edges[:-1]]),
        "upper_m3": edges.copy(),
        "n_cusps": np.zeros(edges.size, dtype=int),
    }
    for name in ("mean_box_volume_m3", "mean_longer_side_m", "mean_shorter_side_m", "mean_thickness_m"):
        out[name] = np.full(edges.size, np.nan)
    for i in range(edges.size):
        m = cls == i
        out["n_cusps"][i] = int(m.sum())
        if m.any():
            out["mean_box_volume_m3"][i] = float(np.mean(np.asarray(box_volume_m3)[m]))
            out["mean_longer_side_m"][i] = float(np.mean(np.asarray(longer_m)[m]))
            out["mean_shorter_side_m"][i] = float(np.mean(np.asarray(shorter_m)[m]))
            out["mean_thickness_m"][i] = float(np.mean(np.asarray(thickness_m)[m]))
    return out


def kinetic_energy_j(
    volume_m3, speed_m_s: float = 3.0, density_kg_m3: float = ICE_DENSITY_KG_M3
) -> np.ndarray:
    """E_kin = ½ ρ_ice V v² [J] (thesis Eqs. 27–28). An energy, reported apart from torque (erratum 25)."""
    return 0.5 * density_kg_m3 * np.asarray(volume_m3, dtype=float) * speed_m_s**2


def cusp_geometry(columns: dict[str, np.ndarray], cusp_speed_m_s: float) -> dict[str, np.ndarray]:
    """The per-cusp table's columns that need no load model: run, bow position, box, kinetic energy."""
    longer, shorter, box_volume = box_dimensions(
        columns["bbox_length_m"], columns["bbox_width_m"], columns["thickness_m"]
    )
    return {
        "run_id": columns["run_id"],
        "bow_x_m": columns.get("bow_x_m", np.full(columns["run_id"].size, math.nan)),
        "area_m2": columns["area_m2"],
        "thickness_m": columns["thickness_m"],
        "volume_m3": columns["volume_m3"],
        "bbox_longer_m": longer,
        "bbox_shorter_m": shorter,
        "box_volume_m3": box_volume,
        "kinetic_energy_j": kinetic_energy_j(columns["volume_m3"], cusp_speed_m_s),
    }
