"""Figures: the spectra are probability densities; the breaking pattern draws every piece."""

from __future__ import annotations

import io

import numpy as np
from matplotlib.figure import Figure
from PIL import Image

from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.io.figures import savefig
from floebreak.plotting.field import plot_field
from floebreak.plotting.pattern import plot_breaking_pattern
from floebreak.plotting.spectra import plot_crushing_force_spectrum
from floebreak.ship.hulls import agulhas_ii
from floebreak.simulation import SimulationParams, simulate


def test_crushing_force_spectrum_is_a_density():
    forces_n = np.random.default_rng(0).gamma(2.0, 150e3, size=500)
    figure = plot_crushing_force_spectrum(forces_n, bin_width_kn=50.0)
    ax = figure.axes[0]
    bars = ax.patches
    integral = sum(bar.get_height() * bar.get_width() for bar in bars)
    assert integral == np.float64(1.0) or abs(integral - 1.0) < 1e-9
    assert "[kN]" in ax.get_xlabel() and "[1/kN]" in ax.get_ylabel()


def test_field_and_pattern_figures():
    field = generate_field(get_observation("2019-12-18T20:20"), 100.0, 50.0, np.random.default_rng(1))
    assert isinstance(plot_field(field), Figure)
    result = simulate(field, agulhas_ii(), params=SimulationParams(step_m=1.0))
    figure = plot_breaking_pattern(result)
    assert isinstance(figure, Figure)
    assert figure.axes[0].get_xlabel().endswith("[m]")


def test_savefig_gives_the_pixels_of_figure_savefig_and_keeps_the_layout_engine():
    def figure():
        fig = plot_crushing_force_spectrum(np.random.default_rng(1).gamma(2.0, 150e3, size=300))
        fig.axes[0].legend(loc="upper left", bbox_to_anchor=(1.0, 1.0))  # outside: needs the layout
        return fig

    expected, ours = io.BytesIO(), io.BytesIO()
    figure().savefig(expected, format="png", dpi=150)
    fig = figure()
    engine = fig.get_layout_engine()
    savefig(fig, ours, format="png", dpi=150)
    assert fig.get_layout_engine() is engine and fig.dpi == 100.0
    pixels = [np.asarray(Image.open(buffer)) for buffer in (expected, ours)]
    np.testing.assert_array_equal(pixels[0], pixels[1])
