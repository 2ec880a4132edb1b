"""Inert rows: the flags computed from the configuration, and the reasons they rest on."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from floebreak.mechanics import fracture as fr
from floebreak.studies.field_size import thesis_scenario
from floebreak.validation.inert import inert_flags
from floebreak.validation.statements import STATEMENTS
from floebreak.validation.validate import POINTS

BZ_ROWS = {f"T8.{law}.{q}" for law in ("BZ1", "BZ2") for q in ("dV", "dA_aff", "dA_cusp")}
CAP_ROWS = {"S533.h0.8.dV_max", "S533.h1.2.dV_max"}


@pytest.mark.parametrize("profile", ["default", "thesis"])
def test_the_flags_of_the_profiles(profile):
    """With K_I from the load (both profiles) BZ1/BZ2 are the reference's run, so Table 8's "small effect"
    rows cannot fail (its "slightly more cusps" rows cannot pass: they fail and are not inert); the largest
    cusp's change with h is the cap's, (1.2^1.75 − 1, 0.8^1.75 − 1). Flexural vs tensile stress is not the
    same run (different Tada factors), so its rows are scored."""
    flags = inert_flags(STATEMENTS, thesis_scenario([]), profile, {}, POINTS)
    assert set(flags) == BZ_ROWS | CAP_ROWS
    assert {flags[k].kind for k in BZ_ROWS} == {"identity"} and {flags[k].predicted for k in BZ_ROWS} == {0.0}
    assert flags["S533.h1.2.dV_max"].predicted == pytest.approx(1.2**1.75 - 1)
    assert flags["S533.h0.8.dV_max"].predicted == pytest.approx(0.8**1.75 - 1)
    assert "size-effect law" in flags["T8.BZ1.dV"].reason


def test_a_setting_that_lets_the_size_effect_law_enter_makes_its_rows_live():
    """The flag follows the configuration: with Alg. 7's load-independent stress criterion (the size-effect
    strength is the applied stress) BZ1/BZ2 are runs of their own, and with a random thickness the cap moves
    per floe."""
    variant = {"failure.cracking.stress_mode": "thesis"}
    flags = inert_flags(STATEMENTS, thesis_scenario([]), "thesis", variant, POINTS)
    assert set(flags) == CAP_ROWS
    random_h = {"h0.8": {"ice.thickness_m": None, "ice.thickness_range_m": [0.7, 0.9]}}
    points = {**POINTS, **random_h}
    assert "S533.h0.8.dV_max" not in inert_flags(STATEMENTS, thesis_scenario([]), "default", {}, points)


def test_the_size_effect_settings_do_not_enter_k_i_from_the_load():
    """The hand rule of `UNUSED_SETTINGS`, checked on the criterion over a grid of contacts: under "sif" the
    law, the BZ2 form and the size give the same check bit for bit; under Alg. 7's form they do not."""
    grid = itertools.product((0.01, 0.3, 2.0), (3.0, 15.0), (1e4, 2e6), ("tension", "bending"))
    for a, b, force, loading in grid:
        common = dict(crack_length_m=a, strip_width_m=b, toughness_pa_sqrt_m=145.7e3, loading=loading,
                      horizontal_force_n=force, thickness_m=1.0)  # fmt: skip
        checks = {
            fr.check_stress_sif(law=law, bz2_mode=mode, size_m=size, stress_mode="sif", **common)
            for law, mode, size in itertools.product(
                ("BZ", "BZ1", "BZ2"), ("generalised", "thesis"), (b, 1.5)
            )
        }
        assert len(checks) == 1
        literal = {fr.check_stress_sif(law=law, size_m=b, stress_mode="thesis", **common).driving
                   for law in ("BZ", "BZ1", "BZ2")}  # fmt: skip
        assert len(literal) == 3


SMALL_FIELD = ["field.length_m=60.0", "field.width_m=50.0", "seed=4"]


@pytest.mark.parametrize("profile", ["default", "thesis"])
def test_an_identity_flag_is_a_bit_identical_run_and_the_largest_cusp_sits_at_the_cap(profile):
    """On one small field: BZ1 and the reference give the same pieces bit for bit (the identity's reason);
    no cusp is larger than A_rotate(h)·h at h = 1.0 and 1.2 m, and the largest comes close to it even among
    the few cusps of a small field (on the 16 thesis-size fields of `make validate` the change of the largest
    cusp is the cap's within `inert.CAP_TOLERANCE`, asserted there)."""
    from floebreak.api import run

    base = thesis_scenario(SMALL_FIELD) | {"profile": profile}
    reference = run(base)
    bz1 = run(base, overrides=['failure.size_effect_law="BZ1"'])
    for key in ("n_cusps", "n_flipped", "cusp_area_m2", "flipped_area_m2", "mean_cusp_volume_m3"):
        assert bz1.summary[key] == reference.summary[key], key
    np.testing.assert_array_equal(bz1.cusps["volume_m3"], reference.cusps["volume_m3"])
    for h, result in ((1.0, reference), (1.2, run(base, overrides=["ice.thickness_m=1.2"]))):
        cap = 13.5 * h**0.75 * h  # thesis Eq. 5: A_rotate = 1 m · 13.5 h^(3/4), times h
        volumes = np.asarray(result.cusps["volume_m3"])
        assert volumes.max() <= cap * (1 + 1e-9) and volumes.max() >= cap * 0.9, (h, volumes.max(), cap)
