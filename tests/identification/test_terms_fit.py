"""The terms beside eq. (1) fitted from logs of each transmission kind, and the rule that no parameter
keeps another axis's nominal value.

Each axis of docs/axes/ (one per transmission kind, each with a constant force f0 and friction that
differs by direction) is the plant of a synthetic 1 kHz log (acquisition/logs/synthetic_log.py: the
motor joint in rad and N·m through the transmission, the carriage joint in m and N); the refit starts
from wrong values with f0 given (the gravity or cable chain the user knows) and must find the truth.
"""

from pathlib import Path

import pytest
from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec, write_synthetic_log
from axisflow.identification.errors import IdentificationError
from axisflow.identification.extra_terms import ExtraTerms
from axisflow.identification.fit_terms import choose_parameters
from axisflow.identification.refit import IdentifySettings, identify
from axisflow.model import default_params, load_params
from axisflow.model.params import given_keys

AXES = Path(__file__).parents[2] / "docs" / "axes"
KINDS = ["belt", "ball-screw", "rack-pinion", "linear-motor"]
TERMS = ("coulomb", "viscous", "offset", "asymmetry")


@pytest.mark.slow
@pytest.mark.parametrize("kind", KINDS)
def test_the_fit_finds_each_kinds_offset_and_asymmetric_friction(kind, tmp_path):
    path = AXES / f"{kind}.toml"
    truth = load_params(path).replace(a3=0.0, a4=0.0)  # the fit's terms: no atan
    start = truth.replace(a1=0.7 * truth.a1, a2=1.3 * truth.a2, da1=0.0, da2=0.0).with_equivalent_mass(
        1.1 * truth.M_eq
    )
    log = tmp_path / "excite.mcap"
    write_synthetic_log(log, SyntheticLogSpec(duration_s=12.0, seed=3, params=start, true_params=truth))
    settings = IdentifySettings(
        joint="motor", terms=TERMS, given=given_keys(path), extra=ExtraTerms(0), torque_delay_s=0.0
    )
    ident = identify([log], start, settings)
    assert ident.fit.fitted == ("M_eq", "a1", "a2", "da1", "da2")  # f0 held at the given value
    assert ident.params.f0 == truth.f0
    found = ident.fit.values
    assert found.M_eq == pytest.approx(truth.M_eq, rel=0.02)
    for name in ("a1", "a2", "da1", "da2"):
        assert getattr(found, name) == pytest.approx(getattr(truth, name), rel=0.05), name
    assert ident.params.terms == TERMS and ident.params.kind == truth.kind


def test_fitting_the_textbook_terms_switches_the_packaged_atan_term_off():
    """--fit M_eq,a1,a2 without a parameter file of one's own: a3 = 180 N of the paper's axis is not
    another axis's friction; its term is off, not kept."""
    choice = choose_parameters(default_params(), None, ("M_eq", "a1", "a2"), frozenset())
    assert choice.terms == ("coulomb", "viscous") and choice.switched_off == ("atan",)
    assert choice.start.a3 == 0.0 and choice.start.a4 == 0.0


@pytest.mark.parametrize(
    ("terms", "fit", "given", "match"),
    [
        (None, ("a1", "a2"), frozenset(), r"M_eq \(the carriage mass\) is neither fitted nor given"),
        (("coulomb", "viscous", "atan"), ("M_eq", "a1", "a2", "a3"), frozenset(), r"a4 \(the atan term\)"),
        (("coulomb", "offset", "asymmetry"), None, frozenset(), "f0 and da1 cannot both be fitted"),
        (
            ("coulomb",),
            ("M_eq", "a1", "a2"),
            frozenset(),
            r"a2 \(term viscous\) belong to terms that are off",
        ),
    ],
)
def test_a_parameter_without_a_value_of_its_own_is_refused(terms, fit, given, match):
    with pytest.raises(IdentificationError, match=match):
        choose_parameters(default_params(), terms, fit, given)


def test_a_given_f0_is_held_and_da1_fitted_and_the_reverse():
    p = default_params().replace(f0=30.0, da1=2.0, da2=0.0)
    terms = ("coulomb", "viscous", "offset", "asymmetry")
    assert "f0" in choose_parameters(p, terms, None, frozenset({"m", "f0"})).held
    assert "da1" in choose_parameters(p, terms, None, frozenset({"m", "da1", "da2"})).held
