"""Which parameters a refit estimates, which it holds, and which terms it switches off.

A refit works with the law's terms (:mod:`axisflow.model.terms`) that are on: each of their
parameters is either **fitted** or **held** at a value. A held value must be the user's own (given in
the parameter file of ``--params``): a parameter neither fitted nor given is never left at another
axis's nominal value (the packaged default is the paper's axis) — the run is refused naming it. A
term that is off has its parameters at zero and is neither fitted nor planned with.

* ``terms`` None (not chosen): the terms of the parameter file; when ``--fit`` names parameters,
  a term none of whose parameters is fitted or given is switched off (``--fit M_eq,a1,a2`` fits
  eq. (1) without its atan term).
* ``fit`` None (not chosen): every parameter of the terms that are on, and M_eq.
* **f0 and da1** act as one constant per direction while the axis moves (docs/parameters.md): with
  both the offset and the asymmetry term on, one of them is held at the user's value (f0 if the file
  gives it, else da1) and the other fitted; neither given is refused, and so is fitting both.

``given`` None means the nominal parameters are the user's own (a library caller that passes its own
axis, the demo): every value counts as given.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..model.terms import LAW_TERMS, TERM_OF_PARAMETER, TERMS, canonical_terms
from .errors import IdentificationError
from .fit import PARAMETERS, check_fit_names

if TYPE_CHECKING:
    from ..model import AxisParams

MASS_KEYS = frozenset({"m"})
"""a file gives M_eq when it gives the carriage mass (the transmission's inertias are required keys)"""


@dataclass(frozen=True)
class FitChoice:
    """The outcome: the start parameters (off terms zeroed), the terms on, what is fitted and held."""

    start: AxisParams
    terms: tuple[str, ...]
    fitted: tuple[str, ...]
    held: tuple[str, ...]
    switched_off: tuple[str, ...]
    """terms of the parameter file that the choice switched off (none of their parameters fitted or
    given)"""


def _is_given(name: str, given: frozenset[str] | None) -> bool:
    if given is None:
        return True
    return bool(MASS_KEYS & given) if name == "M_eq" else name in given


def choose_parameters(
    nominal: AxisParams,
    terms: tuple[str, ...] | None = None,
    fit: tuple[str, ...] | None = None,
    given: frozenset[str] | None = None,
) -> FitChoice:
    """The refit's parameters (module docstring); an :class:`IdentificationError` of one line naming
    the parameter and what to do where the choice leaves one without a value."""
    fitted = check_fit_names(tuple(fit)) if fit is not None else None
    if terms is not None:
        chosen = canonical_terms(tuple(terms))
        on = tuple(t for t in chosen if t in LAW_TERMS)
        switched: tuple[str, ...] = ()
    else:
        file_terms = nominal.terms
        if fitted is not None:
            on = tuple(
                t for t in file_terms if any(p in fitted or _is_given(p, given) for p in TERMS[t].parameters)
            )
        else:
            on = file_terms
        switched = tuple(t for t in file_terms if t not in on)
    in_model = ("M_eq", *(p for t in on for p in TERMS[t].parameters))
    if fitted is not None:
        off = [n for n in fitted if n not in in_model]
        if off:
            names = ", ".join(f"{n} (term {TERM_OF_PARAMETER[n]})" for n in off)
            raise IdentificationError(
                f"--fit {','.join(fitted)}: {names} belong to terms that are off; add them to --terms"
            )
    else:
        fitted = tuple(n for n in PARAMETERS if n in in_model)
        if "f0" in fitted and "da1" in fitted:
            if _is_given("f0", given):
                fitted = tuple(n for n in fitted if n != "f0")
            elif _is_given("da1", given):
                fitted = tuple(n for n in fitted if n != "da1")
    if "f0" in fitted and "da1" in fitted:
        raise IdentificationError(
            "f0 and da1 cannot both be fitted: while the axis moves both add one constant per direction; "
            "give one of them in --params FILE (gravity on an incline: f0 = m·g·sin θ), the other is fitted"
        )
    held = tuple(n for n in PARAMETERS if n in in_model and n not in fitted)
    missing = [n for n in held if not _is_given(n, given)]
    if missing:
        name = missing[0]
        where = "the carriage mass" if name == "M_eq" else f"the {TERM_OF_PARAMETER[name]} term"
        raise IdentificationError(
            f"{name} ({where}) is neither fitted nor given in your parameter file: fit it (--fit), give it "
            f"(--params FILE) or switch its term off (--terms); no other axis's nominal value is used"
        )
    zero = {p: 0.0 for t in LAW_TERMS if t not in on for p in TERMS[t].parameters}
    start = nominal.replace(**zero, terms=on) if zero or set(on) != set(nominal.terms) else nominal
    return FitChoice(start, on, fitted, held, switched)
