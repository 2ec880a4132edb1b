"""Cusp tables: reading runs and studies, box volumes and volume classes (thesis Alg. 1)."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from floebreak.errors import InputError
from floebreak.io.geoparquet import write_geoparquet
from floebreak.output.run_files import load_cusps
from floebreak.propeller.cusps import box_dimensions, class_means, cusp_columns, volume_class


def _write_run(directory, n, seed):
    directory.mkdir(parents=True)
    rng = np.random.default_rng(seed)
    length = rng.uniform(1.0, 4.0, n)
    width = rng.uniform(0.5, 1.0, n) * length
    boxes = [shapely.box(0, 0, a, b) for a, b in zip(length, width, strict=True)]
    write_geoparquet(
        directory / "cusps.parquet",
        np.array(boxes, dtype=object),
        {
            "area_m2": length * width,
            "thickness_m": np.full(n, 0.5),
            "volume_m3": length * width * 0.5,
            "bbox_length_m": length,
            "bbox_width_m": width,
            "piece_id": np.arange(n),
        },
        {"kind": "test"},
    )


def test_load_run_and_study(tmp_path):
    _write_run(tmp_path / "study" / "run_000", 3, 1)
    _write_run(tmp_path / "study" / "run_001", 5, 2)
    (tmp_path / "study" / ".run_002.tmp-x").mkdir()  # an unfinished write is ignored
    run = load_cusps(tmp_path / "study" / "run_001")
    assert run.num_rows == 5 and set(run.column("run_id").to_pylist()) == {"run_001"}
    assert "geometry" not in run.column_names
    study = load_cusps(tmp_path / "study")
    assert study.num_rows == 8
    assert study.column("run_id").to_pylist() == ["run_000"] * 3 + ["run_001"] * 5


def test_load_errors(tmp_path):
    with pytest.raises(InputError, match=r"no cusps\.parquet"):
        load_cusps(tmp_path)
    with pytest.raises(InputError, match="not a directory"):
        load_cusps(tmp_path / "nope")


def test_columns_validated():
    good = {
        "volume_m3": [1.0],
        "bbox_length_m": [2.0],
        "bbox_width_m": [1.0],
        "thickness_m": [0.5],
        "area_m2": [2.0],
    }
    assert cusp_columns(good)["run_id"].tolist() == ["run"]
    with pytest.raises(InputError, match=r"missing column.*area_m2"):
        cusp_columns({k: v for k, v in good.items() if k != "area_m2"})
    with pytest.raises(InputError, match="volume_m3"):
        cusp_columns({**good, "volume_m3": [np.nan]})


def test_volume_classes_and_means():
    # classes (0,5], (5,8], (8,11], (11,14] m³ (thesis §6.1.1); 14.5 lies above the last edge
    assert volume_class([0.0, 1.0, 5.0, 5.01, 8.0, 11.0, 14.0, 14.5]).tolist() == [-1, 0, 0, 1, 1, 2, 3, -1]
    longer, shorter, box = box_dimensions([1.0, 4.0, 3.0], [2.0, 2.0, 1.0], [1.0, 1.0, 2.0])
    assert longer.tolist() == [2.0, 4.0, 3.0] and shorter.tolist() == [1.0, 2.0, 1.0]
    assert box.tolist() == [2.0, 8.0, 6.0]
    means = class_means(longer, shorter, [1.0, 1.0, 2.0], box)
    assert means["n_cusps"].tolist() == [1, 2, 0, 0]
    assert means["mean_box_volume_m3"][1] == pytest.approx(7.0)
    assert means["mean_longer_side_m"][1] == pytest.approx(3.5)
    assert means["mean_thickness_m"][1] == pytest.approx(1.5)
    assert np.isnan(means["mean_box_volume_m3"][2])
    with pytest.raises(InputError, match="volume_class_edges_m3"):
        volume_class([1.0], [5.0, 4.0])
