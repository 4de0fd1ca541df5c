"""Bad input, catalogued: the friction terms and the transmission of a parameter file, and the terms a
refit (identify) or an adaptive node (adapt) is asked to fit."""

from __future__ import annotations

from pathlib import Path

from .case import case

SCREW = """m = 25.0
L = 0.5
a1 = 40.0
a2 = 300.0
f0 = {f0}
da1 = {da1}
da2 = 30.0
v_max = 0.5
tau_max = 3.0
energy_accounting = "positive"
{top}
[transmission]
kind = "{kind}"
{keys}
"""
"""a vertical ball-screw axis (docs/axes/ball-screw.toml): F_max = 3 N·m·2π/0.01 m = 1884.96 N"""
SCREW_KEYS = "lead = 0.01\ni_r = 1.0\nJ_m = 1.2e-4\nJ_g = 2.0e-5\nJ_s = 4.5e-5"


def _screw(
    f0: float = 245.25, da1: float = 5.0, kind: str = "ball-screw", keys: str = SCREW_KEYS, top: str = ""
) -> str:
    return SCREW.format(f0=f0, da1=da1, kind=kind, keys=keys, top=top)


def write_terms_inputs(d: Path) -> None:
    """The parameter files the cases below name."""
    belt = (Path(__file__).resolve().parents[2] / "docs" / "axes" / "belt.toml").read_text().splitlines()
    for name, key in (("atan-half", "a4"), ("asymmetry-half", "da2")):  # the belt file, one key left out
        lines = [line for line in belt if not line.startswith(f"{key} =")]
        assert len(lines) == len(belt) - 1, key
        (d / f"{name}.toml").write_text("\n".join(lines) + "\n")
    (d / "screw.toml").write_text(_screw())
    (d / "screw-kind.toml").write_text(_screw(kind="screw"))
    (d / "screw-with-r.toml").write_text(_screw(keys=SCREW_KEYS + "\nr = 0.02"))
    (d / "screw-no-lead.toml").write_text(_screw(keys=SCREW_KEYS.replace("lead = 0.01\n", "")))
    (d / "screw-flat-r.toml").write_text(_screw(top="r = 0.02"))
    (d / "linear-lead.toml").write_text(_screw(kind="linear-motor", keys="lead = 0.01"))
    (d / "screw-da1.toml").write_text(_screw(da1=50.0))
    (d / "screw-falls.toml").write_text(_screw(f0=2000.0))
    (d / "screw-one-way.toml").write_text(_screw(f0=1850.0))


CASES = [
    # the terms of a parameter file
    case(
        "params: the atan term's a3 without a4",
        "params",
        "--params",
        "atan-half.toml",
        says=("atan-half.toml", "the atan term's keys a3 and a4 go together", "a4 is missing"),
    ),
    case(
        "params: the asymmetry's da1 without da2",
        "params",
        "--params",
        "asymmetry-half.toml",
        says=("the asymmetry term's keys da1 and da2 go together", "da2 is missing"),
    ),
    case(
        "params: an asymmetry larger than the Coulomb friction",
        "params",
        "--params",
        "screw-da1.toml",
        says=("a1 = 40.0 N, da1 = 50.0 N", "a1 - |da1| = -10 N", "|da1| must not exceed a1"),
    ),
    case(
        "params: an axis that cannot hold itself (|f0| ≥ F_max)",
        "params",
        "--params",
        "screw-falls.toml",
        says=("F_max = tau_max·2π·i_r/lead = 1884.96 N", "|f0| = 2000 N", "cannot hold itself at rest"),
    ),
    case(
        "params: an axis that cannot move one way",
        "params",
        "--params",
        "screw-one-way.toml",
        says=(
            "F_max = tau_max·2π·i_r/lead = 1884.96 N",
            "c = a1 + da1 + f0 = 1895 N",
            "cannot move that way",
        ),
    ),
    # the transmission table
    case(
        "params: an unknown transmission kind",
        "params",
        "--params",
        "screw-kind.toml",
        says=("kind = 'screw'", "not one of: belt, ball-screw, rack-pinion, linear-motor"),
    ),
    case(
        "params: a key of another kind in the transmission table",
        "params",
        "--params",
        "screw-with-r.toml",
        says=("unknown key(s) r in [transmission] of kind ball-screw", "its keys: J_m, J_g, J_s, lead, i_r"),
    ),
    case(
        "params: a linear motor given a screw's lead",
        "params",
        "--params",
        "linear-lead.toml",
        says=("unknown key(s) lead in [transmission] of kind linear-motor", "its keys: none"),
    ),
    case(
        "params: a transmission key missing",
        "params",
        "--params",
        "screw-no-lead.toml",
        says=("[transmission] of kind ball-screw is missing key(s) lead [m]",),
    ),
    case(
        "params: a belt key beside the transmission table",
        "params",
        "--params",
        "screw-flat-r.toml",
        says=("key(s) r belong in the [transmission] table",),
    ),
    # what a refit fits
    case(
        "identify: f0 and da1 fitted together",
        "identify",
        "still.mcap",
        "--out",
        "ident",
        "--params",
        "screw.toml",
        "--fit",
        "M_eq,f0,da1",
        says=("f0 and da1 cannot both be fitted", "give one of them in --params FILE"),
        untouched=("ident",),
    ),
    case(
        "identify: the offset and the asymmetry with neither value given",
        "identify",
        "still.mcap",
        "--out",
        "ident",
        "--terms",
        "coulomb,viscous,offset,asymmetry",
        says=("f0 and da1 cannot both be fitted", "gravity on an incline: f0 = m·g·sin θ"),
        untouched=("ident",),
    ),
    case(
        "identify: a parameter with no value of the user's",
        "identify",
        "still.mcap",
        "--out",
        "ident",
        "--params",
        "screw.toml",
        "--terms",
        "coulomb,viscous,atan",
        "--fit",
        "M_eq,a1,a2",
        says=("a3 (the atan term) is neither fitted nor given", "no other axis's nominal value is used"),
        untouched=("ident",),
    ),
    case(
        "identify: a parameter of a term that is off",
        "identify",
        "still.mcap",
        "--out",
        "ident",
        "--terms",
        "coulomb,viscous",
        "--fit",
        "M_eq,a1,a3",
        says=("--fit M_eq,a1,a3", "a3 (term atan)", "terms that are off; add them to --terms"),
        untouched=("ident",),
    ),
    # what an adaptive node fits
    case(
        "adapt: f0 and da1 fitted together",
        "adapt",
        "--terms",
        "M_eq,f0,da1",
        says=("terms M_eq,f0,da1", "f0 and da1 cannot both be fitted"),
    ),
]
