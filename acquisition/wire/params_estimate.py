"""What an adaptive node decided about an axis's parameters: ``axisflow_msgs/msg/ParamsEstimate`` on
``<prefix>/<axis>/params``.

``axisflow adapt`` refits the friction (and M_eq) of eq. (1) over a sliding window of the axis's live
samples every few seconds and publishes one :class:`ParamsEstimate` per attempt: the window's
estimate with its σ, the window (drive time), the samples used and the fit error, and the decision —
accepted (it becomes the new ``version``), or not, with the reason (:class:`Decision`, a typed code,
and ``reason``, the text for people). A planner that follows the node (``axisflow planner --adapt``)
plans every next move with the newest accepted set and records its version in each plan record;
``axisflow params --from LOG.mcap`` reads the last accepted one back into a parameter file.

Version 0 is the node's starting set (decision ``initial``); each accepted estimate is the version
before it + 1; a rejected one carries the version that stays in force (``version`` = ``base_version``).
The values are M_eq and the whole friction law of :mod:`axisflow.model.friction` (SI units): eq. (1)'s
a1…a4 and the terms beside it, the offset f0 and the asymmetry da1, da2 — a term fitted is a term
planned with. For an accepted record they are the new set, for a rejected one the estimate that was
turned down (NaN where the fit gave none). A σ is NaN for a parameter the window did not estimate (held
at its accepted value). A term whose values are zero is off.

f0, da1, da2 and their σ are the message's last fields: a shorter record, whose payload ends after
``holdout_rms_kept_nm`` (an older node's), reads with f0 = da1 = da2 = 0 — those terms off — and their
σ NaN.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

from ...model import AxisParams, FrictionLaw
from ...model.terms import PAPER_TERMS
from ..errors import WireError
from .cdr import HEADER_DEPENDENCIES, CdrReader, CdrWriter, read_time, schema_with_dependencies, write_time

PARAMS_ESTIMATE_TYPE = "axisflow_msgs/msg/ParamsEstimate"
PARAMETER_NAMES = ("M_eq", "a1", "a2", "a3", "a4", "f0", "da1", "da2")
"""the parameters an estimate carries, in wire order: eq. (1)'s, then the terms beside it"""
PAPER_NAMES = PARAMETER_NAMES[:5]
"""eq. (1)'s: what a record of five values gives (the offset and asymmetry then off)"""


class Decision(StrEnum):
    """Why an estimate was accepted or turned down (the ``decision`` field)."""

    INITIAL = "initial"
    """version 0: the node's starting parameters"""
    ACCEPTED = "accepted"
    """informative window, plausible change, better on the held-out samples: the new version"""
    UNINFORMATIVE = "uninformative"
    """too few moving samples, too narrow a speed range or too few direction changes"""
    UNCERTAIN = "uncertain"
    """a parameter's σ above its bound"""
    IMPLAUSIBLE = "implausible"
    """a change larger than its bound against the accepted set, or outside the physical ranges"""
    NO_IMPROVEMENT = "no_improvement"
    """not better than the accepted set on the held-out samples by the margin"""
    FIT_FAILED = "fit_failed"
    """the samples could not be fitted (not on a sampling grid, the solver did not converge)"""

    @property
    def accepted(self) -> bool:
        return self in (Decision.INITIAL, Decision.ACCEPTED)


PARAMS_ESTIMATE_SCHEMA = schema_with_dependencies(
    "# An adaptive node's estimate of eq. (1)'s parameters over a window of live samples, and whether it\n"
    "# was accepted. header.stamp: drive time of the window's last sample (ns since the Unix epoch);\n"
    "# header.frame_id: the axis name.\n"
    "std_msgs/Header header\n"
    "# the version in force after this decision (accepted: the new one) and the one it was judged against\n"
    "uint32 version\n"
    "uint32 base_version\n"
    "bool accepted\n"
    "# initial, accepted, uninformative, uncertain, implausible, no_improvement or fit_failed\n"
    "string decision\n"
    "# the decision in words, with the numbers that decided it\n"
    "string reason\n"
    "# the terms the window estimated (e.g. M_eq, a2, coulomb: a1 and a3 scaled together)\n"
    "string[] fitted\n"
    "# the estimate: equivalent mass [kg], Coulomb friction [N], viscous friction [N s/m], low-speed\n"
    "# friction amplitude [N] and shape [s/m]; NaN where the fit gave none\n"
    "float64 m_eq_kg\n"
    "float64 a1_n\n"
    "float64 a2_n_s_m\n"
    "float64 a3_n\n"
    "float64 a4_s_m\n"
    "# their standard deviations, NaN for a parameter held at its accepted value\n"
    "float64 m_eq_std_kg\n"
    "float64 a1_std_n\n"
    "float64 a2_std_n_s_m\n"
    "float64 a3_std_n\n"
    "float64 a4_std_s_m\n"
    "# the window of samples (drive time), the samples the fit used (at its rate) and its RMS error\n"
    "builtin_interfaces/Time window_start\n"
    "builtin_interfaces/Time window_end\n"
    "uint32 samples\n"
    "float64 fit_rms_nm\n"
    "# RMS torque error on the held-out newest part of the window: this estimate, and the accepted set\n"
    "float64 holdout_rms_nm\n"
    "float64 holdout_rms_kept_nm\n"
    "# the terms beside eq. (1), appended (a record without them has them off): the constant force along\n"
    "# +x [N], the Coulomb [N] and viscous [N s/m] asymmetry (a1 +- da1, a2 +- da2 for v > 0 / v < 0);\n"
    "# 0: the term is off\n"
    "float64 f0_n\n"
    "float64 da1_n\n"
    "float64 da2_n_s_m\n"
    "float64 f0_std_n\n"
    "float64 da1_std_n\n"
    "float64 da2_std_n_s_m\n",
    *HEADER_DEPENDENCIES,
)

_NAN = (math.nan,) * len(PARAMETER_NAMES)
_BESIDE_OFF = (0.0, 0.0, 0.0)
"""f0, da1, da2 of a record that does not give them: the terms off"""


@dataclass(frozen=True)
class ParamsEstimate:
    """``axisflow_msgs/msg/ParamsEstimate`` (see the module docstring)."""

    stamp_ns: int
    axis: str
    version: int
    base_version: int
    decision: Decision
    reason: str
    fitted: tuple[str, ...] = ()
    values: tuple[float, ...] = _NAN
    """M_eq [kg], a1 [N], a2 [N·s/m], a3 [N], a4 [s/m], f0 [N], da1 [N], da2 [N·s/m]
    (:data:`PARAMETER_NAMES`); five values are eq. (1)'s, with f0 = da1 = da2 = 0 (off)"""
    std: tuple[float, ...] = _NAN
    """σ of each value, in the same order and units (NaN: not estimated); five: eq. (1)'s"""
    window_start_ns: int = 0
    window_end_ns: int = 0
    samples: int = 0
    fit_rms_nm: float = math.nan
    holdout_rms_nm: float = math.nan
    holdout_rms_kept_nm: float = math.nan

    def __post_init__(self) -> None:
        object.__setattr__(self, "decision", Decision(self.decision))
        for name in ("version", "base_version", "samples"):
            value = getattr(self, name)
            if not 0 <= value < 2**32:
                raise WireError(f"{name} = {value} must be in [0, 2**32)")
        for name, beside in (("values", _BESIDE_OFF), ("std", (math.nan,) * 3)):
            numbers = tuple(float(v) for v in getattr(self, name))
            if len(numbers) == len(PAPER_NAMES):
                numbers += beside
            if len(numbers) != len(PARAMETER_NAMES):
                raise WireError(
                    f"{name} has {len(numbers)} numbers, needs {len(PARAMETER_NAMES)} "
                    f"({', '.join(PARAMETER_NAMES)}) or eq. (1)'s {len(PAPER_NAMES)}"
                )
            object.__setattr__(self, name, numbers)
        expected = self.base_version + 1 if self.decision is Decision.ACCEPTED else self.base_version
        if self.version != expected:
            raise WireError(
                f"version = {self.version} after a decision {self.decision.value} on version "
                f"{self.base_version} must be {expected}"
            )

    @property
    def accepted(self) -> bool:
        return self.decision.accepted

    @property
    def value_of(self) -> dict[str, float]:
        """The estimate by parameter name."""
        return dict(zip(PARAMETER_NAMES, self.values, strict=True))

    @property
    def std_of(self) -> dict[str, float]:
        """σ by parameter name (NaN: not estimated)."""
        return dict(zip(PARAMETER_NAMES, self.std, strict=True))

    @property
    def friction(self) -> FrictionLaw:
        """The friction law of this record's values (:mod:`axisflow.model.friction`)."""
        v = self.value_of
        return FrictionLaw(v["a1"], v["a2"], v["a3"], v["a4"], v["f0"], v["da1"], v["da2"])

    def applied_to(self, params: AxisParams) -> AxisParams:
        """``params`` with this record's M_eq (through the cart mass m) and its whole friction law: the
        set a planner uses. The offset and the asymmetry are this record's, on or off as it has them
        (an older record, without them: off), whatever ``params`` had. A :class:`WireError` for a
        record without values, or values no axis has."""
        values = self.value_of
        if not all(math.isfinite(v) for v in values.values()):
            raise WireError(f"parameter estimate version {self.version} of axis {self.axis!r} has no values")
        law = {name: values[name] for name in PARAMETER_NAMES if name != "M_eq"}
        # the paper's terms as params name them; the offset and asymmetry on where the record has values
        named = tuple(t for t in params.terms if t in PAPER_TERMS)
        try:
            friction = params.replace(**law, terms=named)
            return friction.with_equivalent_mass(values["M_eq"])
        except ValueError as exc:
            raise WireError(
                f"parameter estimate version {self.version} of axis {self.axis!r}: {exc}"
            ) from None

    def encode(self) -> bytes:
        w = CdrWriter()
        write_time(w, self.stamp_ns)
        w.string(self.axis)
        w.uint32(self.version)
        w.uint32(self.base_version)
        w.uint8(1 if self.accepted else 0)
        w.string(self.decision.value)
        w.string(self.reason)
        w.string_sequence(tuple(self.fitted))
        for value in (*self.values[:5], *self.std[:5]):  # eq. (1)'s, in their original place
            w.float64(value)
        write_time(w, self.window_start_ns)
        write_time(w, self.window_end_ns)
        w.uint32(self.samples)
        for value in (self.fit_rms_nm, self.holdout_rms_nm, self.holdout_rms_kept_nm):
            w.float64(value)
        for value in (*self.values[5:], *self.std[5:]):  # appended: the terms beside eq. (1)
            w.float64(value)
        return w.to_bytes()

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> ParamsEstimate:
        r = CdrReader(data, PARAMS_ESTIMATE_TYPE)
        stamp_ns, axis, version, base = read_time(r), r.string(), r.uint32(), r.uint32()
        accepted, decision_text, reason = r.uint8(), r.string(), r.string()
        try:
            decision = Decision(decision_text)
        except ValueError:
            choices = ", ".join(d.value for d in Decision)
            raise WireError(
                f"{PARAMS_ESTIMATE_TYPE}: decision {decision_text!r} is not one of {choices}"
            ) from None
        if bool(accepted) != decision.accepted:
            raise WireError(
                f"{PARAMS_ESTIMATE_TYPE}: accepted = {accepted} contradicts the decision {decision.value}"
            )
        fitted = r.string_sequence()
        numbers = [r.float64() for _ in range(10)]
        window = (read_time(r), read_time(r))
        samples = r.uint32()
        fit_rms, holdout, kept = r.float64(), r.float64(), r.float64()
        if r.at_end:  # written before the terms beside eq. (1) were appended: they are off
            beside, beside_std = _BESIDE_OFF, (math.nan,) * 3
        else:
            beside = (r.float64(), r.float64(), r.float64())
            beside_std = (r.float64(), r.float64(), r.float64())
        return cls(
            stamp_ns, axis, version, base, decision, reason, fitted,
            (*numbers[:5], *beside), (*numbers[5:], *beside_std),
            window[0], window[1], samples, fit_rms, holdout, kept,
        )  # fmt: skip
