"""A simulated fleet: N axes, each recording one log a day for D days, some of them wearing.

Each axis is the packaged ``realistic`` plant (acquisition/drives/plant_realistic.toml: drive units,
coloured current noise, cogging, an elastic belt, friction along the stroke, jittered stamps, lost
samples) with its own true parameters: ``[scale]`` factors on the nominal ones drawn once per axis,
M_eq's cart mass within ±:data:`MASS_SPREAD` and a1…a4 within ±:data:`FRICTION_SPREAD` (relative,
normal, clipped at 2.5 σ). A worn axis (``--wear AXIS:DAY:PERCENT[:RAMP_DAYS]``) has its Coulomb-like
friction a1 and a3 raised by PERCENT from day DAY on, at once or over RAMP_DAYS days; an idle day
(``--idle AXIS:DAY``) is a log of the axis standing still.

A day's log is the axis's working day in miniature: the simulated drive (:class:`SimulatedAxis`, the
plant integrated offline, not at real time) runs :data:`DAY_BURSTS` — sinusoidal bursts of the
identification excitation (:class:`~axisflow.identification.excitation.Burst`) at speeds from 2 cm/s
to 0.5 m/s both ways, in an order drawn per day — through the bridge's move queue, validated like live
moves. The state and setpoint topics are written by the recorder's writer
(:class:`~axisflow.acquisition.logs.recording_writer.RecordingWriter`: ROS 2 profile, zstd chunks),
encoded in bulk (:class:`~axisflow.acquisition.logs.joint_state_layout.JointStateLayout`).
Every random draw comes from the fleet's seed, so a fleet is reproducible.

``truth.json`` beside the logs (:class:`FleetTruth`) holds what the simulation knows and a fit can
only estimate: each axis's true parameters, its friction along the stroke and its wear;
:meth:`FleetTruth.params_on` gives the true parameters of a day with a1 averaged over a stretch, as the
refit's stroke terms report it.
"""

from __future__ import annotations

import json
import math
import re
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from ..acquisition.bridge.move_queue import MoveQueue
from ..acquisition.drives.plant import PlantConfig, StrokeFrictionConfig, load_profile, plant_from_mapping
from ..acquisition.drives.sim_axis import SimulatedAxis
from ..acquisition.logs.chunking import DEFAULT_CHUNK_SIZE
from ..acquisition.logs.joint_state_layout import JointStateLayout
from ..acquisition.logs.recording_writer import RecordingWriter
from ..acquisition.wire.keys import AxisKeys, topic_for_key
from ..acquisition.wire.messages import (
    APPEND,
    AXIS_JOINTS,
    JOINT_STATE_TYPE,
    SAMPLED_LAW,
    AxisSample,
    JointState,
    Knots,
    MoveCommand,
)
from ..identification.excitation import Burst, ExcitationPlan
from ..model import AxisParams, motor_angle, motor_speed, motor_torque, move_ticks
from ..model.files import atomic_path, write_atomic
from .errors import FleetValueError

NS_PER_DAY = 86_400_000_000_000
DEFAULT_FIRST_DAY = "2026-01-05"
"""the first simulated day (UTC)"""
DAY_START_S = 8 * 3600.0
"""each day's log starts at 08:00 UTC, the axes a minute apart"""
MASS_SPREAD = 0.03
FRICTION_SPREAD = 0.08
"""relative standard deviations of the axes' true parameters around nominal"""
DAY_BURSTS: tuple[tuple[float, float], ...] = (
    (0.02, 0.5),
    (0.06, 0.35),
    (0.15, 0.5),
    (0.3, 0.35),
    (0.5, 0.5),
)
"""(velocity amplitude [m/s], frequency [Hz]) of a day's bursts, each held one period between its
ramps: 35 s of motion. Two frequencies, so that the same speeds come with different accelerations and
the fit can resolve the torque/position offset (a single frequency cannot: docs/identification.md)"""
SETTLE_S = 0.5
"""drive time at rest before the first burst and after the last [s]"""
IDLE_S = 30.0
"""length of an idle day's log [s]"""
RECORD_DELAY_NS = 400_000
"""log time − stamp of the written messages [ns] (the recorder on loopback)"""
MAX_AXES = 1000
MAX_DAYS = 3660

_AXIS_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_-]*$")


def axis_names(count: int) -> tuple[str, ...]:
    """The simulated axes' names: a00, a01, … (as many digits as the count needs)."""
    width = len(str(max(count - 1, 0)))
    return tuple(f"a{i:0{width}d}" for i in range(count))


@dataclass(frozen=True)
class WearSpec:
    """Coulomb-like friction (a1 and a3) of ``axis`` up by ``percent`` from day ``day`` (0-based), at
    once (``ramp_days`` 0) or linearly over ``ramp_days`` days."""

    axis: str
    day: int
    percent: float
    ramp_days: int = 0

    @classmethod
    def parse(cls, text: str) -> WearSpec:
        """``AXIS:DAY:PERCENT`` or ``AXIS:DAY:PERCENT:RAMP_DAYS`` (``a03:12:25``: +25 % from day 12)."""
        parts = text.split(":")
        if len(parts) not in (3, 4) or not parts[0]:
            raise FleetValueError(f"--wear {text!r} must be AXIS:DAY:PERCENT or AXIS:DAY:PERCENT:RAMP_DAYS")
        try:
            day, percent = int(parts[1]), float(parts[2])
            ramp = int(parts[3]) if len(parts) == 4 else 0
        except ValueError:
            raise FleetValueError(
                f"--wear {text!r}: DAY and RAMP_DAYS must be whole days, PERCENT a number"
            ) from None
        return cls(parts[0], day, percent, ramp)

    def __post_init__(self) -> None:
        if self.day < 0:
            raise FleetValueError(f"wear of {self.axis}: day {self.day} must be >= 0")
        if not (math.isfinite(self.percent) and -50.0 <= self.percent <= 200.0):
            raise FleetValueError(f"wear of {self.axis}: {self.percent} % must be within [-50, 200] %")
        if self.ramp_days < 0:
            raise FleetValueError(f"wear of {self.axis}: ramp {self.ramp_days} days must be >= 0 days")

    def factor(self, day: int) -> float:
        """a1, a3 on ``day`` over their values before the wear [-]."""
        if day < self.day:
            return 1.0
        if self.ramp_days == 0:
            return 1.0 + self.percent / 100.0
        done = min((day - self.day + 1) / self.ramp_days, 1.0)
        return 1.0 + done * self.percent / 100.0


@dataclass(frozen=True)
class IdleSpec:
    """``axis`` stands still on ``day``: its log of that day has no motion."""

    axis: str
    day: int

    @classmethod
    def parse(cls, text: str) -> IdleSpec:
        """``AXIS:DAY``."""
        parts = text.split(":")
        try:
            if len(parts) != 2 or not parts[0]:
                raise ValueError
            return cls(parts[0], int(parts[1]))
        except ValueError:
            raise FleetValueError(f"--idle {text!r} must be AXIS:DAY (a whole day number)") from None


@dataclass(frozen=True)
class FleetSpec:
    """What :func:`simulate_fleet` simulates; equal specs give identical logs."""

    axes: int = 12
    days: int = 30
    seed: int = 0
    first_day: str = DEFAULT_FIRST_DAY
    """the first day, ISO date (UTC)"""
    wear: tuple[WearSpec, ...] = ()
    idle: tuple[IdleSpec, ...] = ()
    bursts: tuple[tuple[float, float], ...] = DAY_BURSTS
    """a day's bursts: (velocity amplitude [m/s], frequency [Hz]) (the tests use fewer)"""

    def __post_init__(self) -> None:
        if not self.bursts:
            raise FleetValueError("a simulated day needs at least one burst")
        for speed, f_hz in self.bursts:
            if not (0.001 <= speed <= 1.0 and 0.1 <= f_hz <= 2.0):
                raise FleetValueError(
                    f"burst ({speed} m/s, {f_hz} Hz) must be within [0.001, 1] m/s and [0.1, 2] Hz"
                )
        if not 1 <= self.axes <= MAX_AXES:
            raise FleetValueError(f"--axes {self.axes} must be within [1, {MAX_AXES}] axes")
        if not 1 <= self.days <= MAX_DAYS:
            raise FleetValueError(f"--days {self.days} must be within [1, {MAX_DAYS}] days")
        try:
            datetime.strptime(self.first_day, "%Y-%m-%d")
        except ValueError:
            raise FleetValueError(f"first day {self.first_day!r} must be an ISO date (YYYY-MM-DD)") from None
        names = set(self.names)
        seen: set[str] = set()
        for w in self.wear:
            if w.axis not in names:
                raise FleetValueError(f"--wear {w.axis}: no such axis (the fleet has {_span(self.names)})")
            if w.day >= self.days:
                raise FleetValueError(
                    f"--wear {w.axis}: day {w.day} is outside the {self.days} days simulated "
                    f"(0…{self.days - 1})"
                )
            if w.axis in seen:
                raise FleetValueError(f"--wear {w.axis}: given twice (one wear per axis)")
            seen.add(w.axis)
        for i in self.idle:
            if i.axis not in names:
                raise FleetValueError(f"--idle {i.axis}: no such axis (the fleet has {_span(self.names)})")
            if not 0 <= i.day < self.days:
                raise FleetValueError(
                    f"--idle {i.axis}: day {i.day} is outside the {self.days} days simulated "
                    f"(0…{self.days - 1})"
                )

    @property
    def names(self) -> tuple[str, ...]:
        return axis_names(self.axes)

    @property
    def first_day_ns(self) -> int:
        """Midnight UTC of the first day [ns since the Unix epoch]."""
        day = datetime.strptime(self.first_day, "%Y-%m-%d").replace(tzinfo=UTC)
        return int(day.timestamp()) * 1_000_000_000

    def day_start_ns(self, axis_index: int, day: int) -> int:
        """The first stamp of an axis's log of ``day`` [ns]."""
        return self.first_day_ns + day * NS_PER_DAY + int((DAY_START_S + 60.0 * axis_index) * 1e9)

    def wear_of(self, axis: str) -> WearSpec | None:
        return next((w for w in self.wear if w.axis == axis), None)

    def idle_on(self, axis: str, day: int) -> bool:
        return any(i.axis == axis and i.day == day for i in self.idle)


def _span(names: Sequence[str]) -> str:
    return f"{names[0]}…{names[-1]}" if len(names) > 1 else names[0]


@dataclass(frozen=True)
class AxisTruth:
    """One simulated axis: its plant's ``[scale]`` factors on the nominal parameters, the true
    parameters they give (new, before any wear), its friction along the stroke and its wear."""

    axis: str
    scale: dict[str, float]
    params: dict[str, float]
    """the true parameters (a parameter file's keys, SI) before any wear"""
    stroke_friction: dict[str, list[float]]
    """the plant's [stroke_friction] (amplitudes, cycles, phases_rad)"""
    wear: WearSpec | None = None
    idle_days: tuple[int, ...] = ()


@dataclass(frozen=True)
class FleetTruth:
    """``truth.json``: the fleet's spec and each axis's truth (see the module docstring)."""

    spec: FleetSpec
    axes: tuple[AxisTruth, ...]
    nominal: dict[str, float] = field(default_factory=dict)

    def axis(self, name: str) -> AxisTruth:
        found = next((a for a in self.axes if a.axis == name), None)
        if found is None:
            raise FleetValueError(f"axis {name} is not in the simulated fleet ({_span(self.spec.names)})")
        return found

    def params_on(self, name: str, day: int, stretch_m: tuple[float, float] | None = None) -> AxisParams:
        """The true parameters of axis ``name`` on ``day``: wear applied to a1 and a3, a1 averaged over
        ``stretch_m`` (None: the whole stroke)."""
        truth = self.axis(name)
        params = _params(truth.params)
        factor = truth.wear.factor(day) if truth.wear is not None else 1.0
        stroke = StrokeFrictionConfig(**{k: tuple(v) for k, v in truth.stroke_friction.items()})
        lo, hi = stretch_m if stretch_m is not None else (0.0, params.L)
        mean = stroke.mean_factor(lo, hi, params.L)
        return params.replace(a1=params.a1 * factor * mean, a3=params.a3 * factor)

    def to_json(self) -> dict[str, Any]:
        return {
            "spec": {
                "axes": self.spec.axes,
                "days": self.spec.days,
                "seed": self.spec.seed,
                "first_day": self.spec.first_day,
                "wear": [asdict(w) for w in self.spec.wear],
                "idle": [asdict(i) for i in self.spec.idle],
                "bursts": [list(b) for b in self.spec.bursts],
            },
            "nominal": self.nominal,
            "axes": [
                {
                    "axis": a.axis,
                    "scale": a.scale,
                    "params": a.params,
                    "stroke_friction": a.stroke_friction,
                    "wear": asdict(a.wear) if a.wear is not None else None,
                    "wear_onset": self.onset_iso(a) if a.wear is not None else None,
                    "idle_days": list(a.idle_days),
                }
                for a in self.axes
            ],
        }

    def onset_iso(self, truth: AxisTruth) -> str:
        """The start of the wear of an axis: its first worn day's log start, ISO 8601 UTC."""
        assert truth.wear is not None
        index = self.spec.names.index(truth.axis)
        stamp = self.spec.day_start_ns(index, truth.wear.day)
        return datetime.fromtimestamp(stamp / 1e9, UTC).isoformat().replace("+00:00", "Z")

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> FleetTruth:
        s = data["spec"]
        spec = FleetSpec(
            axes=s["axes"],
            days=s["days"],
            seed=s["seed"],
            first_day=s["first_day"],
            wear=tuple(WearSpec(**w) for w in s["wear"]),
            idle=tuple(IdleSpec(**i) for i in s["idle"]),
            bursts=tuple((float(v), float(f)) for v, f in s.get("bursts", DAY_BURSTS)),
        )
        axes = tuple(
            AxisTruth(
                axis=a["axis"],
                scale=a["scale"],
                params=a["params"],
                stroke_friction=a["stroke_friction"],
                wear=WearSpec(**a["wear"]) if a["wear"] is not None else None,
                idle_days=tuple(a["idle_days"]),
            )
            for a in data["axes"]
        )
        return cls(spec, axes, data.get("nominal", {}))


def _file_keys(params: AxisParams) -> dict[str, Any]:
    """The parameters as a parameter file's keys (M_eq follows from them)."""
    return {k: v for k, v in params.to_dict().items() if k != "M_eq"}


def _params(mapping: dict[str, float]) -> AxisParams:
    from ..model.params import params_from_mapping

    return params_from_mapping(mapping, "truth.json")


def read_truth(path: str | Path) -> FleetTruth:
    """A ``truth.json`` written by :func:`simulate_fleet`."""
    return FleetTruth.from_json(json.loads(Path(path).read_text("utf-8")))


def draw_scale(spec: FleetSpec, axis_index: int) -> dict[str, float]:
    """The ``[scale]`` factors of one axis's plant, drawn around 1 (see the module docstring)."""
    rng = np.random.default_rng([spec.seed, axis_index, 0x5CA1E])
    spreads = {"m": MASS_SPREAD, "J_m": 0.0, "a1": FRICTION_SPREAD, "a2": FRICTION_SPREAD}
    spreads |= {"a3": FRICTION_SPREAD, "a4": FRICTION_SPREAD}
    draws = np.clip(rng.standard_normal(len(spreads)), -2.5, 2.5)
    return {name: float(1.0 + s * g) for (name, s), g in zip(spreads.items(), draws, strict=True)}


def axis_truth(spec: FleetSpec, axis_index: int, nominal: AxisParams) -> AxisTruth:
    name = spec.names[axis_index]
    scale = draw_scale(spec, axis_index)
    plant = _plant(spec, axis_index, 0, nominal, scale, 1.0)
    stroke = plant.stroke_friction
    assert stroke is not None  # the realistic profile has friction along the stroke
    return AxisTruth(
        axis=name,
        scale=scale,
        params=_file_keys(plant.axis),
        stroke_friction={
            "amplitudes": list(stroke.amplitudes),
            "cycles": list(stroke.cycles),
            "phases_rad": list(stroke.phases_rad),
        },
        wear=spec.wear_of(name),
        idle_days=tuple(i.day for i in spec.idle if i.axis == name),
    )


def _plant(
    spec: FleetSpec,
    axis_index: int,
    day: int,
    nominal: AxisParams,
    scale: dict[str, float],
    coulomb_factor: float,
) -> PlantConfig:
    """The realistic plant of one axis on one day: its scale factors, wear on a1 and a3, the day's
    seed, starting at mid-stroke."""
    factors = dict(scale)
    factors["a1"] *= coulomb_factor
    factors["a3"] *= coulomb_factor
    mapping = {
        "profile": "realistic",
        "base": "realistic",
        "scale": factors,
        "torque_sensor": {"seed": (spec.seed * MAX_AXES + axis_index) * MAX_DAYS + day + 1},
        "simulation": {"initial_position_m": nominal.L / 2.0},
    }
    return plant_from_mapping(mapping, nominal, f"fleet axis {spec.names[axis_index]} day {day}")


def day_plan(spec: FleetSpec, axis_index: int, day: int, nominal: AxisParams) -> ExcitationPlan:
    """The day's bursts around mid-stroke, in an order drawn for the axis and day."""
    order = np.random.default_rng([spec.seed, axis_index, day]).permutation(len(spec.bursts))
    bursts = []
    for i in order:
        speed, f_hz = spec.bursts[int(i)]
        bursts.append(Burst(speed / (2.0 * math.pi * f_hz), f_hz, 1))
    return ExcitationPlan(nominal.L / 2.0, tuple(bursts), 1.0)


@dataclass(frozen=True)
class SimulatedDay:
    """One log :func:`simulate_day` wrote."""

    axis: str
    day: int
    path: Path
    samples: int
    lost: int
    coulomb_factor: float


@dataclass(frozen=True)
class _Columns:
    """A topic's samples as the loop collects them: the carriage joint (m, m/s, N); the motor joint
    follows from it through the nominal geometry (:func:`_joints`), as :class:`AxisSample` has it."""

    stamp_ns: list[int] = field(default_factory=list)
    position: list[float] = field(default_factory=list)
    velocity: list[float] = field(default_factory=list)
    effort: list[float] = field(default_factory=list)


def log_path(out: Path, axis: str, spec: FleetSpec, day: int) -> Path:
    """Where the log of ``axis`` on ``day`` goes: ``OUT/<axis>/<axis>_<date>.mcap``."""
    date = datetime.fromtimestamp((spec.first_day_ns + day * NS_PER_DAY) / 1e9, UTC).date().isoformat()
    return out / axis / f"{axis}_{date}.mcap"


def simulate_day(
    spec: FleetSpec, axis_index: int, day: int, out: str | Path, nominal: AxisParams
) -> SimulatedDay:
    """Simulate one axis's day and write its log under ``out`` (atomically; see the module docstring)."""
    name = spec.names[axis_index]
    wear = spec.wear_of(name)
    factor = wear.factor(day) if wear is not None else 1.0
    plant = _plant(spec, axis_index, day, nominal, draw_scale(spec, axis_index), factor)
    start_ns = spec.day_start_ns(axis_index, day)
    keys = AxisKeys(name)
    drive = SimulatedAxis(plant, nominal, start_ns, name)
    first = drive.read()
    queue = MoveQueue(nominal, first.position_m, first.stamp_ns, name)
    settle = move_ticks(SETTLE_S)
    end_tick = move_ticks(IDLE_S)
    if not spec.idle_on(name, day):
        queued = None
        for i, t in enumerate(day_plan(spec, axis_index, day, nominal).trajectories()):
            cmd = MoveCommand(
                start_ns, name, i + 1, APPEND, SAMPLED_LAW, t.x0_m, t.x1_m, t.duration_s, Knots.of(t)
            )
            queued = queue.submit(cmd, settle if queued is None else 0)
        assert queued is not None
        end_tick = queued.end_tick + settle
    state, setpoint = _Columns(), _Columns()
    fresh_ticks: list[int] = []
    for tick in range(end_tick):
        sample = drive.read()
        target = queue.setpoint(tick)
        if tick == 0 or drive.status().fresh:
            fresh_ticks.append(tick)
            _append(state, sample.stamp_ns, sample)
        setpoint.stamp_ns.append(queue.stamp_of(tick))
        setpoint.position.append(target.position_m)
        setpoint.velocity.append(target.velocity_m_s)
        setpoint.effort.append(target.force_ff_n)
        drive.apply(target)
    path = log_path(Path(out), name, spec, day)
    path.parent.mkdir(parents=True, exist_ok=True)
    _write_log(path, keys, _joints(state, nominal), _joints(setpoint, nominal), state, setpoint, fresh_ticks)
    return SimulatedDay(name, day, path, len(state.stamp_ns), end_tick - len(state.stamp_ns), factor)


def _append(columns: _Columns, stamp_ns: int, sample: AxisSample) -> None:
    columns.stamp_ns.append(stamp_ns)
    columns.position.append(sample.position_m)
    columns.velocity.append(sample.velocity_m_s)
    columns.effort.append(sample.force_n)


def _joints(columns: _Columns, nominal: AxisParams) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(position, velocity, effort) as (n, 2) arrays of the carriage and the motor joint."""
    x, v, f = (np.asarray(c, dtype=float) for c in (columns.position, columns.velocity, columns.effort))
    return (
        np.column_stack([x, motor_angle(x, nominal)]),
        np.column_stack([v, motor_speed(v, nominal)]),
        np.column_stack([f, motor_torque(f, nominal)]),
    )


def _write_log(
    path: Path,
    keys: AxisKeys,
    state_joints: tuple[np.ndarray, np.ndarray, np.ndarray],
    setpoint_joints: tuple[np.ndarray, np.ndarray, np.ndarray],
    state: _Columns,
    setpoint: _Columns,
    state_ticks: list[int],
) -> None:
    """Both topics in tick order, state before setpoint, as the recorder writes them."""
    layout, template = JointStateLayout.for_message(
        JointState(0, keys.axis, AXIS_JOINTS, (0.0, 0.0), (0.0, 0.0), (0.0, 0.0))
    )
    size = layout.size
    blobs = []
    for cols, joints in ((state, state_joints), (setpoint, setpoint_joints)):
        stamps = np.asarray(cols.stamp_ns, dtype=np.int64)
        blobs.append(layout.encode(template, stamps, *joints).tobytes())
    with atomic_path(path) as part:
        writer = RecordingWriter(part, "zstd", DEFAULT_CHUNK_SIZE)
        try:
            s_ch, p_ch = (
                writer.channel_for(topic_for_key(k), JOINT_STATE_TYPE) for k in (keys.state, keys.setpoint)
            )
            s_blob, p_blob = blobs
            s_stamps, p_stamps = state.stamp_ns, setpoint.stamp_ns
            add = writer.add
            next_state = 0
            for tick, stamp in enumerate(p_stamps):
                if next_state < len(state_ticks) and state_ticks[next_state] == tick:
                    i = next_state
                    t = s_stamps[i]
                    add(s_ch, t + RECORD_DELAY_NS, t, i + 1, s_blob[i * size : (i + 1) * size])
                    next_state += 1
                add(p_ch, stamp + RECORD_DELAY_NS, stamp, tick + 1, p_blob[tick * size : (tick + 1) * size])
        finally:
            writer.finish()
        if writer.dropped:  # a backlog larger than any day's log: never expected
            raise FleetValueError(f"{path}: the writer dropped messages {writer.dropped}")


def check_simulation_dir(out: str | Path, overwrite: bool) -> Path:
    """``out`` as a folder for a new fleet: a fleet already there (its truth.json) only with
    ``overwrite``."""
    from ..model.files import ensure_dir

    folder = ensure_dir(out)
    if (folder / TRUTH_FILE).exists() and not overwrite:
        raise FleetValueError(
            f"{folder} holds a simulated fleet already ({TRUTH_FILE}): give --overwrite or another folder"
        )
    return folder


TRUTH_FILE = "truth.json"


def write_truth(out: Path, spec: FleetSpec, nominal: AxisParams) -> FleetTruth:
    truth = FleetTruth(
        spec, tuple(axis_truth(spec, i, nominal) for i in range(spec.axes)), _file_keys(nominal)
    )
    write_atomic(out / TRUTH_FILE, json.dumps(truth.to_json(), indent=1) + "\n")
    return truth


def default_nominal() -> AxisParams:
    """The nominal parameters of a simulated fleet (the packaged defaults)."""
    from ..model import default_params

    return default_params()


def realistic_plant(nominal: AxisParams) -> PlantConfig:
    """The packaged realistic plant (what every axis builds on)."""
    return load_profile("realistic", nominal)


@dataclass(frozen=True)
class SimulatedFleet:
    """What :func:`simulate_fleet` wrote."""

    out: Path
    truth: FleetTruth
    days: tuple[SimulatedDay, ...]
    wall_s: float


def simulate_fleet(
    spec: FleetSpec,
    out: str | Path,
    client: Any,
    nominal: AxisParams,
    progress: Callable[[int, int], None] | None = None,
) -> SimulatedFleet:
    """Every axis's every day on ``client``'s cluster (a task per log, written on the worker), then
    ``truth.json``; ``progress(done, total)`` after each log."""
    from distributed import as_completed

    t0 = time.perf_counter()
    folder = Path(out)
    futures = [
        client.submit(simulate_day, spec, i, day, folder, nominal, pure=False)
        for day in range(spec.days)
        for i in range(spec.axes)
    ]
    days = []
    for done, future in enumerate(as_completed(futures), 1):
        days.append(future.result())
        if progress is not None:
            progress(done, len(futures))
    truth = write_truth(folder, spec, nominal)
    days.sort(key=lambda d: (d.axis, d.day))
    return SimulatedFleet(folder, truth, tuple(days), time.perf_counter() - t0)
