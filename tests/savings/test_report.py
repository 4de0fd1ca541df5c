"""The savings record: savings.json round trip, the derived figures, the page."""

import json

import pytest

from axisflow.savings.report import (
    J_PER_KWH,
    MoveRow,
    RunRow,
    SavingsReport,
    SavingsReportError,
    markdown,
    read_report,
    write_report,
)


def _row(k, T, e, measured):
    return MoveRow(k, 0.1 * k, 0.1 * k + 0.2, T, e, measured, 3.0, 3.1, 500.0, 520.0, 2.0 * T, 2.1 * T)


def _report():
    runs = (
        RunRow("baseline", "trapezoid", None, (_row(1, 0.5, 100.0, 105.0), _row(2, 0.0, 0.0, None))),
        RunRow("equal-time", "poly3", None, (_row(1, 0.5, 96.0, 101.0), _row(2, 0.0, 0.0, None)), (1,)),
        RunRow("matched-omega", "poly3", 0.99, (_row(1, 0.5, 95.0, None), _row(2, 0.0, 0.0, None))),
    )
    return SavingsReport(
        source="a test",
        params_source="default",
        energy_accounting="positive",
        baseline="trapezoid",
        limits={"velocity_m_s": 1.5, "acceleration_m_s2": 3.0, "jerk_m_s3": None},
        law="poly3",
        match_status="matched",
        runs=runs,
        front=((0.9, 3.0, 80.0), (0.99, 0.5, 95.0)),
        baseline_points={"trapezoid": (0.5, 100.0), "scurve": (0.6, 99.0)},
        cycles_per_day=1000.0,
        days_per_year=250.0,
        price_per_kwh=0.3,
        plant="ideal",
    )


def test_round_trip(tmp_path):
    report = _report()
    write_report(report, tmp_path)
    assert read_report(tmp_path / "savings.json") == report
    with pytest.raises(SavingsReportError, match="no field 'runs'"):
        SavingsReport.decode({k: v for k, v in report.encode().items() if k != "runs"})


def test_savings_per_cycle_and_per_year():
    report = _report()
    assert report.saving_pct("equal-time", measured=False) == pytest.approx(4.0)
    assert report.saving_pct("equal-time", measured=True) == pytest.approx((105 - 101) / 105 * 100)
    assert report.saving_pct("matched-omega", measured=True) is None  # a move not measured
    s = report.summary()["runs"]["baseline"]
    assert s["kwh_per_year_model"] == pytest.approx(100.0 * 1000 * 250 / J_PER_KWH)
    assert s["cost_per_year_measured"] == pytest.approx(105.0 * 1000 * 250 / J_PER_KWH * 0.3)
    assert s["rms_torque_model_nm"] == pytest.approx((2.0 * 0.5 / 0.5) ** 0.5)
    assert json.loads(json.dumps(report.encode(), allow_nan=False))["summary"]["runs"]["equal-time"][
        "slower_moves"
    ] == [1]


def test_the_page_states_its_assumptions():
    page = markdown(_report())
    assert "| axisflow, move by move | poly3 | 0.500 | 96.0 | 101.0 | +4.00 % | +3.81 % |" in page
    assert "motor's and the drive's efficiency" in page and "1000 cycles a day on 250 days" in page
