"""Fuzz campaign: random valid scenarios over the options and the edges of the ranges, each run checked.

``python -m fuzz --n 5000 --seed 1 --jobs 2 --out fuzz-report`` (or ``make fuzz N=5000 SEED=1``)
draws `n` whole scenarios with hypothesis (`scenario_dicts`), runs each through `floebreak.run` in worker
processes and checks: no internal error (an `InputError` is a refusal, allowed), the area balance
(≤ `AREA_TOLERANCE`), every output polygon valid (`shapely.is_valid`), and each run's peak resident memory
(≤ `--max-rss-mb`). Each run's record is appended to ``records.jsonl`` in ``--out`` as it completes
(``--resume`` continues a stopped campaign with the scenarios kept in ``scenarios.jsonl``, ``--resume
--retry`` also runs the flagged ones again, ``--summarize`` rebuilds ``summary.json`` from the records);
each violation's scenario is saved there as TOML with its traceback (with the files it names beside it).
Warnings a run raises are kept in its record. SIGTERM or Ctrl-C stops the campaign and its workers (the
records so far are kept). The test suite runs a small fixed sample (tests/test_fuzz.py); the campaign is
the documented command (benchmarks/README.md, fuzz). ``--generator adversarial`` draws hostile field files,
bow CSVs and policies instead (`fuzz.adversarial`); ``make fuzz`` runs both. A run longer than
``--max-seconds`` (120 s) is flagged; every drawn scenario has the wall-time budget `MAX_WALL_S`.

Ranges are those of the code, each from its one place: the scenario's sections (their pydantic schema), the
failure modes' `Bounds`, the parametric hull's `floebreak.ship.hulls.HULL_PARAMETER_BOUNDS`, the bow reader's
`floebreak.ship.bow.FRAME_ANGLE_DEG`. To keep a run to about a second of CPU on average (5 000 runs in well
under an hour on 2 shared cores), a run's cost is capped where it grows without exercising another code
path: fields are at most 100 m × 100 m (a bow is 20–25 m wide), the thinnest ice (< 0.1 m, which breaks
into thousands of pieces: ≈ 8 ms each) gets 10 m of transit, a run at most `MAX_STEPS` steps (short steps
a short transit: 0.5 m at 1 mm; a bow from parameters or a file always ends there, as its length is not
known when drawn) and a budget of `MAX_PIECES` pieces (a run that reaches it is a refusal, exit 2, as for a
user); the ``sqp`` generator (SLSQP over all floe pairs: 150 floes take ≈ 1 min, benchmarks/README.md)
gets fields shrunk to about `SQP_MAX_FLOES` floes. The caps leave the options and range edges drawn as
they were.

Drawn: the profile; the field (observation, user observation, inline floes or a field file; generator
circles, voronoi or sqp, cover, clustering); every [ice] number; the ship (a built-in hull, one with
``hull_parameters`` or a bow CSV file; step, waterlines, initial contact, speed); the flat [failure] keys,
any setting of every registered mode's ``[failure.<mode>]`` table (numbers within their `Bounds`, choices
among their `Literal` values) and the dispatch policy ``[failure.policy]`` (per failure class a list of
registered modes — any order, repeats, 1 to 4 — or a table of such lists per bow region, or an empty one);
the [propeller] section (validated with the scenario; `floebreak.run` does not read it, the propeller
analysis does). A bow CSV file is drawn as its text (a built-in hull's waterlines with drawn parameters,
scaled, in either format, with the variants the reader accepts: `_bow_csv`), a field file as a recipe (a
generated field saved by `floebreak.output.field_files.save_field`, or without floebreak's domain metadata);
both travel in the drawn record under `FILES`, not in the scenario, and `check_one` writes them into a
temporary folder that the scenario's relative paths name. Not drawn: invalid inputs (tests/test_bad_inputs.py
and the scenario's tests cover refusals).
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import functools
import importlib
import json
import math
import multiprocessing
import os
import pkgutil
import resource
import shutil
import signal
import sys
import tempfile
import time
import traceback
import typing
import warnings
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from pathlib import Path
from typing import Any, Literal

import numpy as np
from hypothesis import HealthCheck, Phase, given, seed, settings
from hypothesis import strategies as st

from floebreak.config import scenario as sc
from floebreak.config.profiles import field_switches
from floebreak.errors import Bounds, InputError, field_bounds
from floebreak.failure import BOW_REGIONS, FAILURE_CLASSES, get_mode, mode_names
from floebreak.ice.generation import floe_counts, generate_field
from floebreak.ice.observations import Observation, get_observation, thesis_observations
from floebreak.io.atomic import write_text_atomic
from floebreak.mechanics.fracture import wedge_splitting_fraction
from floebreak.ship import bow as bows
from floebreak.ship import hulls
from floebreak.ship.hulls import HULLS
from fuzz.limits import FILES, MAX_PIECES, MAX_WALL_S

AREA_TOLERANCE = 1e-9  # the engine's own (`floebreak.engine.loop.AREA_BALANCE_TOLERANCE`)
MAX_STEPS = 500
SQP_MAX_FLOES = 30  # the `sqp` generator's fields are shrunk to at most about this many floes (docstring)


def _edge_or_inside(low: float, high: float, log: bool = False) -> st.SearchStrategy[float]:
    """The range's edges, or a value inside it (log-uniform for ranges over decades)."""
    if log:
        inside = st.floats(math.log10(low), math.log10(high)).map(
            lambda e: float(min(max(10.0**e, low), high))
        )
    else:
        inside = st.floats(low, high, allow_nan=False, allow_infinity=False)
    return st.one_of(st.sampled_from([low, high]), inside, inside)


def _within(bounds: Bounds) -> st.SearchStrategy[float]:
    """A value of a `floebreak.errors.Bounds` interval: its edges (nudged inside where open) or inside it."""
    low = bounds.low if bounds.low_inclusive else math.nextafter(bounds.low, math.inf)
    high = bounds.high if bounds.high_inclusive else math.nextafter(bounds.high, -math.inf)
    return _edge_or_inside(low, high, log=low > 0 and high / low >= 100.0)


@functools.cache
def _schema_bounds(model: type, key: str) -> Bounds:
    """The interval of the number `key` of a scenario section, from its pydantic model's JSON schema (the
    one place the scenario states its ranges)."""
    node = model.model_json_schema()["properties"][key]
    node = next((option for option in node.get("anyOf", [node]) if option.get("type") != "null"), node)
    return Bounds(
        node.get("minimum", node.get("exclusiveMinimum")),
        node.get("maximum", node.get("exclusiveMaximum")),
        low_inclusive="minimum" in node,
        high_inclusive="maximum" in node,
    )


ICE_NUMBERS = (
    "fracture_toughness_pa_sqrt_m",
    "flexural_strength_pa",
    "crushing_strength_pa",
    "contact_coefficient",
    "friction_coefficient",
    "youngs_modulus_pa",
    "poisson_ratio",
)


def _ice() -> st.SearchStrategy[dict[str, Any]]:
    numbers = {key: _within(_schema_bounds(sc.IceSection, key)) for key in ICE_NUMBERS}
    thickness = _edge_or_inside(*sc.THICKNESS_M, log=True)
    return st.fixed_dictionaries({}, optional={"thickness_m": thickness, **numbers})


def _thickness_source(draw) -> dict[str, Any]:
    """``thickness_m`` or ``thickness_range_m`` (as in [ice]), or nothing."""
    kind = draw(st.sampled_from(["none", "fixed", "range"]))
    if kind == "fixed":
        return {"thickness_m": draw(_edge_or_inside(*sc.THICKNESS_M, log=True))}
    if kind == "range":
        low = draw(_edge_or_inside(*sc.THICKNESS_M, log=True))
        return {"thickness_range_m": [low, draw(_edge_or_inside(low, sc.THICKNESS_M[1], log=True))]}
    return {}


@st.composite
def _field(draw, profile: str) -> tuple[dict[str, Any], dict[str, Any]]:
    """The [field] section and the files it names (a field file's recipe, see `write_files`)."""
    source = draw(st.sampled_from(["observation", "observation", "user_observation", "floes", "file"]))
    if source == "floes":
        n = draw(st.integers(1, 6))
        floes, x = [], 5.0
        for _ in range(n):  # placed along x without overlap
            d = draw(_edge_or_inside(1.0, 40.0))
            y = draw(st.floats(-20.0, 20.0))
            floes.append({"x_m": x + d / 2, "y_m": y, "diameter_m": d})
            x += d + draw(st.floats(0.01, 10.0))
        return {"floes": floes}, {}
    field: dict[str, Any] = {
        "length_m": draw(_edge_or_inside(20.0, 100.0)),
        "width_m": draw(_edge_or_inside(20.0, 100.0)),
        "generator": draw(st.sampled_from(["circles", "voronoi", "circles", "voronoi", "sqp"])),
    }
    if source in ("observation", "file"):
        field["observation"] = draw(st.sampled_from(list(thesis_observations())))
    else:
        k = draw(st.integers(1, 3))
        field["diameter_classes_m"] = sorted(
            draw(st.lists(_edge_or_inside(1.0, 30.0), min_size=k, max_size=k, unique=True))
        )
        shares = draw(st.lists(st.integers(1, 10), min_size=k, max_size=k))
        field["percentages"] = [100.0 * s / sum(shares) for s in shares]
        field["concentration"] = draw(_edge_or_inside(0.05, 0.9))
    if draw(st.booleans()):
        field["concentration"] = draw(_edge_or_inside(0.05, 1.0))
    if draw(st.booleans()):
        field["clustering"] = draw(_edge_or_inside(0.0, 10.0))
    if field["generator"] == "sqp":
        field.update(_sqp_size(field, profile))
    if source != "file":
        return field, {}
    recipe = {
        **{key: field.pop(key) for key in ("observation", "length_m", "width_m", "generator")},
        "concentration": field.pop("concentration", None),
        "clustering": field.pop("clustering", 0.05),
        "seed": draw(st.integers(0, 2**32 - 1)),
        "domain_metadata": draw(st.booleans()),  # False: a file of another tool (domain inferred, a warning)
        **_thickness_source(draw),
    }
    return {"file": "field.parquet"}, {"field.parquet": {"field": recipe}}


def _sqp_size(field: dict[str, Any], profile: str) -> dict[str, float]:
    """`field`'s length and width shrunk (same aspect) to hold about `SQP_MAX_FLOES` floes at most
    (`floebreak.ice.generation.floe_counts`): SLSQP's constraints are all n(n − 1)/2 floe pairs."""
    try:
        if "observation" in field:
            observation = get_observation(field["observation"])
            if "concentration" in field:
                observation = dataclasses.replace(observation, concentration=field["concentration"])
        else:
            observation = Observation(
                field["concentration"], 1.0, tuple(field["diameter_classes_m"]), tuple(field["percentages"])
            )
        area = field["length_m"] * field["width_m"]
        total = floe_counts(observation, area, field_switches(profile).floe_area_factor).total
    except InputError:  # refused later by the scenario's own checks
        return {}
    shrink = min(1.0, math.sqrt(SQP_MAX_FLOES / total))
    return {"length_m": field["length_m"] * shrink, "width_m": field["width_m"] * shrink}


@st.composite
def _mode_tables(draw, drawn_flat: set[tuple[str, str]]) -> dict[str, dict[str, Any]]:
    """``[failure.<mode>]`` tables: some settings of every registered mode, each number within its `Bounds`
    and each choice among its `Literal` values (settings given by a flat [failure] key are left out)."""
    tables: dict[str, dict[str, Any]] = {}
    for name in mode_names():
        spec = get_mode(name)
        if spec.settings is None:
            continue
        bounds = field_bounds(spec.settings)
        hints = typing.get_type_hints(spec.settings)
        for key in spec.table_keys():
            if (name, key) in drawn_flat or not draw(st.booleans()):
                continue
            choices = typing.get_args(hints[key]) if typing.get_origin(hints[key]) is Literal else ()
            if key in bounds:
                tables.setdefault(name, {})[key] = draw(_within(bounds[key]))
            elif choices:
                tables.setdefault(name, {})[key] = draw(st.sampled_from(choices))
            elif hints[key] is bool:
                tables.setdefault(name, {})[key] = draw(st.booleans())
    return tables


def _unlock_the_wedge(failure: dict[str, Any]) -> None:
    """Drop a drawn ``cracking.wedge_friction`` that makes the line load's wedge self-locking with the tip
    angle (μ tan(α/2) ≥ 1, `floebreak.mechanics.fracture.wedge_splitting_fraction`): the scenario would be
    refused when read (its test: tests/failure/test_cracking.py), and the default μ = 0 runs instead."""
    cracking = failure.get("cracking", {})
    if failure.get("crack_criterion") != "line_load" or "wedge_friction" not in cracking:
        return
    defaults = {item.name: item.default for item in dataclasses.fields(get_mode("cracking").settings)}
    try:
        wedge_splitting_fraction(
            cracking.get("tip_angle_deg", defaults["tip_angle_deg"]), cracking["wedge_friction"]
        )
    except InputError:
        del cracking["wedge_friction"]


@st.composite
def _policy(draw) -> dict[str, Any]:
    """``[failure.policy]``: for some failure classes a list of registered modes (any order, repeats, 1 to 4
    of them) for both bow regions, or a table of such lists for some regions (none: the default stays)."""
    modes = st.lists(st.sampled_from(mode_names()), min_size=1, max_size=4)
    regions = st.dictionaries(st.sampled_from(BOW_REGIONS), modes, max_size=len(BOW_REGIONS))
    return draw(
        st.dictionaries(
            st.sampled_from(FAILURE_CLASSES), st.one_of(modes, regions), max_size=len(FAILURE_CLASSES)
        )
    )


@st.composite
def _hull_parameters(draw) -> dict[str, Any]:
    """Some keyword overrides of the parametric hull, each within `floebreak.ship.hulls`' ranges (the bow
    they make may still be refused, e.g. a waterline crossing itself)."""
    numbers = [key for key in hulls.HULL_PARAMETER_BOUNDS if key != "ice_thickness_m"]  # the waterlines'
    parameters: dict[str, Any] = {}
    for key in draw(st.lists(st.sampled_from(numbers), max_size=4, unique=True)):
        parameters[key] = draw(_within(hulls.HULL_PARAMETER_BOUNDS[key]))
    if draw(st.booleans()):
        low, high = hulls.N_PANELS_PER_SIDE_RANGE
        parameters["n_panels_per_side"] = draw(
            st.one_of(st.sampled_from([low, high]), st.integers(low, high))
        )
    if draw(st.booleans()):
        parameters["stem_angle_interpretation"] = draw(st.sampled_from(hulls.STEM_ANGLE_INTERPRETATIONS))
    if draw(st.integers(0, 9)) == 0:
        parameters["name"] = draw(st.sampled_from(["fuzz", "Ω bow"]))
    return parameters


@st.composite
def _bow_csv(draw) -> str:
    """The text of a bow CSV file (`floebreak.ship.bow.Bow.from_csv`): a built-in hull's waterlines (with
    drawn hull parameters) scaled along x and y, in format (a) ``line,x_m,y_m`` or (b) stations with drawn
    frame angles; with what the reader accepts: columns in any order, padding, upper/lower in any case,
    comments and blank lines, CRLF line ends, rounded numbers, heights as z_upper_m/z_lower_m or
    ice_thickness_m (or none: 1 m, format b)."""
    hull = draw(st.sampled_from(list(HULLS)))
    thickness = draw(_edge_or_inside(*sc.THICKNESS_M, log=True))
    try:
        bow = HULLS[hull](ice_thickness_m=thickness, **draw(_hull_parameters()))
    except InputError:
        bow = HULLS[hull](ice_thickness_m=thickness)
    scale = np.array([draw(st.floats(0.5, 2.0)), draw(st.floats(0.5, 2.0))])
    digits = draw(st.sampled_from([None, None, 3, 6]))
    number = repr if digits is None else (lambda v: f"{v:.{digits}f}")
    pad = draw(st.sampled_from(["", " "]))
    lines = ["# bow drawn by fuzz", f"# name = {hull} scaled", "# note = ignored key"]
    stations = draw(st.booleans())
    heights = draw(st.sampled_from(["z", "thickness"] + (["none"] if stations else [])))
    if heights == "z":
        lines += [f"# z_upper_m = {bow.z_upper_m!r}", f"# z_lower_m = {bow.z_lower_m!r}"]
    elif heights == "thickness":
        lines.append(f"# ice_thickness_m = {bow.dz_m!r}")
    columns = list(draw(st.permutations(bows.STATIONS_COLUMNS if stations else bows.LINES_COLUMNS)))
    lines.append(",".join(f"{pad}{name}{pad}" for name in columns))
    if stations:
        port = bow.upper_xy_m[bow.stem_index :: -1] * scale  # stem → port aft
        stem, aft = draw(_within(bows.FRAME_ANGLE_DEG)), draw(_within(bows.FRAME_ANGLE_DEG))
        beta = np.linspace(stem, aft, len(port))
        rows = [
            {"x_m": x, "half_breadth_m": y, "frame_angle_deg": b}
            for (x, y), b in zip(port, beta, strict=True)
        ]
    else:
        case = draw(st.sampled_from([str.lower, str.upper, str.title]))
        rows = [
            {"line": case(line), "x_m": x, "y_m": y}
            for line, xy in (("upper", bow.upper_xy_m), ("lower", bow.lower_xy_m))
            for x, y in xy * scale
        ]
    between = set(draw(st.lists(st.integers(1, len(rows) - 1), max_size=2)))  # rows after a blank/comment
    for i, row in enumerate(rows):
        if i in between:
            lines.append(draw(st.sampled_from(["", "# a comment between rows"])))
        cells = (row[k] if isinstance(row[k], str) else number(float(row[k])) for k in columns)
        lines.append(",".join(f"{pad}{cell}{pad}" for cell in cells))
    return draw(st.sampled_from(["\n", "\r\n"])).join(lines) + "\n"


def _ship(draw) -> tuple[dict[str, Any], dict[str, Any]]:
    """The [ship] section and the files it names (a bow CSV file's text)."""
    ship: dict[str, Any] = {
        "step_m": draw(st.one_of(st.sampled_from([sc.STEP_M[0], sc.STEP_M[1]]), _edge_or_inside(0.05, 3.0))),
        "initial_contact": draw(st.sampled_from(["shift_field", "shift_floes"])),
    }
    files: dict[str, Any] = {}
    bow = draw(st.sampled_from(["hull", "hull", "parameters", "file"]))
    if bow == "file":
        ship["file"] = "bow.csv"
        files["bow.csv"] = {"text": draw(_bow_csv())}
    else:
        ship["hull"] = draw(st.sampled_from(list(HULLS)))
        if bow == "parameters":
            ship["hull_parameters"] = draw(_hull_parameters())
    if draw(st.booleans()):
        ship["waterlines"] = draw(st.sampled_from(["follow_thickness", "fixed"]))
        ship["waterline_ice_thickness_m"] = draw(_edge_or_inside(*sc.THICKNESS_M, log=True))
    if draw(st.booleans()):
        ship["speed_m_s"] = draw(_within(_schema_bounds(sc.ShipSection, "speed_m_s")))
    return ship, files


def _propeller(draw) -> dict[str, Any]:
    """The [propeller] section: validated with the scenario, read by the propeller analysis only."""
    fraction = _within(_schema_bounds(sc.PropellerSection, "fraction_reaching"))
    low, high = sc.PROPELLER_COUNT
    count = st.one_of(st.sampled_from([low, high]), st.integers(low, high))
    return draw(st.fixed_dictionaries({}, optional={"fraction_reaching": fraction, "count": count}))


def _thinnest_m(data: dict[str, Any], files: dict[str, Any]) -> float:
    """The thinnest ice a drawn scenario may hold (for its cost caps)."""
    for source in (data["ice"], files.get("field.parquet", {}).get("field", {})):
        if "thickness_m" in source or "thickness_range_m" in source:
            return source.get("thickness_m") or source["thickness_range_m"][0]
    key = data["field"].get("observation") or files.get("field.parquet", {}).get("field", {}).get(
        "observation"
    )
    return get_observation(key).mean_thickness_m if key else 1.0


@st.composite
def scenario_dicts(draw) -> dict[str, Any]:
    """A whole valid scenario (a dict as read from TOML); the files it names (a bow CSV file's text, a field
    file's recipe) under the key `FILES`, which `check_one` writes next to it."""
    profile = draw(st.sampled_from(["default", "thesis"]))
    field, field_files = draw(_field(profile))
    ship, ship_files = _ship(draw)
    data: dict[str, Any] = {
        "profile": profile,
        "seed": draw(st.integers(0, 2**31)),
        "field": field,
        "ice": draw(_ice()),
        "ship": ship,
        "failure": {
            "crack_criterion": draw(
                st.sampled_from(["point_load", "line_load", "tensile_stress", "flexural_stress"])
            ),
            "size_effect_law": draw(st.sampled_from(["BZ", "BZ1", "BZ2"])),
            "stress_mode": draw(st.sampled_from(["thesis", "strength", "sif"])),
            "wedge_angle_deg": draw(_edge_or_inside(1.0, 60.0)),
            "next_crack_angle_deg": draw(_edge_or_inside(0.0, 90.0)),
            "shoulder_region_start": draw(_edge_or_inside(0.0, 1.0)),
            "flip_uncracked_at_shoulder": draw(st.booleans()),
        },
        "simulation": {"max_pieces": MAX_PIECES, "max_wall_s": MAX_WALL_S},
    }
    flat = {sc.FLAT_FAILURE_KEYS[key] for key in data["failure"] if key in sc.FLAT_FAILURE_KEYS}
    data["failure"].update(draw(_mode_tables(flat)))
    _unlock_the_wedge(data["failure"])
    if draw(st.booleans()):
        data["failure"]["policy"] = draw(_policy())
    if draw(st.booleans()):
        data["propeller"] = _propeller(draw)
    if "thickness_m" not in data["ice"] and draw(st.booleans()):
        low = draw(_edge_or_inside(*sc.THICKNESS_M, log=True))
        data["ice"]["thickness_range_m"] = [low, draw(_edge_or_inside(low, sc.THICKNESS_M[1], log=True))]
    elif not {"observation", "file"} & set(field) and "thickness_m" not in data["ice"]:  # none observed
        data["ice"]["thickness_m"] = draw(_edge_or_inside(*sc.THICKNESS_M, log=True))
    files = {**field_files, **ship_files}
    transit_m = min(10.0 if _thinnest_m(data, files) < 0.1 else math.inf, MAX_STEPS * data["ship"]["step_m"])
    if (
        transit_m < 150.0 or "hull" not in ship or "hull_parameters" in ship
    ):  # else: the hull passes the field
        data["ship"]["x_end_m"] = transit_m
    if files:
        data[FILES] = files
    return data


def _import_every_module() -> None:
    """Import every floebreak module (once per process). Hypothesis mixes literal constants of the loaded
    modules of the project's own source into its draws (`hypothesis.internal.constants_ast`), so what was
    drawn depended on what the process had imported before (a test suite's order, a lazy import): with all of
    floebreak loaded, a seed gives the same scenarios in every process with the same floebreak source."""
    import floebreak

    for module in pkgutil.walk_packages(floebreak.__path__, "floebreak."):
        if not module.name.endswith(".__main__"):
            importlib.import_module(module.name)


GENERATORS = ("valid", "adversarial")  # `scenario_dicts`, `fuzz.adversarial.adversarial_dicts`


def _strategy(generator: str) -> st.SearchStrategy[dict[str, Any]]:
    if generator == "adversarial":
        from fuzz.adversarial import adversarial_dicts

        return adversarial_dicts()
    if generator != "valid":
        raise ValueError(f"unknown generator {generator!r} (one of {', '.join(GENERATORS)})")
    return scenario_dicts()


def draw_scenarios(n: int, campaign_seed: int, generator: str = "valid") -> list[dict[str, Any]]:
    """`n` scenarios drawn by hypothesis from `campaign_seed` with `generator` ("valid": `scenario_dicts`,
    "adversarial": `fuzz.adversarial.adversarial_dicts`; same seed and floebreak source → same
    scenarios; `_import_every_module`)."""
    _import_every_module()
    strategy = _strategy(generator)
    drawn: list[dict[str, Any]] = []

    @seed(campaign_seed)
    @settings(
        max_examples=n,
        phases=[Phase.generate],
        database=None,
        deadline=None,
        suppress_health_check=list(HealthCheck),
    )
    @given(strategy)
    def collect(data):
        drawn.append(data)

    collect()
    return drawn[:n]


def _peak_rss_reset() -> bool:
    """Reset this process's peak resident memory (Linux ``/proc/self/clear_refs``); False if unsupported."""
    try:
        Path("/proc/self/clear_refs").write_text("5")
    except OSError:
        return False
    return True


def _peak_rss_mb(reset: bool) -> float:
    """Peak resident memory in MB: of this run (``VmHWM`` after a reset), else of the process so far."""
    if reset:
        try:
            for line in Path("/proc/self/status").read_text().splitlines():
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024
        except OSError:
            pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def write_files(files: dict[str, Any], folder: Path) -> None:
    """Write the files a drawn scenario names into `folder`: ``{"text": ...}`` as it is (a bow CSV file),
    ``{"field": recipe}`` as a field file generated from the recipe (`floebreak.ice.generation
    .generate_field`, rng from the recipe's seed) and saved by `floebreak.output.field_files.save_field`, or,
    for ``domain_metadata = false``, without floebreak's domain metadata (as another tool writes it)."""
    from floebreak.io.geoparquet import write_geoparquet
    from floebreak.io.provenance import provenance
    from floebreak.output.field_files import field_columns, save_field

    for name, spec in files.items():
        if "text" in spec:
            (folder / name).write_bytes(spec["text"].encode("utf-8"))  # bytes: CRLF line ends kept
            continue
        if "adversarial_field" in spec:
            from fuzz.adversarial import write_field_file

            write_field_file(spec["adversarial_field"], folder / name)
            continue
        recipe = spec["field"]
        observation = get_observation(recipe["observation"])
        if recipe["concentration"] is not None:
            observation = dataclasses.replace(observation, concentration=recipe["concentration"])
        range_m = recipe.get("thickness_range_m")
        floe_field = generate_field(
            observation,
            recipe["length_m"],
            recipe["width_m"],
            np.random.default_rng(recipe["seed"]),
            generator=recipe["generator"],
            thickness_m=recipe.get("thickness_m"),
            thickness_range_m=None if range_m is None else tuple(range_m),
            clustering=recipe["clustering"],
            seed=recipe["seed"],
            max_floes=MAX_PIECES,
        )
        if recipe["domain_metadata"]:
            save_field(floe_field, folder / name)
        else:
            meta = provenance(kind="floe_field")
            write_geoparquet(folder / name, floe_field.polygons, field_columns(floe_field), meta)


def check_one(data: dict[str, Any]) -> dict[str, Any]:
    """Run one drawn scenario (its files written into a temporary folder, which its relative paths name) and
    check it; returns a JSON-able record (runs in a worker process)."""
    import shapely

    import floebreak

    scenario = {key: value for key, value in data.items() if key != FILES}
    files = data.get(FILES, {})
    reset = _peak_rss_reset()
    started, cpu = time.perf_counter(), time.process_time()
    record: dict[str, Any] = {"scenario": scenario, "status": "ok", "problems": []}
    if files:
        record["files"] = files
    with (
        tempfile.TemporaryDirectory(prefix="floebreak-fuzz-") as folder,
        warnings.catch_warnings(record=True) as seen,
    ):
        warnings.simplefilter("always")
        try:
            try:
                write_files(files, Path(folder))
            except InputError as error:  # the harness's field recipe, not the scenario, was refused
                raise InputError("fuzz field file recipe", str(error)) from None
            result = floebreak.run(sc.Scenario.from_dict(scenario, base_dir=folder))
        except InputError as error:
            record.update(status="refused", message=str(error))
        except Exception as error:  # everything else is what the campaign looks for
            record.update(status="crash", message="".join(traceback.format_exception(error)))
        else:
            balance = result.summary["area_balance_rel_error"]
            record["area_balance_rel_error"] = balance
            if not balance <= AREA_TOLERANCE:
                record["problems"].append(f"area balance {balance:.3e}")
            for name in ("cusps", "flipped", "remaining", "pieces"):
                geometry = np.asarray(getattr(result, name)["geometry"], dtype=object)
                invalid = int((~shapely.is_valid(geometry)).sum()) if geometry.size else 0
                if invalid:
                    record["problems"].append(f"{invalid} invalid polygons in {name}")
        # warnings are kept (e.g. numpy's invalid value: a sign of numbers the engine should not meet)
        shown = dict.fromkeys(f"{w.category.__name__}: {w.message}"[:300] for w in seen)
        if shown:
            record["warnings"] = list(shown)[:5]
    record["seconds"] = time.perf_counter() - started
    record["cpu_seconds"] = time.process_time() - cpu  # the run's own cost, whatever the host's load
    record["peak_rss_mb"] = _peak_rss_mb(reset)
    return record


WORKER_SCENARIOS = 100  # scenarios per fresh worker process (bounds what a leak could accumulate)


def _indexed(check: Callable[[dict[str, Any]], dict[str, Any]], index: int, data: dict[str, Any]):
    return {"index": index, **check(data)}


def _worker_signals() -> None:
    """In a worker process: SIGTERM's default action (not the parent's handler, inherited through fork), and
    Ctrl-C ignored (it reaches the whole process group; the parent stops its workers)."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _records(todo: list[tuple[int, dict[str, Any]]], jobs: int, check=check_one):
    """The `check` records of `todo` (index, scenario) in completion order, each with its ``index``: in this
    process (jobs = 0, the test suite's sample), else in `jobs` one-worker pools, each replaced by a fresh
    one after `WORKER_SCENARIOS` (not ``max_tasks_per_child``: Python 3.11's executor hangs when a worker
    retires). One task per worker at a time, so a slow scenario holds only its own worker. Stopped early
    (an error, Ctrl-C, SIGTERM via `exit_on_sigterm`, or closed by the caller), it terminates the worker
    processes it started: a pool's shutdown does not stop a running task."""
    if not jobs:
        yield from (_indexed(check, i, data) for i, data in todo)
        return
    pending = iter(todo)
    slots: dict[Future, tuple[ProcessPoolExecutor, int]] = {}
    others = set(multiprocessing.active_children())  # children of this process that are not our workers

    def submit(pool: ProcessPoolExecutor | None, done: int) -> None:
        task = next(pending, None)
        if pool is not None and (task is None or done >= WORKER_SCENARIOS):
            pool.shutdown()
            pool, done = None, 0
        if task is not None:
            pool = pool or ProcessPoolExecutor(max_workers=1, initializer=_worker_signals)
            slots[pool.submit(_indexed, check, *task)] = (pool, done + 1)

    try:
        for _ in range(jobs):
            submit(None, 0)
        while slots:
            finished, _ = wait(slots, return_when=FIRST_COMPLETED)
            for future in finished:
                pool, done = slots.pop(future)
                yield future.result()
                submit(pool, done)
    finally:
        if slots:
            _terminate(set(multiprocessing.active_children()) - others)
            for pool, _ in slots.values():
                pool.shutdown(wait=False, cancel_futures=True)


def _terminate(processes: set) -> None:
    """Stop `processes` (multiprocessing children): SIGTERM, then SIGKILL for one still alive after 10 s."""
    for process in processes:
        process.terminate()
    for process in processes:
        process.join(10.0)
        if process.is_alive():
            process.kill()
            process.join()


@contextlib.contextmanager
def exit_on_sigterm():
    """Within the block, SIGTERM raises ``SystemExit(143)`` (128 + SIGTERM, the shell's convention) in the
    main thread, so that the campaign unwinds like after Ctrl-C: `_records` terminates its workers."""

    def stop(signum: int, frame: Any) -> None:
        raise SystemExit(128 + signum)

    previous = signal.signal(signal.SIGTERM, stop)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _percentile(values: list[float], q: float) -> float:
    """The nearest-rank percentile (the smallest value with at least `q` of the values at or below it)."""
    ordered = sorted(values)
    return ordered[max(0, math.ceil(q * len(ordered)) - 1)] if ordered else 0.0


def _distribution(values: list[float]) -> dict[str, float]:
    return {
        "total": sum(values),
        "p50": _percentile(values, 0.5),
        "p90": _percentile(values, 0.9),
        "max": max(values, default=0.0),
    }


MAX_SECONDS = 120.0  # `--max-seconds`: a longer run (wall time) is flagged, a runaway the guards missed


def _flagged(record: dict[str, Any], max_rss_mb: float, max_seconds: float = math.inf) -> bool:
    return (
        record["status"] == "crash"
        or bool(record["problems"])
        or record["peak_rss_mb"] > max_rss_mb
        or record["seconds"] > max_seconds
    )


def summarize(
    records: list[dict[str, Any]],
    n: int,
    campaign_seed: int,
    max_rss_mb: float,
    max_seconds: float = math.inf,
) -> dict[str, Any]:
    """The campaign's summary from its records (so it can be rebuilt from ``records.jsonl``): counts, the
    worst area balance and peak memory, the time distribution and the 10 slowest scenarios."""
    counts = {"runs": len(records), "ok": 0, "refused": 0, "crash": 0, "violations": 0, "over_memory": 0}
    counts["warned"] = 0  # runs that raised a warning (recorded, not a violation)
    counts["over_time"] = 0  # runs longer than `max_seconds`
    for record in records:
        counts["over_time"] += record["seconds"] > max_seconds
        counts[record["status"]] += 1
        counts["violations"] += bool(record["problems"])
        counts["over_memory"] += record["peak_rss_mb"] > max_rss_mb
        counts["warned"] += bool(record.get("warnings"))
    slowest = sorted(records, key=lambda record: -record["seconds"])[:10]
    return {
        "n": n,
        "seed": campaign_seed,
        **counts,
        "max_rss_mb": max_rss_mb,
        "worst": {
            "area_balance_rel_error": max(
                (r.get("area_balance_rel_error") or 0.0 for r in records), default=0
            ),
            "peak_rss_mb": max((r["peak_rss_mb"] for r in records), default=0.0),
        },
        **{key: _distribution([r.get(key, 0.0) for r in records]) for key in ("seconds", "cpu_seconds")},
        "slowest": [
            {key: r.get(key) for key in ("index", "status", "seconds", "cpu_seconds", "scenario")}
            for r in slowest
        ],
    }


def read_records(out: Path, n: int, campaign_seed: int) -> list[dict[str, Any]]:
    """The records already in ``out/records.jsonl`` (none if absent); refuses those of another campaign.
    A line cut by a stopped campaign (the last, unterminated) is dropped: that scenario is run again."""
    path = out / "records.jsonl"
    if not path.exists():
        return []
    records = []
    for line in path.read_text(encoding="utf-8").splitlines(keepends=True):
        if not line.endswith("\n"):
            break
        record = json.loads(line)
        if (record["n"], record["seed"]) != (n, campaign_seed):
            raise SystemExit(
                f"{path} holds the campaign n={record['n']} seed={record['seed']}, "
                f"not n={n} seed={campaign_seed}"
            )
        records.append(record)
    return records


def _write_case(out: Path, record: dict[str, Any]) -> None:
    """A flagged record's scenario as ``case-NNNNN.toml`` (its record in comments), or, if it names files,
    as ``case-NNNNN/scenario.toml`` with the files beside it (``floebreak run`` reruns either)."""
    import tomli_w

    text = "".join(f"# {line}\n" for line in json.dumps(record, default=str, indent=1).splitlines())
    path = out / f"case-{record['index']:05d}.toml"
    if record.get("files"):
        path = out / path.stem / "scenario.toml"
        path.parent.mkdir(exist_ok=True)
        try:
            write_files(record["files"], path.parent)
        except Exception:  # a field recipe the generator refuses or fails on: the record says how
            pass
    path.write_text(text + tomli_w.dumps(record["scenario"]), "utf-8")


def run_campaign(
    n: int,
    campaign_seed: int,
    jobs: int,
    out: Path,
    max_rss_mb: float,
    resume: bool = False,
    check: Callable[[dict[str, Any]], dict[str, Any]] = check_one,
    retry: bool = False,
    generator: str = "valid",
    max_seconds: float = math.inf,
) -> dict[str, Any]:
    """Draw and `check` `n` scenarios. The drawn scenarios are kept in ``out/scenarios.jsonl``; each record is
    appended to ``out/records.jsonl`` as it completes (with `resume`, the indices already recorded there are
    skipped — with `retry` as well, the flagged ones are run again —, and the scenarios are those kept;
    without `resume` an existing campaign is refused), each violation saved as ``case-NNNNN.toml``; writes
    ``summary.json`` and returns the summary."""
    out.mkdir(parents=True, exist_ok=True)
    records = read_records(out, n, campaign_seed)
    if records and not resume:
        raise SystemExit(f"{out / 'records.jsonl'} exists: pass --resume to continue it, or another --out")
    path = out / "records.jsonl"
    if path.exists():  # drop a line cut by a stopped campaign
        os.truncate(path, path.read_bytes().rfind(b"\n") + 1)
    if retry:
        records = _drop_flagged(out, records, max_rss_mb, max_seconds)
    done = {record["index"] for record in records}
    scenarios = _campaign_scenarios(out, n, campaign_seed, generator)
    todo = [(i, data) for i, data in enumerate(scenarios) if i not in done]
    with path.open("a", encoding="utf-8") as log, contextlib.closing(_records(todo, jobs, check)) as results:
        for record in results:
            record.update(n=n, seed=campaign_seed)
            log.write(json.dumps(record, default=str) + "\n")
            log.flush()
            records.append(record)
            if _flagged(record, max_rss_mb, max_seconds):
                _write_case(out, record)
            if len(records) % 25 == 0:
                brief = _brief(records, max_rss_mb, max_seconds)
                print(f"{len(records)} of {n}: {brief}", file=sys.stderr, flush=True)
    summary = summarize(records, n, campaign_seed, max_rss_mb, max_seconds)
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    return summary


def _campaign_scenarios(
    out: Path, n: int, campaign_seed: int, generator: str = "valid"
) -> list[dict[str, Any]]:
    """The campaign's scenarios: those kept in ``out/scenarios.jsonl`` (a resumed campaign runs what was
    drawn, even after a change of floebreak's source), else drawn and kept there."""
    path = out / "scenarios.jsonl"
    if path.exists():
        header, *scenarios = (json.loads(line) for line in path.read_text(encoding="utf-8").splitlines())
        held = (header["n"], header["seed"], header.get("generator", "valid"))
        if held != (n, campaign_seed, generator) or len(scenarios) != n:
            raise SystemExit(
                f"{path} holds the campaign n={held[0]} seed={held[1]} generator={held[2]}, not n={n} "
                f"seed={campaign_seed} generator={generator}"
            )
        return scenarios
    scenarios = draw_scenarios(n, campaign_seed, generator)
    header = {"n": n, "seed": campaign_seed, "generator": generator}
    lines = [json.dumps(header), *(json.dumps(data) for data in scenarios)]
    write_text_atomic(path, "\n".join(lines) + "\n")
    return scenarios


def _drop_flagged(
    out: Path, records: list[dict[str, Any]], max_rss_mb: float, max_seconds: float = math.inf
) -> list[dict[str, Any]]:
    """`records` without the flagged ones, also in ``out/records.jsonl``; their case files removed."""
    kept = [record for record in records if not _flagged(record, max_rss_mb, max_seconds)]
    for record in records:
        if _flagged(record, max_rss_mb, max_seconds):
            case = out / f"case-{record['index']:05d}"
            case.with_suffix(".toml").unlink(missing_ok=True)
            shutil.rmtree(case, ignore_errors=True)
    lines = "".join(json.dumps(record, default=str) + "\n" for record in kept)
    write_text_atomic(out / "records.jsonl", lines)
    return kept


def _brief(records: list[dict[str, Any]], max_rss_mb: float, max_seconds: float) -> dict[str, int]:
    summary = summarize(records, 0, 0, max_rss_mb, max_seconds)
    keys = ("ok", "refused", "crash", "violations", "over_memory", "over_time", "warned")
    return {key: summary[key] for key in keys}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m fuzz", description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=200, help="number of scenarios")
    parser.add_argument("--seed", type=int, default=1, help="campaign seed (same seed → same scenarios)")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes")
    parser.add_argument("--out", type=Path, default=Path("fuzz-report"), help="records, violations")
    parser.add_argument("--max-rss-mb", type=float, default=1024.0, help="peak memory allowed per run")
    parser.add_argument(
        "--max-seconds", type=float, default=MAX_SECONDS, help="wall time allowed per run [s]"
    )
    parser.add_argument(
        "--generator",
        choices=GENERATORS,
        default="valid",
        help="valid scenarios over the options, or hostile files and policies (fuzz.adversarial)",
    )
    parser.add_argument("--resume", action="store_true", help="continue the campaign recorded in --out")
    parser.add_argument(
        "--retry", action="store_true", help="with --resume: run the flagged scenarios again (after a fix)"
    )
    parser.add_argument(
        "--summarize", action="store_true", help="only rebuild summary.json from --out/records.jsonl"
    )
    args = parser.parse_args(argv)
    started = time.perf_counter()
    if args.summarize:
        records = read_records(args.out, args.n, args.seed)
        summary = summarize(records, args.n, args.seed, args.max_rss_mb, args.max_seconds)
        (args.out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    else:
        try:
            with exit_on_sigterm():
                summary = run_campaign(
                    args.n,
                    args.seed,
                    args.jobs,
                    args.out,
                    args.max_rss_mb,
                    args.resume,
                    retry=args.retry,
                    generator=args.generator,
                    max_seconds=args.max_seconds,
                )
        except KeyboardInterrupt:
            print(
                "interrupted (Ctrl-C); the records so far are kept: continue with --resume", file=sys.stderr
            )
            return 130
    print(json.dumps(summary, indent=2), f"\n{time.perf_counter() - started:.0f} s")
    flagged = ("crash", "violations", "over_memory", "over_time")
    return 1 if any(summary[key] for key in flagged) else 0


if __name__ == "__main__":
    raise SystemExit(main())
