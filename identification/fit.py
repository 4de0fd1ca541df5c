"""The refit: eq. (1)'s inertia and friction parameters by SQP, so that model effort matches measured.

With the prepared samples (ẋ_k, ẍ_k, F_k: filtered, decimated; :mod:`.preparation`) and k_e the joint's
effort per cart force (r/i_r for a motor joint), the residuals and the problem are

    e_k(p) = k_e·(F_k − M_eq·ẍ_k − F_c(ẋ_k; p) − X_k·β),   F_c of :mod:`axisflow.model.friction`
    min_p  ½·Σ_k (e_k/σ_e)²  s.t.  a1 … a4 ≥ 0,  M_eq > 0  (f0, da1, da2 of either sign),
           a1 ± da1 ≥ 0,  a2 ± da2 ≥ 0  (each direction's friction, where an asymmetry is fitted),

F_c with every term of the law (f0 + a1·sign ẋ + da1·|sign ẋ| + a2·ẋ + da2·|ẋ| + a3·atan(a4·ẋ)), over
the parameters chosen with ``fit`` (the rest stay at their start values: zero for a term that is off,
:mod:`.fit_terms` decides) and the coefficients β
of any extra linear terms X (:mod:`.extra_terms`: friction along the stroke, cogging; unbounded), σ_e
the RMS of the measured effort (so the objective starts near 1). The variables are scaled,
p_i = θ_i·|p_i,nominal| (β by the terms' typical sizes); the solve starts from the nominal values, or
from a previous result (a warm start: :func:`fit_window` over a sliding window).

Solver: CasADi's ``sqpmethod`` (the paper's SQP) with qrqp for the QP steps and a **Gauss–Newton
Hessian** JᵀJ/σ_e² supplied through ``hess_lag`` (the exact Hessian of this least-squares problem is
indefinite away from the optimum, where qrqp then fails; Gauss–Newton is positive semi-definite and
converges in a few iterations; when its step falls below the step tolerance first — the point is
stationary to rounding — the result counts as converged if the KKT conditions hold to 1e-7). F_c is
nonlinear only in a4, so the problem is nearly linear and its
optimum is unique when the excitation separates the terms (see :mod:`.uncertainty`). The result
carries the Jacobian at the optimum for the uncertainty analysis.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..model import friction_expression, friction_force
from ..model.units import PARAMETER_UNITS as MODEL_UNITS
from .errors import IdentificationError
from .preparation import FitSamples
from .uncertainty import Uncertainty, estimate_uncertainty

if TYPE_CHECKING:
    from ..model import AxisParams

PARAMETERS: tuple[str, ...] = ("M_eq", "a1", "a2", "a3", "a4", "f0", "da1", "da2")
"""what a refit may estimate, in report order (the paper's five first)"""
PARAMETER_UNITS: dict[str, str] = {name: MODEL_UNITS[name] for name in PARAMETERS}
"""the unit of each, the model's (:data:`axisflow.model.units.PARAMETER_UNITS`)"""
PAPER_PARAMETERS: tuple[str, ...] = PARAMETERS[:5]
"""eq. (1)'s parameters: M_eq and a1…a4 (what a fit estimates unless told otherwise)"""
SIGNED_PARAMETERS = frozenset({"f0", "da1", "da2"})
"""the parameters of either sign (no lower bound in the fit)"""
DEFAULT_MAX_ITER = 50


@dataclass(frozen=True)
class FrictionValues:
    """The model parameters a fit works with (SI units): M_eq and the friction law's."""

    M_eq: float
    a1: float
    a2: float
    a3: float
    a4: float
    f0: float = 0.0
    da1: float = 0.0
    da2: float = 0.0

    @classmethod
    def of(cls, params: AxisParams) -> FrictionValues:
        return cls(params.M_eq, params.a1, params.a2, params.a3, params.a4, params.f0, params.da1, params.da2)

    def as_dict(self) -> dict[str, float]:
        return {name: getattr(self, name) for name in PARAMETERS}

    def force_n(self, velocity_m_s: np.ndarray, acceleration_m_s2: np.ndarray) -> np.ndarray:
        """eq. (1): M_eq·ẍ + F_c(ẋ) [N]."""
        return self.M_eq * np.asarray(acceleration_m_s2) + friction_force(velocity_m_s, self)


@dataclass(frozen=True, eq=False)
class FitResult:
    """What the SQP found, and how."""

    values: FrictionValues
    initial: FrictionValues
    fitted: tuple[str, ...]
    """the parameters estimated (the others kept their initial, nominal values)"""
    status: str
    """CasADi's return status"""
    success: bool
    iterations: int
    solve_time_s: float
    residuals: np.ndarray
    """e_k at the optimum [effort units: N·m or N]"""
    jacobian: np.ndarray
    """∂e_k/∂p_i at the optimum, (n, len(terms)), per unit of each parameter"""
    extra: dict[str, float] = field(default_factory=dict)
    """the extra terms' coefficients β, by name (in their columns' order)"""

    @property
    def terms(self) -> tuple[str, ...]:
        """Everything estimated, in the Jacobian's column order: ``fitted``, then the extra terms."""
        return self.fitted + tuple(self.extra)

    @property
    def estimates(self) -> dict[str, float]:
        """The value of every term, by name."""
        values = self.values.as_dict()
        return {name: values[name] for name in self.fitted} | self.extra

    @property
    def extra_vector(self) -> np.ndarray:
        return np.array(list(self.extra.values()), dtype=float)

    @property
    def rms(self) -> float:
        return float(np.sqrt(np.mean(self.residuals**2)))


def check_fit_names(names: tuple[str, ...] | list[str]) -> tuple[str, ...]:
    """The parameters to fit, validated, in :data:`PARAMETERS` order."""
    unknown = [n for n in names if n not in PARAMETERS]
    if unknown or not names:
        raise IdentificationError(
            f"--fit {','.join(names)!s}: {'unknown ' + ', '.join(unknown) if unknown else 'nothing to fit'}; "
            f"choose from {', '.join(PARAMETERS)}"
        )
    return tuple(n for n in PARAMETERS if n in names)


class FrictionFit:
    """The SQP problem for fixed kinematics; :meth:`solve` fits one measured force (several forces, e.g.
    shifted in time by :mod:`.alignment`, reuse the same solver)."""

    def __init__(
        self,
        velocity_m_s: np.ndarray,
        acceleration_m_s2: np.ndarray,
        effort_per_force: float,
        nominal: AxisParams,
        fit: tuple[str, ...] = PAPER_PARAMETERS,
        max_iter: int = DEFAULT_MAX_ITER,
        extra: np.ndarray | None = None,
        extra_names: tuple[str, ...] = (),
        extra_scales: tuple[float, ...] = (),
    ) -> None:
        """``extra``: (n, p) columns of extra linear terms (cart force per unit of coefficient), named
        ``extra_names``, of typical sizes ``extra_scales``."""
        import casadi as ca  # here, not at import: reading logs and designing excitations need none

        self.names = check_fit_names(fit)
        self.initial = FrictionValues.of(nominal)
        n_samples = int(np.size(velocity_m_s))
        columns = np.zeros((n_samples, 0)) if extra is None else np.asarray(extra, dtype=float)
        if columns.shape != (n_samples, len(extra_names)) or len(extra_scales) != len(extra_names):
            raise IdentificationError(
                f"extra terms: {columns.shape} columns for {n_samples} samples and {len(extra_names)} names"
            )
        self.extra_names = tuple(extra_names)
        start = self.initial.as_dict()
        # a start of zero (a term switched on from nothing) is scaled by the friction's size
        typical = max(abs(start["a1"]), abs(start["a3"]), 1.0)
        self._scale = np.array(
            [max(abs(start[n]), 0.05 * typical if n in SIGNED_PARAMETERS else 1e-3) for n in self.names]
            + list(extra_scales),
            dtype=float,
        )
        n_vars = len(self.names) + len(self.extra_names)
        theta = ca.MX.sym("theta", n_vars)
        value = {n: start[n] for n in PARAMETERS}
        for i, n in enumerate(self.names):
            value[n] = theta[i] * self._scale[i]
        force = ca.MX.sym("force", n_samples)
        sigma = ca.MX.sym("sigma")
        kept = ca.MX.sym("kept", n_samples)  # 1: the sample is fitted, 0: held out (scored, not fitted)
        v, a = ca.DM(velocity_m_s), ca.DM(acceleration_m_s2)
        sign_v = ca.DM(np.sign(velocity_m_s))
        k = effort_per_force
        friction = friction_expression(
            v,
            sign_v,
            value["a1"],
            value["a2"],
            value["a3"],
            value["a4"],
            ca.atan,
            f0=value["f0"],
            da1=value["da1"],
            da2=value["da2"],
        )
        residual = k * (force - value["M_eq"] * a - friction)
        if self.extra_names:
            beta = theta[len(self.names) :] * ca.DM(self._scale[len(self.names) :])
            residual = residual - k * ca.mtimes(ca.DM(columns), beta)
        weight = 1.0 / (sigma * sigma * ca.sum1(kept))
        jac = ca.jacobian(residual, theta)
        lam_f = ca.MX.sym("lam_f")
        data = ca.vertcat(force, sigma, kept)
        # each direction's friction stays ≥ 0 (a ± da ≥ 0) where an asymmetry is fitted: linear in θ
        pairs = (("a1", "da1"), ("a2", "da2"))
        sides = [value[a] + s * value[d] for a, d in pairs if d in self.names for s in (1, -1)]
        g = ca.vertcat(*sides) if sides else ca.MX(0, 1)
        g_jacobian = ca.Function("g_jacobian", [theta], [ca.jacobian(g, theta)])
        self._g_jacobian = np.array(g_jacobian(np.zeros(n_vars)))
        hess_lag = ca.Function(
            "gauss_newton",
            [theta, data, lam_f, ca.MX.sym("lam_g", len(sides))],
            [lam_f * weight * ca.mtimes(jac.T, ca.mtimes(ca.diag(kept), jac))],
            ["x", "p", "lam_f", "lam_g"],
            ["hess_gamma_x_x"],
        )
        self._solver = ca.nlpsol(
            "friction_fit",
            "sqpmethod",
            {"x": theta, "p": data, "f": 0.5 * weight * ca.dot(kept, residual * residual), "g": g},
            {
                "qpsol": "qrqp",
                "qpsol_options": {"print_iter": False, "print_header": False, "error_on_fail": False},
                "hess_lag": hess_lag,
                "max_iter": max_iter,
                "tol_du": 1e-13,
                "tol_pr": 1e-13,
                "print_header": False,
                "print_iteration": False,
                "print_status": False,
                "print_time": False,
            },
        )
        self._evaluate = ca.Function("residual_and_jacobian", [theta, force], [residual, jac])
        self._lower = np.array(
            [1e-6 if name == "M_eq" else -np.inf if name in SIGNED_PARAMETERS else 0.0 for name in self.names]
            + [-np.inf] * len(self.extra_names)
        )

        self._k = k

    def solve(
        self,
        force_n: np.ndarray,
        start: FrictionValues | None = None,
        start_extra: np.ndarray | None = None,
        kept: np.ndarray | None = None,
    ) -> FitResult:
        """Fit the measured cart force ``force_n`` [N] (one value per sample of the kinematics), starting
        from the nominal values (β = 0) or from ``start`` (and ``start_extra``): a warm start. ``kept``
        (bool, one per sample; None: all) fits only those samples; the result's residuals cover every
        sample (the others are held out: scored, not fitted)."""
        mask = np.ones(np.size(force_n), dtype=bool) if kept is None else np.asarray(kept, dtype=bool)
        if not mask.any():
            raise IdentificationError("no sample is kept for the fit")
        sigma = float(np.sqrt(np.mean((self._k * np.asarray(force_n)[mask]) ** 2))) or 1.0
        first = (start or self.initial).as_dict()
        beta0 = (
            np.zeros(len(self.extra_names)) if start_extra is None else np.asarray(start_extra, dtype=float)
        )
        x0 = np.r_[[first[n] for n in self.names], beta0] / self._scale
        t0 = time.perf_counter()
        solution = self._solver(
            x0=x0, lbx=self._lower, lbg=0.0, ubg=np.inf, p=np.r_[force_n, sigma, mask.astype(float)]
        )
        elapsed = time.perf_counter() - t0
        stats = self._solver.stats()
        # the QP steps may end a hair outside a bound (−1e-13): the bound is the value
        theta_opt = np.maximum(np.array(solution["x"]).ravel(), self._lower)
        found = self.initial.as_dict()
        for i, name in enumerate(self.names):
            found[name] = float(theta_opt[i] * self._scale[i])
        for a, d in (("a1", "da1"), ("a2", "da2")):  # and a hair outside a ± da ≥ 0 is on it
            found[d] = float(np.clip(found[d], -found[a], found[a]))
        offset = len(self.names)
        extra = {
            n: float(theta_opt[offset + j] * self._scale[offset + j]) for j, n in enumerate(self.extra_names)
        }
        r_opt, j_opt = self._evaluate(theta_opt, force_n)
        residuals, jac_theta = np.array(r_opt).ravel(), np.array(j_opt)
        status = str(stats.get("return_status", "unknown"))
        success = bool(stats.get("success", False))
        if not success and status == "Search_Direction_Becomes_Too_Small":
            # the QP step fell below the step tolerance: converged if the point is stationary (KKT with
            # the bounds) for the normalised objective, to 1e-7
            grad = jac_theta[mask].T @ residuals[mask] / (sigma * sigma * np.count_nonzero(mask))
            if self._g_jacobian.size:  # the Lagrangian's gradient: the constraints' multipliers added
                grad = grad + self._g_jacobian.T @ np.array(solution["lam_g"]).ravel()
            at_bound = theta_opt <= self._lower + 1e-12
            success = bool(np.all(np.where(at_bound, grad >= -1e-7, np.abs(grad) <= 1e-7)))
        return FitResult(
            values=FrictionValues(**found),
            initial=self.initial,
            fitted=self.names,
            status=status,
            success=success,
            iterations=int(stats.get("iter_count", -1)),
            solve_time_s=elapsed,
            residuals=residuals,
            jacobian=jac_theta / self._scale,  # per unit of each parameter, not of θ
            extra=extra,
        )


def fit_parameters(
    samples: FitSamples,
    nominal: AxisParams,
    fit: tuple[str, ...] = PAPER_PARAMETERS,
    max_iter: int = DEFAULT_MAX_ITER,
) -> FitResult:
    """Estimate the ``fit`` parameters from ``samples`` starting at ``nominal`` (see the module doc)."""
    problem = FrictionFit(
        samples.velocity_m_s, samples.acceleration_m_s2, samples.effort_per_force, nominal, fit, max_iter
    )
    return problem.solve(samples.force_n)


@dataclass(frozen=True, eq=False)
class WindowFit:
    """One fit over a window of samples: what ``identify`` does once over whole logs, and what an
    adaptive node does every few seconds over a sliding window (warm-started from the last one)."""

    result: FitResult
    uncertainty: Uncertainty

    @property
    def success(self) -> bool:
        return self.result.success

    @property
    def values(self) -> FrictionValues:
        return self.result.values

    @property
    def std(self) -> dict[str, float]:
        """σ of every estimated term, by name."""
        return self.uncertainty.std

    @property
    def samples(self) -> int:
        """Samples the fit used."""
        return int(self.result.residuals.size)

    @property
    def rms(self) -> float:
        """RMS of the fit's residuals (effort units)."""
        return self.result.rms


def fit_window(
    samples: FitSamples,
    nominal: AxisParams,
    fit: tuple[str, ...] = PAPER_PARAMETERS,
    start: FitResult | None = None,
    extra_names: tuple[str, ...] = (),
    extra_scales: tuple[float, ...] = (),
    max_iter: int = DEFAULT_MAX_ITER,
) -> WindowFit:
    """Fit ``fit`` (and the extra terms of ``samples.extra``, named ``extra_names``) over the window
    ``samples``, from the nominal values or warm-started from a previous ``start``, with σ and
    correlations (:mod:`.uncertainty`)."""
    problem = FrictionFit(
        samples.velocity_m_s,
        samples.acceleration_m_s2,
        samples.effort_per_force,
        nominal,
        fit,
        max_iter,
        samples.extra,
        extra_names,
        extra_scales,
    )
    warm = start is not None and start.fitted == problem.names and tuple(start.extra) == problem.extra_names
    result = problem.solve(
        samples.force_n,
        start.values if warm and start is not None else None,
        start.extra_vector if warm and start is not None else None,
    )
    estimates = result.estimates
    uncertainty = estimate_uncertainty(result.terms, estimates, result.jacobian, result.residuals)
    return WindowFit(result, uncertainty)
