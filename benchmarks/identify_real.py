"""Identify on logs of real axes' kinds, against the textbook least squares fitted in the same run.

Rows:

1. **A simulated axis of each transmission kind** (``--axes FILE…``; default: the example file of
   each kind, docs/axes/*.toml, which give a constant force, and the packaged belt axis, which does
   not). The user's parameter file is the kind's
   file with its friction law cut back to eq. (1) — unless it gives a constant force (gravity on a
   vertical axis), which the user knows and keeps; the true axis has a constant force f0 and a viscous
   asymmetry da2 (and, where the file gives f0, its Coulomb asymmetry da1: only then can a log tell
   da1 from f0). The plant is the ``realistic`` profile's drive — its units (encoder counts, torque in
   per mille), coloured current noise, jittered stamps, 0.1 % of the samples lost — on a rigid axis
   (no cogging, belt or friction along the stroke); it runs the identification excitation twice
   (another noise seed for the validation log) through the bridge's move queue, offline; each log is
   then written as another tool writes it (:mod:`.foreign_log`: one joint, the motor's, position and
   effort only, no velocity). ``identify`` runs with its defaults on the fit log.
   Checked: every fitted law parameter within 2 % (M_eq) or 5 % (friction) of the truth (a parameter
   whose truth is zero: within 5 % of the friction beside it), and the held-out force error within
   :data:`TRUE_MODEL_RATIO` × the error of the TRUE model on the same validation log.
2. **The EMPS-like rig** (:mod:`.emps_rig`: the published facts of a real ball-screw axis under
   closed-loop control, its measured friction curve, position and force only; a fit and a validation
   log with different programs, each a scope-like CSV of t, qm and vir brought in by ``axisflow
   import``'s importer with the force = gtau × vir). The issue's criterion: identify's held-out
   error below the textbook fit's.

Every row's held-out error is the issue's measure (:func:`.textbook_fit.relative_force_error`:
‖F − F̂‖/‖F‖ through a 100 Hz zero-phase filter, over the moving samples), for identify's model, the
true model and the textbook four-parameter least squares with offset (:func:`.textbook_fit.fit_textbook`,
on the very samples identify fits).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
import tempfile
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..arguments import non_negative_int, positive_int

if TYPE_CHECKING:
    from ..identification.preparation import PreparedLog
    from ..model import AxisParams

TRUE_MODEL_RATIO = 1.05
"""identify's held-out error may be at most this many times the true model's"""
M_TOLERANCE = 0.02
FRICTION_TOLERANCE = 0.05
OFFSET_OF_A1 = -0.12
"""the true constant force, as a fraction of a1 (where the file gives none): an amplifier's offset"""
VISCOUS_ASYMMETRY_OF_A2 = 0.15
"""the true viscous asymmetry da2 as a fraction of a2 (where the file gives none)"""
SIMULATED_TORQUE_DELAY_S = 0.5e-3
"""the simulated drive's torque sample is the current of the tick before (docs/plant.md)"""
EMPS_TORQUE_DELAY_S = -0.5e-3
"""the rig's force sample acts over the tick after it"""
_EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "axes"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--axes",
        nargs="*",
        metavar="FILE",
        default=None,
        help="parameter files of the simulated axes (default: docs/axes/*.toml and the packaged axis)",
    )
    parser.add_argument(
        "--laps", type=positive_int, default=4, help="laps of the EMPS-like logs (default 4: ~25 s)"
    )
    parser.add_argument(
        "--seed", type=non_negative_int, default=0, help="noise seed of the fit logs (validation: +1)"
    )


def _say(args: argparse.Namespace, text: str) -> None:
    if not args.json:
        print(f"  … {text}", file=sys.stderr, flush=True)


def run(args: argparse.Namespace) -> int:
    rows = []
    with tempfile.TemporaryDirectory(prefix="axisflow-bench-identify-real-") as tmpdir:
        folder = Path(tmpdir)
        for path in _axis_files(args.axes):
            _say(args, f"simulated axis {path.name if path else 'packaged'}: two excitation runs, identify")
            rows.append(simulated_axis_row(path, folder, args.seed))
        _say(args, f"EMPS-like rig: {args.laps} laps to fit, {args.laps} to validate, identify")
        rows.append(emps_row(folder, args.laps, args.seed))
    result = {
        "rows": rows,
        "true_model_ratio": TRUE_MODEL_RATIO,
        "tolerances": {"M_eq": M_TOLERANCE, "friction": FRICTION_TOLERANCE},
        "all_pass": all(r["pass"] for r in rows),
    }
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        _print(result)
    return 0


def _axis_files(given: list[str] | None) -> list[Path | None]:
    if given:
        return [Path(p) for p in given]
    found = sorted(_EXAMPLES.glob("*.toml")) if _EXAMPLES.is_dir() else []
    return [*found, None]  # the packaged axis too: a file without f0, so f0 is fitted


# ---- the simulated axes ------------------------------------------------------------------------------


def truth_and_nominal(path: Path | None) -> tuple[AxisParams, AxisParams]:
    """(the true axis, the user's file) of a simulated-axis row (module docstring)."""
    from ..model import default_params, load_params

    kind_file = default_params() if path is None else load_params(path)
    given = "offset" in kind_file.terms
    user = kind_file.replace(
        f0=kind_file.f0 if given else 0.0, da1=0.0, da2=0.0, terms=("offset",) if given else ()
    )
    true = kind_file.replace(
        f0=kind_file.f0 if given else OFFSET_OF_A1 * kind_file.a1,
        da1=kind_file.da1 if given else 0.0,
        da2=kind_file.da2 or VISCOUS_ASYMMETRY_OF_A2 * kind_file.a2,
    )
    return true, user


def simulated_axis_row(path: Path | None, folder: Path, seed: int) -> dict[str, Any]:
    from ..identification.excitation import design_excitation
    from .toolkit.offline_excitation import record_offline_excitation

    true, user = truth_and_nominal(path)
    name = path.stem if path else "packaged belt axis"
    plant = realistic_drive(true)
    plan = design_excitation(user)
    logs = []
    for role, offset in (("fit", 0), ("validation", 1)):
        sensor = dataclasses.replace(plant.torque_sensor, seed=plant.torque_sensor.seed + seed + offset)
        recorded = folder / f"{name}-{role}-recorded.mcap"
        record_offline_excitation(recorded, plan, dataclasses.replace(plant, torque_sensor=sensor), user)
        logs.append(_as_foreign(recorded, folder / f"{name}-{role}.mcap"))
    return _scored_row(
        name=name,
        kind=user.kind,
        fit_log=logs[0],
        validation_log=logs[1],
        joint="motor",
        nominal=user,
        true_model=lambda log: _law_force(true, log),
        true_delay_s=SIMULATED_TORQUE_DELAY_S,
        truth=true,
    )


def realistic_drive(true: AxisParams) -> Any:
    """The ``realistic`` profile's drive on the rigid axis ``true`` (no cogging, belt or friction along
    the stroke): its units (the rated torque 40 % of the axis's peak, as the profile's), its current
    and sensor noise scaled with the axis's peak torque (or force), its jittered and lost samples."""
    from ..acquisition.drives.plant import load_profile
    from ..model import default_params

    profile = load_profile("realistic", default_params())
    scale = true.tau_max / profile.axis.tau_max
    loop, sensor, drive = profile.current_loop, profile.torque_sensor, profile.drive
    return dataclasses.replace(
        profile,
        axis=true,
        cogging=None,
        belt=None,
        stroke_friction=None,
        drive=None if drive is None else dataclasses.replace(drive, rated_torque_nm=0.4 * true.tau_max),
        torque_sensor=dataclasses.replace(sensor, noise_std_nm=sensor.noise_std_nm * scale),
        current_loop=None
        if loop is None
        else dataclasses.replace(
            loop,
            torque_noise_std_nm=loop.torque_noise_std_nm * scale,
            measurement_noise_std_nm=loop.measurement_noise_std_nm * scale,
        ),
    )


def _as_foreign(recorded: Path, out: Path) -> Path:
    """The recording's state topic, motor joint, re-written as another tool writes a log."""
    from ..acquisition import read_joint_states
    from ..acquisition.wire.keys import AxisKeys, topic_for_key
    from .foreign_log import write_joint_log

    motor = read_joint_states(recorded, topic_for_key(AxisKeys().state)).joint("motor")
    return write_joint_log(out, motor.stamp_ns, motor.position, motor.effort, "motor")


def _law_force(params: Any, log: PreparedLog) -> np.ndarray:
    from ..identification.fit import FrictionValues

    return FrictionValues.of(params).force_n(log.velocity_m_s, log.acceleration_m_s2)


# ---- the EMPS-like rig -------------------------------------------------------------------------------


def emps_row(folder: Path, laps: int, seed: int) -> dict[str, Any]:
    from . import emps_rig as rig

    fit = rig.write_imported(folder, "emps-fit", rig.simulate(rig.RigSpec(laps=laps, seed=seed)))
    validation = rig.simulate(rig.RigSpec(program=rig.VALIDATION_PROGRAM, laps=laps, seed=seed + 1))
    val = rig.write_imported(folder, "emps-validation", validation)

    def true_model(log: PreparedLog) -> np.ndarray:
        v = log.velocity_m_s
        friction = np.array([rig.friction_n(float(x)) if x else 0.0 for x in v])
        return rig.MASS_KG * log.acceleration_m_s2 + friction

    return _scored_row(
        name="EMPS-like rig",
        kind="ball-screw (closed loop, position and force only)",
        fit_log=fit,
        validation_log=val,
        joint=rig.RIG_JOINT,
        nominal=None,
        true_model=true_model,
        true_delay_s=EMPS_TORQUE_DELAY_S,
        truth=None,
    )


# ---- scoring -----------------------------------------------------------------------------------------


def _scored_row(
    *,
    name: str,
    kind: str,
    fit_log: Path,
    validation_log: Path,
    joint: str,
    nominal: AxisParams | None,
    true_model: Any,
    true_delay_s: float,
    truth: AxisParams | None,
) -> dict[str, Any]:
    from ..identification.preparation import PreparationSettings, prepare
    from ..identification.refit import IdentifySettings, identify
    from ..identification.signals import joint_kind, load_joint
    from ..model import default_params
    from .textbook_fit import SCORE_CUTOFF_HZ, fit_textbook, relative_force_error

    params = nominal or default_params()
    topic = _only_topic(fit_log)
    kind_of = joint_kind(joint, "motor" if joint == "motor" else "carriage").value
    settings = IdentifySettings(topic=topic, joint=joint, joint_kind=kind_of)
    t0 = time.perf_counter()
    ident = identify([fit_log], params, settings)
    identify_s = time.perf_counter() - t0
    validation = load_joint(validation_log, topic, joint, params, kind_of)
    scoring = PreparationSettings(cutoff_hz=SCORE_CUTOFF_HZ)

    def identified(log: PreparedLog) -> np.ndarray:
        return ident.model_force(log, ident.extra.columns(log, ident.stretch_m, params, scoring))

    limit = params.tau_max if kind_of == "motor" else params.f_max
    ls = fit_textbook([prepare(ident.logs[0].signals, PreparationSettings(), limit)])
    errors = {
        "identify": relative_force_error(validation, identified, ident.delay_s),
        "true_model": relative_force_error(validation, true_model, true_delay_s),
        "textbook": relative_force_error(
            validation, lambda log: ls.force_n(log.velocity_m_s, log.acceleration_m_s2)
        ),
    }
    held = ident.choice.held if ident.choice is not None else ()
    checks = _parameter_checks(ident.fit.values, ident.fit.fitted, held, truth) if truth is not None else []
    ratio = errors["identify"] / errors["true_model"]
    passed = errors["identify"] < errors["textbook"]
    if truth is not None:
        passed = passed and ratio <= TRUE_MODEL_RATIO and all(c["pass"] for c in checks)
    return {
        "name": name,
        "kind": kind,
        "samples": int(ident.logs[0].signals.t_s.size),
        "chosen": ident.selection.chosen.label if ident.selection else None,
        "errors_pct": {k: 100.0 * v for k, v in errors.items()},
        "ratio_to_true_model": ratio,
        "ratio_to_textbook": errors["identify"] / errors["textbook"],
        "textbook": dataclasses.asdict(ls),
        "identified": {n: getattr(ident.fit.values, n) for n in ident.fit.fitted},
        "parameters": checks,
        "delay_s": ident.delay_s,
        "identify_s": identify_s,
        "pass": passed,
    }


def _only_topic(path: Path) -> str:
    """The log's only JointState topic (as identify chooses it without --topic)."""
    from ..acquisition.logs.joint_topics import only_joint_state_topic

    topic = only_joint_state_topic([path])
    assert topic is not None  # the rigs write one
    return topic


def _parameter_checks(
    values: Any, fitted: tuple[str, ...], held: tuple[str, ...], truth: AxisParams
) -> list[dict[str, Any]]:
    """Each parameter fitted or in the truth against the truth; one held at the user's value (a
    constant force the file gives) is checked as held."""
    from ..identification.fit import FrictionValues

    true = FrictionValues.of(truth).as_dict()
    found = values.as_dict()
    beside = {"f0": "a1", "da1": "a1", "da2": "a2", "a3": "a1", "a4": "a4"}
    out = []
    for name in ("M_eq", "a1", "a2", "f0", "da1", "da2", "a3", "a4"):
        if name not in fitted and true[name] == 0.0:
            continue
        if name in held:
            ok = found[name] == true[name]
            out.append(
                {
                    "name": name,
                    "true": true[name],
                    "fitted": None,
                    "held": found[name],
                    "relative_error": None,
                    "tolerance": 0.0,
                    "pass": ok,
                }
            )
            continue
        tolerance = M_TOLERANCE if name == "M_eq" else FRICTION_TOLERANCE
        scale = abs(true[name]) if true[name] else abs(true[beside[name]])
        error = (found[name] - true[name]) / scale if scale else math.inf
        out.append(
            {
                "name": name,
                "true": true[name],
                "fitted": found[name] if name in fitted else None,
                "held": None,
                "relative_error": error if name in fitted else None,
                "tolerance": tolerance,
                "pass": name in fitted and abs(error) <= tolerance,
            }
        )
    return out


def _print(result: dict[str, Any]) -> None:
    print(
        "identify-real: identify (its defaults) against the textbook 4-parameter least squares with offset "
        "and the true model, on the same logs; held-out error ‖F − F̂‖/‖F‖ through 100 Hz, moving samples"
    )
    print(
        f"{'axis':24} {'chosen terms':44} {'identify':>9} {'textbook':>9} {'true':>7} {'÷true':>6} "
        f"{'÷textbook':>9} {'pass':>5}"
    )
    for r in result["rows"]:
        e = r["errors_pct"]
        print(
            f"{r['name']:24} {r['chosen'] or '-':44} {e['identify']:>8.2f}% {e['textbook']:>8.2f}% "
            f"{e['true_model']:>6.2f}% {r['ratio_to_true_model']:>6.3f} {r['ratio_to_textbook']:>9.3f} "
            f"{'yes' if r['pass'] else 'NO':>5}"
        )
        for c in r["parameters"]:
            err = "dropped" if c["relative_error"] is None else f"{100 * c['relative_error']:+.2f} %"
            if c["held"] is not None:
                err = "held: given"
            fitted = "-" if c["fitted"] is None else f"{c['fitted']:.6g}"
            print(
                f"    {c['name']:5} true {c['true']:>10.6g}  fitted {fitted:>10}  {err:>9} "
                f"(±{100 * c['tolerance']:.0f} %) {'ok' if c['pass'] else 'OUT'}"
            )
        tb = r["textbook"]
        print(
            f"    textbook: M {tb['mass_kg']:.4g} kg, Fv {tb['viscous_n_s_per_m']:.4g} N·s/m, "
            f"Fc {tb['coulomb_n']:.4g} N, offset {tb['offset_n']:.4g} N; identify {r['identify_s']:.1f} s "
            f"on {r['samples']} samples"
        )
    criteria = (
        f"parameters within {100 * M_TOLERANCE:.0f} % (M_eq) / {100 * FRICTION_TOLERANCE:.0f} % (friction), "
        f"held-out error within {result['true_model_ratio']:g}× the true model's and below the textbook fit's"
    )
    print(f"{criteria}: {'all rows pass' if result['all_pass'] else 'NOT all rows pass'}")
