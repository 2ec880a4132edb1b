"""Regression tests: what a user types must not crash the program, exhaust the machine or lose a
result. Each test is one failure a campaign found (bad numbers, environment errors, Ctrl-C,
memory on thin ice); the fuzz harness (`floebreak.testing.fuzz`, `make fuzz`) keeps looking for more. The
cases that are one command line and its exit code and message (a pseudo file system, a full disk, a bow
CSV's bad row, an unknown figure format, the piece budget, …) are rows of tests/test_bad_inputs.py."""

from __future__ import annotations

import errno
import importlib
import re
import sys
from pathlib import Path

import numpy as np
import pytest

import floebreak
from floebreak.config.scenario import json_schema
from floebreak.engine.loop import PieceBudgetError
from floebreak.errors import InputError
from floebreak.io.storage import StorageError, probe_directory

SMALL = ["field.length_m=60.0"]


def _scenario(tmp_path: Path, text: str = "[field]\nlength_m = 60.0\n") -> str:
    path = tmp_path / "s.toml"
    path.write_text(text, encoding="utf-8")
    return str(path)


# --- inputs: non-finite and absurd numbers ---------------------------------------

ISSUE_INPUTS = [
    ("ice.youngs_modulus_pa=inf", "ice.youngs_modulus_pa"),
    ("ship.x_start_m=nan", "ship.x_start_m"),
    ("ice.crushing_strength_pa=inf", "ice.crushing_strength_pa"),
    ("field.length_m=inf", "field.length_m"),
    ("ice.thickness_range_m=[1e-9, 1e9]", "ice.thickness_range_m[0]"),
    ("ice.fracture_toughness_pa_sqrt_m=inf", "ice.fracture_toughness_pa_sqrt_m"),
    ("ship.step_m=inf", "ship.step_m"),
    ("failure.bending.kashtelyan_coefficient=inf", "failure.bending.kashtelyan_coefficient"),
    ("failure.cracking.total_porosity_ppt=nan", "failure.cracking.total_porosity_ppt"),
]


@pytest.mark.parametrize(("override", "key"), ISSUE_INPUTS, ids=[i[1] for i in ISSUE_INPUTS])
def test_non_finite_or_absurd_numbers_exit_2_naming_the_key(tmp_path, override, key, cli):
    out = tmp_path / "out"
    code, _, err = cli("run", _scenario(tmp_path), "--out", str(out), "--set", override)
    assert code == 2, err
    assert err.strip().startswith(f"error: {key}:") and err.strip().count("\n") == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


def test_schema_states_the_ranges():
    schema = floebreak.Scenario.model_json_schema()
    ice = schema["$defs"]["IceSection"]["properties"]
    thickness = next(option for option in ice["thickness_m"]["anyOf"] if option.get("type") == "number")
    assert thickness["minimum"] == 0.01 and thickness["maximum"] == 10.0
    assert ice["youngs_modulus_pa"]["minimum"] > 0 and np.isfinite(ice["youngs_modulus_pa"]["maximum"])


# every number of a scenario file as `floebreak schema` states it (JSON schema walked, $refs followed)
def _schema_numbers(node, defs, path=()):
    if "$ref" in node:
        node = defs[node["$ref"].rsplit("/", 1)[-1]]
    for option in node.get("anyOf", []):
        yield from _schema_numbers(option, defs, path)
    if node.get("type") in ("number", "integer"):
        yield ".".join(path), node
    for name, child in node.get("properties", {}).items():
        yield from _schema_numbers(child, defs, (*path, name))
    for key, child in (("[]", node.get("items")), ("*", node.get("additionalProperties"))):
        if isinstance(child, dict):
            yield from _schema_numbers(child, defs, (*path, key))
    for i, child in enumerate(node.get("prefixItems", [])):
        yield from _schema_numbers(child, defs, (*path, f"[{i}]"))


SCHEMA = json_schema()
# [ice_motion] is range-checked by its settings dataclass (`validated_ice_motion`, tests/dynamics), whose
# positive coefficients have no upper bound; the schema lists them for `floebreak schema`
NUMBERS = [
    (key, node) for key, node in _schema_numbers(SCHEMA, SCHEMA["$defs"]) if not key.startswith("ice_motion.")
]
# ship.hull_parameters is a table of keyword overrides of any name: each is range-checked by the hull
# (test_new_upper_bounds_exit_2 below), so the schema gives the names and ranges in its description only
FREE = ("ship.hull_parameters.*",)


def test_every_number_of_the_schema_has_a_range():
    def bounded(node):
        return {"minimum", "exclusiveMinimum"} & set(node) and {"maximum", "exclusiveMaximum"} & set(node)

    assert len(NUMBERS) > 30  # the walk found the sections, the failure modes' tables included
    assert [key for key, node in NUMBERS if key not in FREE and not bounded(node)] == []


def _edges(node):
    low = node.get("minimum", node.get("exclusiveMinimum"))
    high = node.get("maximum", node.get("exclusiveMaximum"))
    below, above = low - (abs(low) or 1), high + (abs(high) or 1)
    return [below, above] if node["type"] == "number" else [int(below), int(above)]


# one key a scalar can be --set to (list items, tuple items and the free table are tested by hand)
SCALARS = [
    (key, value)
    for key, node in NUMBERS
    if "[" not in key and "*" not in key
    for value in _edges(node)
    if abs(value) < 2**63  # TOML integers are 64 bit: a seed of 2⁶³ cannot even be written
]


@pytest.mark.parametrize(("key", "value"), SCALARS, ids=[f"{k}={v:g}" for k, v in SCALARS])
def test_a_number_beyond_its_stated_range_exits_2_naming_key_and_range(tmp_path, key, value, cli):
    out = str(tmp_path / "out")
    code, _, err = cli("run", _scenario(tmp_path), "--out", out, "--set", f"{key}={value!r}")
    assert code == 2, err
    assert err.startswith(f"error: {key}:") and "allowed: " in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


# the bounds added to the failure modes' settings, the ship, the propellers and the hull (physical ranges:
# see each field's description), by hand
NEW_BOUNDS = [
    ("failure.bending.wedge_angle_deg=61.0", "failure.bending.wedge_angle_deg"),
    ("failure.wedge_angle_deg=0.0", "failure.wedge_angle_deg"),  # the flat spelling
    ("failure.bending.kashtelyan_coefficient=11.0", "failure.bending.kashtelyan_coefficient"),
    ("failure.bending.foundation_modulus_n_m3=-5.0", "failure.bending.foundation_modulus_n_m3"),
    ("failure.bending.foundation_modulus_n_m3=1e6", "failure.bending.foundation_modulus_n_m3"),
    ("failure.cracking.total_porosity_ppt=1001.0", "failure.cracking.total_porosity_ppt"),
    ("failure.cracking.tip_angle_deg=180.0", "failure.cracking.tip_angle_deg"),
    ("failure.cracking.wedge_friction=2.5", "failure.cracking.wedge_friction"),
    ("failure.next_crack_angle_deg=91.0", "failure.next_crack_angle_deg"),
    ("ship.speed_m_s=25.0", "ship.speed_m_s"),
    ("propeller.count=9", "propeller.count"),
    ("ship.hull_parameters.beam_m=150.0", "ship.hull_parameters.beam_m"),
    ("ship.hull_parameters.midbody_length_m=1000.0", "ship.hull_parameters.midbody_length_m"),
    ("ship.hull_parameters.shape_exponent=11.0", "ship.hull_parameters.shape_exponent"),
    ("ship.hull_parameters.n_panels_per_side=5000", "ship.hull_parameters.n_panels_per_side"),
]


@pytest.mark.parametrize(("override", "key"), NEW_BOUNDS, ids=[o for o, _ in NEW_BOUNDS])
def test_new_upper_bounds_exit_2(tmp_path, override, key, cli):
    code, _, err = cli("run", _scenario(tmp_path), "--out", str(tmp_path / "out"), "--set", override)
    assert code == 2, err
    assert err.strip().startswith(f"error: {key}:") and re.search(r"[\[(]-?[\d.e+]+, [\d.e+]+[\])]", err), err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


@pytest.mark.parametrize("line", ["n_fields = 0", "n_fields = 10001", "root_seed = -1"])
def test_study_numbers_beyond_their_range_exit_2(tmp_path, line, cli):
    study = tmp_path / "study.toml"
    study.write_text(f'name = "s"\n{line}\n[base.field]\nlength_m = 50.0\n', encoding="utf-8")
    code, _, err = cli("study", str(study), "--out", str(tmp_path / "out"), "--workers", "1")
    assert code == 2 and err.startswith(f"error: {line.split()[0]}:") and "allowed: " in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.toml"]


VOYAGE_OPTIONS = [("--speed-m-s", "25"), ("--max-length-m", "1e7"), ("--n-fields", "0")]


@pytest.mark.parametrize(("option", "value"), VOYAGE_OPTIONS)
def test_voyage_options_beyond_their_range_exit_2(tmp_path, option, value, cli):
    header = "start_utc,end_utc,concentration_percent,mean_thickness_m,share_d5m_percent,share_d20m_percent"
    (tmp_path / "log.csv").write_text(f"{header}\n2020-01-01T00:00,2020-01-01T00:10,50,0.5,60,40\n", "utf-8")
    code, _, err = cli("voyage", tmp_path / "log.csv", "--out", tmp_path / "v", "--workers", 1, option, value)
    assert code == 2 and err.startswith(f"error: {option[2:].replace('-', '_')}:"), err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["log.csv"]


# --- memory: the piece budget and lineage (failure 1) --------------------------------------------------


def test_piece_budget_error_from_the_python_api():
    with pytest.raises(PieceBudgetError) as info:
        floebreak.run(overrides=[*SMALL, "simulation.max_pieces=40"])
    assert info.value.field == "simulation.max_pieces"


def test_a_generated_field_over_the_budget_is_refused_before_it_is_placed():
    # 1000 km × 10 km of the reference observation: ≈ 4.9e7 floes (c·A / Ā, thesis §2.1), never generated
    with pytest.raises(InputError) as info:
        floebreak.run(overrides=["field.length_m=1e6", "field.width_m=1e4"])
    assert info.value.field == "simulation.max_pieces"


def test_an_inline_field_over_the_budget_is_refused():
    floes = (
        "[" + ", ".join(f"{{x_m = {20.0 + 3.0 * i}, y_m = 0.0, diameter_m = 2.0}}" for i in range(5)) + "]"
    )
    scenario = floebreak.Scenario.from_toml_text(
        f"[field]\nfloes = {floes}\n[ice]\nthickness_m = 1.0\n[simulation]\nmax_pieces = 4\n"
    )
    with pytest.raises(InputError) as info:
        floebreak.run(scenario)
    assert info.value.field == "simulation.max_pieces" and "5 floes" in str(info.value)


def test_failure_chain_is_rebuilt_from_parent_ids():
    """Lineage is stored once (parent ids + the mode that ended each piece): a cusp's chain has one entry per
    ancestor, each the mode that broke it, and the modes of all broken pieces add up to the break counters."""
    result = floebreak.run(overrides=SMALL)
    sim = result.simulation
    broken = sim.fate == "broken"
    modes, counts = np.unique(sim.ended_by[broken].astype(str), return_counts=True)
    by_mode = dict(zip(modes.tolist(), counts.tolist(), strict=True))
    whole = (sim.fate != "broken") & (sim.ended_by != "")
    assert sum(by_mode.values()) == sim.n_breaks
    assert sum(by_mode.values()) + int(whole.sum()) == sum(sim.breaks_by_mode.values())
    for i in np.flatnonzero(sim.fate == "cusp")[:50]:
        depth, parent = 0, int(sim.parent_piece_id[i])
        while parent >= 0:
            depth, parent = depth + 1, int(sim.parent_piece_id[parent])
        chain = sim.failure_chain(int(i))
        assert len(chain) == depth + (1 if sim.ended_by[i] else 0)
        assert chain[-1] == result.cusps["failure_mode"][list(result.cusps["piece_id"]).index(i)]


# --- environment and interruption (failure 4) ----------------------------------------------------------


def test_probe_reports_the_os_error(tmp_path, monkeypatch):
    def refuse(*args, **kwargs):
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr("tempfile.mkstemp", refuse)
    with pytest.raises(StorageError) as info:
        probe_directory(tmp_path, tmp_path / "out")
    assert info.value.errno == errno.EROFS and "Read-only file system" in str(info.value)


@pytest.mark.parametrize("inside_kernel", [False, True])
def test_ctrl_c_exits_130_with_one_line_and_no_failed_scenario(tmp_path, monkeypatch, inside_kernel, cli):
    api = importlib.import_module("floebreak.app.run")

    def interrupted(*args, **kwargs):
        if not inside_kernel:
            raise KeyboardInterrupt
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as error:  # how numba reports it: a SystemError with the interrupt set
            raise SystemError(
                "CPUDispatcher(<function zone_rows>) returned a result with an exception set"
            ) from error

    monkeypatch.setattr(api, "simulate", interrupted)
    out = tmp_path / "out"
    code, _, err = cli("run", _scenario(tmp_path), "--out", str(out), "-q")
    assert code == 130 and err.strip().count("\n") == 0 and "interrupted" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


def _console_command() -> list[str]:
    """The console command `floebreak` as pip's generated script runs it: import the target of
    pyproject.toml's [project.scripts] and call it (read from the project, not from an installed copy)."""
    import tomllib

    pyproject = Path(__file__).resolve().parents[1] / "pyproject.toml"
    target = tomllib.loads(pyproject.read_text(encoding="utf-8"))["project"]["scripts"]["floebreak"]
    module, function = target.split(":")
    return [sys.executable, "-c", f"import sys; from {module} import {function}; sys.exit({function}())"]


@pytest.mark.skipif(not Path("/proc/self/maps").exists(), reason="reads /proc/<pid>/maps (Linux)")
def test_ctrl_c_while_the_command_line_loads_exits_130_with_one_line(tmp_path):
    """SIGINT as soon as the console command imports the command line's libraries (numpy's core is mapped
    into the process: `import floebreak` alone loads no numpy) — before typer, rich and the engine are in."""
    import signal
    import subprocess
    import time

    out = tmp_path / "out"
    command = [*_console_command(), "run", _scenario(tmp_path), "--out", str(out), "--quiet"]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    maps = Path(f"/proc/{process.pid}/maps")
    deadline = time.monotonic() + 120.0  # generous: a loaded machine; the poll itself does not sleep
    try:
        while "_multiarray_umath" not in maps.read_text():
            assert process.poll() is None and time.monotonic() < deadline, "never started loading"
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=120)
    finally:
        process.kill()
    assert process.returncode == 130, err
    assert err == "interrupted (Ctrl-C); nothing half-written was kept\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


# --- exact geometry (failure 2) ------------------------------------------------------------------------

# a crescent 0.7 mm wide between two bending arcs (from the issue's AreaBalanceError case, seed 9 below),
# bow frame; moved to the field frame at bow x = 179.0814 m its ends cross within rounding
CRESCENT_XY_M = [
    (-8.344472466178557, -12.292066799138839),
    (-8.380454579083722, -12.26954830937957),
    (-8.392388385519642, -12.262079840289811),
    (-8.400693662717273, -12.256882193892121),
    (-8.401842405106285, -12.256163282698909),
    (-8.563515984523598, -12.154983986973587),
    (-8.748865863824488, -12.038987481434297),
    (-9.783753258001948, -11.258029162148434),
    (-10.746637590831192, -10.389846245545488),
    (-11.63019073113394, -9.441046127843986),
    (-12.427688306008504, -8.418849750840819),
    (-12.656569500259831, -8.065873220953558),
    (-12.656643497194652, -8.065148819620664),
    (-12.42702231659368, -8.41926654336929),
    (-11.629524741719116, -9.441462920372457),
    (-10.745971601416368, -10.39026303807396),
    (-9.783087268587124, -11.258445954676905),
    (-8.748199874409664, -12.039404273962768),
    (-8.341065077721355, -12.294199226500222),
]


def test_a_crescent_made_invalid_by_translation_keeps_its_area():
    import shapely

    from floebreak.engine.loop import _translate_pieces

    crescent = shapely.Polygon(CRESCENT_XY_M)
    assert crescent.is_valid
    moved = _translate_pieces(np.array([crescent], dtype=object), 179.0814)[0]
    assert moved.is_valid
    # the shoelace area of the given ring, independent of the engine
    x, y = np.array(CRESCENT_XY_M).T
    shoelace = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    assert moved.area == pytest.approx(shoelace, rel=1e-9)


@pytest.mark.parametrize("seed", [2, 9, 11])
def test_issue_area_balance_case_conserves_area_with_valid_pieces(seed):
    """Thesis profile, voronoi, Polarstern, obs 2019-12-19T04:40, 3 floes in 264 m × 256 m, h = 0.7028 m,
    step 1.8462 m, flexural_stress, BZ2: seed 9 raised AreaBalanceError (1.9e-8), seeds 2, 11 lost 2.5e-11."""
    import shapely

    scenario = floebreak.Scenario.from_toml_text(
        'profile = "thesis"\n[field]\nobservation = "2019-12-19T04:40"\nlength_m = 264.0\nwidth_m = 256.0\n'
        'generator = "voronoi"\n[ice]\nthickness_m = 0.7028\n[ship]\nhull = "polarstern"\nstep_m = 1.8462\n'
        '[failure]\ncrack_criterion = "flexural_stress"\nsize_effect_law = "BZ2"\n',
        overrides=[f"seed={seed}"],
    )
    result = floebreak.run(scenario)
    assert result.summary["area_balance_rel_error"] <= 1e-12
    for table in (result.cusps, result.flipped, result.remaining, result.pieces):
        assert shapely.is_valid(np.asarray(table["geometry"], dtype=object)).all()


# --- the field command and CSV errors (failure 7) ------------------------------------------------------


def test_field_refuses_an_existing_output_without_overwrite(tmp_path, cli):
    out = tmp_path / "f.parquet"
    out.write_bytes(b"keep me")
    args = ("field", "--out", str(out), "--obs", "2019-12-18T20:20", "--length", "60")
    code, _, err = cli(*args)
    assert code == 2 and "error: out:" in err and "--overwrite" in err and out.read_bytes() == b"keep me"
    code, _, err = cli(*args, "--overwrite")
    assert code == 0, err
    assert out.read_bytes()[:4] == b"PAR1"


@pytest.mark.parametrize(("option", "value"), [("--length", "inf"), ("--thickness", "nan")])
def test_field_refuses_non_finite_numbers(tmp_path, option, value, cli):
    args = ("field", "--out", str(tmp_path / "f.parquet"), "--obs", "2019-12-18T20:20", option, value)
    code, _, err = cli(*args)
    assert code == 2 and f"error: {option.lstrip('-')}:" in err and "finite" in err
    assert list(tmp_path.iterdir()) == []


# --- scale (failure 7) ---------------------------------------------------------------------------------


def test_field_generation_reports_progress_and_the_field_is_unchanged():
    import shapely

    from floebreak.ice.generation import generate_field
    from floebreak.ice.observations import get_observation

    calls = []
    observation = get_observation("2019-12-18T20:20")
    args = (observation, 200.0, 50.0)
    quiet = generate_field(*args, np.random.default_rng(3))
    told = generate_field(*args, np.random.default_rng(3), progress=lambda *a: calls.append(a))
    assert shapely.equals_exact(quiet.polygons, told.polygons, tolerance=0.0).all()
    assert calls[0][0].startswith(f"placing {quiet.n_floes:,} floes") and calls[-1][0].endswith("placed")
    rounds = [(done, most) for stage, done, most in calls[1:-1]]
    assert rounds and all(0 < done <= most for done, most in rounds)
    assert [done for done, _ in rounds] == list(range(1, len(rounds) + 1))


def test_ten_thousand_inline_floes_are_checked_for_overlap_by_index():
    """10 000 floes in a grid (3 m apart, 2 m wide): no overlap; one moved onto its neighbour: named."""
    from floebreak import api

    floes = [
        {"x_m": 20.0 + 3.0 * (i // 50), "y_m": -75.0 + 3.0 * (i % 50), "diameter_m": 2.0}
        for i in range(10_000)
    ]
    scenario = floebreak.Scenario.from_dict({"field": {"floes": floes}, "ice": {"thickness_m": 1.0}})
    assert api.build_field(scenario, np.random.default_rng(1)).n_floes == 10_000
    floes[777] = {**floes[776], "y_m": floes[776]["y_m"] + 1.0}
    scenario = floebreak.Scenario.from_dict({"field": {"floes": floes}, "ice": {"thickness_m": 1.0}})
    with pytest.raises(InputError) as info:
        api.build_field(scenario, np.random.default_rng(1))
    assert info.value.field == "field.floes[777]" and "field.floes[776]" in str(info.value)


def test_failure_chain_from_the_written_pieces_file(tmp_path):
    import pyarrow.parquet as pq

    from floebreak.engine.records import failure_chain

    result = floebreak.run(overrides=SMALL)
    result.write(tmp_path / "run", figures=False, report=False)
    table = pq.read_table(
        tmp_path / "run" / "pieces.parquet", columns=["piece_id", "parent_piece_id", "ended_by"]
    )
    columns = {name: table.column(name).to_numpy(zero_copy_only=False) for name in table.column_names}
    cusps = np.flatnonzero(result.simulation.fate == "cusp")
    assert cusps.size
    for i in cusps[:: max(1, cusps.size // 20)]:
        assert failure_chain(columns, int(i)) == ">".join(result.simulation.failure_chain(int(i)))
        assert failure_chain(columns, int(i))  # a cusp was made by a break or a rotation
