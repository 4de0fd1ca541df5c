"""The adaptation's decisions, table-driven, on windows made in closed form (tests/.../moves.py): what
an informative window with a real change gives (accepted, version + 1, near the truth), and each rule
that turns an estimate down, observed in the record's decision and reason."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from axisflow.acquisition.wire.params_estimate import Decision, ParamsEstimate
from axisflow.identification.online import AcceptanceRules, Adapter, AdaptSettings
from axisflow.model import load_params

from .moves import NOMINAL, T0_NS, at_rest, moves, truth

FIXED = AdaptSettings(torque_delay_s=0.0)  # the closed-form torque has no offset to estimate
WARM = truth(coulomb=0.95, viscous=0.85)
"""the axis a few minutes into warming up: a2 −15 %, a1 and a3 −5 %"""


def _first_step(samples, settings=FIXED, params=NOMINAL) -> tuple[Adapter, ParamsEstimate]:
    adapter = Adapter("a0", params, settings)
    adapter.add(samples.stamp_ns, samples.angle_rad, samples.torque_nm)
    assert adapter.due()
    return adapter, adapter.step()


def _fit_then_holdout(fit_values, holdout_values, settings=FIXED):
    """A window whose fitted part comes from one axis and whose held-out part from another."""
    s = settings
    first = moves(fit_values, s.window_s - s.holdout_s, seed=3)
    rest = moves(holdout_values, s.holdout_s + 0.5, seed=4, start_ns=int(first.stamp_ns[-1]) + 1_000_000)
    return first.then(rest)


CASES = [
    # (id, samples, settings, decision, fragments of the reason)
    ("a good window", lambda: moves(WARM, 30.5), FIXED, Decision.ACCEPTED, ("accepted: held-out RMS error",)),
    (
        "at rest",
        lambda: at_rest(30.5),
        FIXED,
        Decision.UNINFORMATIVE,
        ("0 samples to fit", "0 direction changes"),
    ),
    (
        "slow moves",
        lambda: moves(WARM, 30.5, speed_m_s=0.05),
        FIXED,
        Decision.UNINFORMATIVE,
        ("a speed range of", "(at least 0.2 m/s)"),
    ),
    (
        "an implausible jump",
        lambda: moves(truth(viscous=1.6), 30.5),
        FIXED,
        Decision.IMPLAUSIBLE,
        ("implausible change: a2", "+60.0 %, bound ±30 %"),
    ),
    (
        "worse on the held-out samples",
        lambda: _fit_then_holdout(WARM, truth()),
        FIXED,
        Decision.NO_IMPROVEMENT,
        ("no improvement: held-out RMS error", "needs -2.0 % on version 0"),
    ),
    (
        "σ above its bound",
        lambda: moves(WARM, 30.5, noise_nm=0.05),
        dataclasses.replace(FIXED, rules=AcceptanceRules(max_relative_std={"a2": 0.001})),
        Decision.UNCERTAIN,
        ("too uncertain: σ(a2)", "(bound 0.1 %)"),
    ),
]


@pytest.mark.parametrize(("name", "make", "settings", "decision", "says"), CASES, ids=[c[0] for c in CASES])
def test_each_rule_decides_and_says_why(name, make, settings, decision, says):
    adapter, record = _first_step(make(), settings)
    assert record.decision is decision, record.reason
    for fragment in says:
        assert fragment in record.reason
    accepted = decision is Decision.ACCEPTED
    assert (record.version, record.base_version, record.accepted) == (int(accepted), 0, accepted)
    assert adapter.version == record.version
    assert (adapter.accepted is NOMINAL) is not accepted
    assert ParamsEstimate.decode(record.encode()).reason == record.reason  # it crosses the wire as it is


def test_an_accepted_estimate_lands_near_the_truth_with_its_sigma():
    adapter, record = _first_step(moves(WARM, 30.5, noise_nm=0.01))
    assert record.decision is Decision.ACCEPTED and record.fitted == ("M_eq", "a2", "coulomb")
    for name in ("M_eq", "a1", "a2", "a3"):
        value, sigma, true = record.value_of[name], record.std_of[name], getattr(WARM, name)
        assert abs(value - true) <= max(4 * sigma, 1e-3 * true), (name, value, true, sigma)
        assert 0 < sigma < 0.02 * true
    assert np.isnan(record.std_of["a4"]) and record.value_of["a4"] == NOMINAL.a4  # held
    assert adapter.accepted.a2 == pytest.approx(record.value_of["a2"])
    assert adapter.accepted.M_eq == pytest.approx(record.value_of["M_eq"])
    assert record.window_end_ns - record.window_start_ns == pytest.approx(30e9, abs=2e6)
    assert record.samples > 500 and record.holdout_rms_nm < record.holdout_rms_kept_nm


def test_versions_count_up_and_a_settled_estimate_is_kept():
    """The next window of the same axis brings no improvement: the version stays; a window of an axis
    that has drifted further is accepted as version 2, judged against version 1."""
    settings = FIXED
    adapter, first = _first_step(moves(WARM, 30.5, seed=5))
    assert first.version == 1
    same = moves(WARM, 5.5, seed=6, start_ns=int(adapter.ring.newest_ns) + 1_000_000)
    adapter.add(same.stamp_ns, same.angle_rad, same.torque_nm)
    assert adapter.due()
    kept = adapter.step()
    assert (kept.decision, kept.version, kept.base_version) == (Decision.NO_IMPROVEMENT, 1, 1)
    hotter = truth(coulomb=0.9, viscous=0.75)
    later = moves(hotter, settings.window_s + 0.5, seed=7, start_ns=int(adapter.ring.newest_ns) + 1_000_000)
    adapter.add(later.stamp_ns, later.angle_rad, later.torque_nm)
    steps = []
    while adapter.due():
        steps.append(adapter.step())
    assert steps[-1].decision is Decision.ACCEPTED, [s.reason for s in steps]
    assert (steps[-1].version, steps[-1].base_version) == (2, 1)
    assert steps[-1].value_of["a2"] == pytest.approx(hotter.a2, rel=0.03)


def test_slow_moves_hold_the_inertia_and_say_so():
    settings = dataclasses.replace(FIXED, rules=AcceptanceRules(min_inertial_share=5.0))  # never reached
    _adapter, record = _first_step(moves(WARM, 30.5), settings)
    assert "M_eq held: inertial share" in record.reason
    assert "M_eq" not in record.fitted and np.isnan(record.std_of["M_eq"])


def test_stamps_off_any_grid_are_a_failed_fit_not_an_error():
    samples = moves(WARM, 30.5)
    bad = samples.stamp_ns.copy()
    bad[1000] += 600_000  # 0.6 ms late: 0.4 ms before the next sample
    _adapter, record = _first_step(dataclasses.replace(samples, stamp_ns=bad))
    assert record.decision is Decision.FIT_FAILED
    assert "are 0.400 ms apart, less than half the log's step of 1.000 ms" in record.reason


def test_the_offset_is_estimated_on_windows_apart_and_then_held():
    adapter = Adapter("a0", NOMINAL, AdaptSettings())  # the offset to be estimated
    samples = moves(WARM, 95.0, seed=11)
    decisions = []
    for lo in range(0, samples.stamp_ns.size, 2000):
        adapter.add(
            samples.stamp_ns[lo : lo + 2000],
            samples.angle_rad[lo : lo + 2000],
            samples.torque_nm[lo : lo + 2000],
        )
        if adapter.due():
            decisions.append(adapter.step())
    assert len(adapter.delay_windows) >= 1  # windows 30 s apart: at most three in 95 s
    assert all(abs(d.estimate_s) < 3 * d.std_s + 1e-4 for d in adapter.delay_windows)  # the truth: 0
    assert adapter.delay is not None and abs(adapter.delay_s) <= 1e-3
    assert {d.decision for d in decisions} <= {Decision.ACCEPTED, Decision.NO_IMPROVEMENT}


def test_the_initial_record_is_version_zero_with_the_starting_values():
    record = Adapter("a0", NOMINAL).initial_record(T0_NS)
    assert (record.version, record.decision, record.accepted) == (0, Decision.INITIAL, True)
    assert record.value_of["M_eq"] == NOMINAL.M_eq and record.value_of["a2"] == NOMINAL.a2


def test_an_axis_with_an_offset_and_an_asymmetry_refits_them_and_carries_every_term():
    """The belt file of docs/axes (f0 25 N, da1 6 N, da2 −12 N·s/m; the packaged transmission): its
    asymmetry drifts with the rest; the accepted record carries f0 (held: the force at rest) and the
    refit da1, da2, and the set it gives a planner is the adapter's."""
    axis = load_params(Path(__file__).parents[3] / "docs" / "axes" / "belt.toml")
    warm = dataclasses.replace(truth(axis, coulomb=0.95, viscous=0.85), f0=axis.f0, da1=9.0, da2=-8.0)
    adapter, record = _first_step(moves(warm, 30.5, noise_nm=0.01), params=axis)
    assert record.decision is Decision.ACCEPTED, record.reason
    assert record.fitted == ("M_eq", "a2", "da1", "da2", "coulomb")
    for name in ("da1", "da2"):
        value, sigma = record.value_of[name], record.std_of[name]
        assert abs(value - getattr(warm, name)) <= 4 * sigma and 0 < sigma < 1.0, (name, value, sigma)
    assert record.value_of["f0"] == axis.f0 and np.isnan(record.std_of["f0"])
    planned = ParamsEstimate.decode(record.encode()).applied_to(axis)
    assert planned.friction == adapter.accepted.friction and planned.terms == axis.terms
    assert planned.M_eq == pytest.approx(adapter.accepted.M_eq, rel=1e-12)
    start = adapter.initial_record(T0_NS).value_of
    assert (start["f0"], start["da1"], start["da2"]) == (axis.f0, axis.da1, axis.da2)
