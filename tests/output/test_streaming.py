"""Bounded memory: contact records streamed to Parquet row groups while the run goes on, large
tables written row group by row group, long fields drawn in a window — each giving what the in-memory path
gives."""

from __future__ import annotations

import json

import numpy as np
import pyarrow.parquet as pq
import pytest
import shapely

import floebreak
from floebreak.api import CONTACTS_FILE, FIGURE_WINDOW_M
from floebreak.engine.loop import SimulationParams, simulate
from floebreak.engine.records import ContactRecorder
from floebreak.errors import InputError
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.io import geoparquet
from floebreak.io.geoparquet import ROW_GROUP_ROWS, read_geoparquet, write_geoparquet
from floebreak.ship.hulls import agulhas_ii

SMALL = ["field.length_m=60.0"]


def _same_columns(a: dict, b: dict) -> None:
    assert list(a) == list(b)
    for name in a:
        if np.asarray(a[name]).dtype.kind == "f":
            np.testing.assert_array_equal(a[name], b[name])
        else:
            assert np.asarray(a[name]).tolist() == np.asarray(b[name]).tolist(), name


def test_a_recorder_with_a_sink_keeps_no_records_and_loses_none():
    """Chunks of 8 zones go to the sink; what stays (forces, failures) matches the whole table's."""
    field = generate_field(
        get_observation("2019-12-18T20:20"), 60.0, 50.0, np.random.default_rng(3), thickness_m=1.0
    )
    params = SimulationParams(step_m=0.5)
    bow = agulhas_ii(ice_thickness_m=1.0)
    kept = ContactRecorder()
    simulate(field, bow, params=params, callbacks=[kept])
    sunk_chunks: list[dict] = []
    streamed = ContactRecorder(chunk_zones=8, sink=sunk_chunks.append)
    simulate(field, bow, params=params, callbacks=[streamed])
    full = kept.table()
    records = streamed.records()
    assert len(sunk_chunks) > 2  # the test exercises several chunks
    assert records.columns is None
    assert len(streamed.table()["step"]) == 0  # nothing held back in memory
    sunk = {name: np.concatenate([chunk[name] for chunk in sunk_chunks]) for name in full}
    _same_columns(full, sunk)
    assert records.n_rows == len(full["step"])
    # the crushing force of each evaluated zone, independently: group the whole table's rows by
    # (step, piece, zone) in a dict, sum F_c in row order, sort by the key
    sums: dict[tuple[int, int, int], float] = {}
    for step, piece, zone, force in zip(
        full["step"], full["piece_id"], full["zone"], full["f_c_n"], strict=True
    ):
        key = (int(step), int(piece), int(zone))
        sums[key] = sums.get(key, 0.0) + float(force)
    np.testing.assert_array_equal(records.crushing_forces_n, [sums[key] for key in sorted(sums)])
    failed = full["outcome"] != "no_failure"
    assert records.failed_piece_id.tolist() == full["piece_id"][failed].tolist()
    assert records.failed_step.tolist() == full["step"][failed].tolist()


def test_a_spooled_run_gives_the_in_memory_run_and_files(tmp_path):
    in_memory = floebreak.run(overrides=SMALL)
    spool = tmp_path / "spool"
    spool.mkdir()
    spooled = floebreak.run(overrides=SMALL, spool=spool)
    assert spooled.contact_records.columns is None  # the records are in the spool's file, not in memory
    assert pq.ParquetFile(spool / CONTACTS_FILE).metadata.num_rows == in_memory.summary["n_contact_records"]
    without_time = {k: v for k, v in in_memory.summary.items() if k != "wall_time_s"}
    assert {k: v for k, v in spooled.summary.items() if k != "wall_time_s"} == without_time
    _same_columns(in_memory.contacts, spooled.contacts)
    _same_columns(in_memory.pieces, spooled.pieces)
    np.testing.assert_array_equal(in_memory.crushing_forces_n, spooled.crushing_forces_n)
    a = in_memory.write(tmp_path / "a", report=False, figures=False)
    b = spooled.write(tmp_path / "b", report=False, figures=False)
    table_a, table_b = pq.read_table(a / CONTACTS_FILE), pq.read_table(b / CONTACTS_FILE)
    assert table_a.schema.equals(table_b.schema, check_metadata=True)
    assert table_a.equals(table_b)
    files_a = json.loads((a / "summary.json").read_text())["files"]
    files_b = json.loads((b / "summary.json").read_text())["files"]
    assert files_a == files_b  # a single row group either way: byte-identical files


def test_a_failed_spooled_run_leaves_no_contact_file(tmp_path, monkeypatch):
    def fail(event):
        if type(event).__name__ == "StepDone" and event.step == 20:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        floebreak.run(overrides=SMALL, spool=tmp_path, callbacks=[fail])
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(InputError, match="spool"):
        floebreak.run(overrides=SMALL, spool=tmp_path / "missing")


def test_a_large_table_is_written_in_row_groups(tmp_path):
    n = ROW_GROUP_ROWS + 1000
    centres = np.column_stack([np.arange(n, dtype=float) * 3.0, np.zeros(n)])
    polygons = shapely.buffer(shapely.points(centres), 1.0, quad_segs=2)
    columns = {"piece_id": np.arange(n), "fate": np.array(["cusp", "remaining"] * (n // 2), dtype=object)}
    path = write_geoparquet(tmp_path / "t.parquet", polygons, columns, {"kind": "test"})
    assert pq.ParquetFile(path).metadata.num_row_groups == 2
    geometries, read, meta = read_geoparquet(path)
    assert shapely.equals_exact(geometries, polygons, tolerance=0.0).all()
    assert read["piece_id"].tolist() == list(range(n))
    assert read["fate"].tolist() == columns["fate"].tolist()
    assert meta == {"kind": "test"}
    bbox = json.loads(pq.read_schema(path).metadata[b"geo"])["columns"]["geometry"]["bbox"]
    assert bbox == [-1.0, -1.0, 3.0 * (n - 1) + 1.0, 1.0]  # of the whole table, not of one row group


def test_figures_of_a_long_field_show_a_window():
    result = floebreak.run(overrides=SMALL)
    figure = result.plot_breaking_pattern()
    x0, x1 = figure.axes[0].get_xlim()
    assert x1 - x0 < 200.0  # a short transit: whole, both bow outlines (the field is 60 m)
    from floebreak.plotting.pattern import plot_breaking_pattern

    sim = result.simulation
    window = (10.0, 30.0)
    figure = plot_breaking_pattern(sim, x_window_m=window, bow_at_end=False)
    assert figure.axes[0].get_xlim() == window
    assert figure.axes[0].get_title() == "x = 10 to 30 m of the 60 m field"  # no title given: the note alone
    drawn = sum(len(c.get_paths()) for c in figure.axes[0].collections)
    bounds = shapely.bounds(sim.polygon)
    shown = sim.fate != "broken"
    inside = shown & (bounds[:, 0] <= window[1]) & (bounds[:, 2] >= window[0])
    assert 0 < drawn == int(shapely.get_num_geometries(sim.polygon[inside]).sum()) < shown.sum()
    assert FIGURE_WINDOW_M >= 1000.0


def test_the_run_figures_of_a_long_field_say_which_part_they_show(monkeypatch):
    """The run directory's figures of a field longer than the window state it in their title (here a 60 m
    field and a window of 20 m standing in for 10 km and 2 km)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    result = floebreak.run(overrides=SMALL)
    monkeypatch.setattr("floebreak.app.run.FIGURE_WINDOW_M", 20.0)
    for figure, what in (
        (result.plot_breaking_pattern(), "breaking pattern"),
        (result.plot_field(), "initial floe field"),
    ):
        title = figure.axes[0].get_title()
        assert title.startswith(what) and title.endswith("\nfirst 20 m of the 60 m field"), title
        canvas = FigureCanvasAgg(figure)
        canvas.draw()
        extent = figure.axes[0].title.get_window_extent(canvas.get_renderer())
        assert extent.y1 <= figure.bbox.y1  # both lines inside the figure
    assert result.plot_breaking_pattern().axes[0].get_xlim()[1] == 20.0  # the field starts at x = 0


def _pixels(figure) -> np.ndarray:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(figure)
    canvas.draw()
    return np.asarray(canvas.buffer_rgba()).copy()


def test_the_figure_calls_of_a_long_field_carry_only_what_the_window_draws(monkeypatch):
    """A figure worker is sent a figure's call pickled: for a field longer than the window the call holds the
    floes and pieces in the window, not the whole field or run (a 100 km run's result pickles to hundreds of
    MB), and draws exactly what plotting the whole field or result in that window draws (a 60 m field and a
    20 m window standing in for 100 km and 2 km)."""
    from floebreak.output.figure_process import draw_figure, pickled
    from floebreak.plotting.field import plot_field
    from floebreak.plotting.pattern import plot_breaking_pattern
    from floebreak.plotting.pattern_data import BreakingPattern

    result = floebreak.run(overrides=SMALL)
    sim = result.simulation
    monkeypatch.setattr("floebreak.app.run.FIGURE_WINDOW_M", 20.0)
    x0 = result.field.domain_m[0]

    _, _, (sent_field,), kwargs = call = result.figure_call("field")
    bounds = shapely.bounds(result.field.polygons)
    inside = (bounds[:, 0] <= x0 + 20.0) & (bounds[:, 2] >= x0)
    assert 0 < sent_field.n_floes == inside.sum() < result.field.n_floes
    whole = plot_field(result.field, title=kwargs["title"], x_window_m=(x0, x0 + 20.0))
    np.testing.assert_array_equal(_pixels(draw_figure(call)), _pixels(whole))

    _, _, (pattern,), kwargs = call = result.figure_call("breaking_pattern")
    assert isinstance(pattern, BreakingPattern)
    window = pattern.x_window_m
    shown = sim.fate != "broken"
    drawn = sum(len(p) for p in pattern.polygons.values())
    assert 0 < drawn < shown.sum()
    assert pattern.counts == {f: int((sim.fate == f).sum()) for f in ("remaining", "flipped", "cusp")}
    whole = plot_breaking_pattern(sim, title=kwargs["title"], x_window_m=window, bow_at_end=False)
    np.testing.assert_array_equal(_pixels(draw_figure(call)), _pixels(whole))
    assert len(pickled(call)) < len(pickled(sim)) / 2
    with pytest.raises(ValueError, match="x_window_m"):
        plot_breaking_pattern(pattern, x_window_m=(0.0, 1.0))


def test_the_engine_keeps_finished_pieces_as_wkb_and_gives_them_back_exactly():
    """Pieces the run has finished with are held as WKB bytes, not GEOS geometries; decoding gives the
    polygons back exactly (the areas the engine measured on the geometries when it made them)."""
    result = floebreak.run(overrides=SMALL).simulation
    field = result.field
    stored = result.stored_polygon
    created = result.piece_id >= field.n_floes
    gone = created & np.isin(result.fate, ["cusp", "flipped"])
    assert gone.sum() > 10
    assert all(type(stored[i]) is bytes for i in np.flatnonzero(gone))
    assert all(isinstance(stored[i], shapely.Geometry) for i in range(field.n_floes))  # the field's own
    polygons = result.polygons(np.flatnonzero(gone))
    assert all(isinstance(p, shapely.Polygon) for p in polygons)
    np.testing.assert_array_equal(shapely.area(polygons), result.piece_area_m2[gone])
    np.testing.assert_array_equal(shapely.bounds(polygons), result.piece_bounds_m[gone])
    assert shapely.equals_exact(result.polygon[gone], polygons, tolerance=0.0).all()


def test_writing_a_run_directory_decodes_no_piece_table_whole(tmp_path, monkeypatch):
    """The writer builds the piece files a row group at a time: neither the cached tables of the Result
    nor every polygon at once (`SimulationResult.polygon`) is made; the files hold what one row group
    would."""
    result = floebreak.run(overrides=SMALL)
    whole = result.write(tmp_path / "whole", report=False, figures=False)
    sim = result.simulation
    decoded = []
    polygons = type(sim).polygons

    def counting(self, index=slice(None)):
        out = polygons(self, index)
        decoded.append(len(out))
        return out

    monkeypatch.setattr(type(sim), "polygons", counting)
    monkeypatch.setattr(geoparquet, "ROW_GROUP_ROWS", 32)
    grouped = result.write(tmp_path / "grouped", report=False, figures=False)
    assert decoded and max(decoded) <= 32 < len(sim.piece_id)
    assert not {"cusps", "flipped", "remaining", "pieces"} & set(vars(result))  # no cached table
    assert "polygon" not in vars(sim)
    for name in ("cusps.parquet", "remaining.parquet", "pieces.parquet", "contacts.parquet"):
        meta = pq.ParquetFile(grouped / name).metadata
        assert meta.num_row_groups == -(-meta.num_rows // 32) or meta.num_rows == 0, name
        assert name == "remaining.parquet" or meta.num_row_groups > 1, name
        a, b = pq.read_table(whole / name), pq.read_table(grouped / name)
        assert a.schema.equals(b.schema, check_metadata=True), name
        _same_columns(
            *({n: t.column(n).to_numpy(zero_copy_only=False) for n in t.column_names} for t in (a, b))
        )


def test_floebreak_field_figure_of_a_long_field_shows_the_window(monkeypatch):
    """`floebreak field --figure` draws its field as the run directory does: a field longer than the window
    shows its first part and says so (a 60 m field, a 20 m window)."""
    from floebreak.api import plot_field_figure

    field = generate_field(
        get_observation("2019-12-18T20:20"), 60.0, 50.0, np.random.default_rng(3), thickness_m=1.0
    )
    assert "first" not in plot_field_figure(field).axes[0].get_title()  # 60 m: shorter than the window
    monkeypatch.setattr("floebreak.app.run.FIGURE_WINDOW_M", 20.0)
    figure = plot_field_figure(field, title="field")
    assert figure.axes[0].get_title().endswith("\nfirst 20 m of the 60 m field")
    assert figure.axes[0].get_xlim()[1] < field.domain_m[0] + 30.0  # the window and a margin, not 60 m
