"""The exact solver's inlined copies of the friction law against the model's functions.

The solver's scalar Newton loops write φ(v) = a1 + a2·v + a3·atan(a4·v) and its velocity derivatives
out with ``math.atan`` for speed (torque_limit.TorqueLimit.force_derivatives, energy.braking_margin).
Each copy is checked here, through the quantity it computes, against model/friction.py's forward law
of the move's direction (ForwardLaw.value, .slope, .curvature) at a set of velocities, on the paper's
axis and on axes with an offset and asymmetric friction in both directions (a load that helps the
move among them, whose braking half has a limit of its own, on −φ): a change of the model's law that
is not made in the copies fails here.
"""

import numpy as np
import pytest
from axisflow.model import ForwardLaw, default_params, polynomial_law
from axisflow.model.params import forward_axis
from axisflow.planner.exact import law_model
from axisflow.planner.exact.energy import braking_margin
from axisflow.planner.exact.torque_limit import torque_limit

VELOCITIES_M_S = [1e-6, 1e-4, 1e-3, 0.01, 0.05, 0.1, 0.3, 0.7, 1.2, 1.5]
LAWS = ["poly3", "poly5", "poly7"]
REL = 1e-12
TERMS = default_params().replace(f0=60.0, da1=-20.0, da2=50.0)
"""an offset along +x and friction that differs by direction"""
DOWNHILL = default_params().replace(f0=-400.0, a2=150.0, da2=-30.0)
"""a load that drives the cart towards +x harder than friction holds it: c < 0 moving that way"""
CASES = [
    (default_params(), 1.0),
    (default_params().replace(a2=0.0, a4=100.0), 1.0),
    (TERMS, 1.0),
    (TERMS, -1.0),
    (DOWNHILL, 1.0),
    (DOWNHILL, -1.0),
]


def _shape(law, u):
    """s', s'', s''', s'''' at u."""
    d4 = np.polynomial.polynomial.polyder(np.asarray(law.derivatives[2], dtype=float))
    return (
        float(law.shape(u, 1)),
        float(law.shape(u, 2)),
        float(law.shape(u, 3)),
        float(np.polynomial.polynomial.polyval(u, d4)),
    )


def _close(got, want, *terms):
    """got ≈ want to REL of the largest term that makes up the value (the sum cancels)."""
    scale = max(abs(t) for t in (want, *terms))
    assert got == pytest.approx(want, rel=0.0, abs=REL * scale)


def _sides(law, params, direction):
    """(limit, φ as the model writes it) for the driving side, and the braking side's where it has one."""
    limit = torque_limit(law, forward_axis(params, direction))
    phi = params.forward(direction)
    sides = [(limit, phi)]
    if limit.braking is not None:  # -φ without the Coulomb friction's help: A·s'' - φ_b
        sides.append((limit.braking, ForwardLaw(-direction * params.f0, -phi.b, -phi.a3, phi.a4)))
    return sides


def test_a_helping_load_gives_the_braking_half_a_limit_of_its_own():
    law = polynomial_law("poly5")
    assert DOWNHILL.forward(1.0).c < 0.0 < DOWNHILL.forward(-1.0).c
    assert torque_limit(law, forward_axis(DOWNHILL, 1.0)).braking is not None
    assert torque_limit(law, forward_axis(DOWNHILL, -1.0)).braking is None


@pytest.mark.parametrize("law_name", LAWS)
@pytest.mark.parametrize(("params", "direction"), CASES)
def test_the_torque_limits_force_derivatives_use_the_models_friction(law_name, params, direction):
    for limit, law_phi in _sides(polynomial_law(law_name), params, direction):
        _check_force_derivatives(polynomial_law(law_name), params, limit, law_phi)


def _check_force_derivatives(law, params, limit, law_phi):
    M, D = params.M_eq, 0.4
    for u in (0.0, 0.05, 0.21, 0.37):
        s1, s2, s3, s4 = _shape(law, u)
        for v in VELOCITIES_M_S:
            y = v / (D * s1) if s1 > 0.0 else 1.0 / 0.7  # at u = 0 the move is at rest
            v = D * y * s1
            phi = float(law_phi.value(v))
            fp = float(law_phi.slope(v))
            fpp = float(law_phi.curvature(v))
            inertia = M * D * y * y
            F, Fu, Fuu, Fy, Fuy = limit.force_derivatives(u, y, D)
            _close(F, inertia * s2 + phi, inertia * s2, phi)
            _close(Fu, inertia * s3 + fp * D * y * s2, inertia * s3, fp * D * y * s2)
            fuu_terms = (inertia * s4, fpp * (D * y * s2) ** 2, fp * D * y * s3)
            _close(Fuu, sum(fuu_terms), *fuu_terms)
            _close(Fy, 2.0 * M * D * y * s2 + fp * D * s1, 2.0 * M * D * y * s2, fp * D * s1)
            fuy_terms = (2.0 * M * D * y * s3, D * s2 * fp, D * s2 * fpp * v)
            _close(Fuy, sum(fuy_terms), *fuy_terms)


@pytest.mark.parametrize("law_name", LAWS)
@pytest.mark.parametrize(("params", "direction"), CASES)
def test_the_braking_margin_uses_the_models_friction(law_name, params, direction):
    law = polynomial_law(law_name)
    lm = law_model(law, forward_axis(params, direction))
    law_phi = params.forward(direction)
    D = 0.05
    for u in (0.02, 0.1, 0.25, 0.4):
        s1, s2, s3, s4 = _shape(law, u)
        for v in VELOCITIES_M_S:
            beta = v / s1
            A = params.M_eq * beta * beta / D
            value, bend = braking_margin(lm, A, beta)
            v = beta * s1
            phi = float(law_phi.value(v))
            fp = float(law_phi.slope(v))
            fpp = float(law_phi.curvature(v))
            h, h_u, s2_got = value(u)
            assert s2_got == pytest.approx(s2, rel=1e-13, abs=1e-13)
            _close(h, A * s2 - phi, A * s2, phi)
            _close(h_u, A * s3 - fp * beta * s2, A * s3, fp * beta * s2)
            bend_u, bend_uu = bend(u)
            _close(bend_u, A * s3 - fp * beta * s2, A * s3, fp * beta * s2)
            huu_terms = (A * s4, fpp * (beta * s2) ** 2, fp * beta * s3)
            _close(bend_uu, huu_terms[0] - huu_terms[1] - huu_terms[2], *huu_terms)
