"""The paper's Fig. 5: the axis through random way points, per motion law, in both cases.

For each law (poly3, poly5, poly7) the moves between consecutive way points, one after the other as
the bridge runs them (each starts on the tick the previous one ends), drawn as position, velocity and
motor torque over time, with the limits dashed (the stroke [0, L], ±v_max, ±tau_max) and a vertical
line at each way point. One figure per case: minimum time (the paper's Fig. 5a) and minimum
time-energy with ω = 0.9 (Fig. 5b).

The traces come either

* from the plans (:func:`planned_traces`): each move planned by the exact back-end, sampled at the
  drive's 1 kHz ticks (:mod:`axisflow.model.sampling`) and its motor torque computed with the model,
  eq. (1) — what the axis is commanded, not what it measured; or
* from a recording of the planner's runs (:func:`recorded_traces`): the plan records and move statuses
  give each run's moves and ticks, the measured samples of ``…/state`` give x, ẋ and τ_m.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from itertools import pairwise
from pathlib import Path

import numpy as np

from ..acquisition.logs.reader import read_joint_states, read_messages
from ..acquisition.wire.keys import AxisKeys, topic_for_key
from ..acquisition.wire.move_status import MOVE_STATUS_TYPE, MoveState, MoveStatus
from ..acquisition.wire.plan_record import PLAN_TYPE, PlanRecord
from ..model import EXECUTION_PERIOD_S, AxisParams, cart_force, motor_torque, move_ticks
from ..planner import DEFAULT_OMEGA, Case, MoveProblem, make_backend
from .errors import VizError
from .png import png_bytes, pyplot
from .samples import AxisSamples

LAWS = ("poly3", "poly5", "poly7")
CASE_TITLES = {
    Case.MIN_TIME: "Fig. 5a — minimum time",
    Case.MIN_TIME_ENERGY: f"Fig. 5b — minimum time-energy, ω = {DEFAULT_OMEGA:g}",
}


@dataclass(frozen=True)
class LawTrace:
    """One law's run: samples over time ``t_s`` [s from the first move's start] and the times [s] at
    which the axis reaches each way point (the first at 0)."""

    law: str
    t_s: np.ndarray
    position_m: np.ndarray
    velocity_m_s: np.ndarray
    torque_nm: np.ndarray
    waypoint_times_s: np.ndarray


def planned_traces(
    params: AxisParams, waypoints: Sequence[float], case: Case, omega: float = DEFAULT_OMEGA
) -> list[LawTrace]:
    """Per law: the exact planner's moves through ``waypoints`` [m], sampled at 1 kHz with the model."""
    backend = make_backend("exact")
    traces = []
    for law in LAWS:
        parts_t, parts = [], []
        t0_ticks = 0
        arrivals = [0.0]
        for x0, x1 in pairwise(waypoints):
            move = backend.solve(MoveProblem(float(x0), float(x1), law, case, omega), params).move
            ticks = move_ticks(move.duration_s)
            local = np.arange(ticks) * EXECUTION_PERIOD_S
            parts_t.append((t0_ticks + np.arange(ticks)) * EXECUTION_PERIOD_S)
            parts.append(move.sample(local))
            t0_ticks += ticks
            arrivals.append(t0_ticks * EXECUTION_PERIOD_S)
        t = np.concatenate([*parts_t, [t0_ticks * EXECUTION_PERIOD_S]])
        x = np.concatenate([*(p.position_m for p in parts), [float(waypoints[-1])]])
        v = np.concatenate([*(p.velocity_m_s for p in parts), [0.0]])
        a = np.concatenate([*(p.acceleration_m_s2 for p in parts), [0.0]])
        tau = motor_torque(cart_force(v, a, params), params)
        traces.append(LawTrace(law, t, x, v, tau, np.array(arrivals)))
    return traces


def recorded_traces(
    path: str | Path, case: Case, keys: AxisKeys | None = None, label: str | None = None
) -> list[LawTrace]:
    """Per law the recording has: the measured samples of the recorded run of ``case`` (the first run
    label, or ``label``), from its first move's start tick to its last move's end tick."""
    keys = keys or AxisKeys()
    plans = [PlanRecord.decode(m.data) for m in read_messages(path, topic_for_key(keys.plan), PLAN_TYPE)]
    plans = [p for p in plans if p.case == case.value and p.waypoint_index > 0]
    if label is None and plans:
        label = min(plans, key=lambda p: p.stamp_ns).run
    plans = [p for p in plans if p.run == label]
    if not plans:
        raise VizError(
            f"{path} holds no plan records of a {case.value} run on {topic_for_key(keys.plan)}"
            + (f" labelled {label!r}" if label else "")
        )
    accepted: dict[tuple[str, int], MoveStatus] = {}
    for m in read_messages(path, topic_for_key(keys.event), MOVE_STATUS_TYPE):
        st = MoveStatus.decode(m.data)
        if st.state is MoveState.ACCEPTED:
            accepted.setdefault((st.sender, st.move_id), st)
    state = AxisSamples.of_columns(read_joint_states(path, topic_for_key(keys.state))).sorted()
    traces = []
    for law in LAWS:
        spans = []
        for p in sorted((p for p in plans if p.law == law), key=lambda p: p.stamp_ns):
            st = accepted.get((p.sender, p.move_id))
            if st is not None:
                spans.append((st.stamp_of(st.start_tick), st.stamp_of(st.end_tick)))
        if not spans:
            continue  # the recording has no run of this law
        start, end = spans[0][0], spans[-1][1]
        sl = slice(
            int(np.searchsorted(state.stamp_ns, start, "left")),
            int(np.searchsorted(state.stamp_ns, end, "right")),
        )
        t = (state.stamp_ns[sl] - start) * 1e-9
        arrivals = np.array([0.0, *((e - start) * 1e-9 for _s, e in spans)])
        traces.append(
            LawTrace(law, t, state.position_m[sl], state.velocity_m_s[sl], state.torque_nm[sl], arrivals)
        )
    if not traces:
        raise VizError(
            f"{path}: no {case.value} move of the plans was accepted on {topic_for_key(keys.event)}"
        )
    return traces


def trajectory_png(traces: Sequence[LawTrace], params: AxisParams, title: str, caption: str) -> bytes:
    """One case as PNG bytes: rows position, velocity, torque; one column per law."""
    plt = pyplot()
    fig, axes = plt.subplots(3, len(traces), figsize=(14, 8.2), sharey="row", squeeze=False)
    rows = (
        ("position_m", "position x [m]", (0.0, params.L)),
        ("velocity_m_s", "velocity ẋ [m/s]", (-params.v_max, params.v_max)),
        ("torque_nm", "motor torque τ_m [N·m]", (-params.tau_max, params.tau_max)),
    )
    for col, trace in enumerate(traces):
        for row, (field, label, limits) in enumerate(rows):
            ax = axes[row, col]
            for t in trace.waypoint_times_s:
                ax.axvline(t, color="0.82", lw=0.6, zorder=0)
            ax.plot(trace.t_s, getattr(trace, field), color="tab:blue", lw=0.8)
            for value in limits:
                ax.axhline(value, color="tab:red", lw=1.0, ls="--")
            ax.set_xlim(0.0, float(trace.t_s[-1]) if len(trace.t_s) else 1.0)
            ax.grid(alpha=0.25, axis="y")
            if col == 0:
                ax.set_ylabel(label)
            if row == 0:
                total = trace.waypoint_times_s[-1]
                ax.set_title(
                    f"{trace.law}: {len(trace.waypoint_times_s) - 1} moves in {total:.2f} s", fontsize=10
                )
            if row == len(rows) - 1:
                ax.set_xlabel("time [s]")
    for row, (_f, _l, limits) in enumerate(rows):
        span = limits[1] - limits[0]
        axes[row, 0].set_ylim(limits[0] - 0.08 * span, limits[1] + 0.08 * span)
    fig.suptitle(title, fontsize=12)
    legend = " Dashed: the limits (stroke [0, L], ±v_max, ±tau_max); grey: the way points."
    fig.text(0.01, 0.006, caption + legend, fontsize=8)
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    return png_bytes(fig)
