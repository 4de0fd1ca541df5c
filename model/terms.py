"""The model's terms by name: what each one adds, its parameters, and the one parser of term lists.

A term is switched on in a parameter file by giving its keys (:mod:`.params`) and in ``axisflow
identify --terms NAMES`` by naming it. The names here are the stable spellings every command, report
and file uses:

| term | parameters | force it adds [N] |
|---|---|---|
| ``coulomb`` | a1 | a1·sign(ẋ) |
| ``viscous`` | a2 | a2·ẋ |
| ``offset`` | f0 | f0: a constant force along +x the motor supplies (offset, cable chain, gravity) |
| ``asymmetry`` | da1, da2 | da1·|sign ẋ| + da2·|ẋ|: Coulomb a1 ± da1 and viscous a2 ± da2 for ẋ > 0 / ẋ < 0 |
| ``atan`` | a3, a4 | a3·atan(a4·ẋ), the paper's low-speed term |
| ``stroke`` | c1…cK | Coulomb friction along the stroke (identification's extra terms) |
| ``cogging`` | cog<n>_sin, cog<n>_cos | the motor's cogging torque (identification's extra terms) |

The first five make the friction law (:mod:`.friction`); ``stroke`` and ``cogging`` are fitted beside
it by identification and planned without (their mean over the stroke and a revolution is zero).
"""

from __future__ import annotations

from dataclasses import dataclass

from .errors import ParameterError


@dataclass(frozen=True)
class Term:
    """One term: its name, its parameters (the keys of a parameter file) and what it models."""

    name: str
    parameters: tuple[str, ...]
    meaning: str


TERMS: dict[str, Term] = {
    t.name: t
    for t in (
        Term("coulomb", ("a1",), "Coulomb friction a1·sign(v)"),
        Term("viscous", ("a2",), "viscous friction a2·v"),
        Term("offset", ("f0",), "a constant force f0 along +x (amplifier offset, cable chain, gravity)"),
        Term("asymmetry", ("da1", "da2"), "friction by direction: a1 ± da1, a2 ± da2 for v > 0 / v < 0"),
        Term("atan", ("a3", "a4"), "the paper's low-speed friction a3·atan(a4·v)"),
        Term("stroke", (), "Coulomb friction along the stroke (Legendre terms, identification only)"),
        Term("cogging", (), "the motor's cogging torque (orders per revolution, identification only)"),
    )
}
"""every term by name, in the canonical order of lists"""

LAW_TERMS: tuple[str, ...] = ("coulomb", "viscous", "offset", "asymmetry", "atan")
"""the terms of the friction law (planned, simulated, fitted)"""
EXTRA_TERMS: tuple[str, ...] = ("stroke", "cogging")
"""identification's extra terms (fitted beside the law, never planned)"""
PAPER_TERMS: tuple[str, ...] = ("coulomb", "viscous", "atan")
"""eq. (1) of the paper: the law's terms of a parameter file of today"""
TERM_OF_PARAMETER: dict[str, str] = {p: t.name for t in TERMS.values() for p in t.parameters}
"""the term each friction parameter belongs to"""
LAW_PARAMETERS: tuple[str, ...] = tuple(p for name in LAW_TERMS for p in TERMS[name].parameters)
"""the friction law's parameters, in term order: a1, a2, f0, da1, da2, a3, a4"""


class TermError(ParameterError):
    """A term list that names no term, an unknown one, or a keyword where none is allowed."""


def canonical_terms(names: tuple[str, ...] | list[str] | set[str] | frozenset[str]) -> tuple[str, ...]:
    """``names`` in the canonical order of :data:`TERMS`, each once; unknown names are a
    :class:`TermError` listing the known ones."""
    unknown = sorted(set(names) - set(TERMS))
    if unknown:
        raise TermError(f"unknown term(s) {', '.join(unknown)}; the terms are: {', '.join(TERMS)}")
    return tuple(name for name in TERMS if name in names)


def parse_terms(text: str, option: str = "--terms", keywords: tuple[str, ...] = ()) -> tuple[str, ...] | str:
    """A comma-separated term list as given on a command line: the canonical tuple of its names, or
    one of ``keywords`` given alone (a caller that adds a mode, e.g. ``auto``, passes its word and
    handles it). Empty lists, unknown names and repeated names are a :class:`TermError` naming
    ``option`` and the value."""
    parts = [p.strip() for p in text.split(",")]
    if len(parts) == 1 and parts[0] in keywords:
        return parts[0]
    words = [p for p in parts if p]
    if not words:
        allowed = ", ".join((*TERMS, *keywords))
        raise TermError(f"{option} {text!r}: names no term; choose from {allowed}")
    unknown = [w for w in words if w not in TERMS]
    if unknown:
        extra = f" (or {', '.join(keywords)} alone)" if keywords else ""
        raise TermError(
            f"{option} {text}: unknown term(s) {', '.join(unknown)}; the terms are {', '.join(TERMS)}{extra}"
        )
    repeated = sorted({w for w in words if words.count(w) > 1})
    if repeated:
        raise TermError(f"{option} {text}: term(s) {', '.join(repeated)} named twice")
    return canonical_terms(words)
