"""The fit over a window of samples (what identify does once and an adaptive node every few seconds):
closed forms from known parameters and known extra terms, a warm start, σ, the result object."""

import numpy as np
import pytest
from axisflow.identification.fit import FitSamples, FrictionValues, fit_window
from axisflow.model import default_params

NOMINAL = default_params()
K = NOMINAL.r / NOMINAL.i_r
TRUE = FrictionValues(M_eq=115.0, a1=81.0, a2=193.0, a3=216.0, a4=10.2)


def _window(values=TRUE, beta=(), start_s=0.0, seconds=20.0, noise_nm=0.0, seed=0, rate=100.0):
    """Decimated samples of a two-sine motion; force = eq. (1) + Σ β_j·X_j, X_j known columns (a
    Coulomb term along the stroke and a cogging-like sine of the position)."""
    rng = np.random.default_rng(seed)
    t = start_s + np.arange(0.0, seconds, 1.0 / rate)
    x = 0.4 + 0.2 * np.sin(2 * np.pi * 0.2 * t) + 0.03 * np.sin(2 * np.pi * 0.9 * t)
    v = 0.2 * 2 * np.pi * 0.2 * np.cos(2 * np.pi * 0.2 * t) + 0.03 * 2 * np.pi * 0.9 * np.cos(
        2 * np.pi * 0.9 * t
    )
    a = -0.2 * (2 * np.pi * 0.2) ** 2 * np.sin(2 * np.pi * 0.2 * t) - 0.03 * (2 * np.pi * 0.9) ** 2 * np.sin(
        2 * np.pi * 0.9 * t
    )
    keep = np.abs(v) > 0.005
    columns = np.column_stack([np.sign(v) * (x - 0.4) / 0.2, -np.sin(2 * np.pi * x / 0.01) * (1 / K)])
    force = values.force_n(v, a) + columns[:, : len(beta)] @ np.asarray(beta, dtype=float)
    force += rng.normal(0.0, noise_nm / K, t.size)
    extra = columns[keep, : len(beta)] if beta else None
    return FitSamples(v[keep], a[keep], force[keep], K, extra)


def test_a_noiseless_window_gives_back_its_parameters_exactly():
    window = fit_window(_window(), NOMINAL)
    assert window.success and window.samples > 1500
    for name, true in list(TRUE.as_dict().items())[:5]:
        assert window.values.as_dict()[name] == pytest.approx(true, rel=1e-7), name
    assert window.rms < 1e-9


def test_the_extra_terms_are_fitted_beside_eq1_exactly():
    beta = (3.5, 0.006)  # N along the stroke; N·m of the position sine
    window = fit_window(_window(beta=beta), NOMINAL, extra_names=("c1", "s1"), extra_scales=(4.0, 0.02))
    assert window.result.extra == pytest.approx({"c1": 3.5, "s1": 0.006}, rel=1e-6)
    assert window.values.M_eq == pytest.approx(TRUE.M_eq, rel=1e-7)
    assert set(window.std) == {"M_eq", "a1", "a2", "a3", "a4", "c1", "s1"}
    assert window.uncertainty.correlation.shape == (7, 7)


def test_a_warm_start_from_the_last_window_starts_there_and_ends_at_the_same_answer():
    first = fit_window(_window(noise_nm=0.01, seed=1), NOMINAL)
    later = _window(noise_nm=0.01, seed=2, start_s=20.0)
    cold = fit_window(later, NOMINAL)
    warm = fit_window(later, NOMINAL, start=first.result)
    for name in list(TRUE.as_dict())[:5]:
        assert warm.values.as_dict()[name] == pytest.approx(cold.values.as_dict()[name], rel=1e-6), name
    assert warm.result.iterations <= cold.result.iterations
    # one step from the last window's estimate lands nearer than one step from the nominal values
    one_cold = fit_window(later, NOMINAL, max_iter=1).values
    one_warm = fit_window(later, NOMINAL, start=first.result, max_iter=1).values

    def distance(v):
        return max(abs(v.as_dict()[n] / cold.values.as_dict()[n] - 1) for n in list(TRUE.as_dict())[:5])

    assert distance(one_warm) < 0.1 * distance(one_cold)


def test_sigma_of_a_window_matches_the_scatter_of_its_estimates():
    """Over 30 noise draws, the spread of each estimate is what the window's σ says (within 35 %)."""
    fits = [fit_window(_window(noise_nm=0.03, seed=s, seconds=10.0), NOMINAL) for s in range(30)]
    for name in list(TRUE.as_dict())[:5]:
        spread = np.std([f.values.as_dict()[name] for f in fits], ddof=1)
        assert fits[0].std[name] == pytest.approx(spread, rel=0.35), name
