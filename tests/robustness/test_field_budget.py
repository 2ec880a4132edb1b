"""Fields whose cost would pass a run's memory or time bound are refused before any work starts, naming the
bound and the size keys; a field file with a floe larger than the largest class, or whose farthest floe
would make the bow travel farther than the longest field, is refused naming the file and the row."""

from __future__ import annotations

import time

import numpy as np
import pytest
import shapely

from floebreak.errors import InputError
from floebreak.ice.budget import (
    GENERATION_BYTES_PER_FLOE,
    MAX_FLOE_SIZE_M,
    MAX_TRANSIT_M,
    FieldBudget,
    check_generation_budget,
)
from floebreak.ice.field import FloeField
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.output.field_files import save_field

OBS = "2019-12-18T20:20"


def test_the_budget_arithmetic_names_the_bound():
    budget = FieldBudget(memory_bytes=1e6, time_s=1e6, memory_key="M", time_key="T", size_keys="K")
    fits = int(1e6 // GENERATION_BYTES_PER_FLOE)
    check_generation_budget(fits, 10.0, 10.0, budget)
    with pytest.raises(InputError, match="more than M") as info:
        check_generation_budget(fits + 1, 10.0, 10.0, budget)
    assert info.value.field == "K"
    with pytest.raises(InputError, match="more than T"):
        check_generation_budget(10, 10.0, 10.0, FieldBudget(time_s=1e-6, time_key="T"))


@pytest.mark.parametrize(
    ("args", "key"),
    [
        (["--length", "1000000", "--width", "100000"], "--length/--width"),
        (["--length", "385", "--width", "100000"], "--length/--width"),
    ],
)
def test_field_command_refuses_a_field_past_the_budget_at_once(cli, tmp_path, args, key):
    started = time.perf_counter()
    code, _, err = cli("field", "--obs", OBS, *args, "--seed", "1", "--out", tmp_path / "f.parquet")
    assert code == 2, err
    assert err.strip().startswith(f"error: {key}: ") and "GB, more than the memory bound" in err
    assert time.perf_counter() - started < 10.0
    assert not (tmp_path / "f.parquet").exists()


@pytest.mark.parametrize("setting", ["field.length_m=1e6", "field.width_m=1e5"])
def test_run_refuses_a_field_past_its_memory_bound(cli, tmp_path, setting):
    started = time.perf_counter()
    code, _, err = cli("run", "examples/reference.toml", "--set", setting, "--out", tmp_path / "o", "-q")
    assert code == 2, err
    assert "field.length_m/field.width_m" in err and "simulation.max_pieces" in err
    assert time.perf_counter() - started < 20.0
    assert not (tmp_path / "o").exists()


def test_a_short_time_bound_refuses_a_field_too_slow_to_place():
    with pytest.raises(InputError, match=r"simulation.max_wall_s \(1 s\)"):
        generate_field(
            get_observation(OBS),
            20_000.0,
            100.0,
            np.random.default_rng(1),
            budget=FieldBudget.of_run(None, 1.0, 20_000.0),
        )


def _file_field(path, centres, radius_m, domain):
    polygons = shapely.buffer(shapely.points(np.asarray(centres, dtype=float)), radius_m)
    n = len(polygons)
    save_field(
        FloeField(
            polygons=polygons,
            thickness_m=np.ones(n),
            diameter_class_m=np.full(n, 2 * radius_m),
            floe_id=np.arange(n),
            domain_m=domain,
        ),
        path,
    )


def _run_file(cli, tmp_path, name):
    scenario = tmp_path / "s.toml"
    scenario.write_text(f'[field]\nfile = "{name}"\n', encoding="utf-8")
    started = time.perf_counter()
    code, _, err = cli("run", scenario, "--out", tmp_path / "out", "--quiet")
    assert time.perf_counter() - started < 30.0
    assert not (tmp_path / "out").exists()
    return code, err


def test_a_file_with_a_floe_larger_than_the_largest_class_is_refused(cli, tmp_path):
    _file_field(tmp_path / "huge.parquet", [[5.0e6, 0.0]], 5.0e6, (0.0, -5e6, 1e7, 5e6))  # 1e7 m across
    code, err = _run_file(cli, tmp_path, "huge.parquet")
    assert code == 2, err
    assert "huge.parquet', row 1, column 'geometry'" in err and f"{MAX_FLOE_SIZE_M:g} m" in err


def test_a_file_whose_only_floe_on_the_path_is_far_ahead_is_refused(cli, tmp_path):
    _file_field(tmp_path / "far.parquet", [[1.0e7, 0.0]], 4.0, (1.0e7 - 10.0, -10.0, 1.0e7 + 10.0, 10.0))
    code, err = _run_file(cli, tmp_path, "far.parquet")
    assert code == 2, err
    assert "far.parquet" in err and "row 1" in err
    assert f"farther than the longest transit ({MAX_TRANSIT_M:g} m" in err
