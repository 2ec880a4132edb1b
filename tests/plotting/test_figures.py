"""Figures: the spectra are probability densities; the breaking pattern draws every piece."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure
from PIL import Image

from floebreak.engine.loop import SimulationParams, simulate
from floebreak.errors import InputError
from floebreak.ice.field import FloeField, circle_polygons
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.io.figures import save_figure
from floebreak.plotting.common import window_note
from floebreak.plotting.field import plot_field
from floebreak.plotting.pattern import plot_breaking_pattern
from floebreak.plotting.spectra import plot_crushing_force_spectrum, plot_cusp_volume_spectrum
from floebreak.ship.hulls import agulhas_ii


def test_crushing_force_spectrum_is_a_density():
    forces_n = np.random.default_rng(0).gamma(2.0, 150e3, size=500)
    figure = plot_crushing_force_spectrum(forces_n, bin_width_kn=50.0)
    ax = figure.axes[0]
    (stairs,) = ax.patches
    density, edges, baseline = stairs.get_data()
    assert len(density) == int(np.ceil(forces_n.max() / 50e3))  # bins of 50 kN from 0 past the largest force
    assert edges[0] == 0.0 and np.allclose(np.diff(edges), 50.0) and baseline == 0.0
    assert abs(np.sum(density * np.diff(edges)) - 1.0) < 1e-9
    assert ax.get_ylim()[0] == 0.0  # the density axis starts at zero, as for bars
    assert [text.get_text() for text in ax.get_legend().get_texts()] == ["floebreak"]
    assert "[kN]" in ax.get_xlabel() and "[1/kN]" in ax.get_ylabel()


def test_a_run_without_cusps_gets_a_spectrum_saying_no_data_and_no_warning():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # matplotlib warns for a legend without labelled artists
        figure = plot_cusp_volume_spectrum(np.zeros(0))
    (ax,) = figure.axes
    assert ax.get_legend() is None and [t.get_text() for t in ax.texts] == ["no data"]


def test_field_and_pattern_figures():
    field = generate_field(get_observation("2019-12-18T20:20"), 100.0, 50.0, np.random.default_rng(1))
    assert isinstance(plot_field(field), Figure)
    result = simulate(field, agulhas_ii(), params=SimulationParams(step_m=1.0))
    figure = plot_breaking_pattern(result)
    assert isinstance(figure, Figure)
    assert figure.axes[0].get_xlabel().endswith("[m]")


def test_save_figure_writes_the_png_with_its_metadata_and_no_temporary_file(tmp_path):
    fig = Figure(figsize=(2.0, 1.0))
    fig.add_subplot().plot([0, 1], [0, 1])
    path = save_figure(fig, tmp_path / "line.png", dpi=100, metadata={"Description": "a line"})
    with Image.open(path) as image:
        assert image.format == "PNG" and image.size == (200, 100)
        assert image.text["Description"] == "a line"
    assert [p.name for p in tmp_path.iterdir()] == ["line.png"]


def test_save_figure_into_a_missing_directory_names_the_field(tmp_path):
    with pytest.raises(InputError, match="figure"):
        save_figure(Figure(), tmp_path / "missing" / "x.png")


def _title_fits(figure) -> bool:
    """The axes title lies inside the figure (drawn on an Agg canvas; no pixels compared)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(figure)
    canvas.draw()
    extent = figure.axes[0].title.get_window_extent(canvas.get_renderer())
    return figure.bbox.x0 <= extent.x0 and extent.x1 <= figure.bbox.x1 and extent.y1 <= figure.bbox.y1


@pytest.mark.parametrize(
    ("window", "field_x", "note"),
    [
        ((-32.0, 2000.0), (0.0, 10000.0), "first 2 000 m of the 10 000 m field"),
        ((0.0, 2000.0), (0.0, 12345.6), "first 2 000 m of the 12 345.6 m field"),
        ((10.0, 30.0), (0.0, 60.0), "x = 10 to 30 m of the 60 m field"),
    ],
)
def test_window_note_states_the_part_shown(window, field_x, note):
    assert window_note(window, field_x) == note


def test_a_long_field_figure_says_in_its_title_which_part_it_shows():
    # 11 floes of 10 m every 1 000 m in a 10 km × 200 m field: the window holds 3 of them
    centres = np.column_stack([np.arange(11) * 1000.0 + 5.0, np.zeros(11)])
    polygons = circle_polygons(centres, np.full(11, 5.0), 16)
    field = FloeField(polygons, np.ones(11), np.full(11, 10.0), np.arange(11), (0.0, -100.0, 10000.0, 100.0))
    figure = plot_field(field, title="initial floe field", x_window_m=(0.0, 2000.0))
    assert figure.axes[0].get_title() == "initial floe field\nfirst 2 000 m of the 10 000 m field"
    assert _title_fits(figure)
    assert sum(len(c.get_paths()) for c in figure.axes[0].collections) == 3  # floes at x = 5, 1005, 2005 m
