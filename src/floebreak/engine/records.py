"""Recording and summarising a run: the contact-record callback, piece tables and summary statistics.

The columns of the thesis' Tables 5–8: V̄_cusp, Ā_cusp, n_cusp, n_flip, A_cusp^tot, A_flip^tot.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely

from floebreak.engine.loop import ContactEvaluated, Event, SimulationResult, lineage_chain
from floebreak.failure import Fate

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


_ZONE_SCALARS = (
    "step",
    "bow_x_m",
    "floe_id",
    "piece_id",
    "zone",
    "a_u_m2",
    "a_l_m2",
    "failure_class",
    "outcome",
)
_ZONE_SCALAR_TYPES = (np.int64, float, np.int64, np.int64, np.int64, float, float, object, object)
_PANEL_ARRAYS = ("panel", "a_h_m2", "a_c_m2", "psi_deg", "f_c_n", "f_v_n", "f_h_n")


class ContactRecorder:
    """Callback for `simulate`: one row per floe–panel pair of every contact evaluation.

    Zone-level quantities (A_u, A_l) repeat on each panel row of the zone; per panel, Σ a_h = a_u − a_l.
    Only numbers are kept, never the zones themselves (a zone references the evaluated floe's polygon:
    keeping zones kept a copy of every evaluated floe alive), and every `chunk_zones` zones are packed into
    numpy columns, ≈ 130 bytes per row. Per-row Python work is avoided (it was a measurable share of the
    stepping engine's time): the columns are built per chunk.

    With a `sink` (e.g. `floebreak.io.contacts.ContactFile.write`) each packed chunk goes to it and leaves
    memory: a long transit makes ≈ 20 000 rows per km. What the run's summary and piece table need of the
    records is kept either way (`records`): the crushing force of each evaluation and the failed
    evaluations.
    """

    def __init__(self, chunk_zones: int = 4096, sink: Callable[[dict[str, np.ndarray]], None] | None = None):
        self._chunk_zones = chunk_zones
        self._sink = sink
        self._scalars: list[tuple] = []
        self._panels: list[tuple[np.ndarray, ...]] = []
        self._chunks: list[dict[str, np.ndarray]] = []
        self._keys: list[np.ndarray] = []  # per chunk: (step, piece_id, zone) of each evaluated zone
        self._forces: list[np.ndarray] = []  # per chunk: F_c of each evaluated zone [N]
        self._failed: list[tuple[np.ndarray, np.ndarray]] = []  # per chunk: (piece_id, step) of failures
        self._n_rows = 0

    def __call__(self, event: Event) -> None:
        if not isinstance(event, ContactEvaluated):
            return
        label = outcome_label(event)
        failure_class = event.classification.failure_class
        for zone in event.contact.zones:
            self._scalars.append(
                (
                    event.step,
                    event.bow_x_m,
                    event.parent_floe_id,
                    event.piece_id,
                    zone.zone,
                    zone.a_u_m2,
                    zone.a_l_m2,
                    failure_class,
                    label,
                )
            )
            self._panels.append(
                (zone.panels, zone.a_h_m2, zone.a_c_m2, zone.psi_rad, zone.f_c_n, zone.f_v_n, zone.f_h_n)
            )
            self._n_rows += len(zone.panels)
        if len(self._scalars) >= self._chunk_zones:
            self._pack()

    def __len__(self) -> int:
        return self._n_rows

    def _pack(self) -> None:
        """Move the pending zones into one chunk of numpy columns (to the sink, if there is one)."""
        if not self._scalars:
            return
        counts = np.array([len(arrays[0]) for arrays in self._panels], dtype=np.int64)
        chunk = {
            name: np.repeat(np.array([row[k] for row in self._scalars], dtype=dtype), counts)
            for k, (name, dtype) in enumerate(zip(_ZONE_SCALARS, _ZONE_SCALAR_TYPES, strict=True))
        }
        for k, name in enumerate(_PANEL_ARRAYS):
            column = np.concatenate([arrays[k] for arrays in self._panels])
            chunk[name] = column.astype(np.int64 if name == "panel" else float, copy=True)
        chunk["psi_deg"] = np.degrees(chunk["psi_deg"])
        chunk = {name: chunk[name] for name in CONTACT_COLUMNS}
        keys, forces = _evaluation_forces(chunk)  # an evaluated zone's rows are never split between chunks
        self._keys.append(keys)
        self._forces.append(forces)
        failed = chunk["outcome"] != "no_failure"
        self._failed.append((chunk["piece_id"][failed], chunk["step"][failed]))
        if self._sink is not None:
            self._sink(chunk)
        else:
            self._chunks.append(chunk)
        self._scalars, self._panels = [], []

    def table(self) -> dict[str, np.ndarray]:
        """The records as numpy columns in the order of `CONTACT_COLUMNS` (empty if there was no contact,
        or with a sink: the records went to it)."""
        if self._sink is None:
            self._pack()
        if not self._chunks:
            return empty_contacts()
        if len(self._chunks) > 1:  # one chunk from here on (repeated calls do not concatenate again)
            self._chunks = [
                {name: np.concatenate([c[name] for c in self._chunks]) for name in self._chunks[0]}
            ]
        return dict(self._chunks[0])

    def records(self) -> ContactRecords:
        """What the run keeps of its records (the records themselves too, without a sink)."""
        self._pack()
        keys = np.concatenate(self._keys) if self._keys else np.zeros((0, 3), dtype=np.int64)
        forces = np.concatenate(self._forces) if self._forces else np.zeros(0)
        order = np.lexsort(keys.T[::-1])  # by (step, piece_id, zone), as `crushing_force_per_evaluation_n`
        failed_piece = [p for p, _ in self._failed]
        failed_step = [s for _, s in self._failed]
        return ContactRecords(
            n_rows=self._n_rows,
            crushing_forces_n=forces[order],
            failed_piece_id=np.concatenate(failed_piece) if failed_piece else np.zeros(0, dtype=np.int64),
            failed_step=np.concatenate(failed_step) if failed_step else np.zeros(0, dtype=np.int64),
            columns=self.table() if self._sink is None else None,
        )


def empty_contacts() -> dict[str, np.ndarray]:
    """The contact-record columns of a run without contact."""
    types = dict(zip(_ZONE_SCALARS, _ZONE_SCALAR_TYPES, strict=True)) | {"panel": np.int64}
    return {name: np.zeros(0, dtype=types.get(name, float)) for name in CONTACT_COLUMNS}


@dataclass(frozen=True, eq=False)
class ContactRecords:
    """What a run keeps of its contact records: their number, the crushing force of each evaluated zone
    (thesis Fig. 13, ordered by step, piece, zone), the failed evaluations (piece id, step), and the
    records themselves (`columns`) unless they were streamed to a file."""

    n_rows: int
    crushing_forces_n: np.ndarray
    failed_piece_id: np.ndarray
    failed_step: np.ndarray
    columns: dict[str, np.ndarray] | None = None


def crushing_force_per_evaluation_n(contacts: dict[str, np.ndarray]) -> np.ndarray:
    """Total crushing force F_c of each contact-zone evaluation (summed over its panels) [N], ordered by
    (step, piece_id, zone)."""
    return _evaluation_forces(contacts)[1]


def _evaluation_forces(contacts: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(step, piece_id, zone) of each contact-zone evaluation, sorted, and its total crushing force [N]."""
    if len(contacts["step"]) == 0:
        return np.zeros((0, 3), dtype=np.int64), np.zeros(0)
    keys = np.stack([contacts["step"], contacts["piece_id"], contacts["zone"]], axis=1)
    unique, inverse = np.unique(keys, axis=0, return_inverse=True)
    return unique, np.bincount(inverse.reshape(-1), weights=contacts["f_c_n"])


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


def piece_table(result: SimulationResult, fate: str, index: np.ndarray | None = None) -> dict[str, Any]:
    """Columns of the pieces with `fate` ("cusp", "flipped", "remaining"), geometry included; `index`: of
    those only the pieces with these ids (ascending), e.g. a row group's worth of a long run's pieces."""
    mask = np.flatnonzero(result.mask(fate)) if index is None else np.asarray(index, dtype=np.int64)
    polygons = result.polygons(mask)
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
        "parent_piece_id": result.parent_piece_id[mask],
        "failure_mode": result.failure_mode[mask],
    }


def summary(
    result: SimulationResult, contacts: dict[str, np.ndarray] | ContactRecords | None = None
) -> dict[str, Any]:
    """Summary statistics of a run (thesis Tables 5–8 columns and the area balance); with the contact
    records (columns, or what `ContactRecorder.records` keeps of them) their number and the largest
    crushing force."""
    cusp_mask, flip_mask = result.mask("cusp"), result.mask("flipped")
    cusp_area = result.piece_area_m2[cusp_mask]  # each = shapely.area of its polygon
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
    if isinstance(contacts, ContactRecords):
        out["n_contact_records"] = contacts.n_rows
        forces = contacts.crushing_forces_n
    elif contacts is not None:
        out["n_contact_records"] = len(contacts["step"])
        forces = crushing_force_per_evaluation_n(contacts)
    if contacts is not None:
        out["crushing_force_max_n"] = float(forces.max()) if len(forces) else 0.0
    return out


def failure_chain(pieces: dict[str, Any], piece_id: int) -> str:
    """The failure chain of a piece of a run's ``pieces.parquet`` (columns ``piece_id``, ``parent_piece_id``,
    ``ended_by``), as "mode>mode>…" from the initial floe on (`SimulationResult.failure_chain`).

    Runs store lineage once (parent ids) rather than a chain per piece, whose length grows with the
    number of breaks (thin ice: thousands of entries per cusp); this rebuilds the chain when needed.
    """
    ids = np.asarray(pieces["piece_id"], dtype=np.int64)
    row = np.full(int(ids.max()) + 1, -1, dtype=np.int64)
    row[ids] = np.arange(ids.size)
    parents = np.asarray(pieces["parent_piece_id"], dtype=np.int64)[row]  # indexed by piece id
    ended_by = np.asarray(pieces["ended_by"], dtype=object)[row]
    return ">".join(lineage_chain(piece_id, parents, ended_by))
