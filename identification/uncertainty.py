"""How well a log determines each parameter: standard deviations, correlations, warnings.

Near the optimum the residuals are linear in the parameters, e(p) ≈ e(p*) + J·(p − p*), so for
independent residuals of variance s² = Σe²/(n − m) the estimate's covariance is C = s²·(JᵀJ)⁻¹
(J: n × m, the Jacobian of the *unsquared* residuals). The residuals of a 1 kHz log are not
independent: the filter and the unmodelled dynamics colour them. The correction used here is the
**effective sample size**: with ρ_k the residuals' autocorrelation at lag k, summed over the initial
positive sequence (until the first lag where ρ_k ≤ 0.05),

    n_eff = n / (1 + 2·Σ ρ_k),     C_eff = C · n / n_eff,

which is the variance inflation of the mean of an AR-like series (the residuals here are those of the
decimated fit samples). The correlations are C_ij/√(C_ii·C_jj); |ρ| > :data:`FLAG_CORRELATION` is
flagged. The condition number is that of J with each column scaled to unit length (1 when the
parameters' effects are orthogonal; in the thousands when two of them are nearly collinear).

A log that cannot separate parameters gets a warning naming them instead of confident numbers: a pair
with |ρ| > :data:`INSEPARABLE_CORRELATION`, or a parameter whose σ exceeds half its value. For a1 and
a3 the warning says why (a3·atan(a4·ẋ) is a constant a3·π/2 above |ẋ| ≈ 3/a4, where it adds to a1).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

FLAG_CORRELATION = 0.8
INSEPARABLE_CORRELATION = 0.95
INSEPARABLE_RELATIVE_STD = 0.5
_MAX_LAG = 2000
METHOD = "effective sample size from the residuals' autocorrelation (initial positive sequence)"


@dataclass(frozen=True, eq=False)
class Uncertainty:
    names: tuple[str, ...]
    std: dict[str, float]
    correlation: np.ndarray
    condition_number: float
    samples: int
    effective_samples: float
    method: str = METHOD
    flagged: list[tuple[str, str, float]] = field(default_factory=list)
    """pairs with |ρ| > FLAG_CORRELATION"""
    warnings: list[str] = field(default_factory=list)


def effective_sample_size(residuals: np.ndarray) -> float:
    """n/(1 + 2·Σρ_k) over the initial positive sequence of the autocorrelation."""
    e = np.asarray(residuals, dtype=float) - np.mean(residuals)
    n = e.size
    var = float(np.dot(e, e))
    if n < 3 or var == 0.0:
        return float(n)
    nfft = 1 << int(np.ceil(np.log2(2 * n)))
    spectrum = np.fft.rfft(e, nfft)
    acf = np.fft.irfft(spectrum * np.conj(spectrum), nfft)[: min(n, _MAX_LAG)] / var
    total = 0.0
    for rho in acf[1:]:
        if rho <= 0.05:
            break
        total += float(rho)
    return n / (1.0 + 2.0 * total)


def estimate_uncertainty(
    names: tuple[str, ...], values: dict[str, float], jacobian: np.ndarray, residuals: np.ndarray
) -> Uncertainty:
    """σ, correlations, condition number and warnings for the fitted ``names`` (module docstring)."""
    n, m = jacobian.shape
    s2 = float(np.dot(residuals, residuals)) / max(n - m, 1)
    jtj = jacobian.T @ jacobian
    cov = s2 * np.linalg.pinv(jtj)
    n_eff = effective_sample_size(residuals)
    cov *= n / n_eff
    std = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(std, std)
    corr = np.where(np.isfinite(corr), corr, 0.0)
    np.fill_diagonal(corr, 1.0)
    norms = np.linalg.norm(jacobian, axis=0)
    scaled = jacobian / np.where(norms > 0, norms, 1.0)
    cond = float(np.linalg.cond(scaled))
    flagged = [
        (names[i], names[j], float(corr[i, j]))
        for i in range(m)
        for j in range(i + 1, m)
        if abs(corr[i, j]) > FLAG_CORRELATION
    ]
    warnings = _warnings(names, values, dict(zip(names, std, strict=True)), flagged)
    return Uncertainty(
        names=names,
        std={name: float(s) for name, s in zip(names, std, strict=True)},
        correlation=corr,
        condition_number=cond,
        samples=n,
        effective_samples=n_eff,
        flagged=flagged,
        warnings=warnings,
    )


def _warnings(
    names: tuple[str, ...],
    values: dict[str, float],
    std: dict[str, float],
    flagged: list[tuple[str, str, float]],
) -> list[str]:
    out = []
    for a, b, rho in flagged:
        if abs(rho) <= INSEPARABLE_CORRELATION:
            continue
        why = ""
        if {a, b} == {"a1", "a3"}:
            why = (
                ": a3·atan(a4·v) is nearly the constant a3·π/2 above |v| ≈ 3/a4, where it adds to a1; "
                "the log needs motion at low speeds (run `axisflow excite`) to tell them apart, or fit "
                "fewer parameters (--fit)"
            )
        out.append(f"this log cannot separate {a} from {b} (correlation {rho:+.3f}){why}")
    for name in names:
        value = values[name]
        if value != 0.0 and std[name] > INSEPARABLE_RELATIVE_STD * abs(value):
            out.append(
                f"{name} is not determined by this log: σ = {std[name]:.3g} is more than "
                f"{INSEPARABLE_RELATIVE_STD:.0%} of its value {value:.4g}"
            )
    return out
