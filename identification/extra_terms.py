"""Terms of the measured effort beyond eq. (1) that a real axis shows and a fit can take in.

Both are linear in their coefficients, so they join the fit as extra columns of its Jacobian:

* **Coulomb friction along the stroke.** A guide's preload and straightness vary along the rail, so
  the Coulomb force does: a1(x) = a1 + Σ_{k=1..K} c_k·P_k(ξ), P_k the Legendre polynomials and
  ξ ∈ [−1, 1] the position over the stretch the fitted samples cover. The terms are c_k·sign(ẋ)·P_k(ξ)
  [N]; the Legendre polynomials are orthogonal over the stretch, so a1 stays the Coulomb force
  *averaged over the covered stretch* and the c_k its variation. (Without them, the variation lands
  in the other parameters and in the residual.)
* **Cogging.** The motor's cogging torque τ_c(θ) = Σ_n (s_n·sin nθ + c_n·cos nθ), θ the motor angle,
  acts on the rotor; the current the drive measures is then the rigid-body torque *minus* it,
  whatever the position loop does (the loop's reaction is in the measured acceleration). Its terms are
  −(i_r/r)·filt(sin nθ), −(i_r/r)·filt(cos nθ) [N per N·m of coefficient], filt the fit's zero-phase
  filter applied to the raw angle's sines (the measured effort went through it too), set to zero where
  the cogging frequency n·|θ̇|/2π exceeds a quarter of the sampling rate (there the samples alias it,
  and the filter has removed what it did to the effort).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .errors import IdentificationError
from .preparation import PreparationSettings, PreparedLog

if TYPE_CHECKING:
    from ..model import AxisParams

DEFAULT_STROKE_TERMS = 6
"""Legendre terms of the Coulomb friction along the stroke a refit takes in by default"""
MAX_STROKE_TERMS = 12
ALIAS_FRACTION = 0.25
"""cogging terms are kept where n·|θ̇|/2π is below this fraction of the sampling rate"""


def extra_terms_from_text(
    stroke_terms: int, cogging: str, terms: tuple[str, ...] | None = None
) -> ExtraTerms:
    """The extra terms of a command line: ``stroke_terms`` Legendre terms, ``cogging`` as orders
    ("24,48"), "auto" or "none", and the chosen ``terms`` (None: the model selection's) — a list
    without ``stroke`` or ``cogging`` switches that term off."""
    if terms is not None:
        stroke_terms = stroke_terms if "stroke" in terms else 0
        cogging = cogging if "cogging" in terms else "none"
    text = cogging.strip()
    orders = []
    for part in () if text in ("auto", "none") else (p.strip() for p in text.split(",")):
        if not part:
            continue
        try:
            orders.append(int(part))
        except ValueError:
            raise IdentificationError(
                f"--cogging {cogging}: {part!r} is not a whole number of cycles per motor revolution"
            ) from None
    return ExtraTerms(stroke_terms, tuple(orders), auto_cogging=text == "auto")


@dataclass(frozen=True)
class ExtraTerms:
    """Which extra terms a fit takes in (see the module docstring)."""

    stroke_terms: int = 0
    """K: Legendre terms of the Coulomb friction along the stroke (0: none)"""
    cogging_orders: tuple[int, ...] = ()
    """cogging orders n [cycles per motor revolution] (empty: none)"""
    auto_cogging: bool = False
    """also take in the orders the residual of a first fit shows (:func:`~.refit.auto_cogging_orders`)"""

    def __post_init__(self) -> None:
        if isinstance(self.stroke_terms, bool) or not 0 <= self.stroke_terms <= MAX_STROKE_TERMS:
            raise IdentificationError(
                f"stroke terms = {self.stroke_terms!r} must be a whole number in 0…{MAX_STROKE_TERMS}"
            )
        orders = tuple(self.cogging_orders)
        for n in orders:
            if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 1000:
                raise IdentificationError(
                    f"cogging order {n!r} must be a whole number of cycles per motor revolution in 1…1000"
                )
        if len(set(orders)) != len(orders):
            raise IdentificationError(f"cogging orders {list(orders)} repeat an order")
        object.__setattr__(self, "cogging_orders", orders)

    @property
    def names(self) -> tuple[str, ...]:
        """Coefficient names, in column order: ``c1``…``cK``, then ``cog<n>_sin``, ``cog<n>_cos``."""
        stroke = tuple(f"c{k}" for k in range(1, self.stroke_terms + 1))
        cogging = tuple(f"cog{n}_{f}" for n in self.cogging_orders for f in ("sin", "cos"))
        return stroke + cogging

    @property
    def units(self) -> tuple[str, ...]:
        return ("N",) * self.stroke_terms + ("N·m",) * (2 * len(self.cogging_orders))

    def scales(self, nominal: AxisParams) -> tuple[float, ...]:
        """Typical sizes of the coefficients (the fit's variable scaling): 5 % of a1, 0.5 % of tau_max."""
        stroke = max(0.05 * nominal.a1, 1e-3)
        cogging = max(0.005 * nominal.tau_max, 1e-6)
        return (stroke,) * self.stroke_terms + (cogging,) * (2 * len(self.cogging_orders))

    def __len__(self) -> int:
        return self.stroke_terms + 2 * len(self.cogging_orders)

    def columns(
        self,
        log: PreparedLog,
        stretch_m: tuple[float, float],
        nominal: AxisParams,
        preparation: PreparationSettings,
    ) -> TermColumns:
        """The terms' columns of ``log`` (cart force [N] per unit of each coefficient), computed where
        they are asked for; ``stretch_m`` the covered stretch (:func:`covered_stretch`)."""
        return TermColumns(self, log, stretch_m, nominal, preparation)


class TermColumns:
    """The extra terms' columns of one log: :meth:`at` some samples, or :meth:`force` of coefficients
    (column by column: an hour at 1 kHz never holds every column at once)."""

    def __init__(
        self,
        terms: ExtraTerms,
        log: PreparedLog,
        stretch_m: tuple[float, float],
        nominal: AxisParams,
        preparation: PreparationSettings,
    ) -> None:
        self.terms = terms
        self.log = log
        lo, hi = stretch_m
        self._centre, self._half = 0.5 * (lo + hi), max(0.5 * (hi - lo), 1e-9)
        self._cogging: list[np.ndarray] = []
        if terms.cogging_orders:
            self._cogging = _cogging_columns(terms.cogging_orders, log, nominal, preparation)

    def __len__(self) -> int:
        return len(self.terms)

    def _stroke(self, idx: np.ndarray) -> Iterator[np.ndarray]:
        """sign(ẋ)·P_k(ξ) at ``idx``, k = 1…K, one at a time (Legendre by Bonnet's recurrence)."""
        xi = np.clip((self.log.position_m[idx] - self._centre) / self._half, -1.0, 1.0)
        sign = np.sign(self.log.velocity_m_s[idx])
        previous, current = np.ones_like(xi), xi
        for k in range(1, self.terms.stroke_terms + 1):
            yield sign * current
            previous, current = current, ((2 * k + 1) * xi * current - k * previous) / (k + 1)

    def _each(self, idx: np.ndarray) -> Iterator[np.ndarray]:
        yield from self._stroke(idx)
        for column in self._cogging:
            yield column[idx]

    def at(self, idx: np.ndarray) -> np.ndarray:
        """The columns at samples ``idx``: (len(idx), len(self))."""
        parts = list(self._each(idx))
        return np.column_stack(parts) if parts else np.zeros((np.size(idx), 0))

    def force(self, beta: np.ndarray, idx: np.ndarray | None = None) -> np.ndarray:
        """Σ_j β_j·column_j at samples ``idx`` (None: all) [N]."""
        where = np.arange(len(self.log.signals.t_s)) if idx is None else idx
        total = np.zeros(np.size(where))
        for b, column in zip(beta, self._each(where), strict=True):
            total += b * column
        return total


def _cogging_columns(
    orders: tuple[int, ...], log: PreparedLog, nominal: AxisParams, preparation: PreparationSettings
) -> list[np.ndarray]:
    """−(i_r/r)·filt(sin nθ), −(i_r/r)·filt(cos nθ) per order, at every sample (module docstring)."""
    from scipy.signal import butter, sosfiltfilt  # scipy loads on first use, not with the package

    n = len(log.signals.t_s)
    rate = log.signals.rate_hz
    per_metre = nominal.transmission.radians_per_metre
    theta = log.signals.position_m * per_metre
    omega = np.abs(log.velocity_m_s) * per_metre
    sos = butter(preparation.order, preparation.cutoff_hz, fs=rate, output="sos")
    pad = min(3 * round(rate / preparation.cutoff_hz), n - 1)
    out = []
    for order in orders:
        resolved = order * omega / (2.0 * math.pi) < ALIAS_FRACTION * rate
        for wave in (np.sin, np.cos):
            raw = np.where(resolved, wave(order * theta), 0.0)
            out.append(-per_metre * sosfiltfilt(sos, raw, padlen=pad))
    return out


def covered_stretch(logs: list[PreparedLog], parts: list[np.ndarray]) -> tuple[float, float]:
    """The stretch of the stroke [m] the samples ``parts[i]`` of ``logs`` cover (min, max position)."""
    positions = [log.position_m[p] for log, p in zip(logs, parts, strict=True) if p.size]
    if not positions:
        return 0.0, 0.0
    every = np.concatenate(positions)
    return float(every.min()), float(every.max())
