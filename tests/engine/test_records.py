"""Result tables and summary statistics (floebreak.engine.records): crushing force per evaluation, cusp
boxes, the piece tables and the thesis Tables 5–8 summary."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

import floebreak
from floebreak.engine.loop import SimulationParams, simulate
from floebreak.engine.records import (
    crushing_force_per_evaluation_n,
    oriented_box_dimensions_m,
    piece_table,
    summary,
)
from floebreak.ice.field import FloeField
from floebreak.ship.hulls import agulhas_ii


def test_crushing_force_sums_the_panels_of_each_zone_evaluation():
    contacts = {  # (step, piece, zone) groups: (1, 7, 0) on two panels, (1, 7, 1), (2, 7, 0) on two panels
        "step": np.array([2, 1, 1, 1, 2]),
        "piece_id": np.array([7, 7, 7, 7, 7]),
        "zone": np.array([0, 0, 1, 0, 0]),
        "f_c_n": np.array([5.0, 1.0, 10.0, 2.0, 6.0]),
    }
    # one total per evaluation, in (step, piece, zone) order
    np.testing.assert_array_equal(crushing_force_per_evaluation_n(contacts), [3.0, 10.0, 11.0])
    empty = {key: np.zeros(0) for key in contacts}
    assert crushing_force_per_evaluation_n(empty).size == 0


def test_oriented_boxes_are_the_sides_of_the_minimum_rectangle():
    rectangle = shapely.affinity.rotate(shapely.box(0.0, 0.0, 4.0, 1.0), 30.0)
    square = shapely.box(10.0, 10.0, 12.0, 12.0)
    length, width = oriented_box_dimensions_m(np.array([rectangle, square]))
    np.testing.assert_allclose(length, [4.0, 2.0], rtol=1e-12)
    np.testing.assert_allclose(width, [1.0, 2.0], rtol=1e-12)
    assert [a.size for a in oriented_box_dimensions_m(np.array([], dtype=object))] == [0, 0]


@pytest.fixture(scope="module")
def run():
    # the reference scenario on a 60 m field, ice 0.5 m thick
    result = floebreak.run(overrides=["field.length_m=60.0", "ice.thickness_m=0.5"])
    return result.simulation


def test_piece_tables_describe_each_piece(run):
    for fate in ("cusp", "flipped", "remaining"):
        table = piece_table(run, fate)
        polygons = table["geometry"]
        assert len(polygons) == int(run.mask(fate).sum())
        np.testing.assert_allclose(table["area_m2"], shapely.area(polygons), rtol=1e-12)
        np.testing.assert_allclose(table["volume_m3"], 0.5 * shapely.area(polygons), rtol=1e-12)
        centroids = shapely.get_coordinates(shapely.centroid(polygons))
        np.testing.assert_allclose(table["centroid_x_m"], centroids[:, 0])
        assert np.all(table["bbox_length_m"] >= table["bbox_width_m"])
        # the box holds the piece: its area is at least the piece's
        assert np.all(table["bbox_length_m"] * table["bbox_width_m"] >= table["area_m2"] * (1 - 1e-9))


def test_summary_counts_areas_and_the_balance(run):
    out = summary(run)
    cusps, flipped, remaining = (piece_table(run, fate) for fate in ("cusp", "flipped", "remaining"))
    initial = float(shapely.area(run.field.polygons).sum())
    assert out["n_floes_initial"] == len(run.field.polygons)
    assert out["initial_ice_area_m2"] == pytest.approx(initial)
    assert out["n_cusps"] == len(cusps["geometry"]) > 0
    assert out["cusp_area_m2"] == pytest.approx(cusps["area_m2"].sum())
    assert out["mean_cusp_area_m2"] == pytest.approx(cusps["area_m2"].mean())
    assert out["mean_cusp_volume_m3"] == pytest.approx(0.5 * cusps["area_m2"].mean())  # h = 0.5 m
    assert out["n_flipped"] == len(flipped["geometry"])
    total = out["cusp_area_m2"] + out["flipped_area_m2"] + out["remaining_ice_area_m2"]
    assert total == pytest.approx(initial, rel=1e-9)  # ice area conserved through every break
    assert out["remaining_ice_area_m2"] == pytest.approx(remaining["area_m2"].sum())
    assert sum(out["breaks_by_mode"].values()) >= out["n_breaks"] > 0
    assert "n_contact_records" not in out  # only with a contact table


def test_summary_of_a_run_without_cusps_has_nan_means():
    far = FloeField(
        polygons=np.array([shapely.box(40.0, 0.0, 45.0, 5.0)], dtype=object),  # beyond the transit's end
        thickness_m=np.array([1.0]),
        diameter_class_m=np.array([5.0]),
        floe_id=np.array([0]),
        domain_m=(0.0, -50.0, 30.0, 50.0),
    )
    out = summary(simulate(far, agulhas_ii(), params=SimulationParams(step_m=1.0, x_end_m=5.0)))
    assert out["n_cusps"] == 0 and out["cusp_area_m2"] == 0.0
    assert math.isnan(out["mean_cusp_area_m2"]) and math.isnan(out["mean_cusp_volume_m3"])
