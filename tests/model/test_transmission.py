"""Each transmission kind's k and reflected inertia against the closed forms of model/transmission.py's
table (a belt turns two pulleys, a rack one pinion)."""

import math

import pytest
from axisflow.model.transmission import BallScrew, Belt, LinearMotor, RackPinion

J_M, J_G, J_P, R, I_R = 1.5e-4, 5e-5, 2e-4, 0.03, 10.0


@pytest.mark.parametrize(
    ("transmission", "k", "reflected"),
    [
        (Belt(J_M, J_G, J_P, R, I_R), R / I_R, ((J_M + J_G) * I_R**2 + 2 * J_P) / R**2),
        (RackPinion(J_M, J_G, J_P, R, I_R), R / I_R, ((J_M + J_G) * I_R**2 + J_P) / R**2),
        (
            BallScrew(J_M, J_G, 3e-5, 0.01, 2.0),
            0.01 / (2 * math.pi * 2.0),
            (J_M + J_G) * (2 * math.pi * 2.0 / 0.01) ** 2 + 3e-5 * (2 * math.pi / 0.01) ** 2,
        ),
        (LinearMotor(), 1.0, 0.0),
    ],
    ids=lambda v: getattr(v, "kind", ""),
)
def test_each_kind_gives_its_k_and_reflected_inertia(transmission, k, reflected):
    assert transmission.metres_per_radian == pytest.approx(k, rel=1e-15)
    assert transmission.force_per_torque * transmission.metres_per_radian == pytest.approx(1.0, rel=1e-15)
    assert transmission.reflected_mass_kg() == pytest.approx(reflected, rel=1e-12)
    assert set(transmission.to_dict()) == {"kind", *transmission.keys}
