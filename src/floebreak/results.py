"""Recording and summarising a run: the contact-record callback, piece tables and summary statistics.

The columns of the thesis' Tables 5–8: V̄_cusp, Ā_cusp, n_cusp, n_flip, A_cusp^tot, A_flip^tot.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import shapely

from floebreak.failure import Fate
from floebreak.simulation import ContactEvaluated, Event, SimulationResult

CONTACT_COLUMNS = (
    "step",
    "bow_x_m",
    "floe_id",
    "piece_id",
    "zone",
    "panel",
    "a_u_m2",
    "a_l_m2",
    "a_h_m2",
    "a_c_m2",
    "psi_deg",
    "f_c_n",
    "f_v_n",
    "f_h_n",
    "failure_class",
    "outcome",
)


def outcome_label(event: ContactEvaluated) -> str:
    """A short label of what happened at a contact evaluation."""
    outcome = event.outcome
    if not outcome.failed:
        return "no_failure"
    if len(outcome.pieces) == 1 and outcome.pieces[0].fate != Fate.FLOE:
        return str(outcome.pieces[0].fate)  # the piece leaves the field whole (e.g. direct rotation)
    return outcome.mode


class ContactRecorder:
    """Callback for `simulate`: one row per floe–panel pair of every contact evaluation.

    Zone-level quantities (A_u, A_l) repeat on each panel row of the zone; per panel, Σ a_h = a_u − a_l.
    """

    def __init__(self) -> None:
        # one entry per zone; the columns are assembled once, in `table` (per-row Python work during the run
        # was a measurable share of the stepping engine's time)
        self._zones: list[tuple] = []
        self._n_rows = 0

    def __call__(self, event: Event) -> None:
        if not isinstance(event, ContactEvaluated):
            return
        label = outcome_label(event)
        failure_class = event.classification.failure_class
        for zone in event.contact.zones:
            self._zones.append(
                (event.step, event.bow_x_m, event.parent_floe_id, event.piece_id, zone, failure_class, label)
            )
            self._n_rows += len(zone.panels)

    def __len__(self) -> int:
        return self._n_rows

    def table(self) -> dict[str, np.ndarray]:
        """The records as numpy columns (empty columns if there was no contact)."""
        zones = [entry[4] for entry in self._zones]
        counts = np.array([len(zone.panels) for zone in zones], dtype=np.int64)

        def repeated(index: int, dtype) -> np.ndarray:
            return np.repeat(np.array([entry[index] for entry in self._zones], dtype=dtype), counts)

        def joined(values, dtype=float) -> np.ndarray:
            return np.concatenate(values).astype(dtype, copy=False) if values else np.zeros(0, dtype=dtype)

        return {
            "step": repeated(0, np.int64),
            "bow_x_m": repeated(1, float),
            "floe_id": repeated(2, np.int64),
            "piece_id": repeated(3, np.int64),
            "zone": np.repeat(np.array([zone.zone for zone in zones], dtype=np.int64), counts),
            "panel": joined([zone.panels for zone in zones], np.int64),
            "a_u_m2": np.repeat(np.array([zone.a_u_m2 for zone in zones], dtype=float), counts),
            "a_l_m2": np.repeat(np.array([zone.a_l_m2 for zone in zones], dtype=float), counts),
            "a_h_m2": joined([zone.a_h_m2 for zone in zones]),
            "a_c_m2": joined([zone.a_c_m2 for zone in zones]),
            "psi_deg": np.degrees(joined([zone.psi_rad for zone in zones])),
            "f_c_n": joined([zone.f_c_n for zone in zones]),
            "f_v_n": joined([zone.f_v_n for zone in zones]),
            "f_h_n": joined([zone.f_h_n for zone in zones]),
            "failure_class": repeated(5, object),
            "outcome": repeated(6, object),
        }


def crushing_force_per_evaluation_n(contacts: dict[str, np.ndarray]) -> np.ndarray:
    """Total crushing force F_c of each contact-zone evaluation (summed over its panels) [N]."""
    if len(contacts["step"]) == 0:
        return np.zeros(0)
    keys = np.stack([contacts["step"], contacts["piece_id"], contacts["zone"]], axis=1)
    _, inverse = np.unique(keys, axis=0, return_inverse=True)
    return np.bincount(inverse.reshape(-1), weights=contacts["f_c_n"])


def oriented_box_dimensions_m(polygons: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(longer side, shorter side) of each polygon's minimum rotated bounding rectangle [m]."""
    polygons = np.asarray(polygons, dtype=object)
    if polygons.size == 0:
        return np.zeros(0), np.zeros(0)
    boxes = shapely.oriented_envelope(polygons)
    length = np.zeros(len(polygons))
    width = np.zeros(len(polygons))
    # the first two sides of each rectangle, all boxes at once (degenerate boxes with < 4 points stay 0)
    coords, owner = shapely.get_coordinates(boxes, return_index=True)
    counts = np.bincount(owner, minlength=len(polygons))
    box = counts >= 4
    first = (np.cumsum(counts) - counts)[box]
    side_a = np.hypot(*(coords[first + 1] - coords[first]).T)
    side_b = np.hypot(*(coords[first + 2] - coords[first + 1]).T)
    length[box] = np.maximum(side_a, side_b)
    width[box] = np.minimum(side_a, side_b)
    return length, width


def piece_table(result: SimulationResult, fate: str) -> dict[str, Any]:
    """Columns of the pieces with `fate` ("cusp", "flipped", "remaining"), geometry included."""
    mask = result.mask(fate)
    polygons = result.polygon[mask]
    area = shapely.area(polygons) if polygons.size else np.zeros(0)
    thickness = result.thickness_m[mask]
    length, width = oriented_box_dimensions_m(polygons)
    centroids = shapely.get_coordinates(shapely.centroid(polygons)) if polygons.size else np.zeros((0, 2))
    return {
        "geometry": polygons,
        "piece_id": result.piece_id[mask],
        "area_m2": area,
        "thickness_m": thickness,
        "volume_m3": area * thickness,
        "centroid_x_m": centroids[:, 0],
        "centroid_y_m": centroids[:, 1],
        "bbox_length_m": length,
        "bbox_width_m": width,
        "step": result.step[mask],
        "bow_x_m": result.bow_x_m[mask],
        "parent_floe_id": result.parent_floe_id[mask],
        "failure_chain": np.array(
            [">".join(result.failure_chain[i]) for i in np.flatnonzero(mask)], dtype=object
        ),
    }


def summary(result: SimulationResult, contacts: dict[str, np.ndarray] | None = None) -> dict[str, Any]:
    """Summary statistics of a run (thesis Tables 5–8 columns and the area balance)."""
    cusp_mask, flip_mask = result.mask("cusp"), result.mask("flipped")
    cusp_area = shapely.area(result.polygon[cusp_mask]) if cusp_mask.any() else np.zeros(0)
    cusp_volume = cusp_area * result.thickness_m[cusp_mask]
    n_cusps = int(cusp_mask.sum())
    out: dict[str, Any] = {
        "n_floes_initial": result.field.n_floes,
        "initial_ice_area_m2": result.initial_ice_area_m2,
        "n_cusps": n_cusps,
        "cusp_area_m2": float(cusp_area.sum()),
        "mean_cusp_area_m2": float(cusp_area.mean()) if n_cusps else float("nan"),
        "mean_cusp_volume_m3": float(cusp_volume.mean()) if n_cusps else float("nan"),
        "n_flipped": int(flip_mask.sum()),
        "flipped_area_m2": result.area_m2("flipped"),
        "remaining_ice_area_m2": result.area_m2("remaining"),
        "area_balance_rel_error": result.area_balance_rel_error,
        "n_contacts": result.n_contacts,
        "n_breaks": result.n_breaks,
        "breaks_by_mode": dict(sorted(result.breaks_by_mode.items())),
        "n_steps": result.n_steps,
    }
    if contacts is not None:
        out["n_contact_records"] = len(contacts["step"])
        forces = crushing_force_per_evaluation_n(contacts)
        out["crushing_force_max_n"] = float(forces.max()) if len(forces) else 0.0
    return out
