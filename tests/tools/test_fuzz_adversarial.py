"""The fuzz campaign's adversarial generator: reproducible draws of hostile files and policies,
each written with the project's writers and run to a record (a crash is what the campaign looks for)."""

from __future__ import annotations

import json
from pathlib import Path

import pyarrow.parquet as pq

import fuzz
from fuzz.adversarial import write_field_file


def test_adversarial_draws_are_reproducible_and_hostile():
    first, again = fuzz.draw_scenarios(40, 5, "adversarial"), fuzz.draw_scenarios(40, 5, "adversarial")
    assert json.dumps(first) == json.dumps(again)
    assert first != fuzz.draw_scenarios(40, 5, "valid")
    files = [spec for data in first for spec in data[fuzz.FILES].values()]
    assert any("adversarial_field" in spec for spec in files) and any("text" in spec for spec in files)
    assert any("policy" in data.get("failure", {}) for data in first)
    assert all(data["simulation"]["max_wall_s"] == fuzz.MAX_WALL_S for data in first)


def test_a_hostile_field_file_is_written_as_drawn(tmp_path):
    recipe = {
        "rings": [[[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]], [[5.0, 5.0]] * 4],
        "floe_id": [3, 3],  # repeated
        "thickness_m": [1.0, "1.0"],  # the second as text
        "domain": "inverted",
    }
    write_field_file(recipe, tmp_path / "f.parquet")
    table = pq.read_table(tmp_path / "f.parquet")
    assert table.column("floe_id").to_pylist() == [3, 3]
    assert table.column("thickness_m").to_pylist() == ["1.0", "1.0"]  # a column of one type: text
    domain = json.loads(table.schema.metadata[b"floebreak"])["domain_m"]
    assert domain[0] > domain[2]  # x_min > x_max


def test_a_run_over_the_time_limit_is_flagged():
    record = {
        "index": 0,
        "status": "ok",
        "problems": [],
        "peak_rss_mb": 10.0,
        "seconds": fuzz.MAX_SECONDS + 1,
    }
    summary = fuzz.summarize([record], 1, 1, max_rss_mb=1024.0, max_seconds=fuzz.MAX_SECONDS)
    assert summary["over_time"] == 1 and fuzz._flagged(record, 1024.0, fuzz.MAX_SECONDS)


def test_the_makefile_runs_both_generators():
    makefile = (Path(__file__).resolve().parents[2] / "Makefile").read_text(encoding="utf-8")
    assert "--generator valid" in makefile and "--generator adversarial" in makefile
