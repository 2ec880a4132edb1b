"""Thesis Table 1 observations and user observations."""

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.ice.observations import Observation, get_observation, thesis_observations


def test_table1_has_ten_rows_with_thesis_values():
    table = thesis_observations()
    assert len(table) == 10
    first = table["2019-12-18T20:20"]
    assert first.concentration == pytest.approx(0.44)
    assert first.mean_thickness_m == pytest.approx(0.36)
    assert first.diameter_classes_m == (2.5, 7.5, 15.0)
    assert first.percentages == (20.0, 40.0, 40.0)
    row = table["2019-12-30T13:10"]  # the row with 300 m floes
    assert row.diameter_classes_m == (2.5, 7.5, 15.0, 300.0)
    assert row.percentages == (20.0, 40.0, 30.0, 10.0)


def test_every_row_percentages_sum_to_100():
    for obs in thesis_observations().values():
        assert sum(obs.percentages) == pytest.approx(100.0)
        assert obs.fractions.sum() == pytest.approx(1.0)


def test_unknown_key_lists_the_keys():
    with pytest.raises(InputError, match="2019-12-18T20:20"):
        get_observation("2019-12-18T20:21")


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"concentration": 0.0}, "concentration"),
        ({"concentration": 1.2}, "concentration"),
        ({"mean_thickness_m": 0.0}, "mean_thickness_m"),
        ({"percentages": (50.0, 49.0)}, "percentages"),
        ({"percentages": (50.0,)}, "percentages"),
        ({"diameter_classes_m": (-1.0, 5.0)}, "diameter_classes_m"),
    ],
)
def test_bad_observations(kwargs, field):
    base = {
        "concentration": 0.5,
        "mean_thickness_m": 1.0,
        "diameter_classes_m": (5.0, 10.0),
        "percentages": (50.0, 50.0),
    }
    with pytest.raises(InputError, match=field):
        Observation(**{**base, **kwargs})


def test_percentages_within_half_a_percent_accepted_and_zero_classes_dropped():
    obs = Observation(0.5, 1.0, (5.0, 10.0, 20.0), (50.2, 49.6, 0.0))
    assert obs.diameter_classes_m == (5.0, 10.0)
    np.testing.assert_allclose(obs.fractions.sum(), 1.0)
