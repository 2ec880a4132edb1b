"""Design figures: the rule exceedance with the rule's N_ice, legible legends in two-panel figures,
the Campbell diagram and the rainflow histogram."""

from __future__ import annotations

import io

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image

from floebreak.plotting.common import LEGEND_PT, add_legend, legend_font_pt
from floebreak.plotting.propeller import plot_rule_exceedance
from floebreak.plotting.shaft import plot_campbell, plot_rainflow_histogram
from floebreak.propeller.iceclass import IceClassLoads
from floebreak.shaft.fatigue import rainflow_histogram

RULE = IceClassLoads("PC5", 2.0, 750e3, 520e3, 730e3, "b", "f", "q")


def _render(figure: Figure) -> Image.Image:
    buffer = io.BytesIO()
    FigureCanvasAgg(figure).print_png(buffer)
    return Image.open(io.BytesIO(buffer.getvalue()))


def _labels(ax) -> list[str]:
    legend = ax.get_legend()
    return [] if legend is None else [t.get_text() for t in legend.get_texts()]


def _loads():
    rng = np.random.default_rng(5)
    return (
        {0.0: 200e3 * rng.weibull(0.75, 511), 95.9: 300e3 * rng.weibull(0.75, 511)},
        {0.0: 150e3 * rng.weibull(0.75, 511), 95.9: 250e3 * rng.weibull(0.75, 511)},
    )


def test_rule_exceedance_draws_the_rule_curve_at_n_ice_once():
    force, torque = _loads()
    n_ice = 6e6 * 140 / 60  # PC5 N_class × n, by hand
    figure = plot_rule_exceedance(force, torque, RULE, 0.75, n_ice=n_ice)
    (legend,) = figure.legends  # one legend below both panels, not one over each panel's curves
    labels = [t.get_text() for t in legend.get_texts()]
    assert len(labels) == len(set(labels)) == 4  # two pitches, one rule curve, the rule maximum
    rule_labels = [t for t in labels if "N_ice" in t]
    assert rule_labels == [f"UR I3 exp(−x^0.75 ln N_ice), N_ice = {n_ice:.3g}"]
    assert not any("N = 511" in t for t in labels)
    for ax in figure.axes:
        assert ax.get_legend() is None
        (curve,) = [line for line in ax.lines if line.get_label() == rule_labels[0]]
        x, p = curve.get_data()
        assert p == pytest.approx(np.exp(-(x**0.75) * np.log(n_ice)))  # exp(−x^k ln N_ice), notes §7.3
    assert "not given" not in figure._suptitle.get_text()
    assert _render(figure).size == (1100, 500)


def test_rule_exceedance_without_n_ice_draws_no_rule_curve_and_says_so():
    force, torque = _loads()
    figure = plot_rule_exceedance(force, torque, RULE)
    for ax in figure.axes:
        assert not any("N_ice" in t or "Weibull" in t for t in _labels(ax))
        assert len(ax.lines) == 3  # two simulated steps and the rule maximum
    assert "no rule curve" in figure._suptitle.get_text()
    _render(figure)


def test_legends_of_wide_figures_scale_with_the_width():
    narrow, wide = Figure(figsize=(7.5, 4.0)), Figure(figsize=(11.0, 4.0))
    assert legend_font_pt(narrow) == LEGEND_PT
    assert legend_font_pt(wide) == pytest.approx(LEGEND_PT * 11.0 / 7.5)
    assert legend_font_pt(Figure(figsize=(5.0, 4.0))) == LEGEND_PT
    force, torque = _loads()
    figure = plot_rule_exceedance(force, torque, RULE, n_ice=1e7)
    sizes = [t.get_fontsize() for legend in figure.legends for t in legend.get_texts()]
    assert sizes == pytest.approx([LEGEND_PT * 11.0 / 7.5] * 4)
    # and every other text of the two-panel figure as large, relative to its width, as a single panel's
    ticks = [t.get_fontsize() for ax in figure.axes for t in ax.get_xticklabels()]
    assert ticks == pytest.approx([10.0 * 11.0 / 7.5] * len(ticks))  # matplotlib's 10 pt default, scaled


def test_add_legend_lists_a_repeated_label_once():
    figure = Figure(figsize=(7.5, 4.0))
    ax = figure.add_subplot()
    for i in range(3):
        ax.plot([0, 1], [i, i], color="k", ls="--", label="rule shape")
    ax.plot([0, 1], [0, 2], label="data")
    assert _labels(add_legend(ax).axes) == ["rule shape", "data"]


def test_campbell_diagram_lines_and_crossings():
    # Z = 4 at 140 rpm: order 4 is at 9.33 Hz; a mode at 7.75 Hz (0.83 of it) crosses
    # order 4 at 60·7.75/4 = 116.25 rpm (inside 140 ± 20 %), orders 8 and 12 at 58.1 and 38.75 rpm
    # (outside); a mode at 30 Hz crosses order 12 at 150 rpm (inside) and orders 4 and 8 beyond 154 rpm
    rpm = np.linspace(0.0, 154.0, 221)
    figure = plot_campbell(rpm, [7.75, 30.0], blades=4, operating_rpm=140.0, margin=0.2)
    (ax,) = figure.axes
    labels = _labels(ax)
    assert len(labels) == len(set(labels))
    orders = ["order 4 (k = 1)", "order 8 (k = 2)", "order 12 (k = 3)"]
    assert [t for t in labels if t.startswith("order")] == orders
    assert [t for t in labels if t.startswith("mode")] == ["mode 1: 7.75 Hz", "mode 2: 30.00 Hz"]
    order_4 = next(line for line in ax.lines if line.get_label() == "order 4 (k = 1)")
    x, y = order_4.get_data()
    assert y == pytest.approx(4 * np.asarray(x) / 60.0)
    inside = next(line for line in ax.lines if line.get_label() == "crossing in the band")
    assert sorted(inside.get_xdata()) == pytest.approx([116.25, 150.0])
    outside = next(line for line in ax.lines if line.get_label() == "crossing")
    assert sorted(outside.get_xdata()) == pytest.approx([38.75, 58.125])  # mode 1 with orders 12 and 8
    (band,) = ax.patches
    x0, x1 = band.get_extents().x0, band.get_extents().x1  # display units: compare via data transform
    data_x = ax.transData.inverted().transform([[x0, 0.0], [x1, 0.0]])[:, 0]
    assert data_x == pytest.approx([112.0, 168.0], abs=0.5)  # 140 rpm ± 20 %, drawn beyond the grid's end
    assert "2 crossing(s)" in ax.get_title()
    _render(figure)


def test_rainflow_histogram_figure():
    series = 7e3 + 12.5e3 * np.cos(2.0 * np.pi * np.arange(401) / 40)  # 10 cycles of range 25 kN·m
    hist = rainflow_histogram(series, 10e3)
    figure = plot_rainflow_histogram(hist.range_edges_n_m, hist.counts, "station 3", damage=1.5e-7)
    (ax,) = figure.axes
    assert _labels(ax) == ["cycles per bin", "cycles with range ≥ x"]
    (stairs,) = ax.patches
    assert stairs.get_data().values.tolist() == [0.0, 0.0, 10.0]
    assert stairs.get_data().edges.tolist() == [0.0, 10.0, 20.0, 30.0]  # kN·m
    assert "10 cycles" in ax.get_title() and "D = 1.5e-07" in ax.get_title()
    assert ax.get_yscale() == "log"
    _render(figure)
    empty = plot_rainflow_histogram([0.0, 1e3], [0.0])
    assert any(t.get_text() == "no cycles" for t in empty.axes[0].texts)
