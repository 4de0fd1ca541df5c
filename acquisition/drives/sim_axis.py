"""The simulated axis: eq. (1) integrated at several kHz behind a simulated 1 kHz drive.

The plant has its own "true" parameters, which differ from the nominal ones (``--params``) that the
drive's controller and feed-forward use. A plant file (:data:`DEFAULT_PLANT_RESOURCE` by default) gives
them either as ``[scale]`` factors applied to the nominal parameters (the default file: inertia and
friction off by 5–20 %, so identification has something to find, whatever the nominal set is) or as a
complete ``[axis]`` table (absolute values, the keys of a parameter file). Per 1 ms tick:

1. the drive measures: the pulley encoder is quantised to ``counts_per_rev`` counts per pulley
   revolution (default 2^17: 2π·0.04 m/131072 = 1.917 µm of cart travel per count with the default
   r); the velocity is the encoder difference over the tick through a first-order low-pass
   (``velocity_filter_hz``); the motor torque is the applied torque plus white Gaussian noise
   (``noise_std_nm``, seeded);
2. the controller computes the force command
   ``F = F_ff + Kp·(x_ref − x_meas) + Kd·(v_ref − v_meas)`` with ``Kp = M_eq·ω²``,
   ``Kd = 2ζω·M_eq`` (nominal M_eq, ω = 2π·bandwidth_hz) and the torque ``τ = F·r/i_r``, saturated
   at the plant's ``tau_max``;
3. the plant integrates ``M_eq·ẍ = τ·i_r/r − a1·sign(ẋ) − a2·ẋ − a3·atan(a4·ẋ)`` (true parameters)
   with ``substeps`` semi-implicit Euler steps. Friction is Karnopp-style at rest: the cart sticks
   while |F| ≤ a1 and the velocity is clamped to 0 when it would change sign within a step.
   The stroke ends at 0 and L are hard stops (position clamped, velocity zeroed).

A real axis stays where it is when its drive's software stops. With a ``state_path`` the simulated
plant does too: it keeps its position and velocity in that file (16 bytes, memory-mapped, written
every tick, so they survive a SIGKILL of the bridge), and a new plant on the same file starts where the
old one would have coasted to rest on friction alone (:func:`axisflow.model.stop_profile` with no
motor force), inside the stroke.
"""

from __future__ import annotations

import math
import mmap
import os
import random
import struct
import time
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

from ...model import EXECUTION_PERIOD_NS, EXECUTION_PERIOD_S, AxisflowError, AxisParams, stop_profile
from ...model.params import params_from_mapping
from ...model.toml_file import read_toml
from ..errors import PlantError
from ..wire.messages import AxisSample
from .drive import AlwaysReady, Setpoint

DEFAULT_PLANT_RESOURCE = "default_plant.toml"


@dataclass(frozen=True)
class EncoderConfig:
    counts_per_rev: int = 131072
    """pulley encoder counts per revolution"""
    velocity_filter_hz: float = 500.0
    """cut-off of the first-order low-pass on the encoder velocity [Hz]"""


@dataclass(frozen=True)
class TorqueSensorConfig:
    noise_std_nm: float = 0.01
    """standard deviation of the torque-measurement noise [N·m]"""
    seed: int = 1


@dataclass(frozen=True)
class ControllerConfig:
    bandwidth_hz: float = 20.0
    """closed-loop natural frequency of the position loop [Hz]"""
    damping: float = 1.0
    """damping ratio ζ [-]"""


@dataclass(frozen=True)
class SimulationConfig:
    substeps: int = 4
    """integration steps per 1 ms tick"""
    initial_position_m: float = 0.0


@dataclass(frozen=True)
class PlantConfig:
    """A plant file: the true axis and the simulated drive's sensors and controller."""

    axis: AxisParams
    encoder: EncoderConfig
    torque_sensor: TorqueSensorConfig
    controller: ControllerConfig
    simulation: SimulationConfig

    def __post_init__(self) -> None:
        checks = (
            ("encoder.counts_per_rev", self.encoder.counts_per_rev, 1, "counts"),
            ("encoder.velocity_filter_hz", self.encoder.velocity_filter_hz, 1e-9, "Hz"),
            ("torque_sensor.noise_std_nm", self.torque_sensor.noise_std_nm, 0.0, "N·m"),
            ("controller.bandwidth_hz", self.controller.bandwidth_hz, 1e-9, "Hz"),
            ("controller.damping", self.controller.damping, 0.0, ""),
            ("simulation.substeps", self.simulation.substeps, 1, "steps"),
        )
        for name, value, lower, unit in checks:
            if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
                raise PlantError(f"plant {name} = {value!r} must be a finite number")
            if value < lower:
                raise PlantError(f"plant {name} = {value} {unit} must be >= {lower} {unit}")
        x0 = self.simulation.initial_position_m
        if not 0.0 <= x0 <= self.axis.L:
            raise PlantError(f"plant simulation.initial_position_m = {x0} m is outside [0, {self.axis.L}] m")


_SECTIONS: dict[str, type] = {
    "encoder": EncoderConfig,
    "torque_sensor": TorqueSensorConfig,
    "controller": ControllerConfig,
    "simulation": SimulationConfig,
}
_INT_FIELDS = {"counts_per_rev", "seed", "substeps"}


def _section(name: str, cls: type, data: dict[str, Any], source: str) -> Any:
    allowed = [f.name for f in fields(cls)]
    unknown = sorted(set(data) - set(allowed))
    if unknown:
        raise PlantError(
            f"{source}: unknown key(s) {', '.join(unknown)} in [{name}]; allowed: {', '.join(allowed)}"
        )
    for key, value in data.items():
        if key in _INT_FIELDS and not (isinstance(value, int) and not isinstance(value, bool)):
            raise PlantError(f"{source}: [{name}] {key} = {value!r} must be an integer")
    return cls(**data)


_SCALABLE = ("m", "J_m", "J_g", "J_p", "a1", "a2", "a3", "a4")


def _true_axis(data: dict[str, Any], nominal: AxisParams, source: str) -> AxisParams:
    if ("axis" in data) == ("scale" in data):
        raise PlantError(
            f"{source}: give the true axis either as [scale] factors on the nominal parameters or as a "
            "complete [axis] table (exactly one of them)"
        )
    if "axis" in data:
        try:
            return params_from_mapping(data["axis"], f"{source} [axis]")
        except AxisflowError as exc:
            raise PlantError(str(exc)) from None
    factors = data["scale"]
    unknown = sorted(set(factors) - set(_SCALABLE))
    if unknown:
        raise PlantError(
            f"{source}: unknown key(s) {', '.join(unknown)} in [scale]; allowed: {', '.join(_SCALABLE)}"
        )
    for key, value in factors.items():
        if isinstance(value, bool) or not isinstance(value, int | float) or not 0.0 < value < math.inf:
            raise PlantError(f"{source}: [scale] {key} = {value!r} must be a finite factor > 0")
    try:
        return nominal.replace(**{k: getattr(nominal, k) * v for k, v in factors.items()})
    except AxisflowError as exc:
        raise PlantError(f"{source}: {exc}") from None


def plant_from_mapping(data: dict[str, Any], nominal: AxisParams, source: str = "plant") -> PlantConfig:
    """Validate a plant mapping: ``[scale]`` or ``[axis]``, optional sensor/controller sections."""
    allowed = ["axis", "scale", *_SECTIONS]
    unknown = sorted(set(data) - set(allowed))
    if unknown:
        raise PlantError(f"{source}: unknown section(s) {', '.join(unknown)}; allowed: {', '.join(allowed)}")
    axis = _true_axis(data, nominal, source)
    parts = {name: _section(name, cls, data.get(name, {}), source) for name, cls in _SECTIONS.items()}
    return PlantConfig(axis=axis, **parts)


def load_plant(path: str | Path | None, nominal: AxisParams) -> PlantConfig:
    """Load a plant file (None: the packaged default) relative to the ``nominal`` parameters."""
    data, source = read_toml(
        path, package=__package__, resource=DEFAULT_PLANT_RESOURCE, kind="plant", error=PlantError
    )
    return plant_from_mapping(data, nominal, source)


def moving_friction(v: float, p: AxisParams) -> float:
    """Friction force [N] on the moving cart (v ≠ 0): the model's law
    (:func:`axisflow.model.friction_force`) in scalar ``math`` form, because the integrator calls it
    4000 times per second of drive time and numpy on scalars costs several times more
    (tests/acquisition/test_sim_axis.py checks this copy against the model's)."""
    return p.a1 * math.copysign(1.0, v) + p.a2 * v + p.a3 * math.atan(p.a4 * v)


class SimulatedAxis(AlwaysReady):
    """A :class:`~axisflow.acquisition.drives.drive.Drive` backed by the integrated plant (see module doc)."""

    def __init__(
        self,
        plant: PlantConfig,
        nominal: AxisParams,
        start_stamp_ns: int | None = None,
        axis: str = "a0",
        state_path: str | Path | None = None,
    ) -> None:
        """``start_stamp_ns``: the stamp of tick 0 [ns since the Unix epoch]; None: the next whole
        millisecond of the wall clock when the first sample is read (the drive's clock starts then).
        ``state_path``: where the plant keeps its state between runs (see the module docstring)."""
        self.axis = axis
        self.plant = plant
        self.nominal = nominal
        self.tick = 0
        self._start_ns = start_stamp_ns
        p = plant.axis
        self._M = p.M_eq
        self._dt = EXECUTION_PERIOD_S / plant.simulation.substeps
        self._substeps = plant.simulation.substeps
        self._m_per_count = 2.0 * math.pi * p.r / plant.encoder.counts_per_rev
        self._alpha_v = 1.0 - math.exp(-2.0 * math.pi * plant.encoder.velocity_filter_hz * EXECUTION_PERIOD_S)
        w = 2.0 * math.pi * plant.controller.bandwidth_hz
        self.kp_n_m = nominal.M_eq * w * w
        self.kd_n_s_m = 2.0 * plant.controller.damping * w * nominal.M_eq
        self._rng = random.Random(plant.torque_sensor.seed)
        # true state
        self.position_m = plant.simulation.initial_position_m
        self.velocity_m_s = 0.0
        self._state: _PlantState | None = None
        if state_path is not None:
            self._state = _PlantState(Path(state_path))
            saved = self._state.load()
            if saved is not None:
                self.position_m = _at_rest_after_coasting(*saved, plant.axis)
            self._state.save(self.position_m, 0.0)
        self.applied_torque_nm = 0.0
        # drive's measurement state
        self._x_meas = self._encoder(self.position_m)
        self._v_meas = 0.0

    def _encoder(self, x_m: float) -> float:
        return math.floor(x_m / self._m_per_count) * self._m_per_count

    @property
    def stamp_ns(self) -> int:
        if self._start_ns is None:
            self._start_ns = -(-time.time_ns() // EXECUTION_PERIOD_NS) * EXECUTION_PERIOD_NS
        return self._start_ns + self.tick * EXECUTION_PERIOD_NS

    def read(self) -> AxisSample:
        p = self.nominal
        tau_meas = self.applied_torque_nm + self._rng.gauss(0.0, self.plant.torque_sensor.noise_std_nm)
        return AxisSample(
            stamp_ns=self.stamp_ns,
            axis=self.axis,
            position_m=self._x_meas,
            velocity_m_s=self._v_meas,
            force_n=tau_meas * p.i_r / p.r,
            motor_angle_rad=self._x_meas * p.i_r / p.r,
            motor_speed_rad_s=self._v_meas * p.i_r / p.r,
            motor_torque_nm=tau_meas,
        )

    def apply(self, setpoint: Setpoint) -> None:
        nominal = self.nominal
        force_cmd = (
            setpoint.force_ff_n
            + self.kp_n_m * (setpoint.position_m - self._x_meas)
            + self.kd_n_s_m * (setpoint.velocity_m_s - self._v_meas)
        )
        tau_max = self.plant.axis.tau_max
        tau = min(max(force_cmd * nominal.r / nominal.i_r, -tau_max), tau_max)
        self.applied_torque_nm = tau
        self._integrate(tau)
        self.tick += 1
        if self._state is not None:
            self._state.save(self.position_m, self.velocity_m_s)
        x_new = self._encoder(self.position_m)
        v_raw = (x_new - self._x_meas) / (EXECUTION_PERIOD_S)
        self._v_meas += self._alpha_v * (v_raw - self._v_meas)
        self._x_meas = x_new

    def _integrate(self, tau_nm: float) -> None:
        p = self.plant.axis
        force = tau_nm * p.i_r / p.r
        x, v, dt, M = self.position_m, self.velocity_m_s, self._dt, self._M
        for _ in range(self._substeps):
            if v == 0.0:
                if abs(force) <= p.a1:
                    continue  # static friction holds the cart
                direction = 1.0 if force > 0.0 else -1.0
                v = (force - p.a1 * direction) / M * dt
            else:
                friction = moving_friction(v, p)
                v_next = v + (force - friction) / M * dt
                v = 0.0 if v_next * v < 0.0 else v_next
            x += v * dt
            if x < 0.0:
                x, v = 0.0, 0.0
            elif x > p.L:
                x, v = p.L, 0.0
        self.position_m, self.velocity_m_s = x, v

    def close(self) -> None:
        """Release the state file (its last state stays in it)."""
        if self._state is not None:
            self._state.close()
            self._state = None


_STATE = struct.Struct("<dd")


class _PlantState:
    """The plant's (position, velocity) in a memory-mapped file: a write per tick costs a memory copy,
    and the kernel keeps the page when the process is killed."""

    def __init__(self, path: Path) -> None:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise PlantError(f"plant state file {path} cannot be opened: {exc.strerror}") from None
        self.path = path
        with os.fdopen(fd, "r+b") as fh:
            size = os.fstat(fh.fileno()).st_size
            if size not in (0, _STATE.size):  # not ours: never truncate someone's file
                raise PlantError(
                    f"plant state file {path} holds {size} bytes, not a plant state ({_STATE.size} bytes: "
                    "x [m], v [m/s]); give a new file or one a bridge wrote"
                )
            self._fresh = size == 0
            if self._fresh:
                fh.truncate(_STATE.size)
            self._map = mmap.mmap(fh.fileno(), _STATE.size)

    def load(self) -> tuple[float, float] | None:
        """The saved (x, v), or None for a new (empty) file."""
        if self._fresh:
            return None
        x, v = _STATE.unpack_from(self._map, 0)
        if not (math.isfinite(x) and math.isfinite(v)):
            raise PlantError(f"plant state file {self.path} holds no valid state (x = {x}, v = {v})")
        return x, v

    def save(self, x_m: float, v_m_s: float) -> None:
        _STATE.pack_into(self._map, 0, x_m, v_m_s)

    def close(self) -> None:
        self._map.flush()
        self._map.close()


def _at_rest_after_coasting(x_m: float, v_m_s: float, axis: AxisParams) -> float:
    """Where a cart at ``x_m`` moving at ``v_m_s`` comes to rest on friction alone, inside [0, L]."""
    end = stop_profile(x_m, v_m_s, axis, force_fraction=0.0).trajectory.x1_m if v_m_s else x_m
    return min(max(end, 0.0), axis.L)
