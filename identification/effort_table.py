"""The fit per sample, for other tools: ``DIR/effort.parquet``, one row per sample of every log.

A refit's figures and errors come from these rows; with them a user can plot or re-score the fit in
pandas, polars or duckdb. Columns (SI units; forces on the cart side, whatever the joint — multiply by
the file's ``effort_per_force`` metadata for a motor joint's N·m):

* ``log`` (the log's path), ``role`` (``fit`` or ``validation``: a ``--validate`` log);
* ``stamp_ns`` (int64): the sample's place on the drive's sampling grid [ns since the Unix epoch]
  (within the log's stamp jitter of its recorded stamp; a missing sample's grid point);
* ``position_m``, ``velocity_m_s``, ``acceleration_m_s2``: the kinematics the fit used (the position
  through the fit's zero-phase filter and its derivatives);
* ``force_measured_n``: the measured force through the same filter, taken at the fitted
  torque/position offset (what the fit compares with); ``force_raw_n``: the log's own, unfiltered;
* ``force_model_n`` and each term's share ``force_<term>_n`` (``inertia`` M_eq·ẍ, then the friction
  law's terms and the extra terms the fit took in; their sum is ``force_model_n``);
* ``status``: ``fitted`` (a sample the fit used or, between its decimated samples, could have),
  ``held_out`` (a validation sample: another log, or the held-out last part of a log) or ``left_out``;
  ``reason``: why (for ``left_out`` the first of :data:`~.preparation.LEFT_OUT` that applies; for
  ``fitted`` whether the SQP saw it or it lies between the decimated samples).

The table is written in row groups of at most :data:`ROW_GROUP` rows (an hour of 1 kHz log never
sits in memory at once), to a temporary file that the caller renames into place.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..model import friction_force
from .preparation import LEFT_OUT

if TYPE_CHECKING:
    from .extra_terms import TermColumns
    from .fit import FrictionValues
    from .preparation import PreparedLog
    from .refit import Identification

EFFORT_TABLE = "effort.parquet"
ROW_GROUP = 500_000
STATUS = ("fitted", "held_out", "left_out")
LABELS = ("log", "role", "status", "reason")
"""the table's label columns (dictionary-encoded)"""

_LAW_SHARES = {"coulomb": ("a1",), "viscous": ("a2",), "atan": ("a3", "a4")}
"""each friction term's parameters: its share is the law with the others at zero"""


def term_shares(
    values: FrictionValues, velocity_m_s: np.ndarray, acceleration_m_s2: np.ndarray
) -> dict[str, np.ndarray]:
    """The model force's parts [N]: ``inertia`` M_eq·ẍ and each friction term that is on (the friction
    law of :mod:`axisflow.model.friction` with every other term's parameters at zero)."""
    shares = {"inertia": values.M_eq * np.asarray(acceleration_m_s2)}
    zero = {name: 0.0 for names in _LAW_SHARES.values() for name in names}
    for term, names in _LAW_SHARES.items():
        if not getattr(values, names[0]):
            continue  # the term is off (its first parameter, the size, is zero)
        only = dataclasses.replace(values, **{**zero, **{n: getattr(values, n) for n in names}})
        shares[term] = friction_force(velocity_m_s, only)
    return shares


def write_effort_table(path: str | Path, ident: Identification) -> int:
    """Write the rows of ``ident``'s logs to ``path`` (module docstring); returns the rows written."""
    import pyarrow as pa  # loads here: only a refit writes the table
    import pyarrow.parquet as pq

    rows = 0
    writer = None
    try:
        for batch in _batches(ident):
            table = pa.table(batch)
            if writer is None:
                metadata = {b"effort_per_force": str(ident.logs[0].signals.effort_per_force).encode()}
                # dictionary pages for the labels only: on the float columns they cost 4× the time of
                # the whole write and save a fifth of the size
                writer = pq.ParquetWriter(
                    str(path), table.schema.with_metadata(metadata), use_dictionary=list(LABELS)
                )
            writer.write_table(table, row_group_size=ROW_GROUP)
            rows += table.num_rows
    finally:
        if writer is not None:
            writer.close()
    return rows


def _batches(ident: Identification) -> Iterator[dict[str, object]]:
    import pyarrow as pa

    holdout = ident.settings.holdout
    rate = ident.settings.preparation.fit_rate_hz
    logs = [(log, cols, "fit") for log, cols in zip(ident.logs, ident.columns, strict=True)]
    logs += [
        (log, cols, "validation")
        for log, cols in zip(ident.validation_logs, ident.validation_columns, strict=True)
    ]
    for log, columns, role in logs:
        n = log.signals.t_s.size
        held = np.zeros(n, dtype=bool)
        if role == "validation":
            held[:] = True
        elif holdout:
            t = log.signals.t_s
            held = t >= t[0] + (1.0 - holdout) * (t[-1] - t[0])
        picked = np.zeros(n, dtype=bool)
        picked[log.fit_indices(rate, None if role == "validation" else ~held)] = True
        for start in range(0, n, ROW_GROUP):
            idx = np.arange(start, min(n, start + ROW_GROUP))
            yield _rows(ident, log, columns, role, idx, held[idx], picked[idx], pa)


def _rows(
    ident: Identification,
    log: PreparedLog,
    columns: TermColumns,
    role: str,
    idx: np.ndarray,
    held: np.ndarray,
    picked: np.ndarray,
    pa: object,
) -> dict[str, object]:
    signals = log.signals
    fit = ident.fit
    v, a = log.velocity_m_s[idx], log.acceleration_m_s2[idx]
    shares = term_shares(fit.values, v, a)
    extra = ident.extra
    if len(extra):
        beta = fit.extra_vector
        split = extra.stroke_terms
        parts = columns.at(idx)
        if split:
            shares["stroke"] = parts[:, :split] @ beta[:split]
        if extra.cogging_orders:
            shares["cogging"] = parts[:, split:] @ beta[split:]
    model = np.sum(list(shares.values()), axis=0)
    code = log.left_out[idx] if log.left_out is not None else np.where(log.usable[idx], 0, 3)
    usable = code == 0
    status = np.where(usable & held, 1, np.where(usable, 0, 2)).astype(np.int8)
    reasons = [*LEFT_OUT, "fit sample", "between fit samples (decimated)", "validation log", "holdout"]
    reason = code.astype(np.int8)
    reason = np.where(usable & ~held & picked, len(LEFT_OUT), reason)
    reason = np.where(usable & ~held & ~picked, len(LEFT_OUT) + 1, reason)
    reason = np.where(usable & held, len(LEFT_OUT) + (2 if role == "validation" else 3), reason)
    stamps = signals.start_ns + np.rint(signals.grid.period_ns * idx).astype(np.int64)
    t = signals.t_s
    dictionary = pa.DictionaryArray.from_arrays  # type: ignore[attr-defined]
    out: dict[str, object] = {
        "log": dictionary(np.zeros(idx.size, dtype=np.int8), [signals.source]),
        "role": dictionary(np.zeros(idx.size, dtype=np.int8), [role]),
        "stamp_ns": stamps,
        "position_m": log.position_m[idx],
        "velocity_m_s": v,
        "acceleration_m_s2": a,
        "force_measured_n": log.force_at(idx, ident.delay_s),
        "force_raw_n": np.interp(t[idx] + ident.delay_s, t, signals.force_n),
        "force_model_n": model,
    }
    out.update({f"force_{term}_n": share for term, share in shares.items()})
    out["status"] = dictionary(status, list(STATUS))
    out["reason"] = dictionary(reason, reasons)
    return out
