"""`floebreak validate thesis --samples FILE --sample NAME` scores a registered sample: its seed,
observation, field size, number of fields and profiles come from the registry, the options it fixes are
refused, and fields.csv holds every field's checksum, which a regenerated field reproduces."""

from __future__ import annotations

import csv
import hashlib

import numpy as np
import pytest
from typer.testing import CliRunner

from floebreak.cli import app
from floebreak.errors import InputError
from floebreak.studies.aggregate import collect_runs
from floebreak.studies.design import run_seed

runner = CliRunner()
TINY = """[[sample]]
name = "tiny"
seed = 77
observation = "2020-01-03T13:40"
n_fields = 1
length_m = 40.0
width_m = 100.0
profiles = ["default"]
registered = 2026-12-07
"""


@pytest.fixture
def registry(tmp_path):
    path = tmp_path / "samples.toml"
    path.write_text(TINY, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--sample", "huge"], "'huge' is not registered"),
        (["--sample", "tiny", "--seed", "3"], "the sample fixes --seed"),
        (["--sample", "tiny", "--n-fields", "2", "--holdout"], "fixes --n-fields, --holdout"),
        (["--sample", "tiny", "--set", "field.width_m=50"], "fixes --set field.*"),
    ],
)
def test_a_sample_option_it_fixes_or_an_unknown_name_is_refused_before_anything_runs(
    tmp_path, registry, extra, message
):
    out = tmp_path / "out"
    result = runner.invoke(app, ["validate", "thesis", "--out", str(out), "--samples", str(registry), *extra])
    assert isinstance(result.exception, InputError) and message in str(result.exception), result.output
    assert not out.exists()


def test_a_missing_registry_is_an_input_error_naming_it(tmp_path):
    out = tmp_path / "out"
    missing = tmp_path / "nowhere.toml"
    result = runner.invoke(app, ["validate", "thesis", "--out", str(out), "--samples", str(missing),
                                 "--sample", "tiny"])  # fmt: skip
    assert isinstance(result.exception, InputError) and "--samples" in str(result.exception)
    assert not out.exists()


def coordinates_sha256(path) -> str:
    """The checksum of fields.csv written out by hand from the file: floe ids and exterior rings."""
    import pyarrow.parquet as pq
    import shapely

    table = pq.read_table(path, columns=["floe_id", "geometry"])
    digest = hashlib.sha256()
    ids, geometries = table.column("floe_id").to_pylist(), table.column("geometry").to_pylist()
    for floe_id, wkb in zip(ids, geometries, strict=True):
        digest.update(int(floe_id).to_bytes(8, "little", signed=True))
        ring = np.asarray(shapely.from_wkb(wkb).exterior.coords, dtype="<f8")
        digest.update(ring.tobytes())
    return digest.hexdigest()


@pytest.mark.slow
def test_a_registered_sample_runs_by_name_and_writes_its_fields_checksums(tmp_path, registry):
    out = tmp_path / "v"
    args = ["validate", "thesis", "--out", str(out), "--samples", str(registry), "--sample", "tiny"]
    result = runner.invoke(app, [*args, "--workers", "1", "--set", "ship.step_m=0.5"])
    assert result.exit_code == 0, result.output
    with (out / "scoreboard.csv").open(encoding="utf-8") as handle:
        header = next(csv.reader(handle))
    assert "default_status" in header and "thesis_status" not in header  # the sample's one profile
    with (out / "fields.csv").open(encoding="utf-8") as handle:
        (row,) = list(csv.DictReader(handle))
    assert (row["sample"], row["config"], row["field_index"]) == ("tiny", "default", "0")
    (run,) = [r["run"] for r in collect_runs(out / "study") if r["group"] == "default | reference"]
    assert row["field_sha256"] == coordinates_sha256(out / "study" / "runs" / run / "field.parquet")
    assert row["seed"] == str(run_seed(77, 0))  # field 0 of root seed 77
    assert len(row["field_sha256"]) == 64
    markdown = (out / "scoreboard.md").read_text(encoding="utf-8")
    assert "Registered sample `tiny`" in markdown and "observation 2020-01-03T13:40" in markdown
    assert "--sample tiny" in markdown and "40 m × 100 m" in markdown
