"""The fit of what drifts, on windows of known synthetic data: the closed form (the problem is linear
in M_eq, a2 and β), against an independent least-squares solve, the mapping back to a1…a4 and σ."""

import numpy as np
import pytest
from axisflow.identification.errors import IdentificationError
from axisflow.identification.fit import FitSamples, FrictionValues
from axisflow.identification.online import COULOMB, check_terms, fit_drift
from axisflow.model import default_params, friction_force

BASE = default_params()
K = BASE.r / BASE.i_r


def _samples(values: FrictionValues, noise_n: float = 0.0, seed: int = 0) -> FitSamples:
    """Decimated samples (100 Hz) of two sines: every speed from 0.02 to 1 m/s both ways."""
    t = np.arange(0.0, 30.0, 0.01)
    w1, w2 = 2 * np.pi * 0.3, 2 * np.pi * 1.1
    v = 0.6 * np.sin(w1 * t) + 0.25 * np.sin(w2 * t)
    a = 0.6 * w1 * np.cos(w1 * t) + 0.25 * w2 * np.cos(w2 * t)
    keep = np.abs(v) > 0.02
    force = values.force_n(v, a) + np.random.default_rng(seed).normal(0.0, noise_n, t.size)
    return FitSamples(v[keep], a[keep], force[keep], K)


def test_a_noiseless_window_gives_back_mass_viscous_and_the_common_scale_exactly():
    beta = -0.07
    true = FrictionValues(
        BASE.M_eq * 1.03, BASE.a1 * (1 + beta), BASE.a2 * 0.8, BASE.a3 * (1 + beta), BASE.a4
    )
    drift = fit_drift(_samples(true), BASE)
    assert drift.success and drift.terms == ("M_eq", "a2", COULOMB)
    assert drift.result.extra[COULOMB] == pytest.approx(beta, abs=1e-9)
    for name, value in true.as_dict().items():
        assert getattr(drift.values, name) == pytest.approx(value, rel=1e-9), name
    assert drift.result.iterations <= 2  # linear: the first Gauss–Newton step lands on the optimum


def test_with_noise_it_is_the_least_squares_solution_of_the_linear_model():
    true = FrictionValues(BASE.M_eq, BASE.a1 * 0.9, BASE.a2 * 0.85, BASE.a3 * 0.9, BASE.a4)
    samples = _samples(true, noise_n=5.0, seed=2)
    drift = fit_drift(samples, BASE)
    shape = FrictionValues(0.0, BASE.a1, 0.0, BASE.a3, BASE.a4)
    columns = np.column_stack(
        [samples.acceleration_m_s2, samples.velocity_m_s, friction_force(samples.velocity_m_s, shape)]
    )
    (m_eq, a2, scale), *_ = np.linalg.lstsq(columns, samples.force_n, rcond=None)
    assert drift.values.M_eq == pytest.approx(m_eq, rel=1e-7)
    assert drift.values.a2 == pytest.approx(a2, rel=1e-7)
    assert drift.values.a1 == pytest.approx(BASE.a1 * scale, rel=1e-7)
    assert drift.values.a3 == pytest.approx(BASE.a3 * scale, rel=1e-7)
    # σ of a1 and a3 are those of β, scaled; a4 was held
    sigma_beta = drift.window.std[COULOMB]
    assert drift.std["a1"] == pytest.approx(BASE.a1 * sigma_beta) and np.isnan(drift.std["a4"])
    assert drift.relative_std[COULOMB] == sigma_beta and 0 < sigma_beta < 0.01
    assert abs(drift.values.a2 - true.a2) < 4 * drift.std["a2"]


def test_a_warm_start_lands_on_the_same_optimum():
    true = FrictionValues(BASE.M_eq, BASE.a1 * 0.95, BASE.a2 * 0.9, BASE.a3 * 0.95, BASE.a4)
    cold = fit_drift(_samples(true, 2.0, 1), BASE)
    warm = fit_drift(_samples(true, 2.0, 1), BASE, start=cold.result)
    assert warm.values.as_dict() == pytest.approx(cold.values.as_dict(), rel=1e-9)


def test_any_subset_of_the_parameters_instead():
    true = FrictionValues(BASE.M_eq, BASE.a1 * 1.1, BASE.a2 * 0.9, BASE.a3 * 0.95, BASE.a4 * 1.05)
    drift = fit_drift(_samples(true), BASE, ("a1", "a2", "a3", "a4"))
    for name in ("a1", "a2", "a3", "a4"):
        assert getattr(drift.values, name) == pytest.approx(getattr(true, name), rel=1e-6), name
    assert drift.values.M_eq == BASE.M_eq and np.isnan(drift.std["M_eq"])  # held


@pytest.mark.parametrize(
    ("terms", "match"),
    [
        (("M_eq", "a9"), "unknown a9; choose from M_eq, a1, a2, a3, a4, coulomb"),
        (("a3", COULOMB), "coulomb scales a1 and a3 together; fit it or them, not both"),
        ((COULOMB,), "fit at least one of M_eq, a1, a2, a3, a4"),
        ((), "nothing to fit"),
    ],
)
def test_bad_terms_are_named(terms, match):
    with pytest.raises(IdentificationError, match=match):
        check_terms(terms)


def test_terms_come_in_a_fixed_order():
    assert check_terms([COULOMB, "a2", "M_eq", "a2"]) == ("M_eq", "a2", COULOMB)
