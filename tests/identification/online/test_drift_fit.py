"""The fit of what drifts, on windows of known synthetic data: the closed form (the problem is linear
in M_eq, a2 and β), against an independent least-squares solve, the mapping back to a1…a4 and σ."""

from pathlib import Path

import numpy as np
import pytest
from axisflow.identification.errors import IdentificationError
from axisflow.identification.fit import FitSamples, FrictionValues
from axisflow.identification.online import COULOMB, check_terms, default_terms, fit_drift, signed_scale
from axisflow.model import default_params, friction_force, load_params

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
        (("M_eq", "a9"), "unknown a9; choose from M_eq, a1, a2, a3, a4, f0, da1, da2, coulomb"),
        (("M_eq", "f0", "da1"), "f0 and da1 cannot both be fitted"),
        (("a3", COULOMB), "coulomb scales a1 and a3 together; fit it or them, not both"),
        ((COULOMB,), "fit at least one of M_eq, a1, a2, a3, a4, f0, da1, da2"),
        ((), "nothing to fit"),
    ],
)
def test_bad_terms_are_named(terms, match):
    with pytest.raises(IdentificationError, match=match):
        check_terms(terms)


def test_terms_come_in_a_fixed_order():
    assert check_terms([COULOMB, "a2", "M_eq", "a2"]) == ("M_eq", "a2", COULOMB)


AXES = Path(__file__).parents[3] / "docs" / "axes"


@pytest.mark.parametrize(
    ("kind", "terms"),
    [
        ("belt", ("M_eq", "a2", "da1", "da2", COULOMB)),  # offset and asymmetry: f0 held, da1 fitted
        ("ball-screw", ("M_eq", "a2", "da1", "da2", COULOMB)),
        ("paper", ("M_eq", "a2", COULOMB)),
    ],
)
def test_an_axis_refits_the_terms_beside_eq1_it_has_on_by_default(kind, terms):
    params = BASE if kind == "paper" else load_params(AXES / f"{kind}.toml")
    assert default_terms(params) == terms
    only_offset = params.replace(da1=0.0, da2=0.0, f0=25.0, terms=("coulomb", "viscous", "offset"))
    assert default_terms(only_offset) == ("M_eq", "a2", "f0", COULOMB)


def test_the_terms_beside_eq1_are_fitted_with_the_drift_and_carried_into_the_set():
    axis = load_params(AXES / "belt.toml")  # f0 25 N, da1 6 N, da2 -12 N·s/m
    true = FrictionValues(axis.M_eq * 1.02, axis.a1 * 0.95, axis.a2 * 0.9, axis.a3 * 0.95, axis.a4,
                          axis.f0, 9.0, -8.0)  # fmt: skip
    samples = _samples(true, noise_n=2.0, seed=3)  # the belt file's transmission is the packaged axis's
    drift = fit_drift(samples, axis, default_terms(axis))
    assert drift.success
    assert drift.values.da1 == pytest.approx(9.0, abs=4 * drift.std["da1"])
    assert drift.values.da2 == pytest.approx(-8.0, abs=4 * drift.std["da2"])
    assert drift.values.f0 == axis.f0 and np.isnan(drift.std["f0"])  # held: the force at rest
    assert drift.std["da1"] < 1.0 and drift.relative_std["da1"] == drift.std["da1"] / signed_scale(
        "da1", drift.values
    )
    carried = drift.params()
    assert (carried.f0, carried.da1, carried.da2) == (axis.f0, drift.values.da1, drift.values.da2)
    assert carried.terms == axis.terms
    # the default terms of the paper's axis on this axis: the asymmetry is still carried, not fitted
    paper = fit_drift(samples, axis)
    assert (paper.params().da1, paper.params().da2) == (axis.da1, axis.da2)


def test_the_size_a_signed_term_is_measured_against_is_the_friction_it_shifts():
    axis = load_params(AXES / "belt.toml")
    dry = axis.a1 + axis.a3 * np.pi / 2
    assert signed_scale("da1", axis) == pytest.approx(dry) and signed_scale("f0", axis) == pytest.approx(dry)
    assert signed_scale("da2", axis) == axis.a2
    assert signed_scale("f0", axis.replace(f0=900.0)) == 900.0  # a force larger than the friction: itself
