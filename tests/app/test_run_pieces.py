"""pieces.parquet: every piece of a run with its life span, checked against independent records — the other
tables of the run directory, the engine's per-step counters (StepDone events) and plain geometry (area
conservation and no overlap of the ice in the field at every step)."""

from __future__ import annotations

import json

import numpy as np
import pyarrow.parquet as pq
import pytest
import shapely

import floebreak
from floebreak.engine.loop import StepDone

SMALL = ["field.length_m=60.0"]  # a short reference field, as in tests/test_run.py


@pytest.fixture(scope="module")
def pieces_run(tmp_path_factory):
    steps: list[StepDone] = []
    result = floebreak.run(
        overrides=SMALL, callbacks=[lambda e: steps.append(e) if isinstance(e, StepDone) else None]
    )
    out = tmp_path_factory.mktemp("pieces") / "run"
    result.write(out, figures=False, report=False)
    table = pq.read_table(out / "pieces.parquet")
    columns = {name: table.column(name).to_numpy(zero_copy_only=False) for name in table.column_names}
    geometry = shapely.from_wkb(columns.pop("geometry"))
    return out, table, columns, geometry, steps


def _read(out, name):
    table = pq.read_table(out / name)
    return table, shapely.from_wkb(table.column("geometry").to_numpy(zero_copy_only=False))


def test_pieces_file_is_geoparquet_with_provenance_and_stepping(pieces_run):
    out, table, columns, geometry, _ = pieces_run
    meta = table.schema.metadata
    assert json.loads(meta[b"geo"])["columns"]["geometry"]["crs"] is None
    prov = json.loads(meta[b"floebreak"])
    summary = json.loads((out / "summary.json").read_text())
    assert prov["kind"] == "pieces" and prov["scenario_hash"] == summary["scenario_hash"]
    assert prov["x_start_m"] == 0.0 and prov["step_m"] == 0.25 and prov["n_steps"] == summary["n_steps"]
    assert {
        "piece_id",
        "parent_piece_id",
        "parent_floe_id",
        "fate",
        "created_step",
        "ended_step",
        "thickness_m",
        "area_m2",
    } <= set(table.column_names)
    assert np.all(shapely.is_valid(geometry))
    kept = ~shapely.is_empty(geometry)
    np.testing.assert_allclose(columns["area_m2"][kept], shapely.area(geometry[kept]), rtol=1e-12)
    assert set(columns["fate"]) <= {"broken", "cusp", "flipped", "remaining"}


def test_only_transient_pieces_lack_geometry_and_their_area_is_their_childrens(pieces_run):
    """A piece created and broken at one bow position is never in the field between two steps: its polygon
    is not kept (memory), its area is, and it equals the sum of its children's areas."""
    _, _, columns, geometry, _ = pieces_run
    empty = shapely.is_empty(geometry)
    transient = (columns["fate"] == "broken") & (columns["created_step"] == columns["ended_step"])
    assert transient.any()  # the run chips floes more than once at a position
    np.testing.assert_array_equal(empty, transient)
    children_area = np.zeros(len(geometry))
    np.add.at(
        children_area,
        columns["parent_piece_id"][columns["parent_piece_id"] >= 0],
        columns["area_m2"][columns["parent_piece_id"] >= 0],
    )
    np.testing.assert_allclose(children_area[transient], columns["area_m2"][transient], rtol=1e-9)


def test_initial_floes_are_the_field(pieces_run):
    out, _, columns, geometry, _ = pieces_run
    field, field_geometry = _read(out, "field.parquet")
    initial = columns["parent_piece_id"] == -1
    assert initial.sum() == field.num_rows
    assert np.all(columns["created_step"][initial] == -1)
    assert np.all(columns["created_step"][~initial] >= 0)
    summary = json.loads((out / "summary.json").read_text())
    area = shapely.area(geometry[initial]).sum()
    assert area == pytest.approx(shapely.area(field_geometry).sum(), rel=1e-12)
    assert area == pytest.approx(summary["initial_ice_area_m2"], rel=1e-12)
    np.testing.assert_array_equal(columns["parent_floe_id"][initial], field.column("floe_id").to_numpy())


def test_every_child_has_a_broken_parent(pieces_run):
    _, _, columns, _, _ = pieces_run
    index = {int(pid): i for i, pid in enumerate(columns["piece_id"])}
    children = np.flatnonzero(columns["parent_piece_id"] >= 0)
    assert children.size > 0  # the run breaks floes
    for i in children:
        parent = index[int(columns["parent_piece_id"][i])]
        assert columns["fate"][parent] == "broken"
        assert columns["parent_floe_id"][i] == columns["parent_floe_id"][parent]
        assert columns["thickness_m"][i] == columns["thickness_m"][parent]
        assert columns["created_step"][i] == columns["ended_step"][parent]  # born when the parent broke
    ended, created, fate = columns["ended_step"], columns["created_step"], columns["fate"]
    assert np.all(ended[fate == "remaining"] == -1)
    done = fate != "remaining"
    assert np.all(ended[done] >= np.maximum(created[done], 0))


def test_fates_match_the_piece_files(pieces_run):
    out, _, columns, _, _ = pieces_run
    for fate, name in (("cusp", "cusps"), ("flipped", "flipped"), ("remaining", "remaining")):
        table, _ = _read(out, f"{name}.parquet")
        mask = columns["fate"] == fate
        order = np.argsort(columns["piece_id"][mask])
        ids = table.column("piece_id").to_numpy()
        np.testing.assert_array_equal(np.sort(ids), columns["piece_id"][mask][order])
        if fate != "remaining":  # the step column of cusps/flipped is the step they left the field
            by_id = dict(zip(ids.tolist(), table.column("step").to_numpy().tolist(), strict=True))
            assert [by_id[p] for p in columns["piece_id"][mask].tolist()] == columns["ended_step"][
                mask
            ].tolist()


def test_replay_counts_match_the_engine_counters(pieces_run):
    """Cusps and flipped pieces gone by the end of each step = the engine's StepDone counters."""
    _, _, columns, _, steps = pieces_run
    for fate, key in (("cusp", "n_cusps"), ("flipped", "n_flipped")):
        ended = np.sort(columns["ended_step"][columns["fate"] == fate])
        counted = np.searchsorted(ended, [event.step for event in steps], side="right")
        assert counted.tolist() == [getattr(event, key) for event in steps]


def test_area_is_conserved_and_field_ice_never_overlaps_at_every_step(pieces_run):
    """After each step: ice in the field + ice gone as cusps/flipped = initial ice (no piece counted twice,
    none missing), and the pieces in the field do not overlap (a broken parent is never kept alive next to
    its children)."""
    out, _, columns, geometry, steps = pieces_run
    initial_area = json.loads((out / "summary.json").read_text())["initial_ice_area_m2"]
    area = shapely.area(geometry)
    created, ended, fate = columns["created_step"], columns["ended_step"], columns["fate"]
    broken = fate == "broken"
    for event in steps:
        s = event.step
        exists = (created <= s) & ~(broken & (ended <= s))  # in the field, or gone as a cusp / flipped
        assert area[exists].sum() == pytest.approx(initial_area, rel=1e-9), s
    for s in range(0, len(steps), 25):
        in_field = np.flatnonzero((created <= s) & ((ended < 0) | (ended > s)))
        polygons = geometry[in_field]
        pairs = shapely.STRtree(polygons).query(polygons, predicate="intersects")
        pairs = pairs[:, pairs[0] < pairs[1]]
        overlap = shapely.area(shapely.intersection(polygons[pairs[0]], polygons[pairs[1]])).sum()
        assert overlap <= 1e-9 * initial_area, s
