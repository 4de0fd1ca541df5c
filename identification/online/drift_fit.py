"""The fit of what drifts, over one window: M_eq, a2 and a common scale of a1 and a3 by default, and
the terms beside eq. (1) that the axis has on.

What point-to-point moves can tell. A move accelerates from rest and brakes to rest; the stretches near
rest are left out (stick, release, and the filter's smearing of the Coulomb step: :mod:`..preparation`),
so a window of moves holds almost only speeds above 3/a4, where a3·atan(a4·ẋ) is nearly the constant
a3·π/2 and adds to a1: the moves determine a1 + a3·π/2 but not a1 and a3 apart, nor a4
(PAPER-NOTES: the two are nearly collinear without slow motion). What drifts is what they determine:
warming lubricant lowers the viscous a2 and, less, the boundary friction a1 and a3 together; wear
raises a1 and a3 together. So the paper's axis fits (:data:`DEFAULT_TERMS`)

    F = M_eq·ẍ + (1 + β)·(a1·sign(ẋ) + a3·atan(a4·ẋ)) + a2·ẋ,

a1, a3, a4 the accepted values, β the common relative change of the Coulomb-like terms (the extra term
``coulomb`` of :func:`~..fit.fit_window`, one linear column), M_eq and a2 fitted as usual. The problem
is then linear in its unknowns: the first Gauss–Newton step lands on the optimum, and the warm start
(:func:`~..fit.fit_window`'s ``start``, the last window's result) changes nothing but the iteration
count.

**The terms beside eq. (1)** (:mod:`axisflow.model.friction`) are linear too, and a term fitted is a
term planned with: an axis whose accepted set has them on refits them by default
(:func:`default_terms`) — the asymmetry's da1 and da2 (one column each: |sign ẋ|, |ẋ|) and the offset
f0 (a column of ones). While the axis moves f0 and da1 add the same constant per direction, so at most
one of them is fitted: da1 when the asymmetry is on (f0, the force at rest, which moves do not show,
stays at its accepted value: gravity, say), else f0. A term that is off stays off; one that is not
fitted keeps its accepted value, and every accepted set carries all of them.

Any subset of M_eq, a1…a4, f0, da1, da2 may be fitted instead (``coulomb`` then must not appear with
a1 or a3, nor f0 with da1); with a4 among them the problem is nonlinear and the warm start saves
iterations.

The result maps back to the law's parameters: a1' = a1·(1 + β), a3' = a3·(1 + β), with
σ(a1') = a1·σ(β), σ(a3') = a3·σ(β) (fully correlated); a parameter not estimated keeps its accepted
value and has σ = NaN. The signed parameters f0, da1, da2 may be near zero, so their σ and change are
measured against a size of the friction they shift (:func:`signed_scale`), not their own value.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ...model import AxisParams, friction_force
from ..errors import IdentificationError
from ..fit import PARAMETERS, SIGNED_PARAMETERS, FitResult, FrictionValues, WindowFit, fit_window
from ..preparation import FitSamples, PreparedLog

COULOMB = "coulomb"
"""the term of a common relative change β of a1 and a3"""
DEFAULT_TERMS: tuple[str, ...] = ("M_eq", "a2", COULOMB)
"""what the paper's axis fits (the default of an axis without the terms beside eq. (1))"""
COULOMB_SCALE = 0.05
"""the typical size of β (the fit's variable scaling)"""


def default_terms(params: AxisParams) -> tuple[str, ...]:
    """What an axis refits by default (module docstring): :data:`DEFAULT_TERMS`, and da1 and da2 when
    its asymmetry term is on, f0 when its offset term is on without the asymmetry."""
    on = set(params.terms)
    beside = ("da1", "da2") if "asymmetry" in on else ("f0",) if "offset" in on else ()
    return check_terms((*DEFAULT_TERMS, *beside))


def signed_scale(name: str, params: AxisParams | FrictionValues) -> float:
    """The size [N, or N·s/m for da2] that σ and the change of a signed parameter are measured against:
    its own magnitude, or the friction it shifts if that is larger — the dry friction at speed
    a1 + a3·π/2 for f0 and da1 (each direction's constant), the viscous a2 for da2. A 0.5 N asymmetry
    known to ±0.3 N is well known on an axis with 40 N of friction, though not to 5 % of itself."""
    value = abs(getattr(params, name))
    if name == "da2":
        return max(value, params.a2)
    return max(value, params.a1 + params.a3 * math.pi / 2.0)


def check_terms(terms: tuple[str, ...] | list[str]) -> tuple[str, ...]:
    """The terms to fit, validated, in :data:`~..fit.PARAMETERS` order with ``coulomb`` last."""
    names = tuple(dict.fromkeys(t.strip() for t in terms if t.strip()))
    unknown = [n for n in names if n not in (*PARAMETERS, COULOMB)]
    if unknown or not names:
        raise IdentificationError(
            f"terms {','.join(names)!s}: {'unknown ' + ', '.join(unknown) if unknown else 'nothing to fit'}; "
            f"choose from {', '.join((*PARAMETERS, COULOMB))}"
        )
    if not set(names) & set(PARAMETERS):
        raise IdentificationError(f"terms {','.join(names)}: fit at least one of {', '.join(PARAMETERS)}")
    if COULOMB in names and {"a1", "a3"} & set(names):
        raise IdentificationError(
            f"terms {','.join(names)}: {COULOMB} scales a1 and a3 together; fit it or them, not both"
        )
    if {"f0", "da1"} <= set(names):
        raise IdentificationError(
            f"terms {','.join(names)}: f0 and da1 cannot both be fitted: while the axis moves both add "
            "one constant per direction; fit one, the other keeps its accepted value"
        )
    return tuple(n for n in PARAMETERS if n in names) + ((COULOMB,) if COULOMB in names else ())


class CoulombColumn:
    """The column of β at the samples of one prepared log: a1·sign(ẋ) + a3·atan(a4·ẋ) [N] with the
    accepted a1, a3, a4 (the :class:`~..preparation.Columns` protocol of the offset search)."""

    def __init__(self, log: PreparedLog, base: AxisParams) -> None:
        self._log, self._base = log, base

    def at(self, idx: np.ndarray) -> np.ndarray:
        return coulomb_column(self._log.velocity_m_s[idx], self._base)


def coulomb_column(velocity_m_s: np.ndarray, base: AxisParams) -> np.ndarray:
    """(n, 1): the Coulomb-like friction a1·sign(ẋ) + a3·atan(a4·ẋ) of ``base`` at ``velocity_m_s``."""
    shape = FrictionValues(base.M_eq, base.a1, 0.0, base.a3, base.a4)
    return friction_force(velocity_m_s, shape)[:, None]


@dataclass(frozen=True, eq=False)
class DriftFit:
    """One window's fit, mapped back to the law's parameters (see the module docstring)."""

    window: WindowFit
    base: AxisParams
    """the accepted parameters the fit started from (and held what it did not estimate)"""
    terms: tuple[str, ...]
    values: FrictionValues
    std: dict[str, float]
    """σ of each of M_eq, a1…a4, f0, da1, da2 (NaN: not estimated)"""

    @property
    def success(self) -> bool:
        return self.window.success

    @property
    def result(self) -> FitResult:
        return self.window.result

    @property
    def relative_std(self) -> dict[str, float]:
        """σ/|value| of each estimated term (``coulomb``: σ(β), already relative; f0, da1, da2: σ over
        :func:`signed_scale`)."""
        out = {}
        for name in self.terms:
            if name == COULOMB:
                out[name] = self.window.std[COULOMB]
            elif name in SIGNED_PARAMETERS:
                out[name] = self.std[name] / signed_scale(name, self.values)
            else:
                out[name] = self.std[name] / abs(getattr(self.values, name))
        return out

    def params(self) -> AxisParams:
        """The base parameters with the fitted values — the whole friction law, M_eq through the cart
        mass; a :class:`~axisflow.model.ParameterError` for values outside the physical ranges."""
        law = {name: value for name, value in self.values.as_dict().items() if name != "M_eq"}
        return self.base.replace(**law).with_equivalent_mass(self.values.M_eq)


def fit_drift(
    samples: FitSamples,
    base: AxisParams,
    terms: tuple[str, ...] = DEFAULT_TERMS,
    start: FitResult | None = None,
) -> DriftFit:
    """Fit ``terms`` over the window ``samples`` (kinematics and force, no extra columns), holding the
    rest at ``base``; warm-started from ``start`` (a previous window's :attr:`DriftFit.result`)."""
    terms = check_terms(terms)
    fitted = tuple(t for t in terms if t != COULOMB)
    extra_names: tuple[str, ...] = ()
    scales: tuple[float, ...] = ()
    if COULOMB in terms:
        samples = dataclasses.replace(samples, extra=coulomb_column(samples.velocity_m_s, base))
        extra_names, scales = (COULOMB,), (COULOMB_SCALE,)
    window = fit_window(samples, base, fitted, start=start, extra_names=extra_names, extra_scales=scales)
    found = window.values.as_dict()
    std = {name: window.std[name] if name in fitted else math.nan for name in PARAMETERS}
    if COULOMB in terms:
        beta, sigma = window.result.extra[COULOMB], window.std[COULOMB]
        found["a1"], found["a3"] = base.a1 * (1.0 + beta), base.a3 * (1.0 + beta)
        std["a1"], std["a3"] = base.a1 * sigma, base.a3 * sigma
    return DriftFit(window, base, terms, FrictionValues(**found), std)
