"""Figures: the spectra are probability densities; the breaking pattern draws every piece."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure
from PIL import Image

from floebreak.errors import InputError
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.io.figures import save_figure
from floebreak.plotting.field import plot_field
from floebreak.plotting.pattern import plot_breaking_pattern
from floebreak.plotting.spectra import plot_crushing_force_spectrum
from floebreak.ship.hulls import agulhas_ii
from floebreak.simulation import SimulationParams, simulate


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
