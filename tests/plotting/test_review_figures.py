"""Figures fit for a review: spectrum bins chosen from the data, axes fitted to the data, and the
propeller-load line visible over the shaft torque."""

from __future__ import annotations

import numpy as np
import pytest

from floebreak.plotting.propeller import plot_spectrum
from floebreak.plotting.shaft import plot_densities, plot_series
from floebreak.propeller.spectra import FIGURE_MIN_BINS, figure_curves, figure_edges


def test_small_loads_get_a_histogram_not_two_10_kn_bars():
    loads_kn = np.random.default_rng(3).uniform(0.0, 19.0, 40)  # the case of two 10 kN bins over 0–19 kN
    edges = figure_edges(loads_kn)
    assert edges.size - 1 >= FIGURE_MIN_BINS
    assert edges[0] == loads_kn.min() and edges[-1] == loads_kn.max()
    counts, _ = np.histogram(loads_kn, edges)
    assert counts.sum() == loads_kn.size


def test_many_loads_follow_the_freedman_diaconis_rule():
    loads = np.random.default_rng(4).normal(300.0, 30.0, 20_000)
    edges = figure_edges(loads)
    iqr = np.subtract(*np.percentile(loads, [75, 25]))
    assert np.diff(edges)[0] == pytest.approx(2 * iqr / loads.size ** (1 / 3), rel=0.05)


def test_torque_spectrum_axis_spans_the_data_not_zero_to_it():
    torque = {0.0: {"r1": np.linspace(270.0, 400.0, 50)}, 95.0: {"r1": np.linspace(280.0, 390.0, 50)}}
    curves = figure_curves("torque", torque)
    for j in range(2):  # each pitch's density integrates to one on the shared edges
        assert np.sum(curves.density[j] * np.diff(curves.edges)) == pytest.approx(1.0)
    ax = plot_spectrum(curves).axes[0]
    assert ax.get_xlim() == pytest.approx((270.0, 400.0))
    assert "bins of" in ax.get_title()


def test_zero_loads_draw_no_loads():
    curves = figure_curves("force", {0.0: {"r1": np.array([np.nan, np.nan])}})
    ax = plot_spectrum(curves, log=True).axes[0]
    assert [t.get_text() for t in ax.texts] == ["no loads"]


def test_shaft_spectra_axis_spans_the_occupied_bins():
    edges = np.arange(-600.0, 1510.0, 10.0)
    load = np.where((edges[:-1] >= 300) & (edges[:-1] < 700), 1.0, 0.0)
    shaft = np.where((edges[:-1] >= -500) & (edges[:-1] < 1400), 0.5, 0.0)
    ax = plot_densities(edges, {"load": load, "shaft": shaft}, False, 1e-3, "t").axes[0]
    assert ax.get_xlim() == pytest.approx((-510.0, 1410.0))
    ax = plot_densities(edges, {"load": load}, False, 1e-3, "t").axes[0]
    assert ax.get_xlim() == pytest.approx((290.0, 710.0))


def test_the_propeller_load_is_drawn_over_the_shaft_torque():
    t = np.linspace(0.0, 10.0, 2_000)
    figure = plot_series(t, {"propeller load": 300 + 50 * np.sin(t), "shaft": 300 + 500 * np.sin(9 * t)}, "x")
    for ax in figure.axes:
        load, shaft = ax.get_lines()[:2]
        assert load.get_zorder() > shaft.get_zorder()
        assert shaft.get_alpha() < 1.0 and load.get_alpha() in (None, 1.0)


def test_an_analysis_with_zero_loads_draws_its_figures_without_a_warning(recwarn):
    """No cusps: every figure is drawn, none passes matplotlib an empty log axis (its UserWarning)."""
    import warnings

    from floebreak.app.propeller import analyse_propeller, propeller_figures
    from floebreak.propeller.runs import RateBasis, RunExposure

    columns = ("volume_m3", "bbox_length_m", "bbox_width_m", "thickness_m", "area_m2", "bow_x_m")
    cusps = {name: np.zeros(0) for name in (*columns, "centroid_x_m", "centroid_y_m")}
    cusps["run_id"] = np.array([], dtype=str)
    exposures = {"r": RunExposure(300.0, RateBasis(3.0, None, 2))}
    result = analyse_propeller(cusps, exposures=exposures, polar_class="PC5")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        figures = propeller_figures(result)
    texts = [t.get_text() for t in figures["rule_form.png"].axes[1].texts]
    assert texts == ["no loads"]  # a time base, but nothing to count
