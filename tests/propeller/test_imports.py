"""The propeller and shaft analyses import scipy's heavy modules where they use them:
scipy.interpolate only for the "pchip" interpolation and N-D FEM tables, scipy.optimize for a rule-form
fit, scipy.stats for an interval at a level other than 95 %, scipy.signal for the linear shaft response
(the drive model does not use it). Checked on `sys.modules` of a fresh interpreter, not on timings."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
from scipy import stats

from floebreak.propeller import ruleform


def loaded_after(statement: str) -> set[str]:
    """The modules a fresh interpreter has loaded after running `statement`."""
    code = f"{statement}\nimport json, sys\nprint(json.dumps(sorted(sys.modules)))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    return set(json.loads(out.splitlines()[-1]))


def test_the_analyses_and_their_figures_load_no_heavy_scipy_module():
    loaded = loaded_after(
        "import floebreak.app.propeller, floebreak.app.shaft, floebreak.propeller.summary\n"
        "import floebreak.plotting.propeller, floebreak.plotting.shaft"
    )
    assert not {"scipy.interpolate", "scipy.optimize", "scipy.stats", "scipy.signal"} & loaded


def test_a_fit_and_its_95_percent_intervals_need_no_scipy_stats():
    loaded = loaded_after(
        "import numpy as np\n"
        "from floebreak.propeller.ruleform import fit_rule_form\n"
        "fit = fit_rule_form(np.random.default_rng(1).weibull(0.8, 200))\n"
        "fit.shape_interval(), fit.x_max_interval(1e6)"
    )
    assert "scipy.optimize" in loaded and "scipy.stats" not in loaded


def test_the_95_percent_quantile_is_scipys_to_the_bit():
    assert ruleform.Z_95 == stats.norm.ppf(0.975)
    fit = ruleform.fit_rule_form(np.random.default_rng(2).weibull(1.2, 300))
    sd = np.sqrt(fit.cov_k_log_scale[0][0])
    for level in (0.95, 0.9):  # the constant, and scipy for any other level
        z = stats.norm.ppf(0.5 + level / 2.0)
        assert fit.shape_interval(level) == (fit.shape_k - z * sd, fit.shape_k + z * sd)


def test_the_propeller_command_and_its_figure_worker_do_not_import_the_engine():
    """The figure worker lives apart from the run directory (`floebreak.output.figure_process`): the
    propeller and shaft analyses draw through it without importing the stepping engine or the ice motion."""
    loaded = loaded_after(
        "from floebreak import cli\n"
        "import floebreak.app.propeller, floebreak.app.shaft, floebreak.app.figure_calls\n"
        "from floebreak.output.figure_process import figure_worker, figures_drawn_alongside"
    )
    engine = {"floebreak.engine.loop", "floebreak.output.run_directory", "floebreak.dynamics", "pymunk"}
    assert not engine & loaded
