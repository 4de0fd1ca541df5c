"""Model selection (``--terms auto``): the one-standard-error rule, the σ rule, and the structure a log's
plant has, chosen from its data."""

import math

import numpy as np
import pytest
from axisflow.identification.refit import IdentifySettings, identify
from axisflow.identification.report import report_json, report_markdown
from axisflow.identification.selection import (
    CandidateScore,
    Structure,
    choose,
    fit_plan,
    fold_labels,
    unsupported_terms,
)
from axisflow.identification.uncertainty import Uncertainty
from axisflow.model import cart_force, motor_torque

from .conftest import NOMINAL, PLANT, motion, write_foreign_log

SETTINGS = IdentifySettings(
    topic="/robot/joint_states", joint="slider_motor", joint_kind="motor", torque_delay_s=0.0
)


def _score(law, mean, se, parameters, unsupported=()):
    """A candidate whose five held-out scores have mean ``mean`` and standard error ``se``."""
    spread = se * math.sqrt(5) * math.sqrt(4 / 10)  # sd of (−2,−1,0,1,2)·x is x·√(10/4)
    folds = tuple(mean + spread * k for k in (-2, -1, 0, 1, 2))
    return CandidateScore(Structure(law), folds, (), {}, {}, 1.0, unsupported, (), True, parameters)


@pytest.mark.parametrize(
    ("scores", "chosen"),
    [
        # the richer candidate is better by less than the best's standard error: the simpler one
        ([((), 1.05, 0.1, 3), (("atan",), 1.0, 0.1, 5)], ()),
        # better by more than that: the richer one
        ([((), 1.5, 0.1, 3), (("atan",), 1.0, 0.1, 5)], ("atan",)),
        # the best is not supported (σ larger than its value): it neither wins nor sets the threshold
        ([((), 1.5, 0.1, 3), (("atan",), 1.0, 0.1, 5, ("atan",))], ()),
    ],
)
def test_the_simplest_candidate_within_one_standard_error_of_the_best_is_chosen(scores, chosen):
    picked, best, threshold = choose([_score(*s) for s in scores])
    assert picked.structure == Structure(chosen)
    assert best.standard_error == pytest.approx(next(s[2] for s in scores if s[0] == best.structure.law))
    assert threshold == pytest.approx(best.mean + best.standard_error)


def test_a_term_whose_sigma_exceeds_its_value_is_not_supported():
    structure = Structure(("atan",), stroke_terms=2)
    names = ("M_eq", "a1", "a2", "a3", "a4", "c1", "c2")
    values = {"M_eq": 100.0, "a1": 50.0, "a2": 0.5, "a3": 10.0, "a4": 3.0, "c1": 0.3, "c2": -0.2}
    std = {"M_eq": 1.0, "a1": 1.0, "a2": 2.0, "a3": 1.0, "a4": 4.0, "c1": 1.0, "c2": 1.0}
    unc = Uncertainty(names, std, np.eye(len(names)), 1.0, 1000, 100.0)
    assert unsupported_terms(structure, values, unc) == ("viscous", "atan", "stroke")
    std.update(a2=0.1, a4=0.5, c1=0.1, c2=0.1)
    assert unsupported_terms(structure, values, unc) == ()


@pytest.mark.slow
def test_auto_chooses_the_atan_term_of_a_plant_that_has_it(foreign_log):
    ident = identify([foreign_log], NOMINAL, SETTINGS)
    assert ident.selection is not None and ident.selection.chosen == Structure(("atan",))
    assert ident.fit.fitted == ("M_eq", "a1", "a2", "a3", "a4") and not ident.fit.extra  # no stroke
    assert ident.fit.values.a3 == pytest.approx(PLANT.a3, rel=0.01)
    base = ident.selection.score_of(Structure(()))
    assert base.mean > 10 * ident.selection.score_of(Structure(("atan",))).mean


@pytest.mark.slow
def test_auto_leaves_the_atan_term_off_for_a_plant_without_it(tmp_path):
    plant = PLANT.replace(a3=0.0, a1=PLANT.a1 + PLANT.a3 * math.pi / 2)

    def no_atan(t_ns, pos, vel, eff):
        t = (t_ns - t_ns[0]) * 1e-9
        _x, v, a = motion(t)
        eff[:, 1] = motor_torque(cart_force(v, a, plant), plant) + np.random.default_rng(2).normal(
            0, 0.01, t.size
        )
        return t_ns, pos, vel, eff

    path = write_foreign_log(tmp_path / "no_atan.mcap", edit=no_atan)
    ident = identify([path], NOMINAL, SETTINGS)
    assert ident.selection is not None and ident.selection.chosen == Structure(())
    assert ident.fit.fitted == ("M_eq", "a1", "a2")
    assert ident.params.a3 == 0.0  # the term is off, not left at the nominal axis's 180 N
    assert ident.fit.values.a1 == pytest.approx(plant.a1, rel=0.01)


def test_the_report_has_the_candidates_table(foreign_log):
    report = report_json(identify([foreign_log], NOMINAL, SETTINGS))
    sel = report["selection"]
    assert sel["chosen"] == "coulomb+viscous+atan" and report["structure"]["chosen_by"] == "auto"
    rows = {"+".join(c["terms"]): c for c in sel["candidates"]}
    assert set(rows) >= {"coulomb+viscous", "coulomb+viscous+atan", "coulomb+viscous+atan+stroke"}
    row = rows["coulomb+viscous+atan"]
    assert set(row["parameters_std"]) == {"M_eq", "a1", "a2", "a3", "a4"} and row["condition_number"] > 1
    assert len(row["fold_rms_nm"]) == sel["folds"] == 5
    text = report_markdown(report)
    assert "## Model selection" in text and "| coulomb+viscous+atan | 5 |" in text


def test_fixed_terms_skip_the_selection(foreign_log):
    settings = IdentifySettings(**{**SETTINGS.__dict__, "select": False})
    ident = identify([foreign_log], NOMINAL, settings)
    assert ident.selection is None and len(ident.fit.extra) == 6  # the six stroke terms, as given
    assert report_json(ident)["structure"]["chosen_by"] == "given"


@pytest.mark.parametrize(
    ("law", "given_f0", "fitted", "zero"),
    [
        ((), False, ("M_eq", "a1", "a2"), ("f0", "da1", "da2", "a3", "a4")),
        (("offset", "asymmetry"), False, ("M_eq", "a1", "a2", "f0", "da2"), ("da1", "a3", "a4")),
        # f0 given (gravity on a known incline): held at its value, and the Coulomb asymmetry is fitted
        (("asymmetry", "atan"), True, ("M_eq", "a1", "a2", "da1", "da2", "a3", "a4"), ()),
    ],
)
def test_a_structures_plan_fits_its_terms_and_switches_the_others_off(law, given_f0, fitted, zero):
    nominal = NOMINAL.replace(f0=-30.0, da1=4.0, da2=9.0) if given_f0 else NOMINAL.replace(da1=4.0, da2=9.0)
    given = frozenset({"m", "a1", "f0"} if given_f0 else {"m", "a1"})
    names, start = fit_plan(Structure(law), nominal, given, speed_m_s=0.5)
    assert names == fitted
    assert all(getattr(start, p) == 0.0 for p in zero)  # off: never another axis's nominal value
    assert start.f0 == (-30.0 if given_f0 else 0.0)
    assert set(start.terms) == {"coulomb", "viscous", *law, *(("offset",) if given_f0 else ())}


@pytest.mark.parametrize(("span_s", "blocks"), [(25.0, 10), (133.0, 20), (3600.0, 20), (9.9, 5), (4.0, 5)])
def test_folds_are_contiguous_blocks_dealt_in_turn(span_s, blocks):
    labels = fold_labels(1000, span_s)
    changes = np.flatnonzero(np.diff(labels)) + 1
    assert len(changes) == blocks - 1  # contiguous blocks, each ≥ 2 s of log where the log allows
    starts = np.r_[0, changes]
    assert list(labels[starts]) == [i % 5 for i in range(blocks)]  # dealt to the five folds in turn
    assert np.bincount(labels).tolist() == [200] * 5


def test_a_holdout_is_scored_as_one_more_fold(foreign_log):
    settings = IdentifySettings(**{**SETTINGS.__dict__, "holdout": 0.25})
    sel = identify([foreign_log], NOMINAL, settings).selection
    assert sel is not None and sel.validation_logs == 1
    for c in sel.candidates:
        assert len(c.fold_rms) == 5 and len(c.validation_rms) == 1 and len(c.scores) == 6
