"""effort.parquet: one row per sample of every log, read back by another Parquet reader (duckdb), the
same errors as the report."""

import duckdb
import numpy as np
import pytest
from axisflow.acquisition import read_joint_states
from axisflow.identification.refit import IdentifySettings

from axisflow.experiment.refit_folder import identify_to

from .conftest import NOMINAL

pytestmark = pytest.mark.slow  # a whole refit with its figure and table

SETTINGS = IdentifySettings(
    topic="/robot/joint_states", joint="slider_motor", joint_kind="motor", torque_delay_s=0.0, holdout=0.25
)


@pytest.fixture(scope="module")
def refit(foreign_log, tmp_path_factory):
    out = tmp_path_factory.mktemp("effort")
    _ident, report = identify_to(out, [foreign_log], NOMINAL, SETTINGS)
    return out / "effort.parquet", report, foreign_log


def _one(sql: str):
    return duckdb.sql(sql).fetchall()[0]


def test_every_sample_has_a_row_with_its_stamp(refit):
    table, report, log = refit
    stamps = read_joint_states(log, SETTINGS.topic).joint(SETTINGS.joint).stamp_ns
    rows = duckdb.sql(f"select stamp_ns from '{table}' order by stamp_ns").fetchnumpy()["stamp_ns"]
    assert report["effort_table"] == {"file": "effort.parquet", "rows": stamps.size}
    assert np.array_equal(rows, stamps)  # the log's own stamps: exact on a grid without jitter


def test_the_rows_rescore_to_the_reports_errors(refit):
    table, report, _log = refit
    error = "sqrt(avg((force_measured_n - force_model_n)^2))"
    n, rms = _one(f"select count(*), {error} from '{table}' where status = 'held_out'")
    k = NOMINAL.r / NOMINAL.i_r  # the report's errors are in the motor joint's N·m
    assert n == report["validation"]["samples"]
    assert k * rms == pytest.approx(report["validation"]["rms_nm"], rel=1e-9)
    fitted, sqp = _one(
        f"select count(*), count(*) filter (reason = 'fit sample') from '{table}' where status = 'fitted'"
    )
    assert fitted == report["samples"]["used"] - report["validation"]["samples"]
    assert sqp == report["samples"]["fitted"]


def test_the_terms_shares_add_up_to_the_model_and_left_out_rows_say_why(refit):
    table, report, _log = refit
    shares = " + ".join(
        c
        for c in duckdb.sql(f"select * from '{table}' limit 0").columns
        if c.startswith("force_") and c not in ("force_measured_n", "force_raw_n", "force_model_n")
    )
    assert {"force_inertia_n", "force_coulomb_n", "force_viscous_n", "force_atan_n"} <= set(
        shares.split(" + ")
    )
    assert _one(f"select max(abs(force_model_n - ({shares}))) from '{table}'")[0] < 1e-9
    reasons = dict(
        duckdb.sql(f"select reason, count(*) from '{table}' where status = 'left_out' group by 1").fetchall()
    )
    assert reasons["stationary"] == report["samples"]["stationary"]
    assert reasons["edge"] == report["samples"]["trimmed"]
