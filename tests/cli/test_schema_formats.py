"""`floebreak schema --format table|markdown` lists every scenario key with its unit, range and default,
the [ice_motion] and failure-mode tables included; JSON stays the default."""

from __future__ import annotations

import dataclasses
import json

from typer.testing import CliRunner

from floebreak.cli import app
from floebreak.dynamics.settings import IceMotionSettings
from floebreak.errors import InputError

runner = CliRunner()


def _markdown_rows() -> dict[str, list[str]]:
    done = runner.invoke(app, ["schema", "--format", "markdown"])
    assert done.exit_code == 0, done.output
    lines = done.output.strip().splitlines()
    assert lines[0] == "| key | type | default | allowed | description |"
    return {
        cells[0]: cells[1:]
        for cells in ([c.strip() for c in line.strip("|").split(" | ")] for line in lines[2:])
    }


def test_every_ice_motion_setting_is_listed_with_its_default_and_range():
    rows = _markdown_rows()
    for item in dataclasses.fields(IceMotionSettings):
        if item.name.startswith("_") or not item.init:
            continue
        assert f"ice_motion.{item.name}" in rows
    drag = rows["ice_motion.form_drag_coefficient"]
    assert drag[1] == "1.0" and drag[2] == "(0, 5]"


def test_sections_keys_units_and_ranges_are_listed():
    rows = _markdown_rows()
    thickness = rows["ice.thickness_m"]
    assert "[m]" in thickness[3] and thickness[2] == "[0.01, 10]"
    assert rows["profile"][2] == "default, thesis"
    assert any(key.startswith("failure.cracking.") for key in rows)


def test_json_stays_the_default_and_a_bad_format_is_refused():
    assert "$defs" in json.loads(runner.invoke(app, ["schema"]).output)
    bad = runner.invoke(app, ["schema", "--format", "yaml"])
    assert isinstance(bad.exception, InputError) and str(bad.exception).startswith(
        "format:"
    )  # exit 2 in main
    table = runner.invoke(app, ["schema", "--format", "table"])
    assert table.exit_code == 0 and "ice_motion" in table.output and "ice.thickness_m" in table.output
