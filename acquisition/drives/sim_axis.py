"""The simulated drive: a 1 kHz servo drive in front of the simulated axis's mechanics.

The plant (:mod:`.plant`: the profile of a plant file) has its own "true" parameters, which differ
from the nominal ones (``--params``) that the drive's controller and feed-forward use. Per 1 ms tick:

1. the drive measures (the sample :meth:`SimulatedAxis.read` returns);
2. the controller computes the force command ``F = F_ff + Kp·(x_ref − x_meas) + Kd·(v_ref − v_meas)``
   with ``Kp = M_eq·ω²``, ``Kd = 2ζω·M_eq`` (nominal M_eq, ω = 2π·bandwidth_hz) and the torque
   ``τ = k·F`` (the nominal transmission's k; a belt: F·r/i_r), saturated at the plant's ``tau_max``;
3. the mechanics (:mod:`.mechanics`) advance one tick under that torque.

**Ideal profile** (a plant file with none of the imperfection sections): the rigid eq. (1); the pulley
encoder is quantised to ``counts_per_rev`` counts per pulley revolution (2^17: 1.917 µm of cart
travel with r = 0.04 m); the velocity is the encoder difference over the tick through a first-order
low-pass (``velocity_filter_hz``); the motor torque is the applied torque plus white Gaussian noise
(``noise_std_nm``, drawn at each read). Stamps advance by exactly 1 ms.

**Realistic profiles** (any imperfection section), each part only when its section is given:

* ``[drive]``: the motor encoder in counts (``counts_per_rev`` per motor revolution) and the torque in
  per mille of ``rated_torque_nm``, through :class:`~axisflow.model.drive_units.DriveUnits` (the one
  home of those conversions); the drive's velocity estimate is the count difference per tick through
  its first-order low-pass, reported in whole counts/s;
* ``[current_loop]``: the torque that acts on the rotor is the command plus the loop's coloured noise;
  the reported torque is the rotor's current torque (of the tick before the sample: the current the
  drive measures at the sample instant) plus the sensor's coloured and white noise
  (``[torque_sensor] noise_std_nm``); cogging is torque on the rotor the current does not show;
* ``[cogging]``: Σ A·sin(n·θ_m + φ) on the rotor, averaged over each tick's travel of the motor angle
  (a sinc factor: no aliasing at speed);
* ``[belt]``: the two-mass axis (:class:`~.mechanics.BeltAxis`): the encoder is on the motor side; an
  axis with no rotating parts (a linear motor: its coil moves with the carriage) has no mass on the
  motor side of a belt and stays rigid;
* ``[stroke_friction]``, ``[thermal]``, ``[wear]``: the friction of this tick, from
  :class:`~.friction_drift.FrictionDrift`; :meth:`SimulatedAxis.true_params` gives its present values;
* ``[sample_clock]``: each sample's stamp is its tick's time plus a uniform error within ±jitter, and a
  sample is lost (:meth:`~SimulatedAxis.status` says it is not fresh; :meth:`~SimulatedAxis.read`
  returns the last sample that arrived) with probability ``drop_fraction``; the
  first sample never is (the bridge starts from it). The drive's own loop runs on every tick.

Every random draw of a realistic tick comes from one generator seeded with ``[torque_sensor] seed``,
in a fixed order, so a run is reproducible.

A real axis stays where it is when its drive's software stops. With a ``state_path`` the simulated
plant does too: it keeps its cart position and velocity in that file (16 bytes, memory-mapped, written
every tick, so they survive a SIGKILL of the bridge), and a new plant on the same file starts where the
old one would have coasted to rest on friction alone (:func:`axisflow.model.stop_profile` with no
motor force), inside the stroke. A file holding a state outside the stroke or beyond the speed limit
is refused, untouched.
"""

from __future__ import annotations

import math
import mmap
import os
import random
import struct
import time
from pathlib import Path

import numpy as np

from ...model import EXECUTION_PERIOD_NS, EXECUTION_PERIOD_S, AxisParams, stop_profile
from ...model.encoder import axis_resolution_m
from ..errors import PlantError
from ..wire.messages import AxisSample
from .drive import READY, AlwaysReady, DriveStatus, Setpoint
from .friction_drift import FrictionDrift
from .mechanics import BeltAxis, RigidAxis
from .plant import (
    CurrentLoopConfig,
    PlantConfig,
    SampleClockConfig,
)

__all__ = ["STATE_SPEED_MARGIN", "SimulatedAxis"]

STATE_SPEED_MARGIN = 0.1
"""a saved plant state may exceed v_max by this fraction (tracking overshoot), no more"""


_LOST = DriveStatus(following=True, fresh=False, commanded=True)
"""the status of a tick whose sample the simulated drive lost"""


class SimulatedAxis(AlwaysReady):
    """A :class:`~axisflow.acquisition.drives.drive.Drive` backed by the simulated plant (see the module
    doc)."""

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
        self._last: AxisSample | None = None
        """the last sample :meth:`read` returned (what it returns again for a lost one)"""
        self._start_ns = start_stamp_ns
        p = plant.axis
        w = 2.0 * math.pi * plant.controller.bandwidth_hz
        self.kp_n_m = nominal.M_eq * w * w
        self.kd_n_s_m = 2.0 * plant.controller.damping * w * nominal.M_eq
        self._rng = random.Random(plant.torque_sensor.seed)
        x0 = plant.simulation.initial_position_m
        self._state: _PlantState | None = None
        if state_path is not None:
            self._state = _PlantState(Path(state_path))
            try:
                saved = self._state.load()
                if saved is not None:
                    _check_saved_state(self._state.path, *saved, p)
                    x0 = _at_rest_after_coasting(*saved, p)
            except PlantError:
                self._state.close()
                self._state = None
                raise
            self._state.save(x0, 0.0)
        self.applied_torque_nm = 0.0
        """the torque the controller commanded for the last tick [N·m]"""
        self._nominal_k = nominal.transmission.metres_per_radian
        """the nominal transmission's k [m/rad] (a belt: r/i_r): force command → motor torque"""
        self._nominal_per_metre = nominal.transmission.radians_per_metre
        """1/k of the nominal transmission (a belt: i_r/r): what the drive reports, through it"""
        self._plant_per_metre = p.transmission.force_per_torque
        """the true transmission's 1/k: applied torque → force on the cart"""
        self._rigid = plant.rigid
        if self._rigid:
            self._mech: RigidAxis | BeltAxis = RigidAxis(p, plant.simulation.substeps, x0)
            self._m_per_count = axis_resolution_m(p, plant.encoder.counts_per_rev)
            self._alpha_v = 1.0 - math.exp(
                -2.0 * math.pi * plant.encoder.velocity_filter_hz * EXECUTION_PERIOD_S
            )
            self._x_meas = self._encoder(x0)
            self._v_meas = 0.0
        else:
            self._real = _DriveSignals(plant, nominal)
            rotating = p.transmission.reflected_mass_kg() > 0.0  # a linear motor has no belt (docstring)
            belt = plant.belt if rotating else None
            self._mech = (
                BeltAxis(p, belt, plant.simulation.substeps, x0)
                if belt is not None
                else RigidAxis(p, plant.simulation.substeps, x0)
            )
            self._drift = FrictionDrift(p, plant.stroke_friction, plant.thermal, plant.wear)
            self._force_per_torque = p.transmission.force_per_torque
            self._real.measure(self._mech.motor_x, 0.0, first=True)
            self._x_meas, self._v_meas = self._real.position_m, self._real.velocity_m_s

    # ---- the true state ----------------------------------------------------------------------------
    @property
    def position_m(self) -> float:
        """The cart's true position [m]."""
        return self._mech.x

    @position_m.setter
    def position_m(self, value: float) -> None:
        self._mech.set_state(value, self._mech.v)

    @property
    def velocity_m_s(self) -> float:
        """The cart's true velocity [m/s]."""
        return self._mech.v

    @velocity_m_s.setter
    def velocity_m_s(self, value: float) -> None:
        self._mech.set_state(self._mech.x, value)

    @property
    def mechanics(self) -> RigidAxis | BeltAxis:
        """The integrated mechanics (the belt's stretch, the motor side's state)."""
        return self._mech

    @property
    def temperature_c(self) -> float:
        """The lubricant's temperature [°C] (NaN without a thermal model)."""
        return math.nan if self._rigid else self._drift.temperature_c

    def true_params(self, x0_m: float = 0.0, x1_m: float | None = None) -> AxisParams:
        """The plant's parameters at this moment: its friction now (temperature, wear), with a1 averaged
        over the stretch [x0, x1] of the stroke (default all of it); the plant file's axis for the
        ideal profile."""
        return self.plant.axis if self._rigid else self._drift.true_params(x0_m, x1_m)

    # ---- the drive ---------------------------------------------------------------------------------
    @property
    def stamp_ns(self) -> int:
        """The drive's time of the current tick [ns since the Unix epoch] (exact; a realistic sample's
        stamp may differ from it by the clock's jitter)."""
        if self._start_ns is None:
            self._start_ns = -(-time.time_ns() // EXECUTION_PERIOD_NS) * EXECUTION_PERIOD_NS
        return self._start_ns + self.tick * EXECUTION_PERIOD_NS

    def _encoder(self, x_m: float) -> float:
        return math.floor(x_m / self._m_per_count) * self._m_per_count

    def status(self) -> DriveStatus:
        """Always following; not fresh at a tick whose sample was lost (realistic profiles only)."""
        return _LOST if not self._rigid and self._real.lost else READY

    def read(self) -> AxisSample:
        """The sample of the current tick; at a tick whose sample was lost (see :meth:`status`), the
        last one that arrived."""
        if self._rigid:
            tau_meas = self.applied_torque_nm + self._rng.gauss(0.0, self.plant.torque_sensor.noise_std_nm)
            x, v, stamp = self._x_meas, self._v_meas, self.stamp_ns
        else:
            real = self._real
            if real.lost and self._last is not None:
                return self._last
            tau_meas, x, v = real.torque_nm, real.position_m, real.reported_velocity_m_s
            stamp = self.stamp_ns + real.jitter_ns
        self._last = AxisSample(
            stamp_ns=stamp,
            axis=self.axis,
            position_m=x,
            velocity_m_s=v,
            force_n=tau_meas * self._nominal_per_metre,
            motor_angle_rad=x * self._nominal_per_metre,
            motor_speed_rad_s=v * self._nominal_per_metre,
            motor_torque_nm=tau_meas,
        )
        return self._last

    def apply(self, setpoint: Setpoint) -> None:
        """Command the setpoint for the current tick and advance to the next tick."""
        force_cmd = (
            setpoint.force_ff_n
            + self.kp_n_m * (setpoint.position_m - self._x_meas)
            + self.kd_n_s_m * (setpoint.velocity_m_s - self._v_meas)
        )
        tau_max = self.plant.axis.tau_max
        tau = min(max(force_cmd * self._nominal_k, -tau_max), tau_max)
        self.applied_torque_nm = tau
        mech = self._mech
        if self._rigid:
            p = self.plant.axis
            mech.advance(tau * self._plant_per_metre, p.a1, p.a2, p.a3, p.a4, p.f0, p.da1, p.da2)
        else:
            self._advance_realistic(tau)
        self.tick += 1
        if self._state is not None:
            self._state.save(mech.x, mech.v)
        if self._rigid:
            x_new = self._encoder(mech.x)
            v_raw = (x_new - self._x_meas) / EXECUTION_PERIOD_S
            self._v_meas += self._alpha_v * (v_raw - self._v_meas)
            self._x_meas = x_new
        else:
            self._x_meas, self._v_meas = self._real.position_m, self._real.velocity_m_s

    def _advance_realistic(self, tau_nm: float) -> None:
        real, mech, drift = self._real, self._mech, self._drift
        tau_rotor = tau_nm + real.loop_torque_nm
        cogging = real.cogging_nm(mech.motor_x, mech.motor_v) if real.cogging else 0.0
        friction = drift.friction_at(mech.x)
        x_before = mech.x
        mech.advance((tau_rotor + cogging) * self._force_per_torque, *friction)
        if drift.drifts:
            drift.step(friction, abs(mech.v), abs(mech.x - x_before))
        real.measure(mech.motor_x, tau_rotor)

    def close(self) -> None:
        """Release the state file (its last state stays in it)."""
        if self._state is not None:
            self._state.close()
            self._state = None


class _DriveSignals:
    """What a realistic drive measures and reports each tick, in its own units (see the module doc)."""

    def __init__(self, plant: PlantConfig, nominal: AxisParams) -> None:
        self._draws = _Draws(plant.torque_sensor.seed)
        drive = plant.drive
        self.units = drive.units(nominal) if drive is not None else None
        self._m_per_count = (
            self.units.metres_per_count
            if self.units is not None
            else axis_resolution_m(plant.axis, plant.encoder.counts_per_rev)
        )
        filter_hz = drive.velocity_filter_hz if drive is not None else plant.encoder.velocity_filter_hz
        self._alpha_v = 1.0 - math.exp(-2.0 * math.pi * filter_hz * EXECUTION_PERIOD_S)
        self._white_nm = plant.torque_sensor.noise_std_nm
        loop = plant.current_loop or CurrentLoopConfig()
        self._loop = _ColouredNoise(loop.torque_noise_std_nm, loop.torque_noise_corner_hz)
        self._sensor = _ColouredNoise(loop.measurement_noise_std_nm, loop.measurement_noise_corner_hz)
        cog = plant.cogging
        self.cogging = tuple(zip(cog.orders, cog.amplitudes_nm, cog.phases_rad, strict=True)) if cog else ()
        """(order, amplitude [N·m], phase [rad]) of each cogging harmonic"""
        self._rad_per_m = plant.axis.transmission.radians_per_metre
        clock = plant.sample_clock or SampleClockConfig()
        self._jitter_ns = clock.jitter_ns
        self._drop = clock.drop_fraction
        self._counts: int | None = None
        self._v_counts_s = 0.0
        self.position_m = 0.0
        self.velocity_m_s = 0.0
        """the drive's velocity estimate [m/s] (what its controller uses)"""
        self.reported_velocity_m_s = 0.0
        """the estimate as reported: whole counts/s"""
        self.torque_nm = 0.0
        self.jitter_ns = 0
        self.lost = False
        self.loop_torque_nm = 0.0
        """the current loop's torque error through the coming tick [N·m] (drawn with the tick's draws)"""

    def cogging_nm(self, motor_x_m: float, motor_v_m_s: float) -> float:
        """Cogging torque [N·m] averaged over the tick's travel of the motor angle."""
        theta = motor_x_m * self._rad_per_m
        dtheta = motor_v_m_s * self._rad_per_m * EXECUTION_PERIOD_S
        middle = theta + 0.5 * dtheta
        total = 0.0
        for order, amplitude, phase in self.cogging:
            half = 0.5 * order * dtheta
            sinc = math.sin(half) / half if abs(half) > 1e-9 else 1.0
            total += amplitude * math.sin(order * middle + phase) * sinc
        return total

    def measure(self, motor_x_m: float, rotor_torque_nm: float, first: bool = False) -> None:
        """The sample of the new tick: the motor encoder at ``motor_x_m`` and the current of the
        ``rotor_torque_nm`` that acted through the tick before; and the draws of the tick."""
        g_loop, g_sensor, g_white, u_jitter, u_lost = self._draws.next()
        units = self.units
        if units is not None:
            counts = units.encoder_counts(motor_x_m)
            self.position_m = units.position_m(counts)
        else:
            counts = math.floor(motor_x_m / self._m_per_count)
            self.position_m = counts * self._m_per_count
        if self._counts is not None:
            raw = (counts - self._counts) / EXECUTION_PERIOD_S
            self._v_counts_s += self._alpha_v * (raw - self._v_counts_s)
        self._counts = counts
        self.velocity_m_s = self._v_counts_s * self._m_per_count
        self.reported_velocity_m_s = round(self._v_counts_s) * self._m_per_count
        sensed = rotor_torque_nm + self._sensor.next(g_sensor) + self._white_nm * g_white
        self.torque_nm = units.torque_nm(units.per_mille(sensed)) if units is not None else sensed
        self.loop_torque_nm = self._loop.next(g_loop)
        jitter = self._jitter_ns
        self.jitter_ns = int(u_jitter * (2 * jitter + 1)) - jitter if jitter else 0
        self.lost = u_lost < self._drop and not first


class _Draws:
    """The random draws of a realistic drive: per tick three standard normals and two uniforms in
    [0, 1), generated by numpy in blocks (one Python call per draw costs more than the tick's physics)
    from one seeded generator, so a run is reproducible."""

    BLOCK = 4096

    def __init__(self, seed: int) -> None:
        self._rng = np.random.default_rng(seed)
        self._rows: list[tuple[float, float, float, float, float]] = []
        self._next = 0

    def next(self) -> tuple[float, float, float, float, float]:
        if self._next == len(self._rows):
            normal = self._rng.standard_normal((self.BLOCK, 3))
            uniform = self._rng.random((self.BLOCK, 2))
            self._rows = [tuple(row) for row in np.hstack([normal, uniform]).tolist()]
            self._next = 0
        row = self._rows[self._next]
        self._next += 1
        return row


class _ColouredNoise:
    """A first-order Gauss–Markov process: n_k = ρ·n_(k−1) + √(1 − ρ²)·σ·g_k, ρ = exp(−2π·f_c·Δt),
    stationary standard deviation σ and corner frequency f_c (starting from 0)."""

    def __init__(self, std: float, corner_hz: float) -> None:
        self._rho = math.exp(-2.0 * math.pi * corner_hz * EXECUTION_PERIOD_S)
        self._step = std * math.sqrt(1.0 - self._rho * self._rho)
        self._value = 0.0

    def next(self, g: float) -> float:
        """The next value, ``g`` the tick's standard normal draw."""
        self._value = self._rho * self._value + self._step * g
        return self._value


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


def _check_saved_state(path: Path, x_m: float, v_m_s: float, axis: AxisParams) -> None:
    """A saved state a bridge of this axis could have written: inside the stroke, within the speed limit
    (plus :data:`STATE_SPEED_MARGIN`)."""
    if not 0.0 <= x_m <= axis.L:
        raise PlantError(
            f"plant state file {path} holds x = {x_m:g} m, outside the stroke [0, {axis.L:g}] m: give a new "
            "file or one a bridge of this axis wrote"
        )
    limit = axis.v_max * (1.0 + STATE_SPEED_MARGIN)
    if not abs(v_m_s) <= limit:
        raise PlantError(
            f"plant state file {path} holds v = {v_m_s:g} m/s, beyond ±{limit:g} m/s (v_max {axis.v_max:g} "
            f"m/s + {STATE_SPEED_MARGIN:.0%}): give a new file or one a bridge of this axis wrote"
        )


def _at_rest_after_coasting(x_m: float, v_m_s: float, axis: AxisParams) -> float:
    """Where a cart at ``x_m`` moving at ``v_m_s`` comes to rest on friction alone, inside [0, L]."""
    end = stop_profile(x_m, v_m_s, axis, force_fraction=0.0).trajectory.x1_m if v_m_s else x_m
    return min(max(end, 0.0), axis.L)
