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
from axisflow.model.friction import FRICTION_PARAMETERS, FrictionLaw

P = default_params()
V = np.array([-1.4, -0.3, -0.02, -1e-4, 1e-4, 0.02, 0.3, 1.4])
# every term on: an offset along +x (gravity uphill), Coulomb and viscous stronger towards +x
Q = P.replace(f0=35.0, da1=-12.0, da2=40.0)


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
    for k, name in enumerate(("a1", "a2", "a3", "a4")):
        h = 1e-6 * max(getattr(P, name), 1.0)
        up = friction_force(V, P.replace(**{name: getattr(P, name) + h}))
        down = friction_force(V, P.replace(**{name: getattr(P, name) - h}))
        assert jac[:, k] == pytest.approx((up - down) / (2 * h), rel=1e-6, abs=1e-9), name


def test_terms_written_out_per_direction():
    for v in V:
        s = math.copysign(1.0, v)
        expected = Q.f0 + (Q.a1 + s * Q.da1) * s + (Q.a2 + s * Q.da2) * v + Q.a3 * math.atan(Q.a4 * v)
        assert float(friction_force(v, Q)) == pytest.approx(expected, rel=1e-14)
    assert float(friction_force(0.0, Q)) == Q.f0  # at rest the motor holds the constant force


def test_forward_law_per_direction_is_the_force_along_the_motion():
    """φ_s(|v|) is the force opposing a motion in direction s: s·F_c(s·|v|)."""
    w = np.abs(V[V > 0])
    for s in (1.0, -1.0):
        law = Q.forward(s)
        assert law.c == Q.a1 + s * Q.da1 + s * Q.f0 and law.b == Q.a2 + s * Q.da2
        assert law.value(w) == pytest.approx(s * friction_force(s * w, Q), rel=1e-14)
        assert forward_friction(w, Q, s) == pytest.approx(law.value(w), rel=0)
        h = 1e-7
        assert law.slope(w) == pytest.approx((law.value(w + h) - law.value(w - h)) / (2 * h), rel=1e-6)
        num = (law.slope(w + h) - law.slope(w - h)) / (2 * h)
        assert law.curvature(w) == pytest.approx(num, rel=1e-5, abs=1e-3)
    downhill = P.replace(f0=-150.0).forward(1.0)  # the load pushes towards +x
    assert downhill.c == P.a1 - 150.0 < 0.0  # a load that helps the move: c < 0


def test_default_axis_is_symmetric_and_the_forward_law_is_todays():
    assert P.friction.is_symmetric and P.forward(1.0) == P.forward(-1.0)
    assert P.forward(1.0) == FrictionLaw(P.a1, P.a2, P.a3, P.a4).forward(1.0)
    assert P.terms == ("coulomb", "viscous", "atan")


def test_every_parameter_column_matches_central_differences():
    jac = friction_regressors(V, Q)
    assert jac.shape == (V.size, len(FRICTION_PARAMETERS))
    for k, name in enumerate(FRICTION_PARAMETERS):
        h = 1e-6 * max(abs(getattr(Q, name)), 1.0)
        up = friction_force(V, FrictionLaw(**{**vars(Q.friction), name: getattr(Q, name) + h}))
        down = friction_force(V, FrictionLaw(**{**vars(Q.friction), name: getattr(Q, name) - h}))
        assert jac[:, k] == pytest.approx((up - down) / (2 * h), rel=1e-6, abs=1e-9), name


def test_symbolic_form_over_casadi_equals_numpy():
    ca = pytest.importorskip("casadi")
    v = ca.SX.sym("v")
    a = ca.SX.sym("a", 4)
    f = ca.Function("f", [v, a], [friction_expression(v, ca.sign(v), a[0], a[1], a[2], a[3], ca.atan)])
    got = [float(f(x, [P.a1, P.a2, P.a3, P.a4])) for x in V]
    assert got == pytest.approx(friction_force(V, P).tolist(), rel=1e-14)


def test_symbolic_form_with_every_term_equals_numpy():
    ca = pytest.importorskip("casadi")
    v = ca.SX.sym("v")
    a = ca.SX.sym("a", 7)
    expr = friction_expression(v, ca.sign(v), a[0], a[1], a[2], a[3], ca.atan, a[4], a[5], a[6])
    f = ca.Function("f", [v, a], [expr])
    got = [float(f(x, [getattr(Q, n) for n in FRICTION_PARAMETERS])) for x in V]
    assert got == pytest.approx(friction_force(V, Q).tolist(), rel=1e-14)
