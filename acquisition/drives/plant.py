"""The plant file: the true axis behind the simulated drive, its sensors, controller and imperfections.

A plant file is TOML. Its top-level ``profile`` names it (shown by the bridge, the demo and the
benchmarks); its sections say what the simulated drive does. Three profiles are packaged
(:data:`~.plant_profiles.PROFILE_RESOURCES`; numbers and sources in docs/plant.md):

* ``ideal`` — eq. (1) of the paper, rigid, with a pulley encoder and white torque noise (the closed-form
  tests rely on it; the default);
* ``realistic`` — a drive as a user meets it: motor encoder in counts and torque in per mille of the
  rated torque (:class:`~axisflow.model.drive_units.DriveUnits`), coloured current-loop noise, cogging
  periodic in the motor angle, an elastic belt between the pulley and the cart, Coulomb friction that
  varies along the stroke, a sample clock with jittered stamps and lost samples;
* ``warm-up`` — realistic, with friction that falls as the lubricant warms (a first-order thermal model
  driven by the dissipated power) and slow wear.

Sections (each optional unless said; unknown sections and keys are errors naming them):

* the true axis, exactly one of ``[scale]`` (factors on the nominal ``--params``: what the default files
  use, so that identification has something to find whatever the nominal set) or ``[axis]`` (a complete
  parameter table, absolute SI values);
* ``[encoder]`` (ideal: pulley encoder), ``[torque_sensor]`` (white measurement noise, the seed of every
  random draw), ``[controller]``, ``[simulation]`` — as before;
* ``[drive]`` — the drive's own units: a motor encoder of ``counts_per_rev`` counts per motor revolution
  and a torque in per mille of ``rated_torque_nm``; replaces ``[encoder]``;
* ``[current_loop]``, ``[cogging]``, ``[belt]``, ``[stroke_friction]``, ``[sample_clock]``,
  ``[thermal]``, ``[wear]`` — the imperfections, described on their dataclasses below.

:func:`load_plant` reads a file (None: the packaged default, ``ideal``); :func:`load_profile` a packaged
profile by name.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from ...model import AxisflowError, AxisParams
from ...model.drive_units import DriveUnits
from ...model.encoder import ENCODER_COUNTS_PER_REV
from ...model.params import params_from_mapping
from ...model.toml_file import read_toml
from ..errors import PlantError
from .plant_profiles import DEFAULT_PLANT_RESOURCE, DEFAULT_PROFILE, PROFILE_RESOURCES


def _check(name: str, value: Any, lower: float, upper: float = math.inf, unit: str = "") -> None:
    """A finite number in [lower, upper], or a :class:`PlantError` naming the key, the range and unit."""
    u = f" {unit}" if unit else ""
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise PlantError(f"plant {name} = {value!r} must be a finite number{u and ' in' + u}")
    if value < lower:
        raise PlantError(f"plant {name} = {value}{u} must be >= {lower}{u}")
    if value > upper:
        raise PlantError(f"plant {name} = {value}{u} must be <= {upper}{u}")


@dataclass(frozen=True)
class EncoderConfig:
    """The ideal profile's pulley encoder and the drive's velocity estimate."""

    counts_per_rev: int = ENCODER_COUNTS_PER_REV
    """pulley encoder counts per revolution"""
    velocity_filter_hz: float = 500.0
    """cut-off of the first-order low-pass on the encoder velocity [Hz]"""

    def __post_init__(self) -> None:
        _check("encoder.counts_per_rev", self.counts_per_rev, 1, unit="counts")
        _check("encoder.velocity_filter_hz", self.velocity_filter_hz, 1e-9, unit="Hz")


@dataclass(frozen=True)
class TorqueSensorConfig:
    noise_std_nm: float = 0.01
    """standard deviation of the white torque-measurement noise [N·m]"""
    seed: int = 1
    """seed of every random draw of the plant (noise, stamps, lost samples)"""

    def __post_init__(self) -> None:
        _check("torque_sensor.noise_std_nm", self.noise_std_nm, 0.0, unit="N·m")


@dataclass(frozen=True)
class ControllerConfig:
    bandwidth_hz: float = 20.0
    """closed-loop natural frequency of the position loop [Hz]"""
    damping: float = 1.0
    """damping ratio ζ [-]"""

    def __post_init__(self) -> None:
        _check("controller.bandwidth_hz", self.bandwidth_hz, 1e-9, unit="Hz")
        _check("controller.damping", self.damping, 0.0)


@dataclass(frozen=True)
class SimulationConfig:
    substeps: int = 4
    """integration steps per 1 ms tick"""
    initial_position_m: float = 0.0

    def __post_init__(self) -> None:
        _check("simulation.substeps", self.substeps, 1, 1000, unit="steps")


@dataclass(frozen=True)
class DriveConfig:
    """What the drive reports in its own units (a motor encoder, per mille torque)."""

    counts_per_rev: int = 65536
    """motor encoder counts per motor revolution"""
    rated_torque_nm: float = 1.6
    """the motor's rated torque [N·m]: the torque is reported in per mille of it"""
    velocity_filter_hz: float = 100.0
    """cut-off of the drive's first-order low-pass on its encoder velocity [Hz]"""

    def __post_init__(self) -> None:
        _check("drive.counts_per_rev", self.counts_per_rev, 1, 1 << 30, unit="counts")
        _check("drive.rated_torque_nm", self.rated_torque_nm, 1e-3, unit="N·m")
        _check("drive.velocity_filter_hz", self.velocity_filter_hz, 1e-9, unit="Hz")

    def units(self, nominal: AxisParams) -> DriveUnits:
        """The drive's unit conversions, configured with the nominal geometry (r, i_r)."""
        return DriveUnits.for_axis(nominal, self.counts_per_rev, self.rated_torque_nm)


@dataclass(frozen=True)
class CurrentLoopConfig:
    """Noise of the current loop, each a first-order (coloured) Gaussian process.

    ``torque_noise_*``: the loop's error, a torque that really acts on the rotor (and so is both in the
    motion and in the measured current); ``measurement_noise_*``: the current measurement's own
    low-frequency noise (sensor offset wander, aliased PWM ripple), in the reported torque only.
    """

    torque_noise_std_nm: float = 0.0
    torque_noise_corner_hz: float = 200.0
    measurement_noise_std_nm: float = 0.0
    measurement_noise_corner_hz: float = 20.0

    def __post_init__(self) -> None:
        _check("current_loop.torque_noise_std_nm", self.torque_noise_std_nm, 0.0, unit="N·m")
        _check("current_loop.torque_noise_corner_hz", self.torque_noise_corner_hz, 1e-3, unit="Hz")
        _check("current_loop.measurement_noise_std_nm", self.measurement_noise_std_nm, 0.0, unit="N·m")
        _check("current_loop.measurement_noise_corner_hz", self.measurement_noise_corner_hz, 1e-3, unit="Hz")


@dataclass(frozen=True)
class CoggingConfig:
    """Cogging torque on the rotor: Σ amplitude_nm[i]·sin(orders[i]·θ_m + phases_rad[i]), θ_m the motor
    angle [rad]; orders are cycles per motor revolution (multiples of the slot/pole count)."""

    orders: tuple[int, ...] = ()
    amplitudes_nm: tuple[float, ...] = ()
    phases_rad: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        for name in ("orders", "amplitudes_nm", "phases_rad"):
            object.__setattr__(self, name, tuple(_list(f"cogging.{name}", getattr(self, name))))
        if not len(self.orders) == len(self.amplitudes_nm) == len(self.phases_rad):
            raise PlantError(
                f"plant cogging: orders, amplitudes_nm and phases_rad must have the same length "
                f"(got {len(self.orders)}, {len(self.amplitudes_nm)}, {len(self.phases_rad)})"
            )
        for i, (n, a, p) in enumerate(zip(self.orders, self.amplitudes_nm, self.phases_rad, strict=True)):
            if isinstance(n, bool) or not isinstance(n, int):
                raise PlantError(
                    f"plant cogging.orders[{i}] = {n!r} must be an integer (cycles per revolution)"
                )
            _check(f"cogging.orders[{i}]", n, 1, 10_000, unit="cycles/rev")
            _check(f"cogging.amplitudes_nm[{i}]", a, 0.0, unit="N·m")
            _check(f"cogging.phases_rad[{i}]", p, -1e3, 1e3, unit="rad")


@dataclass(frozen=True)
class BeltConfig:
    """The toothed belt between the drive pulley and the cart, as a spring-damper.

    A belt span of length l has the stiffness C/l, C the belt's specific spring rate times its width
    (``spring_rate_n``). The cart is pulled by two spans in parallel: from the drive pulley
    (length x + ``end_span_m``) and the other way round the loop, past the idler and back along the
    axis (length 2·L + 3·``end_span_m`` − x). The damping c = 2·ζ·√(k·m_red) is set at mid-stroke
    (m_red: the reduced mass of the rotating parts and the cart) and held constant.
    """

    spring_rate_n: float = 1.0e6
    """specific spring rate × width [N] (stiffness of one metre of belt: N/m)"""
    end_span_m: float = 0.1
    """belt length between a pulley and the cart at the nearest end of the stroke [m]"""
    damping_ratio: float = 0.05
    """ζ of the belt mode at mid-stroke [-]"""

    def __post_init__(self) -> None:
        _check("belt.spring_rate_n", self.spring_rate_n, 1e3, 1e10, unit="N")
        _check("belt.end_span_m", self.end_span_m, 1e-3, 100.0, unit="m")
        _check("belt.damping_ratio", self.damping_ratio, 0.0, 2.0)

    def stiffness_n_m(self, x_m: float, stroke_m: float) -> float:
        """Belt stiffness [N/m] at the cart position ``x_m`` (the two spans in parallel)."""
        near = x_m + self.end_span_m
        far = 2.0 * stroke_m + 3.0 * self.end_span_m - x_m
        return self.spring_rate_n * (1.0 / near + 1.0 / far)


@dataclass(frozen=True)
class StrokeFrictionConfig:
    """Coulomb friction a1 that varies along the stroke (guide preload, rail straightness):
    a1(x) = a1·(1 + Σ amplitudes[j]·sin(2π·cycles[j]·x/L + phases_rad[j])). With whole numbers of
    cycles over the stroke, the average over [0, L] is a1."""

    amplitudes: tuple[float, ...] = ()
    """relative amplitudes [-]"""
    cycles: tuple[float, ...] = ()
    """cycles over the stroke L [-]"""
    phases_rad: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        for name in ("amplitudes", "cycles", "phases_rad"):
            object.__setattr__(self, name, tuple(_list(f"stroke_friction.{name}", getattr(self, name))))
        if not len(self.amplitudes) == len(self.cycles) == len(self.phases_rad):
            raise PlantError(
                "plant stroke_friction: amplitudes, cycles and phases_rad must have the same length "
                f"(got {len(self.amplitudes)}, {len(self.cycles)}, {len(self.phases_rad)})"
            )
        for i, (a, c, p) in enumerate(zip(self.amplitudes, self.cycles, self.phases_rad, strict=True)):
            _check(f"stroke_friction.amplitudes[{i}]", a, 0.0, 0.5)
            _check(f"stroke_friction.cycles[{i}]", c, 0.0, 1000.0)
            _check(f"stroke_friction.phases_rad[{i}]", p, -1e3, 1e3, unit="rad")
        if sum(self.amplitudes) >= 1.0:
            raise PlantError(
                f"plant stroke_friction: the amplitudes add up to {sum(self.amplitudes)}, must be < 1"
            )

    def factor(self, x_m: float, stroke_m: float) -> float:
        """a1(x)/a1 at the cart position ``x_m``."""
        w = 2.0 * math.pi / stroke_m
        return 1.0 + sum(
            a * math.sin(w * c * x_m + p)
            for a, c, p in zip(self.amplitudes, self.cycles, self.phases_rad, strict=True)
        )

    def mean_factor(self, x0_m: float, x1_m: float, stroke_m: float) -> float:
        """The average of a1(x)/a1 over [x0, x1] (exact integral of the sines)."""
        if x1_m <= x0_m:
            return self.factor(x0_m, stroke_m)
        w = 2.0 * math.pi / stroke_m
        total = 0.0
        for a, c, p in zip(self.amplitudes, self.cycles, self.phases_rad, strict=True):
            k = w * c
            if k == 0.0:
                total += a * math.sin(p) * (x1_m - x0_m)
            else:
                total += a * (math.cos(k * x0_m + p) - math.cos(k * x1_m + p)) / k
        return 1.0 + total / (x1_m - x0_m)


@dataclass(frozen=True)
class SampleClockConfig:
    """What happens to the samples on their way from the drive: each stamp is the drive's tick time plus
    a uniform error in ±``jitter_ns`` (the host stamps what it receives), and each sample is lost with
    probability ``drop_fraction`` (a lost frame); the drive's own loop runs on regardless."""

    jitter_ns: int = 0
    drop_fraction: float = 0.0

    def __post_init__(self) -> None:
        _check("sample_clock.jitter_ns", self.jitter_ns, 0, 400_000, unit="ns")
        _check("sample_clock.drop_fraction", self.drop_fraction, 0.0, 0.5)


@dataclass(frozen=True)
class ThermalConfig:
    """The lubricant's temperature T, a first-order model driven by the friction power P dissipated in
    the axis: dT/dt = (ambient + R·P − T)/τ. Viscous and Coulomb-like friction fall with it:
    a2·exp(−viscous_per_k·(T − ambient)), a1 and a3 with exp(−coulomb_per_k·(T − ambient))."""

    ambient_c: float = 20.0
    """ambient (and starting) temperature [°C]"""
    resistance_k_per_w: float = 0.2
    """thermal resistance to ambient [K/W]: the steady rise per watt dissipated"""
    time_constant_s: float = 600.0
    """thermal time constant τ [s]"""
    viscous_per_k: float = 0.012
    """relative fall of a2 per kelvin [1/K]"""
    coulomb_per_k: float = 0.005
    """relative fall of a1 and a3 per kelvin [1/K]"""

    def __post_init__(self) -> None:
        _check("thermal.ambient_c", self.ambient_c, -50.0, 150.0, unit="°C")
        _check("thermal.resistance_k_per_w", self.resistance_k_per_w, 0.0, 100.0, unit="K/W")
        _check("thermal.time_constant_s", self.time_constant_s, 1.0, 1e6, unit="s")
        _check("thermal.viscous_per_k", self.viscous_per_k, 0.0, 0.1, unit="1/K")
        _check("thermal.coulomb_per_k", self.coulomb_per_k, 0.0, 0.1, unit="1/K")


@dataclass(frozen=True)
class WearConfig:
    """Slow wear: a1 and a3 grow by ``coulomb_per_km`` (relative) per kilometre the cart travels."""

    coulomb_per_km: float = 0.0

    def __post_init__(self) -> None:
        _check("wear.coulomb_per_km", self.coulomb_per_km, 0.0, 10.0, unit="1/km")


@dataclass(frozen=True)
class PlantConfig:
    """A plant file: the true axis and the simulated drive's sensors, controller and imperfections."""

    axis: AxisParams
    encoder: EncoderConfig
    torque_sensor: TorqueSensorConfig
    controller: ControllerConfig
    simulation: SimulationConfig
    profile: str = DEFAULT_PROFILE
    """the plant's name (``ideal``, ``realistic``, ``warm-up`` or a user's)"""
    source: str = ""
    """where the file came from (for reports)"""
    drive: DriveConfig | None = None
    current_loop: CurrentLoopConfig | None = None
    cogging: CoggingConfig | None = None
    belt: BeltConfig | None = None
    stroke_friction: StrokeFrictionConfig | None = None
    sample_clock: SampleClockConfig | None = None
    thermal: ThermalConfig | None = None
    wear: WearConfig | None = None
    scale: dict[str, float] = field(default_factory=dict)
    """the ``[scale]`` factors the true axis was made with (empty for an ``[axis]`` table; without a
    factor on a part its transmission does not have)"""

    def __post_init__(self) -> None:
        x0 = self.simulation.initial_position_m
        _check("simulation.initial_position_m", x0, -math.inf, unit="m")
        if not 0.0 <= x0 <= self.axis.L:
            raise PlantError(f"plant simulation.initial_position_m = {x0} m is outside [0, {self.axis.L}] m")

    @property
    def rigid(self) -> bool:
        """True for the ideal profile's plant: eq. (1) with the pulley encoder and white noise only."""
        return all(getattr(self, name) is None for name in _EXTRA_SECTIONS)

    def describe(self) -> str:
        """The profile and where it came from: ``realistic (packaged plant_realistic.toml)``."""
        return f"{self.profile} ({self.source})" if self.source else self.profile


_SECTIONS: dict[str, type] = {
    "encoder": EncoderConfig,
    "torque_sensor": TorqueSensorConfig,
    "controller": ControllerConfig,
    "simulation": SimulationConfig,
}
_EXTRA_SECTIONS: dict[str, type] = {
    "drive": DriveConfig,
    "current_loop": CurrentLoopConfig,
    "cogging": CoggingConfig,
    "belt": BeltConfig,
    "stroke_friction": StrokeFrictionConfig,
    "sample_clock": SampleClockConfig,
    "thermal": ThermalConfig,
    "wear": WearConfig,
}
_INT_FIELDS = {"counts_per_rev", "seed", "substeps", "jitter_ns"}


def _list(name: str, value: Any) -> list[Any]:
    if not isinstance(value, list | tuple):
        raise PlantError(f"plant {name} = {value!r} must be a list")
    return list(value)


def _section(name: str, cls: type, data: Any, source: str) -> Any:
    if not isinstance(data, dict):
        raise PlantError(f"{source}: [{name}] must be a table, got {data!r}")
    allowed = [f.name for f in fields(cls)]
    unknown = sorted(set(data) - set(allowed))
    if unknown:
        raise PlantError(
            f"{source}: unknown key(s) {', '.join(unknown)} in [{name}]; allowed: {', '.join(allowed)}"
        )
    for key, value in data.items():
        if key in _INT_FIELDS and not (isinstance(value, int) and not isinstance(value, bool)):
            raise PlantError(f"{source}: [{name}] {key} = {value!r} must be an integer")
    try:
        return cls(**data)
    except PlantError as exc:
        raise PlantError(f"{source}: {exc}") from None


SCALABLE = ("m", "J_m", "J_g", "J_p", "a1", "a2", "a3", "a4")
"""the true-axis keys a ``[scale]`` table may scale"""
_ROTATING = frozenset({"J_m", "J_g", "J_p"})
"""the keys of :data:`SCALABLE` that belong to a transmission, which not every kind has"""


def _true_axis(data: dict[str, Any], nominal: AxisParams, source: str) -> tuple[AxisParams, dict[str, float]]:
    if ("axis" in data) == ("scale" in data):
        raise PlantError(
            f"{source}: give the true axis either as [scale] factors on the nominal parameters or as a "
            "complete [axis] table (exactly one of them)"
        )
    if "axis" in data:
        try:
            return params_from_mapping(data["axis"], f"{source} [axis]"), {}
        except AxisflowError as exc:
            raise PlantError(str(exc)) from None
    factors = data["scale"]
    unknown = sorted(set(factors) - set(SCALABLE))
    if unknown:
        raise PlantError(
            f"{source}: unknown key(s) {', '.join(unknown)} in [scale]; allowed: {', '.join(SCALABLE)}"
        )
    for key, value in factors.items():
        if isinstance(value, bool) or not isinstance(value, int | float) or not 0.0 < value < math.inf:
            raise PlantError(f"{source}: [scale] {key} = {value!r} must be a finite factor > 0")
    # a factor on a part the transmission does not have (a linear motor's rotor and gearbox, a screw
    # axis's pulley) scales nothing, as a factor on a term that is off does: the packaged profiles
    # scale the rotor of every kind that has one
    applied = {
        k: float(v) for k, v in factors.items() if k not in _ROTATING or k in nominal.transmission.keys
    }
    try:
        axis = nominal.replace(**{k: getattr(nominal, k) * v for k, v in applied.items()})
    except AxisflowError as exc:
        raise PlantError(f"{source}: {exc}") from None
    return axis, applied


_REPLACES = {"axis": "scale", "scale": "axis", "drive": "encoder"}
"""a section of a file that replaces another section of its base"""


def _with_base(data: dict[str, Any], source: str, seen: tuple[str, ...] = ()) -> dict[str, Any]:
    """``data`` on top of its ``base`` profile's mapping: tables merge key by key (the file's keys win),
    other values are replaced; ``[axis]`` replaces a base's ``[scale]`` (and back), ``[drive]`` its
    ``[encoder]``."""
    base = data.get("base")
    if base is None:
        return data
    if not isinstance(base, str) or base not in PROFILE_RESOURCES:
        raise PlantError(
            f"{source}: base = {base!r} is not a packaged profile ({', '.join(PROFILE_RESOURCES)})"
        )
    if base in seen:
        raise PlantError(f"{source}: base profiles form a cycle: {' → '.join((*seen, base))}")
    raw, base_source = read_toml(
        None, package=__package__, resource=PROFILE_RESOURCES[base], kind="plant", error=PlantError
    )
    merged = {
        k: dict(v) if isinstance(v, dict) else v
        for k, v in _with_base(raw, base_source, (*seen, base)).items()
    }
    for key, replaced in _REPLACES.items():
        if key in data:
            merged.pop(replaced, None)
    for key, value in data.items():
        if key == "base":
            continue
        old = merged.get(key)
        merged[key] = {**old, **value} if isinstance(old, dict) and isinstance(value, dict) else value
    return merged


def plant_from_mapping(data: dict[str, Any], nominal: AxisParams, source: str = "plant") -> PlantConfig:
    """Validate a plant mapping (see the module docstring); ``base = NAME`` builds on a packaged
    profile."""
    allowed = ["profile", "base", "axis", "scale", *_SECTIONS, *_EXTRA_SECTIONS]
    unknown = sorted(set(data) - set(allowed))
    if unknown:
        raise PlantError(f"{source}: unknown section(s) {', '.join(unknown)}; allowed: {', '.join(allowed)}")
    data = _with_base(data, source)
    rigid = not any(name in data for name in _EXTRA_SECTIONS)
    profile = data.get("profile", DEFAULT_PROFILE if rigid else "custom")
    if not isinstance(profile, str) or not profile.strip():
        raise PlantError(f"{source}: profile = {profile!r} must be a non-empty name")
    if "drive" in data and "encoder" in data:
        raise PlantError(
            f"{source}: [drive] measures with the motor encoder it describes; [encoder] (the pulley "
            "encoder of the ideal plant) cannot be given with it"
        )
    axis, scale = _true_axis(data, nominal, source)
    parts = {name: _section(name, cls, data.get(name, {}), source) for name, cls in _SECTIONS.items()}
    extras = {
        name: _section(name, cls, data[name], source) for name, cls in _EXTRA_SECTIONS.items() if name in data
    }
    try:
        return PlantConfig(axis=axis, profile=profile, source=source, scale=scale, **parts, **extras)
    except PlantError as exc:
        raise PlantError(f"{source}: {exc}") from None


def load_plant(path: str | Path | None, nominal: AxisParams) -> PlantConfig:
    """Load a plant file (None: the packaged default, the ``ideal`` profile) relative to the ``nominal``
    parameters."""
    if path is None:
        return load_profile(DEFAULT_PROFILE, nominal)
    data, source = read_toml(path, package=__package__, resource="", kind="plant", error=PlantError)
    return plant_from_mapping(data, nominal, source)


def load_profile(name: str, nominal: AxisParams) -> PlantConfig:
    """The packaged plant file of profile ``name`` (one of :data:`PROFILE_RESOURCES`)."""
    resource = PROFILE_RESOURCES.get(name)
    if resource is None:
        raise PlantError(f"plant profile {name!r} is not one of {', '.join(PROFILE_RESOURCES)}")
    data, _source = read_toml(None, package=__package__, resource=resource, kind="plant", error=PlantError)
    return plant_from_mapping(data, nominal, f"packaged {resource}")


def default_scale() -> dict[str, float]:
    """The ``[scale]`` factors of the packaged default plant: the one home of "the simulated plant has
    5 % more inertia and 12–20 % more Coulomb friction" (tests, benchmarks and docs read them here)."""
    data, _source = read_toml(
        None, package=__package__, resource=DEFAULT_PLANT_RESOURCE, kind="plant", error=PlantError
    )
    return {k: float(v) for k, v in data["scale"].items()}
