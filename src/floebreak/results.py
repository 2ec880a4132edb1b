"""Recording and summarising a run: the contact-record callback, piece tables and summary statistics.

The columns of the thesis' Tables 5–8: V̄_cusp, Ā_cusp, n_cusp, n_flip, A_cusp^tot, A_flip^tot.
"""

from __future__ import annotations

from collections import defaultdict
from typing import Any

import numpy as np
import shapely

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
    if outcome.mode == "rotation":
        return str(outcome.pieces[0].fate) if outcome.pieces else "rotation"
    return outcome.mode


class ContactRecorder:
    """Callback for `simulate`: one row per floe–panel pair of every contact evaluation.

    Zone-level quantities (A_u, A_l) repeat on each panel row of the zone; per panel, Σ a_h = a_u − a_l.
    """

    def __init__(self) -> None:
        self._columns: dict[str, list] = defaultdict(list)

    def __call__(self, event: Event) -> None:
        if not isinstance(event, ContactEvaluated):
            return
        label = outcome_label(event)
        columns = self._columns
        for zone in event.contact.zones:
            n = len(zone.panels)
            columns["step"].extend([event.step] * n)
            columns["bow_x_m"].extend([event.bow_x_m] * n)
            columns["floe_id"].extend([event.parent_floe_id] * n)
            columns["piece_id"].extend([event.piece_id] * n)
            columns["zone"].extend([zone.zone] * n)
            columns["panel"].extend(zone.panels.tolist())
            columns["a_u_m2"].extend([zone.a_u_m2] * n)
            columns["a_l_m2"].extend([zone.a_l_m2] * n)
            columns["a_h_m2"].extend(zone.a_h_m2.tolist())
            columns["a_c_m2"].extend(zone.a_c_m2.tolist())
            columns["psi_deg"].extend(np.degrees(zone.psi_rad).tolist())
            columns["f_c_n"].extend(zone.f_c_n.tolist())
            columns["f_v_n"].extend(zone.f_v_n.tolist())
            columns["f_h_n"].extend(zone.f_h_n.tolist())
            columns["failure_class"].extend([event.classification.failure_class] * n)
            columns["outcome"].extend([label] * n)

    def __len__(self) -> int:
        return len(self._columns["step"])

    def table(self) -> dict[str, np.ndarray]:
        """The records as numpy columns (empty columns if there was no contact)."""
        dtypes = {
            "step": np.int64,
            "floe_id": np.int64,
            "piece_id": np.int64,
            "zone": np.int64,
            "panel": np.int64,
            "failure_class": object,
            "outcome": object,
        }
        return {
            name: np.asarray(self._columns[name], dtype=dtypes.get(name, float)) for name in CONTACT_COLUMNS
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
    for i, box in enumerate(boxes):
        coords = shapely.get_coordinates(box)
        if len(coords) >= 4:
            sides = np.hypot(*np.diff(coords[:3], axis=0).T)
            length[i], width[i] = sides.max(), sides.min()
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
