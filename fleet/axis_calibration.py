"""What an axis's windows hold fixed: the torque/position offset and the cogging orders, estimated once
per axis from its first windows.

A day's log of a fleet is short (the simulated one: 35 s of motion). On one such log the offset δ
between the drive's torque and position samples is not resolvable (:mod:`axisflow.identification.
alignment`: its σ is a sample period or more), so a fit of the window alone uses δ = 0 — and δ is not
0: the simulated drive reports the current of the tick before (0.5 ms), and the elastic belt makes the
cart's friction lag the motor's encoder by a further 0.2–0.9 ms depending on speed (b/k, the friction's
slope over the belt's stiffness). Fitted with δ = 0, the Coulomb friction at 0.2 m/s of a simulated
fleet came out +0.05 % high, about 2 σ of a window's fit: only 19 % of the fits lay within 1 σ of the
truth (docs/fleet.md).

So each axis is **calibrated** once, on its first :data:`CALIBRATION_WINDOWS` windows that can be
identified: each is fitted alone with the fleet's fixed structure (:mod:`.window_fit`), δ estimated
with its σ and the cogging orders its residual shows found (``--cogging auto``); the axis's δ is the
estimates' inverse-variance weighted mean (σ = (Σ 1/σᵢ²)^(−1/2): five days of the simulated fleet give
~0.2 ms), and its cogging orders those found in more than half of the windows. Each window keeps its
own friction in this (a pooled fit of several days would mix the friction of days before and after a
change). Every window of the axis is then fitted with that δ and those orders held, so that its
parameters mean the same from window to window.

An error in the held δ moves every window of the axis the same way: a **systematic** part of the
error against the truth that no single window's σ (the spread of its samples) counts, and that each
axis's comparison with its own baseline (:mod:`.alarms`) cancels. It is estimated here, once: the last
calibration window is fitted with δ held and with δ one σ further, and each value's change is its
systematic σ (:attr:`AxisCalibration.systematic`; the Coulomb friction's is in every row of the
axis, :attr:`~.fits.FitRow.coulomb_sys_std_n`). The error of a window's value against the truth then has
σ² = σ_window² + σ_systematic².

A calibration has a key, a hash of the axis's calibration windows (their keys) and the method; it is part
of each of the axis's window keys, so new first windows (an axis that had fewer than
:data:`CALIBRATION_WINDOWS`) calibrate the axis again and fit its windows again, and later windows
change nothing. The calibrations are kept in ``DIR/calibrations.parquet`` (:func:`write_calibrations`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..model import AxisflowError
from ..model.files import atomic_path
from .catalog import FORMAT_KEY, read_parquet_table
from .errors import FleetError
from .fits import FITTED, OK
from .windows import Window, WindowPart

if TYPE_CHECKING:
    from .window_fit import FitSettings

CALIBRATION_WINDOWS = 5
"""an axis's first windows (that can be identified) pooled for its offset and cogging orders"""
CALIBRATIONS_FILE = "calibrations.parquet"
CALIBRATIONS_FORMAT = "axisflow.fleet.calibrations/1"
SYSTEMATIC = (*FITTED, "coulomb_n")
"""the values with a systematic σ: eq. (1)'s parameters and the Coulomb friction at speed"""


@dataclass(frozen=True)
class CalibrationPlan:
    """The windows an axis's calibration pools, and its key."""

    axis: str
    windows: tuple[Window, ...]
    key: str


@dataclass(frozen=True)
class AxisCalibration:
    """One axis's calibration (see the module docstring); SI units, NaN where a value does not exist."""

    axis: str
    key: str
    windows: int
    """calibration windows"""
    start_ns: int
    end_ns: int
    """the span of the calibration windows [ns since the Unix epoch]"""
    torque_delay_s: float
    """the offset every window of the axis holds [s] (NaN: none; each window estimates its own)"""
    torque_delay_std_s: float
    cogging_orders: str
    """the cogging orders every window holds, comma-separated ("" for none)"""
    M_eq_sys_std: float
    a1_sys_std: float
    a2_sys_std: float
    a3_sys_std: float
    a4_sys_std: float
    coulomb_n_sys_std: float
    """systematic σ of each value from the held offset's σ (module docstring)"""
    status: str
    reason: str
    wall_s: float

    @property
    def ok(self) -> bool:
        return self.status == OK

    @property
    def delay_s(self) -> float | None:
        """The offset the windows hold (None: each estimates its own)."""
        return self.torque_delay_s if self.ok and math.isfinite(self.torque_delay_s) else None

    @property
    def orders(self) -> tuple[int, ...]:
        return tuple(int(o) for o in self.cogging_orders.split(",") if o)

    @property
    def systematic(self) -> dict[str, float]:
        """The systematic σ of each of :data:`SYSTEMATIC`."""
        return {name: getattr(self, f"{name}_sys_std") for name in SYSTEMATIC}


def plan_calibrations(
    windows: Sequence[Window], settings: FitSettings, count: int = CALIBRATION_WINDOWS
) -> dict[str, CalibrationPlan]:
    """Per axis, the first ``count`` of its windows that can be identified (enough motion, one joint
    name), and the calibration's key; an axis without such a window has none."""
    by_axis: dict[str, list[Window]] = {}
    for w in sorted(windows, key=lambda w: (w.axis, w.start_ns)):
        if settings.motion.shortfall(w.moving_s, w.reversals, w.speed_high_m_s) or not _one_joint(w.parts):
            continue
        chosen = by_axis.setdefault(w.axis, [])
        if len(chosen) < count:
            chosen.append(w)
    plans = {}
    for axis, chosen in by_axis.items():
        text = json.dumps({"axis": axis, "windows": [w.key for w in chosen], "method": settings.method()})
        key = hashlib.blake2b(text.encode(), digest_size=16).hexdigest()
        plans[axis] = CalibrationPlan(axis, tuple(chosen), key)
    return plans


def _one_joint(parts: Sequence[WindowPart]) -> bool:
    return len({(p.topic, p.joint, p.joint_kind) for p in parts}) == 1


def calibrated_windows(
    windows: Sequence[Window], settings: FitSettings
) -> tuple[list[Window], dict[str, CalibrationPlan]]:
    """The windows (of :func:`~.windows.plan_windows`) keyed with their axis's calibration too (a
    window of an axis without one keeps its key), and the calibrations' plans."""
    plans = plan_calibrations(windows, settings)
    out = []
    for w in windows:
        plan = plans.get(w.axis)
        if plan is not None:
            key = hashlib.blake2b(f"{w.key} {plan.key}".encode(), digest_size=16).hexdigest()
            w = dataclasses.replace(w, key=key)
        out.append(w)
    return out, plans


def calibrate_axis(plan: CalibrationPlan, settings: FitSettings) -> AxisCalibration:
    """The calibration of ``plan`` (module docstring); never raises for the logs' own trouble: a
    calibration that fails is a record saying why (its windows then estimate their own offset)."""
    t0 = time.perf_counter()
    nan = math.nan
    try:
        held, std, orders, systematic = _calibrate(plan, settings)
        status, reason = OK, ""
    except Exception as exc:
        held = std = nan
        orders, systematic, status = (), dict.fromkeys(SYSTEMATIC, nan), "failed"
        reason = str(exc) if isinstance(exc, AxisflowError) else f"{type(exc).__name__}: {exc}"
    return AxisCalibration(
        axis=plan.axis,
        key=plan.key,
        windows=len(plan.windows),
        start_ns=plan.windows[0].start_ns,
        end_ns=plan.windows[-1].end_ns,
        torque_delay_s=held,
        torque_delay_std_s=std,
        cogging_orders=",".join(str(o) for o in orders),
        **{f"{n}_sys_std": v for n, v in systematic.items()},
        status=status,
        reason=reason,
        wall_s=time.perf_counter() - t0,
    )


def _calibrate(
    plan: CalibrationPlan, settings: FitSettings
) -> tuple[float, float, tuple[int, ...], dict[str, float]]:
    """(offset, its σ, cogging orders, systematic σ of each of :data:`SYSTEMATIC`)."""
    from ..identification.refit import identify
    from .window_fit import coulomb_at_speed

    estimates: list[tuple[float, float]] = []
    found: dict[int, int] = {}
    last = None
    for window in plan.windows:
        s = settings.identify_settings(window, None)
        ident = identify([p.path for p in window.parts], settings.nominal, s)
        assert ident.delay is not None  # estimated: the settings give none
        if math.isfinite(ident.delay.std_s) and ident.delay.std_s > 0.0:
            estimates.append((ident.delay.estimate_s, ident.delay.std_s))
        for order in ident.extra.cogging_orders:
            found[order] = found.get(order, 0) + 1
        last = (window, s)
    orders = tuple(sorted(o for o, n in found.items() if 2 * n > len(plan.windows)))
    if not estimates:
        return 0.0, math.nan, orders, dict.fromkeys(SYSTEMATIC, math.nan)
    weights = [1.0 / sd**2 for _, sd in estimates]
    held = sum(w * d for w, (d, _) in zip(weights, estimates, strict=True)) / sum(weights)
    std = 1.0 / math.sqrt(sum(weights))
    assert last is not None
    window, s = last
    extra = dataclasses.replace(s.extra, cogging_orders=orders, auto_cogging=False)
    paths = [p.path for p in window.parts]
    at, shifted = (
        identify(paths, settings.nominal, dataclasses.replace(s, torque_delay_s=d, extra=extra))
        for d in (held, max(-0.1, min(0.1, held + std)))
    )
    a, b = at.fit.values.as_dict(), shifted.fit.values.as_dict()
    systematic = {n: abs(b[n] - a[n]) for n in FITTED}
    systematic["coulomb_n"] = abs(coulomb_at_speed(shifted)[0] - coulomb_at_speed(at)[0])
    return held, std, orders, systematic


_TYPES = {"int": "int64", "float": "float64", "str": "string"}


def write_calibrations(folder: Path, calibrations: Sequence[AxisCalibration]) -> Path:
    """``folder/calibrations.parquet`` (replaced atomically), sorted by axis and start."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    types = {"int64": pa.int64(), "float64": pa.float64(), "string": pa.string()}
    schema = pa.schema(
        [pa.field(f.name, types[_TYPES[str(f.type)]], nullable=False) for f in fields(AxisCalibration)],
        metadata={FORMAT_KEY: CALIBRATIONS_FORMAT.encode()},
    )
    ordered = sorted(calibrations, key=lambda c: (c.axis, c.start_ns, c.key))
    columns = {f.name: [getattr(c, f.name) for c in ordered] for f in fields(AxisCalibration)}
    table = pa.table(columns, schema=schema)
    path = folder / CALIBRATIONS_FILE
    with atomic_path(path) as part:
        pq.write_table(table, part)
    return path


def read_calibrations(folder: str | Path, missing_ok: bool = False) -> list[AxisCalibration]:
    """The records of ``folder/calibrations.parquet`` ([] when it does not exist and ``missing_ok``)."""
    path = Path(folder) / CALIBRATIONS_FILE
    if not path.exists():
        if missing_ok:
            return []
        raise FleetError(f"{folder} has no {CALIBRATIONS_FILE}: run `axisflow fleet identify` first")
    table: Any = read_parquet_table(path, CALIBRATIONS_FORMAT, "fleet calibrations table")
    names = [f.name for f in fields(AxisCalibration)]
    missing = [n for n in names if n not in table.column_names]
    if missing:
        raise FleetError(f"{path} lacks the column(s) {', '.join(missing)}")
    data = table.select(names).to_pydict()
    return [AxisCalibration(**{n: data[n][i] for n in names}) for i in range(table.num_rows)]
