"""The typed certificates: the JSON keys each solver path prints, round trips, and bad input."""

import json
import math

import pytest
from axisflow.model import MoveError, default_params
from axisflow.planner import (
    Active,
    Case,
    MinTimeCertificate,
    MoveProblem,
    TimeEnergyCertificate,
    make_backend,
)
from axisflow.planner.certificates import certificate_from_dict


def _plan(x0, x1, case, accounting="positive", solver="exact", **kw):
    params = default_params().replace(energy_accounting=accounting)
    backend = make_backend(solver)
    problem = MoveProblem(x0, x1, "poly5", case, **kw)
    backend.prepare(problem, params)
    return backend.solve(problem, params)


MIN_TIME = ["t_lower_s", "t_upper_s", "gap_s"]
BRACKET = ["gap_j", "t_lower_s", "t_upper_s", "dJ_dT"]
AT_BOUND = ["gap_j", "dJ_dT"]
AT_LIMIT = ["gap_j", "dJ_dT", "t_infeasible_s"]
TE = Case.MIN_TIME_ENERGY

# (move, case, accounting, options) → what decides it and the keys `axisflow plan --json` prints, in order
PATHS = [
    ((0.2, 0.6), Case.MIN_TIME, "positive", {}, Active.TORQUE, MIN_TIME),
    ((0.2, 0.201), Case.MIN_TIME, "positive", {}, Active.T_MIN, MIN_TIME),
    ((0.2, 0.6), TE, "positive", {}, Active.OPTIMUM, BRACKET),  # no braking energy at the optimum
    ((0.3, 0.33), TE, "absolute", {}, Active.OPTIMUM, BRACKET),  # braking energy: the root of dJ/dT
    ((0.2, 0.6), TE, "signed", {}, Active.OPTIMUM, BRACKET),
    ((0.2, 0.201), TE, "positive", {}, Active.T_MIN, AT_BOUND),
    ((0.2, 0.6), TE, "signed", {"omega": 0.0}, Active.T_MAX, AT_BOUND),
    ((0.0, 0.8), TE, "positive", {"omega": 0.999}, Active.TORQUE, AT_LIMIT),
    ((0.0, 0.8), TE, "signed", {"omega": 0.999}, Active.TORQUE, AT_LIMIT),
]


@pytest.mark.parametrize(("move", "case", "accounting", "options", "active", "keys"), PATHS)
def test_each_path_prints_the_keys_it_always_printed_and_round_trips(
    move, case, accounting, options, active, keys
):
    r = _plan(*move, case, accounting, **options)
    assert r.message == f"exact; active: {active.value}"
    data = r.certificate.to_dict()
    assert list(data) == keys
    assert all(isinstance(v, float) for v in data.values())
    back = certificate_from_dict(json.loads(json.dumps(data)))
    assert back == r.certificate


def test_a_result_without_a_proof_has_none_and_prints_an_empty_object():
    assert _plan(0.2, 0.6, Case.MIN_TIME, solver="ipopt").certificate is None
    zero = _plan(0.4, 0.4, Case.MIN_TIME_ENERGY)
    assert zero.certificate is None and zero.message.startswith("zero move: |x1 - x0| = 0 m")
    assert certificate_from_dict({}) is None


def test_the_active_constraint_keeps_its_strings():
    assert [a.value for a in Active] == ["t_min", "velocity", "torque", "t_max", "optimum", "zero-length"]
    assert Active("torque") is Active.TORQUE and f"{Active.T_MAX}" == "t_max"


def test_the_min_time_gap_is_the_bracket_width():
    cert = MinTimeCertificate(t_lower_s=0.5, t_upper_s=0.625)
    assert cert.gap_s == 0.125
    assert cert.to_dict() == {"t_lower_s": 0.5, "t_upper_s": 0.625, "gap_s": 0.125}


def test_an_unproved_interior_optimum_round_trips_with_a_nan_gap():
    cert = TimeEnergyCertificate(gap_j=math.nan, dJ_dT=0.25)
    back = certificate_from_dict(json.loads(json.dumps(cert.to_dict())))
    assert math.isnan(back.gap_j) and back.dJ_dT == 0.25 and not back.has_bracket


@pytest.mark.parametrize(
    ("data", "match"),
    [
        ({"t_lower_s": 0.1, "gap_s": 0.0}, r"missing keys \['t_upper_s'\]"),
        ({"t_lower_s": 0.1, "t_upper_s": 0.2, "gap_s": 0.1, "x": 1.0}, r"unknown keys \['x'\]"),
        ({"gap_j": 0.0, "dJ_dT": 1.0, "t_max_s": 3.0}, r"unknown keys \['t_max_s'\]"),
        ({"gap_j": 0.0}, r"missing keys \['dJ_dT'\]"),
        ({"gap_j": "0", "dJ_dT": 1.0}, r"certificate gap_j = '0' is not a finite number or NaN"),
        ({"gap_j": 0.0, "dJ_dT": math.inf}, r"certificate dJ_dT = inf is not a finite number or NaN"),
        (
            {"gap_j": 0.0, "dJ_dT": 1.0, "t_lower_s": 2.0},
            r"needs both ends, got t_lower_s = 2.0 and t_upper_s = None",
        ),
    ],
)
def test_bad_certificates_are_refused_with_the_offending_key(data, match):
    with pytest.raises(MoveError, match=match):
        certificate_from_dict(data)
