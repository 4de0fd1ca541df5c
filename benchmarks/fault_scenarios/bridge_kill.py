"""Fault 2: the bridge SIGKILLed mid-move → the recording so far complete; the recorder lists the
restarted bridge as a new publisher; the restart (same ``--plant-state``) starts at rest where the axis
coasted to."""

from __future__ import annotations

import struct
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ...acquisition import MoveSender, MoveState, is_complete, load_plant, open_session
from ...deploy.processes import Exited, Launcher, wait_until
from ...model import default_params, stop_profile
from ...model.encoder import encoder_resolution_m
from .outcome import FaultResult, Outcome
from .rig import KEYS, STATE_TOPIC, Rig, fastest_move_s
from .ticks import TICK_NS, TickRecord, tick_record

_PLANT_STATE = struct.Struct("<dd")
"""the plant state file of ``bridge --plant-state``: x [m], v [m/s] (acquisition/drives/sim_axis.py)"""


@dataclass(frozen=True)
class BridgeKillResult(FaultResult):
    killed_at: tuple[float, float]
    """the plant's (x [m], v [m/s]) when the first bridge was killed (its state file)"""
    coasts_to_m: float
    """where the model says the cart comes to rest from there on friction alone (true parameters)"""
    last_recorded: tuple[float, float]
    """the last state sample of the first bridge in the recording (x [m], v [m/s])"""
    kill_to_last_sample_ms: float
    restart_first: tuple[float, float]
    """the first state sample of the restarted bridge (x [m], v [m/s])"""
    restart_span_m: float
    """how far the restarted bridge's measured position moved during its run [m] (it holds)"""
    restart_ticks: int
    state: TickRecord
    publishers: list[dict[str, Any]]
    """the recorder's summary of the state topic's publishers (id, first/last sequence, messages)"""
    recorder: Exited
    complete: bool
    count_m: float
    """one encoder count [m]"""

    @property
    def restart_offset_m(self) -> float:
        return self.restart_first[0] - self.coasts_to_m

    @property
    def ticks_after_last_sample(self) -> float:
        """How many ticks of travel lie between the last recorded sample and the plant's state at the
        kill: 1 is a complete recording (a state sample is read before its tick moves the plant; the
        file is written after), more is samples lost before the kill."""
        x, v = self.killed_at
        return (x - self.last_recorded[0]) / (v * TICK_NS * 1e-9) if abs(v) > 0.01 else 0.0

    @property
    def passed(self) -> bool:
        runs = self.state.runs
        return (
            self.recorder.returncode == 0
            and self.complete
            and self.state.every_tick
            and len(runs) == 2
            and [(p["first_sequence"], p["last_sequence"]) for p in self.publishers]
            == [(r[1], r[2]) for r in runs]
            and abs(self.restart_offset_m) <= self.count_m
            and self.restart_first[1] == 0.0
            and self.restart_span_m <= 2 * self.count_m
            and runs[1][0] == self.restart_ticks
            and self.ticks_after_last_sample <= 2.5
        )

    def outcome(self) -> Outcome:
        (x, v), (xr, vr) = self.killed_at, self.restart_first
        n1, n2 = (r[0] for r in self.state.runs[:2]) if len(self.state.runs) >= 2 else (0, 0)
        return Outcome(
            "bridge SIGKILL mid-move, restarted on the same --plant-state",
            self.passed,
            f"killed at x = {x:.4f} m, v = {v:.3f} m/s; recording complete ({self.complete}), last sample "
            f"{self.ticks_after_last_sample:.1f} ticks of travel before the kill point (1 = none lost); "
            f"recorder lists 2 publishers "
            f"(seq 1–{n1}, then 1–{n2}, no gap); restart at rest at {xr:.6f} m, v = {vr:g} m/s, "
            f"{self.restart_offset_m * 1e6:+.1f} µm from the coasting end {self.coasts_to_m:.6f} m "
            f"({(self.coasts_to_m - x) * 1e3:.1f} mm past the kill point), held within "
            f"{self.restart_span_m * 1e6:.1f} µm",
            "axisflow bench faults --only bridge_kill",
            {
                "killed_at": self.killed_at,
                "coasts_to_m": self.coasts_to_m,
                "last_recorded": self.last_recorded,
                "kill_to_last_sample_ms": self.kill_to_last_sample_ms,
                "ticks_after_last_sample": self.ticks_after_last_sample,
                "restart_first": self.restart_first,
                "restart_offset_m": self.restart_offset_m,
                "restart_span_m": self.restart_span_m,
                "publishers": self.publishers,
            },
        )


def bridge_kill(work: Path, at_fraction: float = 0.45) -> BridgeKillResult:
    """Fault 2: a minimum-time move over the stroke; the bridge SIGKILLed ``at_fraction`` into it
    (near full speed) while the recorder keeps recording; a new bridge on the same plant state file
    runs 2 s; the recorder is then stopped cleanly."""
    params = default_params()
    plant = load_plant(None, params)
    state_file = work / "plant.state"
    with Launcher(work, cwd=work) as launcher:
        rig = Rig(launcher, "bridge-kill")
        recorder = rig.start_recorder()
        first = rig.start_bridge("bridge-1", "--plant-state", str(state_file))
        with open_session(rig.options()) as session, MoveSender(session, KEYS) as sender:
            sender.require_bridge(30.0)
            duration = fastest_move_s(0.0, params.L, params)
            move = sender.send(0.0, params.L, duration)
            if sender.wait_status(move.move_id, {MoveState.STARTED}, 10.0) is None:
                raise RuntimeError(f"move {move.move_id} did not start: {sender.statuses}")
            time.sleep(at_fraction * duration)  # into the move, near its top speed
            first.kill()
            killed_ns = time.time_ns()
            launcher.wait(first)
            # its token gone: a bridge started now finds the axis free
            if not wait_until(lambda: not sender.bridge_alive, 30.0):
                raise RuntimeError(f"the killed bridge's token {KEYS.alive} did not go")
        x_kill, v_kill = _PLANT_STATE.unpack(state_file.read_bytes())
        second_end = launcher.wait(
            rig.start_bridge("bridge-2", "--plant-state", str(state_file), "--duration", "2"), 60.0
        )
        recorder_end = launcher.stop(recorder)  # its stop proves the last samples have arrived
    state = tick_record(rig.recording)
    n1 = state.runs[0][0]
    coast = stop_profile(x_kill, v_kill, plant.axis, force_fraction=0.0).trajectory.x1_m if v_kill else x_kill
    return BridgeKillResult(
        killed_at=(x_kill, v_kill),
        coasts_to_m=min(max(coast, 0.0), params.L),
        last_recorded=(float(state.position_m[n1 - 1]), float(state.velocity_m_s[n1 - 1])),
        kill_to_last_sample_ms=(killed_ns - state.last_stamp_ns[0]) / 1e6,
        restart_first=(float(state.position_m[n1]), float(state.velocity_m_s[n1])),
        restart_span_m=float(np.ptp(state.position_m[n1:])),
        restart_ticks=second_end.json()["ticks"] if second_end.returncode == 0 else -1,
        state=state,
        publishers=recorder_end.json()["topics"][STATE_TOPIC]["publishers"]
        if recorder_end.returncode == 0
        else [],
        recorder=recorder_end,
        complete=is_complete(rig.recording),
        count_m=encoder_resolution_m(plant.axis.r, plant.encoder.counts_per_rev),
    )
