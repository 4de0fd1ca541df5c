"""An EMPS-like log: a simulation of a real prismatic axis built from the published facts of the
electro-mechanical positioning system (EMPS) benchmark, because its data file cannot be fetched here.

The EMPS (Janot, Gautier, Brunot; nonlinearbenchmark.org) is a prismatic joint driven by a DC motor
through a ball screw, under closed-loop position control at 1 kHz: a proportional position loop
(gain ``kp`` [1/s]) inside a proportional velocity loop (gain ``kv`` [V/(m/s)]) commands the
amplifier's input voltage vir, saturated at ±10 V; the motor force is gtau·vir. The log holds the
encoder position qm (steps of 50 nm) and vir, nothing else: no velocity. This rig simulates such a
log at 1 kHz (a rig: it lives in benchmarks/, never in the product; tests may import it):

* **the plant**: M·q̈ = gtau·vir + d(t) − f(q̇), with M the published inverse-model estimate and f the
  *measured* friction of the real rig — the published curve gtau·vir − M·q̈ binned over ±0.129 m/s
  (:data:`FRICTION_TABLE_N`, 61 bins), interpolated linearly between the bin centres on each side of
  zero and continued with a small viscous slope (:data:`BEYOND_SLOPE_N_S_PER_M`) beyond the last bin.
  The curve is what gtau·vir − M·q̈ measured, so it holds the constant force (the amplifier offset; the
  published least squares put it at −3.16 N) as well: it is asymmetric and of no textbook shape. The
  middle bin (the stick) is not used: at rest the cart sticks until the force leaves the band between
  the two sides' values extrapolated to zero speed (a Karnopp stick model). d(t) is a small random
  force (the guide's roughness: low-passed white noise). The plant is integrated
  :data:`SUBSTEPS` times per control period, the force held over the period.
* **the controller** (every 1 ms): the position is read through the encoder (rounded to 50 nm); the
  velocity is its backward difference; vir = kv·(kp·(q_ref − q) − q̇_est), saturated at ±10 V.
* **the log**: stamp, the encoder position and the force gtau·(vir + n), n the voltage's measurement
  noise; written as a JointState MCAP (one topic, one joint ``carriage``: m and N, empty velocity
  arrays) or as a CSV of time, qm and vir (for ``axisflow import``).
* **the reference**: laps of trapezoidal velocity moves (constant accelerations of ±0.83 m/s²,
  cruising at speeds up to 0.13 m/s), each move changing speed on the way and stopping at its end;
  a lap runs a move forward and its mirror back (so the cart comes home). The fit log and the
  validation log run different programs (:data:`FIT_PROGRAM`, :data:`VALIDATION_PROGRAM`).

Everything random comes from ``numpy.random.default_rng(seed)``: a log is reproducible from its spec.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

GTAU_N_PER_V = 35.15
"""the motor force per volt of the amplifier's input [N/V]"""
KP_PER_S = 160.18
"""the position loop's gain [1/s]"""
KV_V_PER_M_S = 243.45
"""the velocity loop's gain [V/(m/s)]"""
VIR_LIMIT_V = 10.0
"""the amplifier's input saturates at ±this [V]"""
PERIOD_NS = 1_000_000
ENCODER_STEP_M = 5e-8
MASS_KG = 95.1089
"""the plant's inertia: the published inverse-model least-squares estimate [kg]"""
PUBLISHED_LS = {"M": 95.1089, "viscous": 203.5034, "coulomb": 20.3935, "offset": -3.1648}
"""the published four-parameter inverse-model least squares of the real rig [kg, N·s/m, N, N]"""
TABLE_SPEED_M_S = 0.129
"""the friction table's bins are centred evenly over ±this [m/s]"""
FRICTION_TABLE_N = (
    -47.223, -50.535, -46.504, -48.993, -49.714, -47.69, -46.827, -45.364, -45.74, -45.297,
    -40.27, -40.241, -38.596, -38.308, -38.364, -39.029, -37.695, -35.484, -33.997, -32.867,
    -31.425, -28.341, -27.709, -26.87, -26.2, -25.085, -23.496, -22.582, -21.235, -18.707,
    -0.862,
    17.31, 18.966, 20.409, 21.779, 22.694, 23.779, 24.855, 25.264, 25.571, 27.756,
    29.967, 30.85, 30.955, 30.624, 31.025, 32.144, 33.029, 32.981, 34.273, 33.188,
    35.546, 37.757, 38.579, 39.09, 39.609, 38.23, 38.249, 38.361, 40.669, 36.959,
)  # fmt: skip
"""the real rig's friction (gtau·vir − M·q̈) in 61 bins from −0.129 to +0.129 m/s [N]"""
BEYOND_SLOPE_N_S_PER_M = 20.0
"""the friction's slope beyond the table's last bin on either side [N·s/m]"""
SUBSTEPS = 5
"""plant integration steps per control period"""
ACCELERATION_M_S2 = 0.83

Segment = tuple[float, float]
"""(cruising speed [m/s], cruising time [s]) of one stretch of a move"""

FIT_PROGRAM: tuple[tuple[Segment, ...], ...] = (
    ((0.13, 0.3), (0.04, 0.2), (0.09, 0.2), (0.015, 0.3)),
    ((0.02, 0.25), (0.11, 0.2), (0.06, 0.2)),
)
"""the fit log's lap: each move forward, a pause, its mirror back, a pause"""
VALIDATION_PROGRAM: tuple[tuple[Segment, ...], ...] = (
    ((0.07, 0.3), (0.125, 0.2), (0.03, 0.3)),
    ((0.1, 0.25), (0.05, 0.3), (0.01, 0.4), (0.08, 0.2)),
)
"""the validation log's lap: other speeds and pulses"""


def friction_n(velocity_m_s: float) -> float:
    """The plant's friction force f(q̇) [N] while moving (q̇ ≠ 0): the table on the side of the motion,
    linear between bin centres, from the side's value extrapolated to zero speed up to the last bin,
    then :data:`BEYOND_SLOPE_N_S_PER_M`."""
    nodes = _POSITIVE if velocity_m_s > 0.0 else _NEGATIVE
    speed = abs(velocity_m_s)
    sign = 1.0 if velocity_m_s > 0.0 else -1.0
    x = speed / _BIN_M_S
    j = int(x)
    if j >= len(nodes) - 1:
        return nodes[-1] + sign * BEYOND_SLOPE_N_S_PER_M * (speed - TABLE_SPEED_M_S)
    frac = x - j
    return nodes[j] + frac * (nodes[j + 1] - nodes[j])


_BIN_M_S = 2.0 * TABLE_SPEED_M_S / (len(FRICTION_TABLE_N) - 1)
_MIDDLE = len(FRICTION_TABLE_N) // 2
_POSITIVE = [
    2.0 * FRICTION_TABLE_N[_MIDDLE + 1] - FRICTION_TABLE_N[_MIDDLE + 2],
    *FRICTION_TABLE_N[_MIDDLE + 1 :],
]
"""the friction at speeds 0⁺, Δ, 2Δ, … (Δ the bin spacing) [N]"""
_NEGATIVE = [
    2.0 * FRICTION_TABLE_N[_MIDDLE - 1] - FRICTION_TABLE_N[_MIDDLE - 2],
    *FRICTION_TABLE_N[_MIDDLE - 1 :: -1],
]
"""the friction at speeds 0⁻, −Δ, −2Δ, … [N]"""


@dataclass(frozen=True)
class RigSpec:
    """One simulated log; equal specs give identical logs."""

    program: tuple[tuple[Segment, ...], ...] = FIT_PROGRAM
    laps: int = 4
    seed: int = 0
    rest_s: float = 0.5
    """at rest before the first and after the last move [s]"""
    pause_s: float = 0.3
    """at rest between moves [s]"""
    disturbance_n: float = 0.5
    """standard deviation of the random force on the cart [N]"""
    disturbance_time_s: float = 0.02
    """its correlation time [s]"""
    vir_noise_v: float = 0.005
    """standard deviation of the logged voltage's measurement noise [V]"""
    start_ns: int = 1_700_000_000_000_000_000
    mass_kg: float = MASS_KG

    def reference(self) -> tuple[np.ndarray, np.ndarray]:
        """The position reference q_ref [m] at each 1 kHz tick, and the ticks' times [s]."""
        speeds: list[np.ndarray] = [np.zeros(round(self.rest_s / _FINE_S))]
        pause = np.zeros(round(self.pause_s / _FINE_S))
        for _lap in range(self.laps):
            for move in self.program:
                for sign, order in ((1.0, move), (-1.0, move[::-1])):
                    speeds += [sign * _trapezoid(order), pause]
        speeds.append(np.zeros(round(self.rest_s / _FINE_S)))
        v = np.concatenate(speeds)
        q = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * _FINE_S)])
        step = round(PERIOD_NS * 1e-9 / _FINE_S)
        q_ref = q[::step]
        return np.arange(q_ref.size) * (PERIOD_NS * 1e-9), q_ref


_FINE_S = 1e-4
"""the reference's integration step [s]"""


def _trapezoid(segments: tuple[Segment, ...]) -> np.ndarray:
    """The velocity [m/s] of one move at :data:`_FINE_S` steps: from rest through each segment's speed
    (ramps of ±:data:`ACCELERATION_M_S2` between them, each speed held for its time) back to rest."""
    parts: list[np.ndarray] = []
    previous = 0.0
    for speed, hold in (*segments, (0.0, 0.0)):
        ramp = abs(speed - previous) / ACCELERATION_M_S2
        n = max(1, round(ramp / _FINE_S))
        parts.append(np.linspace(previous, speed, n, endpoint=False))
        parts.append(np.full(round(hold / _FINE_S), speed))
        previous = speed
    parts.append(np.zeros(1))
    return np.concatenate(parts)


@dataclass(frozen=True, eq=False)
class RigLog:
    """A simulated run: what the log holds, and the truth behind it."""

    spec: RigSpec
    stamp_ns: np.ndarray
    """int64, one per 1 kHz tick"""
    position_m: np.ndarray
    """the encoder's position (50 nm steps)"""
    vir_v: np.ndarray
    """the logged amplifier input (with its measurement noise) [V]"""
    reference_m: np.ndarray
    true_velocity_m_s: np.ndarray
    """the cart's velocity at each tick (not in the log)"""
    applied_force_n: np.ndarray
    """gtau·vir actually applied over each tick (without the logging noise)"""
    saturated: int = 0
    """ticks at which vir saturated"""
    extra: dict[str, float] = field(default_factory=dict)

    @property
    def force_n(self) -> np.ndarray:
        """The logged force gtau·vir [N]."""
        return GTAU_N_PER_V * self.vir_v

    @property
    def duration_s(self) -> float:
        return (int(self.stamp_ns[-1]) - int(self.stamp_ns[0])) * 1e-9


def simulate(spec: RigSpec | None = None) -> RigLog:
    """Run the closed loop of ``spec`` (see the module docstring)."""
    spec = spec or RigSpec()
    _t, q_ref = spec.reference()
    n = q_ref.size
    rng = np.random.default_rng(spec.seed)
    period = PERIOD_NS * 1e-9
    h = period / SUBSTEPS
    alpha = math.exp(-period / spec.disturbance_time_s)
    kick = spec.disturbance_n * math.sqrt(1.0 - alpha * alpha)
    white = rng.standard_normal(n).tolist()
    vir_noise = rng.normal(0.0, spec.vir_noise_v, n)
    stick_up, stick_down = _POSITIVE[0], _NEGATIVE[0]
    mass = spec.mass_kg
    q, v, d = 0.0, 0.0, 0.0
    q_meas_last = 0.0
    positions, virs, velocities, applied = [0.0] * n, [0.0] * n, [0.0] * n, [0.0] * n
    saturated = 0
    refs = q_ref.tolist()
    for k in range(n):
        q_meas = round(q / ENCODER_STEP_M) * ENCODER_STEP_M
        v_est = (q_meas - q_meas_last) / period
        q_meas_last = q_meas
        vir = KV_V_PER_M_S * (KP_PER_S * (refs[k] - q_meas) - v_est)
        if abs(vir) > VIR_LIMIT_V:
            vir = math.copysign(VIR_LIMIT_V, vir)
            saturated += 1
        positions[k], virs[k], velocities[k] = q_meas, vir, v
        force = GTAU_N_PER_V * vir
        applied[k] = force
        d = alpha * d + kick * white[k]
        drive = force + d
        for _ in range(SUBSTEPS):
            if v == 0.0:
                if drive > stick_up:
                    v_new = h * (drive - stick_up) / mass
                elif drive < stick_down:
                    v_new = h * (drive - stick_down) / mass
                else:
                    continue
            else:
                v_new = v + h * (drive - friction_n(v)) / mass
                if v_new * v < 0.0:  # the motion stops within the step: the cart sticks
                    v_new = 0.0
            q += 0.5 * h * (v + v_new)
            v = v_new
    stamps = spec.start_ns + np.arange(n, dtype=np.int64) * PERIOD_NS
    return RigLog(
        spec=spec,
        stamp_ns=stamps,
        position_m=np.array(positions),
        vir_v=np.array(virs) + vir_noise,
        reference_m=q_ref,
        true_velocity_m_s=np.array(velocities),
        applied_force_n=np.array(applied),
        saturated=saturated,
    )


RIG_TOPIC = "/emps/joint_states"
RIG_JOINT = "carriage"


def write_mcap(path: str | Path, log: RigLog, topic: str = RIG_TOPIC, joint: str = RIG_JOINT) -> Path:
    """``log`` as a JointState MCAP by axisflow's writer (ROS 2 profile): one topic, one joint (m, N),
    empty velocity arrays; written atomically."""
    from .foreign_log import write_joint_log

    return write_joint_log(path, log.stamp_ns, log.position_m, log.force_n, joint, topic)


def write_imported(folder: str | Path, name: str, log: RigLog) -> Path:
    """``log`` the way a user brings a real rig's log: a scope-like CSV (:func:`write_csv`) imported by
    ``axisflow import``'s library function (time ``t`` [s], position ``qm`` [m], effort ``vir`` [V] ×
    gtau) into ``folder/name.mcap``: one JointState topic, joint ``carriage``, no velocity."""
    from ..acquisition.foreign import ColumnMap, Signal, import_logs

    csv = write_csv(Path(folder) / f"{name}.csv", log)
    cmap = ColumnMap(
        time=Signal("t", "s"),
        position=Signal("qm", "m"),
        effort=Signal("vir", "V"),
        effort_scale=GTAU_N_PER_V,
    )
    return import_logs([csv], cmap, Path(folder) / f"{name}.mcap").path


def write_csv(path: str | Path, log: RigLog) -> Path:
    """``log`` as a scope-like CSV: time [s], qm [m] and vir [V] (the force is gtau·vir), written
    atomically."""
    from ..model.files import write_atomic

    t = (log.stamp_ns - log.stamp_ns[0]) * 1e-9
    rows = zip(t.tolist(), log.position_m.tolist(), log.vir_v.tolist(), strict=True)
    lines = ["t,qm,vir", *(f"{a:.3f},{b:.8g},{c:.8g}" for a, b, c in rows)]
    out = Path(path)
    write_atomic(out, "\n".join(lines) + "\n")
    return out
