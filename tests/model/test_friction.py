"""The friction law: its derivatives against finite differences, the forms against each other."""

import math

import numpy as np
import pytest
from axisflow.model import (
    default_params,
    forward_friction,
    friction_curvature,
    friction_expression,
    friction_force,
    friction_regressors,
    friction_slope,
)

P = default_params()
V = np.array([-1.4, -0.3, -0.02, -1e-4, 1e-4, 0.02, 0.3, 1.4])


def test_force_is_the_law_of_eq1_written_out():
    expected = [P.a1 * math.copysign(1, v) + P.a2 * v + P.a3 * math.atan(P.a4 * v) for v in V]
    assert friction_force(V, P) == pytest.approx(expected, rel=1e-15)
    assert float(friction_force(0.0, P)) == 0.0  # sign(0) = 0: no Coulomb force at rest


def test_forward_form_closes_the_coulomb_sign_at_rest():
    assert float(forward_friction(0.0, P)) == P.a1
    v = V[V > 0]
    assert forward_friction(v, P) == pytest.approx(friction_force(v, P), rel=1e-15)


def test_velocity_derivatives_match_central_differences():
    h = 1e-7
    num_slope = (friction_force(V + h, P) - friction_force(V - h, P)) / (2 * h)
    assert friction_slope(V, P) == pytest.approx(num_slope, rel=1e-6)
    num_curv = (friction_slope(V + h, P) - friction_slope(V - h, P)) / (2 * h)
    assert friction_curvature(V, P) == pytest.approx(num_curv, rel=1e-5, abs=1e-3)


def test_parameter_jacobian_matches_central_differences():
    jac = friction_regressors(V, P)
    assert jac.shape == (V.size, 4)
    for k, name in enumerate(("a1", "a2", "a3", "a4")):
        h = 1e-6 * max(getattr(P, name), 1.0)
        up = friction_force(V, P.replace(**{name: getattr(P, name) + h}))
        down = friction_force(V, P.replace(**{name: getattr(P, name) - h}))
        assert jac[:, k] == pytest.approx((up - down) / (2 * h), rel=1e-6, abs=1e-9), name


def test_symbolic_form_over_casadi_equals_numpy():
    ca = pytest.importorskip("casadi")
    v = ca.SX.sym("v")
    a = ca.SX.sym("a", 4)
    f = ca.Function("f", [v, a], [friction_expression(v, ca.sign(v), a[0], a[1], a[2], a[3], ca.atan)])
    got = [float(f(x, [P.a1, P.a2, P.a3, P.a4])) for x in V]
    assert got == pytest.approx(friction_force(V, P).tolist(), rel=1e-14)
