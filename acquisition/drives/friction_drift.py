"""The simulated axis's true friction at any moment: along the stroke, warming up, wearing.

The plant file's true a1…a4 are the values of a cold, new axis averaged over the stroke. Three effects
move them (each only when its section is in the plant file):

* **along the stroke** (``[stroke_friction]``): a1(x) = a1·s(x), s(x) = 1 + Σ A_j·sin(2π·c_j·x/L + φ_j);
* **temperature** (``[thermal]``): the lubricant's temperature T follows the friction power P the cart
  dissipates, dT/dt = (T_amb + R·P − T)/τ (integrated exactly over each tick with P constant; the
  friction law there is inlined like the integrators'), and
  a2 ← a2·exp(−κ_v·(T − T_amb)), a1, a3 ← ·exp(−κ_c·(T − T_amb));
* **wear** (``[wear]``): a1, a3 ← ·(1 + w·d), d the kilometres the cart has travelled.

a4 (the shape of the low-speed term) stays. :meth:`FrictionDrift.true_params` gives the parameters of
this moment (the benchmarks and tests compare identification against it).
"""

from __future__ import annotations

import math

from ...model import EXECUTION_PERIOD_S, AxisParams
from .plant import StrokeFrictionConfig, ThermalConfig, WearConfig


class FrictionDrift:
    """The friction of one simulated axis over its life (see the module docstring)."""

    def __init__(
        self,
        axis: AxisParams,
        stroke: StrokeFrictionConfig | None,
        thermal: ThermalConfig | None,
        wear: WearConfig | None,
    ) -> None:
        self.axis = axis
        self.stroke = stroke
        self.thermal = thermal
        self.wear = wear
        self.temperature_c = thermal.ambient_c if thermal is not None else math.nan
        """the lubricant's temperature [°C] (NaN without a thermal model)"""
        self.travelled_m = 0.0
        """distance the cart has travelled [m] (counted when the friction drifts: thermal or wear)"""
        self.drifts = thermal is not None or wear is not None
        """whether :meth:`step` changes anything (else a caller may skip it)"""
        self._decay = math.exp(-EXECUTION_PERIOD_S / thermal.time_constant_s) if thermal else 1.0
        self._coulomb = 1.0
        self._viscous = 1.0
        w = 2.0 * math.pi / axis.L
        self._waves = (
            tuple(zip(stroke.amplitudes, [w * c for c in stroke.cycles], stroke.phases_rad, strict=True))
            if stroke is not None
            else ()
        )

    @property
    def coulomb_scale(self) -> float:
        """a1, a3 now over their cold, new values (temperature and wear) [-]."""
        return self._coulomb

    @property
    def viscous_scale(self) -> float:
        """a2 now over its cold value [-]."""
        return self._viscous

    def friction_at(self, x_m: float) -> tuple[float, float, float, float, float, float, float]:
        """(a1, a2, a3, a4, f0, da1, da2) acting on the cart at ``x_m`` now (f0 does not drift; the
        asymmetries drift with the Coulomb and the viscous friction)."""
        p = self.axis
        s = 1.0
        for amplitude, k, phase in self._waves:
            s += amplitude * math.sin(k * x_m + phase)
        c, viscous = self._coulomb, self._viscous
        return p.a1 * c * s, p.a2 * viscous, p.a3 * c, p.a4, p.f0, p.da1 * c * s, p.da2 * viscous

    def step(self, friction: tuple[float, ...], speed_m_s: float, distance_m: float) -> None:
        """Advance one tick in which the cart, under the ``friction`` (a1, a2, a3, a4) of
        :meth:`friction_at`, travelled ``distance_m`` [m] and ends at ``speed_m_s`` [m/s] (≥ 0): the
        friction power is taken as F_c(speed)·speed, ample for time constants of minutes."""
        self.travelled_m += distance_m
        thermal = self.thermal
        coulomb = 1.0
        if thermal is not None:
            a1, a2, a3, a4 = friction[:4]
            power = (a1 + a2 * speed_m_s + a3 * math.atan(a4 * speed_m_s)) * speed_m_s if speed_m_s else 0.0
            steady = thermal.ambient_c + thermal.resistance_k_per_w * power
            self.temperature_c = steady + (self.temperature_c - steady) * self._decay
            rise = self.temperature_c - thermal.ambient_c
            coulomb = math.exp(-thermal.coulomb_per_k * rise)
            self._viscous = math.exp(-thermal.viscous_per_k * rise)
        if self.wear is not None:
            coulomb *= 1.0 + self.wear.coulomb_per_km * self.travelled_m * 1e-3
        self._coulomb = coulomb

    def true_params(self, x0_m: float = 0.0, x1_m: float | None = None) -> AxisParams:
        """The axis's parameters now, with a1 averaged over the stretch [x0, x1] of the stroke (default
        the whole stroke)."""
        p = self.axis
        x1 = p.L if x1_m is None else x1_m
        mean = self.stroke.mean_factor(x0_m, x1, p.L) if self.stroke is not None else 1.0
        c, viscous = self._coulomb * mean, self._viscous
        return p.replace(
            a1=p.a1 * c, a2=p.a2 * viscous, a3=p.a3 * self._coulomb, da1=p.da1 * c, da2=p.da2 * viscous
        )
