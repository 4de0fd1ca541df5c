"""The SQP refit against independent references: data made from known parameters, scipy's
least_squares on the same residuals, and the bounds."""

import numpy as np
import pytest
from axisflow.identification.fit import FitSamples, FrictionFit, FrictionValues, fit_parameters
from axisflow.identification.uncertainty import effective_sample_size, estimate_uncertainty
from axisflow.model import default_params
from scipy.optimize import least_squares

NOMINAL = default_params()
TRUE = FrictionValues(M_eq=115.0, a1=81.0, a2=193.0, a3=216.0, a4=10.2)
K = NOMINAL.r / NOMINAL.i_r


def _samples(values=TRUE, n=6000, noise_nm=0.01, seed=3, max_speed=1.2):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 60.0, n)
    v = max_speed * np.sin(2 * np.pi * 0.3 * t) * (0.1 + 0.9 * (t / 60.0))
    a = np.gradient(v, t)
    force = values.force_n(v, a) + rng.normal(0.0, noise_nm / K, n)
    keep = np.abs(v) > 0.002
    return FitSamples(v[keep], a[keep], force[keep], K)


def test_recovers_the_parameters_the_data_were_made_with():
    result = fit_parameters(_samples(), NOMINAL)
    assert result.success and result.iterations <= 10
    for name, true in TRUE.as_dict().items():
        assert result.values.as_dict()[name] == pytest.approx(true, rel=2e-3), name
    assert result.rms == pytest.approx(0.01, rel=0.05)  # the noise, nothing more


def test_agrees_with_scipy_least_squares_on_the_same_residuals():
    samples = _samples(noise_nm=0.05, seed=7)
    result = fit_parameters(samples, NOMINAL)

    def residuals(p):
        values = FrictionValues(*p)
        return K * (samples.force_n - values.force_n(samples.velocity_m_s, samples.acceleration_m_s2))

    start = list(FrictionValues.of(NOMINAL).as_dict().values())[:5]  # eq. (1)'s five: what is fitted
    ref = least_squares(residuals, start, bounds=(0.0, np.inf), x_scale=np.abs(start), xtol=1e-14, ftol=1e-14)
    assert list(result.values.as_dict().values())[:5] == pytest.approx(ref.x, rel=1e-6)


def test_the_bounds_hold_when_the_data_want_a_negative_coefficient():
    values = FrictionValues(M_eq=110.0, a1=0.0, a2=150.0, a3=60.0, a4=8.0)
    samples = _samples(values=values, noise_nm=0.02, seed=11)
    result = fit_parameters(samples, NOMINAL)
    assert result.success
    assert min(result.values.as_dict().values()) >= 0.0
    assert result.values.a1 == pytest.approx(0.0, abs=1.0)


def test_a_subset_keeps_the_others_at_their_nominal_values():
    result = fit_parameters(_samples(), NOMINAL, fit=("a1", "a2"))
    assert result.fitted == ("a1", "a2")
    assert (result.values.M_eq, result.values.a3, result.values.a4) == (NOMINAL.M_eq, NOMINAL.a3, NOMINAL.a4)
    assert result.jacobian.shape == (len(result.residuals), 2)


def test_the_jacobian_is_that_of_the_unsquared_residuals():
    samples = _samples(n=800)
    problem = FrictionFit(samples.velocity_m_s, samples.acceleration_m_s2, K, NOMINAL)
    result = problem.solve(samples.force_n)
    base = result.values.as_dict()
    for i, name in enumerate(result.fitted):
        h = 1e-6 * base[name]
        up, down = (
            FrictionValues(**{**base, name: base[name] + h}),
            FrictionValues(**{**base, name: base[name] - h}),
        )

        def res(values):
            return K * (samples.force_n - values.force_n(samples.velocity_m_s, samples.acceleration_m_s2))

        assert result.jacobian[:, i] == pytest.approx((res(up) - res(down)) / (2 * h), rel=1e-5, abs=1e-9), (
            name
        )


def test_sigma_matches_the_scatter_of_repeated_fits():
    """Over 40 noise draws, the spread of each estimate is what the reported σ says (within 35 %)."""
    fits = [fit_parameters(_samples(noise_nm=0.05, n=2000, seed=s), NOMINAL) for s in range(40)]
    spread = {n: np.std([f.values.as_dict()[n] for f in fits], ddof=1) for n in one_fitted(TRUE)}
    one = fits[0]
    sigma = estimate_uncertainty(one.fitted, one.values.as_dict(), one.jacobian, one.residuals).std
    for name in one_fitted(TRUE):
        assert sigma[name] == pytest.approx(spread[name], rel=0.35), name


def test_effective_sample_size_of_white_and_of_correlated_noise():
    rng = np.random.default_rng(0)
    white = rng.normal(size=20000)
    assert effective_sample_size(white) == pytest.approx(20000, rel=0.1)
    ar = np.zeros(20000)  # AR(1), φ = 0.9: n_eff ≈ n·(1 − φ)/(1 + φ)
    for i in range(1, ar.size):
        ar[i] = 0.9 * ar[i - 1] + white[i]
    assert effective_sample_size(ar) == pytest.approx(20000 * 0.1 / 1.9, rel=0.35)


def test_a_log_without_low_speeds_is_told_it_cannot_separate_a1_from_a3():
    rng = np.random.default_rng(5)
    t = np.linspace(0.0, 30.0, 3000)
    v = 0.6 + 0.5 * np.sin(2 * np.pi * 0.2 * t)  # 0.1 … 1.1 m/s: a3·atan(a4·v) is nearly a constant
    a = np.gradient(v, t)
    force = TRUE.force_n(v, a) + rng.normal(0.0, 0.01 / K, v.size)
    result = fit_parameters(FitSamples(v, a, force, K), NOMINAL)
    unc = estimate_uncertainty(result.fitted, result.values.as_dict(), result.jacobian, result.residuals)
    assert any(w.startswith("this log cannot separate a1 from a3") for w in unc.warnings), unc.warnings


def one_fitted(values):
    """The parameters a default fit estimates: eq. (1)'s five."""
    return [n for n in values.as_dict() if n in ("M_eq", "a1", "a2", "a3", "a4")]


def test_held_out_samples_are_scored_not_fitted():
    samples = _samples(noise_nm=0.05, seed=5)
    n = len(samples)
    kept = np.arange(n) < n // 2
    problem = FrictionFit(samples.velocity_m_s, samples.acceleration_m_s2, K, NOMINAL)
    held = problem.solve(samples.force_n, kept=kept)
    columns = (samples.velocity_m_s, samples.acceleration_m_s2, samples.force_n)
    alone = fit_parameters(FitSamples(*(x[kept] for x in columns), K), NOMINAL)
    found, expected = held.values.as_dict(), alone.values.as_dict()
    assert list(found.values()) == pytest.approx(list(expected.values()), rel=1e-7)
    assert held.residuals.size == n  # every sample's error, the held-out ones too
    model = held.values.force_n(samples.velocity_m_s[~kept], samples.acceleration_m_s2[~kept])
    assert held.residuals[~kept] == pytest.approx(K * (samples.force_n[~kept] - model), abs=1e-12)


def test_an_offset_and_a_viscous_asymmetry_are_found_and_each_directions_friction_stays_positive():
    true = FrictionValues(M_eq=115.0, a1=81.0, a2=193.0, a3=216.0, a4=10.2, f0=-12.0, da2=40.0)
    samples = _samples(values=true, seed=4)
    result = fit_parameters(samples, NOMINAL, fit=("M_eq", "a1", "a2", "a3", "a4", "f0", "da2"))
    assert result.success
    for name in ("M_eq", "a1", "a2", "f0", "da2"):
        assert getattr(result.values, name) == pytest.approx(getattr(true, name), rel=1e-2), name
    # friction of the +x direction that the data want below zero: held at zero, not fitted through it
    lopsided = FrictionValues(M_eq=115.0, a1=81.0, a2=20.0, a3=216.0, a4=10.2, da2=-60.0)
    held = fit_parameters(
        _samples(values=lopsided, seed=6), NOMINAL, fit=("M_eq", "a1", "a2", "a3", "a4", "da2")
    )
    assert held.values.a2 + held.values.da2 >= 0.0 and held.values.a2 - held.values.da2 >= 0.0
