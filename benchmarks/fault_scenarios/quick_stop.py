"""The quick stop at full speed → distance and time against the physical minimum."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...acquisition import MoveSender, MoveState, open_session
from ...acquisition.wire.quick_stop import STOP_MOVE_ID
from ...deploy.processes import Launcher
from ...model import default_params, stop_profile
from .outcome import FaultResult, Outcome
from .rig import KEYS, Rig, RunEnd, fastest_move_s, stop_rig, true_axis
from .ticks import TICK_NS


@dataclass(frozen=True)
class QuickStopResult(FaultResult):
    braking_from: tuple[float, float]
    """the measured (x [m], v [m/s]) at the tick braking began"""
    distance_m: float
    """from there to where the measured speed first falls below REST_SPEED_M_S"""
    time_s: float
    minimum: tuple[float, float]
    """the physical minimum from the same state: stop_profile(x, v, true parameters, 1.0) (distance
    [m], time [s])"""
    bridge_text: str
    """the bridge's STOPPED status (its own figures, with the nominal parameters)"""
    rest_m: float
    """where the axis holds at the end (the braking profile's end: the position loop pulls the cart
    back to it after its first stop)"""
    dropped: int
    L: float
    end: RunEnd

    @property
    def passed(self) -> bool:
        d_min, t_min = self.minimum
        return (
            self.braking_from[1] > 1.0
            and d_min * 0.98 <= self.distance_m <= 1.35 * d_min
            and self.time_s <= 1.25 * t_min + 0.005
            and 0.0 < self.rest_m < self.L
            and self.dropped == 1
            and self.end.telemetry_intact
        )

    def outcome(self) -> Outcome:
        (x, v), (d_min, t_min) = self.braking_from, self.minimum
        return Outcome(
            "quick stop (MoveSender.stop()) at full speed",
            self.passed,
            f"from {v:.3f} m/s at {x:.4f} m: stopped in {self.distance_m * 1e3:.1f} mm and "
            f"{self.time_s * 1e3:.0f} ms; physical minimum (true parameters, full force) "
            f"{d_min * 1e3:.1f} mm and {t_min * 1e3:.0f} ms: ×{self.distance_m / d_min:.2f} distance, "
            f"×{self.time_s / t_min:.2f} time; then held at {self.rest_m:.4f} m "
            f"({(x + self.distance_m - self.rest_m) * 1e3:.1f} mm back); the queued move dropped; "
            f"bridge: '{self.bridge_text}'",
            "axisflow bench faults --only quick_stop",
            {
                "braking_from": self.braking_from,
                "distance_m": self.distance_m,
                "time_s": self.time_s,
                "minimum": self.minimum,
                "ratio_distance": self.distance_m / d_min,
                "ratio_time": self.time_s / t_min,
                "rest_m": self.rest_m,
            },
        )


REST_SPEED_M_S = 0.005
"""a measured speed below this (2.6 encoder counts per tick) counts as at rest"""


def quick_stop(work: Path, at_fraction: float = 0.5) -> QuickStopResult:
    """The quick stop: a minimum-time move over the stroke with a second one queued; at
    ``at_fraction`` of it (full speed) the sender requests a quick stop; distance and time to rest
    measured on the recorded samples, against :func:`~axisflow.model.stop_profile` from the measured
    state with the plant's true parameters at full force."""
    params = default_params()
    with Launcher(work, cwd=work) as launcher:
        rig = Rig(launcher, "quick-stop")
        recorder = rig.start_recorder()
        bridge = rig.start_bridge()
        with open_session(rig.options()) as session, MoveSender(session, KEYS) as sender:
            sender.require_bridge(30.0)
            duration = fastest_move_s(0.0, params.L, params)
            move = sender.send(0.0, params.L, duration)
            sender.send(params.L, 0.2, 1.0)
            if sender.wait_status(move.move_id, {MoveState.STARTED}, 10.0) is None:
                raise RuntimeError(f"move {move.move_id} did not start: {sender.statuses}")
            time.sleep(at_fraction * duration)  # into the move, at full speed
            sender.stop("axisflow bench faults")
            # the bridge publishes in order: the queued move's DROPPED came before this STOPPED
            stopped = sender.wait_status(STOP_MOVE_ID, {MoveState.STOPPED}, 10.0)
            dropped = sum(s.state is MoveState.DROPPED for s in sender.statuses)
        if stopped is None:
            raise RuntimeError(f"the quick stop was not confirmed: {sender.statuses}")
        end = stop_rig(rig, bridge, recorder)
    state = end.state
    k0 = stopped.start_tick
    at_rest = np.flatnonzero(np.abs(state.velocity_m_s[k0:]) < REST_SPEED_M_S)
    k_rest = k0 + (int(at_rest[0]) if at_rest.size else len(state.velocity_m_s) - 1 - k0)
    x0, v0 = float(state.position_m[k0]), float(state.velocity_m_s[k0])
    fastest = stop_profile(x0, v0, true_axis(params), 1.0)
    return QuickStopResult(
        braking_from=(x0, v0),
        distance_m=abs(float(state.position_m[k_rest]) - x0),
        time_s=(k_rest - k0) * TICK_NS * 1e-9,
        minimum=(fastest.distance_m, fastest.time_s),
        bridge_text=stopped.text,
        rest_m=float(state.position_m[-1]),
        dropped=dropped,
        L=params.L,
        end=end,
    )
