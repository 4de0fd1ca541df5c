"""The drive's sampling grid from stamps alone: period and phase, holes, jitter, and what is refused."""

import numpy as np
import pytest
from axisflow.identification.errors import IdentificationError
from axisflow.identification.sample_grid import MAX_LOST_FRACTION, place_on_grid

T0 = 1_700_000_000_000_000_000


def _stamps(n=20_000, period_ns=1_000_000, jitter_ns=50_000, seed=4):
    rng = np.random.default_rng(seed)
    return T0 + np.arange(n) * period_ns + rng.integers(-jitter_ns, jitter_ns + 1, n)


def test_holes_are_found_counted_and_placed():
    stamps = _stamps()
    keep = np.ones(stamps.size, bool)
    keep[[100, 5000, 5001, 5002, 17_000]] = False  # one, three, one samples lost
    grid = place_on_grid(stamps[keep], "log")
    assert grid.size == stamps.size and grid.lost == 5
    assert grid.holes.tolist() == [[100, 1], [5000, 3], [17_000, 1]]
    assert grid.longest_hole == 3
    assert np.array_equal(grid.index, np.flatnonzero(keep))
    assert grid.period_ns == pytest.approx(1_000_000, abs=5)  # least squares over 20 000 stamps
    assert 45e-6 < grid.jitter_s <= 52e-6
    assert grid.describe() == "5 of 20000 samples missing (0.03%) in 3 holes, the longest 3 ms"


def test_values_are_spread_on_the_grid_with_the_holes_interpolated():
    k = np.r_[0:10, 11:20]  # sample 10 lost
    grid = place_on_grid(T0 + k * 1_000_000, "log")
    assert grid.spread(k * 2.0).tolist() == [2.0 * i for i in range(20)]
    assert np.flatnonzero(~grid.observed()).tolist() == [10]
    assert grid.times_s() == pytest.approx(np.arange(20) * 1e-3)


def test_a_log_missing_more_than_a_fifth_is_refused_with_the_count():
    stamps = _stamps(n=10_000, jitter_ns=0)
    keep = np.ones(stamps.size, bool)
    keep[1000:3500] = False  # 25 %
    with pytest.raises(IdentificationError, match=r"2500 of 10000 samples missing \(25.00%\) in 1 holes"):
        place_on_grid(stamps[keep], "log")
    assert MAX_LOST_FRACTION == 0.2


@pytest.mark.parametrize(
    ("spoil", "match"),
    [
        (lambda s: np.r_[s[:50], s[48:]], r"time stamps do not increase: sample 50"),
        (lambda s: np.r_[s[:50], s[49] + 100_000, s[50:]], r"samples 49 and 50 are 0.100 ms apart"),
        (lambda s: np.r_[s[:500], s[500] + (s[500:] - s[500]) * 3 // 2], r"do not sit on a sampling grid"),
    ],
)
def test_stamps_that_go_back_repeat_or_leave_the_grid_are_refused(spoil, match):
    with pytest.raises(IdentificationError, match=match):
        place_on_grid(spoil(_stamps(n=2000, jitter_ns=0)), "log")
