"""Figures: the spectra are probability densities; the breaking pattern draws every piece."""

from __future__ import annotations

import io

import numpy as np
import pytest
from matplotlib.figure import Figure
from PIL import Image

from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.io.figures import save_png, savefig
from floebreak.plotting.field import plot_field
from floebreak.plotting.pattern import plot_breaking_pattern
from floebreak.plotting.spectra import plot_crushing_force_spectrum
from floebreak.ship.hulls import agulhas_ii
from floebreak.simulation import SimulationParams, simulate


def test_crushing_force_spectrum_is_a_density():
    forces_n = np.random.default_rng(0).gamma(2.0, 150e3, size=500)
    figure = plot_crushing_force_spectrum(forces_n, bin_width_kn=50.0)
    ax = figure.axes[0]
    (bars,) = ax.collections
    boxes = [path.get_extents() for path in bars.get_paths()]
    assert len(boxes) == int(np.ceil(forces_n.max() / 50e3))  # bins of 50 kN from 0 past the largest force
    assert all(box.y0 == 0.0 and box.width == pytest.approx(50.0) for box in boxes)
    integral = sum(box.width * box.height for box in boxes)
    assert abs(integral - 1.0) < 1e-9
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
    pixels = [np.asarray(Image.open(buffer).convert("RGBA")) for buffer in (expected, ours)]
    np.testing.assert_array_equal(pixels[0], pixels[1])


def _png(save) -> Image.Image:
    buffer = io.BytesIO()
    save(buffer)
    image = Image.open(io.BytesIO(buffer.getvalue()))
    image.load()
    return image


@pytest.mark.parametrize("transparent", [False, True])
def test_save_png_has_the_pixels_text_and_resolution_of_matplotlibs_png(transparent):
    def figure():
        fig = plot_crushing_force_spectrum(np.random.default_rng(2).gamma(2.0, 150e3, size=300))
        if transparent:  # a see-through background: the alpha channel must stay
            fig.patch.set_alpha(0.0)
            fig.axes[0].patch.set_alpha(0.5)
        return fig

    metadata = {"Software": "floebreak test", "Description": '{"seed": 1}', "Author": None}
    expected = _png(lambda b: figure().savefig(b, format="png", dpi=120, metadata=metadata))
    ours = _png(lambda b: save_png(figure(), b, dpi=120, metadata=metadata))
    assert ours.mode == ("RGBA" if transparent else "RGB")
    assert ours.size == expected.size
    np.testing.assert_array_equal(np.asarray(ours.convert("RGBA")), np.asarray(expected.convert("RGBA")))
    assert ours.text == expected.text == {"Software": "floebreak test", "Description": '{"seed": 1}'}
    assert ours.info["dpi"] == expected.info["dpi"]
    default = _png(lambda b: save_png(figure(), b, dpi=120))  # matplotlib's own "Software" entry
    assert default.text == _png(lambda b: figure().savefig(b, format="png", dpi=120)).text


def test_savefig_writes_png_itself_only_for_plain_png_options(monkeypatch):
    import floebreak.io.figures as figures_module

    calls = []
    monkeypatch.setattr(figures_module, "save_png", lambda *a, **k: calls.append(k))
    fig = plot_crushing_force_spectrum(np.ones(10) * 1e5)
    savefig(fig, io.BytesIO(), format="png", dpi=50, metadata={"Software": "x"})
    assert calls == [{"dpi": 50, "metadata": {"Software": "x"}}]
    savefig(fig, io.BytesIO(), format="png", dpi=50, transparent=True)  # other options: matplotlib's PNG
    savefig(fig, io.BytesIO(), format="svg", dpi=50)
    assert len(calls) == 1
