"""A small run directory shared by the campaign's regression tests (a short reference field)."""

from __future__ import annotations

import pytest

import floebreak


@pytest.fixture(scope="session")
def small_run_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("campaign") / "run"
    floebreak.run(overrides=["field.length_m=40.0"]).write(out)
    return out
