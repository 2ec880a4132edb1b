"""Regression tests: valid input that exhausted the machine. Each test rebuilds one reproducer of a
campaign: a count-setting setting without a lower bound (the bending wedge angle,
the Bates summands), ice that breaks without end (the wall-time guard, also within one step's queue) and a
field whose floes never meet the bow's path."""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest
import shapely

import floebreak
from floebreak.engine.loop import SimulationParams, WallTimeError, simulate
from floebreak.errors import InputError
from floebreak.failure import Fate, NewPiece, Outcome, Status
from floebreak.failure.bending import BendingSettings
from floebreak.ice.field import FloeField
from floebreak.ice.thickness import bounded_random_thickness_m
from floebreak.output.field_files import save_field
from floebreak.ship.hulls import agulhas_ii

ONE_FLOE = "[field]\nfloes = [{ x_m = 20.0, y_m = 0.0, diameter_m = 10.0 }]\n[ice]\nthickness_m = 1.0\n"


# --- count-setting settings have physical lower bounds ----------------------------------------------


@pytest.mark.parametrize("angle_deg", [1e-6, 0.001, 0.5])
def test_a_wedge_angle_below_one_degree_is_refused(angle_deg):
    # 1e-6° grew one 10 m floe past 1.5 GB in 40 s (2π/φ rays); 0.001° ran past 120 s
    text = ONE_FLOE + f"[failure.bending]\nwedge_angle_deg = {angle_deg}\n"
    with pytest.raises(InputError) as info:
        floebreak.run(floebreak.Scenario.from_toml_text(text))
    assert info.value.field == "failure.bending.wedge_angle_deg" and "[1, 60]" in str(info.value)
    with pytest.raises(InputError, match=r"failure\.bending\.wedge_angle_deg"):
        BendingSettings(wedge_angle_deg=angle_deg)


def test_the_smallest_wedge_angle_runs_quickly():
    started = time.perf_counter()
    result = floebreak.run(
        floebreak.Scenario.from_toml_text(ONE_FLOE + "[failure.bending]\nwedge_angle_deg = 1.0\n")
    )
    assert result.simulation.n_contacts > 0
    assert time.perf_counter() - started < 60.0  # 1.5 s on one core (5°: 1.2 s)


def test_thickness_summands_above_ten_thousand_are_refused():
    text = "[field]\nlength_m = 60.0\n[ice]\nthickness_range_m = [0.5, 1.5]\nthickness_summands = 100000\n"
    with pytest.raises(InputError, match=r"ice\.thickness_summands"):
        floebreak.Scenario.from_toml_text(text)


def test_bates_thickness_is_drawn_in_blocks_from_the_same_stream():
    # more values than one block (2^20): the block boundaries must not change a single draw
    size, summands = 300, 5000
    reference = np.random.default_rng(7).random((size, summands)).sum(axis=1) / summands
    drawn = bounded_random_thickness_m(np.random.default_rng(7), 0.5, 1.5, size, summands)
    np.testing.assert_array_equal(drawn, 0.5 + reference)


# --- the wall-time guard ---------------------------------------------------------------------------------


CHURN = """
[field]
floes = [{ x_m = 20.0, y_m = 0.0, diameter_m = 30.0 }]
[ice]
thickness_m = 0.02
[failure.policy]
unbreakable = ["bending"]
bending = ["bending"]
cracking = ["bending"]
[simulation]
max_wall_s = 2.0
"""


def test_thin_ice_breaking_without_end_stops_at_the_wall_time_budget(cli, tmp_path):
    # a custom policy on thin ice churned past 5 000 pieces with 0 cusps without finishing
    scenario = tmp_path / "s.toml"
    scenario.write_text(CHURN, encoding="utf-8")
    started = time.perf_counter()
    code, _, err = cli("run", scenario, "--out", tmp_path / "out", "--quiet")
    assert code == 2, err
    assert err.startswith("error: simulation.max_wall_s: the run took more than 2 s")
    assert "raise simulation.max_wall_s" in err and err.strip().count("\n") == 0
    assert time.perf_counter() - started < 60.0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]  # nothing written, no spool left


@dataclass(frozen=True)
class _SlowHalving:
    """Halves every floe it meets, slowly: one bow position's queue never empties (up to the guard of
    evaluations per step)."""

    name: ClassVar[str] = "slow_halving"
    settings: None = None

    def evaluate(self, inp, ctx) -> Outcome:
        time.sleep(0.02)
        x0, y0, x1, y1 = inp.polygon.bounds
        middle = 0.5 * (x0 + x1)
        halves = [shapely.box(x0 - 1, y0 - 1, middle, y1 + 1), shapely.box(middle, y0 - 1, x1 + 1, y1 + 1)]
        pieces = [NewPiece(shapely.intersection(inp.polygon, h), Fate.FLOE) for h in halves]
        return Outcome(self.name, Status.FAILED, tuple(p for p in pieces if not p.polygon.is_empty))


def test_the_wall_time_guard_stops_within_one_bow_position():
    field = floebreak.Scenario.from_toml_text(ONE_FLOE)
    with floebreak.registered_mode(_SlowHalving):
        scenario = field.model_copy(
            update={
                "failure": floebreak.Scenario.from_toml_text(
                    ONE_FLOE + "[failure.policy]\nbending = ['slow_halving']\ncracking = ['slow_halving']\n"
                    "unbreakable = ['slow_halving']\n"
                ).failure,
                "simulation": floebreak.Scenario.from_toml_text(
                    ONE_FLOE + "[simulation]\nmax_wall_s = 0.5\n"
                ).simulation,
            }
        )
        started = time.perf_counter()
        with pytest.raises(WallTimeError) as info:
            floebreak.run(scenario)
    # 256 evaluations at one position would take ≥ 5 s: the guard acts between evaluations
    assert time.perf_counter() - started < 4.0
    assert info.value.field == "simulation.max_wall_s"


def test_the_default_wall_time_budget_grows_with_the_transit():
    from floebreak.engine.loop import WALL_S_BASE, WALL_S_PER_KM

    assert WALL_S_BASE >= 120.0 and WALL_S_PER_KM >= 6 * 10.0  # ≥ 6 × the slowest measured 10 s per km
    with pytest.raises(InputError, match=r"simulation\.max_wall_s"):
        SimulationParams(max_wall_s=0.0)


# --- a field beside the bow's path -------------------------------------------------------------------------


def _far_field(offset_m: float) -> FloeField:
    centres = np.array([[offset_m + 20.0 * i, offset_m] for i in range(3)])
    polygons = shapely.buffer(shapely.points(centres), 4.0)
    return FloeField(
        polygons=polygons,
        thickness_m=np.ones(3),
        diameter_class_m=np.full(3, 8.0),
        floe_id=np.arange(3),
        domain_m=(offset_m - 10.0, offset_m - 10.0, offset_m + 60.0, offset_m + 10.0),
    )


def test_a_field_in_utm_like_coordinates_is_refused_before_stepping(cli, tmp_path):
    # floes at x, y ≈ 1e7 m ran with no end and no warning that no floe is in the bow's path
    save_field(_far_field(1.0e7), tmp_path / "utm.parquet")
    scenario = tmp_path / "s.toml"
    scenario.write_text('[field]\nfile = "utm.parquet"\n', encoding="utf-8")
    started = time.perf_counter()
    code, _, err = cli("run", scenario, "--out", tmp_path / "out", "--quiet")
    assert code == 2, err
    assert err.startswith("error: field: no floe of 'utm.parquet' lies in the bow's path")
    assert "y ∈ [1e+07" in err and "the bow sweeps y ∈ [" in err
    assert time.perf_counter() - started < 30.0
    assert not (tmp_path / "out").exists()


def test_the_same_field_in_the_field_frame_runs():
    moved = _far_field(1.0e7).shifted(-1.0e7 + 10.0, -1.0e7)  # floes at x = 20, 40, 60 m on the centre line
    result = simulate(moved, agulhas_ii(), params=SimulationParams(step_m=0.5))
    assert result.n_contacts > 0


def test_floes_beyond_an_explicit_end_are_not_refused():
    ahead = _far_field(30.0).shifted(0.0, -30.0)  # floes at x = 30, 50, 70 m on the centre line
    result = simulate(ahead, agulhas_ii(), params=SimulationParams(step_m=0.5, x_end_m=5.0))
    assert result.n_contacts == 0


def test_the_swept_band_check_from_the_python_api():
    with pytest.raises(InputError) as info:
        simulate(_far_field(1.0e7), agulhas_ii(), params=SimulationParams(step_m=0.5))
    assert info.value.field == "field" and "no floe of the field lies in the bow's path" in str(info.value)
