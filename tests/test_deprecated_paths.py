"""The module paths of the previous release still import, for one release, with a DeprecationWarning that
names the new path (`floebreak._MOVED`)."""

import importlib
import subprocess
import sys

import pytest

import floebreak


def test_an_old_path_warns_and_gives_the_new_module():
    # a fresh interpreter: in this one the old name may already be bound by an earlier test
    code = (
        "import warnings\n"
        "with warnings.catch_warnings(record=True) as caught:\n"
        "    warnings.simplefilter('always')\n"
        "    from floebreak.simulation import simulate\n"
        "    import floebreak.app.run_directory as old\n"
        "import floebreak.engine.loop, floebreak.output.run_directory as new\n"
        "assert simulate is floebreak.engine.loop.simulate and old is new\n"
        "print([str(w.message) for w in caught if w.category is DeprecationWarning])\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert "floebreak.simulation is deprecated; import floebreak.engine.loop" in out
    assert "floebreak.app.run_directory is deprecated; import floebreak.output.run_directory" in out


@pytest.mark.parametrize(("old", "new"), sorted(floebreak._MOVED.items()))
def test_every_old_path_points_at_a_module(old, new):
    assert importlib.util.find_spec(new) is not None, new
    assert importlib.util.find_spec(old) is not None, old  # found by the finder, not imported
