"""The adaptation experiment: online re-identification against nominal parameters and a one-time refit,
on a warming axis (``axisflow bench adapt``, ``axisflow demo --adapt``; :func:`run_adaptation` with
:class:`AdaptationSettings`).

Three simulated axes, each its own bridge process with its own ``warm-up`` plant (the same seed, so
the same axis) at ``--speed 0``, named for the way their planner chooses its parameters:

* ``nominal`` — the nominal parameters, throughout;
* ``refit`` — a one-time refit at the start (the demo's excitation and ``identify``), throughout;
* ``adapt`` — online adaptation: ``axisflow adapt --axis adapt`` (a process) refits over a sliding
  window of the axis's samples, and the planner plans every next move with the newest accepted set
  (``adapt_from``: starting from the refit, the default, or from the nominal parameters).

All three run the same excitation first (so their plants share one history), then, in this process
(a planner node per axis, one thread each), the paper's way points over and over — minimum time,
poly3, poly5 and poly7 in turn, each pass through all the way points — for at least ``minutes`` of
axis time, and last one pass of minimum time-energy (ω = 0.9, poly5) through the same way points.
Why three axes at once rather than one after the other: the same wall time runs three times the axis
time, the three plants warm through the same excitation and the same kind of moves, and one
recording holds all of it. One recorder records everything; the results come from it alone:

* per move, E% = (E_th − E_exp)/E_th (:func:`axisflow.experiment.table2.move_energies`) and, per
  minute of axis time since the way points began, the median and the largest |E%| of each way;
* the final pass of each way: total time, E_th, measured E_exp, E% and the objective of eq. (3)
  with the *measured* energy, ω·T + (1 − ω)·E_exp — what the plans really cost;
* the adaptation's decisions (from the ``params`` records).

Writes into ``out``: ``bench.mcap``, ``refit/`` (the one-time refit), ``moves-<way>.csv/json``,
``adapt.json``, ``adapt.md``, ``adapt.png`` (E% per move, :mod:`axisflow.viz.adaptation_figure`) and,
with ``rrd``, ``session.rrd`` (the rerun view of the recording: signals, E% per move, the
adapted parameters with their σ band, the friction curve).

Goals (issue 21): with adaptation, median |E%| ≤ 1 % in every minute after the first two; the one-time
refit drifts past 3 %; the adapted plans compared with the stale ones at the same ω.
"""

from __future__ import annotations

import json
import math
import os
import threading
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..model.energy import energy_error_pct

WAYS = ("nominal", "refit", "adapt")
LAWS = ("poly3", "poly5", "poly7")
GOAL_ADAPT_PCT = 1.0
"""the adapted way's median |E%| in every minute after the first two"""
GOAL_SETTLE_MIN = 2
GOAL_DRIFT_PCT = 3.0
"""the one-time refit's median |E%| is expected to pass this"""
PASS_MARGIN = 1.15
"""passes planned beyond the nominal estimate of the axis time (adapted plans are faster)"""
LOOKAHEAD_S = 10.0
"""drive time each planner keeps queued (the demo's): at --speed 0 a bridge runs several times real time"""
TICKER_S = 20.0
TAIL_S = 120.0
"""drive time each bridge runs on after its last move before the recorder stops [s]: at --speed 0 a
bridge runs ahead of the recorder by what the buffers between them hold (about a minute of drive time
with three axes), and the recorder's stop waits only a second for that backlog"""
TAIL_WAIT_S = 120.0
"""the most wall time the tail may take [s]"""


@dataclass(frozen=True)
class AdaptationSettings:
    """What the adaptation experiment runs, and where it writes."""

    out: Path
    """the output folder (new or empty)"""
    minutes: float = 10.0
    """axis time of way points per way [min]"""
    waypoints: int = 50
    """way points per pass"""
    seed: int = 0
    """way point seed"""
    adapt_from: str = "refit"
    """the adaptive way's starting parameters: ``refit`` (the one-time refit) or ``nominal``"""
    rrd: bool = True
    """write the rerun view session.rrd"""


@dataclass
class WayResult:
    """One way's moves and what they say."""

    name: str
    start_ns: int = 0
    """drive time of the first way-point move's start"""
    minutes: list[dict[str, Any]] = field(default_factory=list)
    energy_pass: dict[str, Any] = field(default_factory=dict)
    moves: int = 0
    versions: tuple[int, int] = (0, 0)


def run_adaptation(
    settings: AdaptationSettings, say: Callable[[str], None], stop: threading.Event
) -> dict[str, Any]:
    """Run the experiment (the module docstring) into ``settings.out``, saying what it does through
    ``say``; ``stop`` ends it early. Returns the results, also written to adapt.json and adapt.md."""
    # everything heavy here: loaded when the experiment runs
    from ..acquisition.bus.axis_state import DriveWatch
    from ..acquisition.bus.readiness import wait_for_token
    from ..acquisition.bus.session import ZenohOptions, open_session
    from ..acquisition.wire.keys import AxisKeys, recorder_token
    from ..deploy.processes import READY_TIMEOUT_S, Launcher, free_port
    from ..experiment.refit_folder import identify_to
    from ..experiment.waypoints import random_waypoints
    from ..identification.excitation import design_excitation
    from ..identification.refit import IdentifySettings
    from ..model import AxisflowError, default_params, load_params
    from ..model.files import check_output_dir, ensure_dir
    from ..nodes.excite import run_excitation

    if settings.adapt_from not in ("refit", "nominal"):
        raise AxisflowError(f"adapt from {settings.adapt_from!r} must be refit or nominal")
    if not (math.isfinite(settings.minutes) and 1.0 <= settings.minutes <= 600.0):
        raise AxisflowError(f"--minutes {settings.minutes:g} must be in [1, 600] min of axis time")
    if not 2 <= settings.waypoints <= 10_000:
        raise AxisflowError(f"--waypoints {settings.waypoints} must be in [2, 10000]")
    out = settings.out
    check_output_dir(out)
    if out.exists() and any(out.iterdir()):
        raise AxisflowError(f"--out {out} is not empty: choose a new folder")
    ensure_dir(out)
    nominal = default_params()
    waypoints = random_waypoints(settings.waypoints, settings.seed, nominal)
    n_passes = _passes(settings.minutes, waypoints, nominal)
    recording = out / "bench.mcap"
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    t_start = time.monotonic()
    load = os.getloadavg()
    wall: dict[str, float] = {}
    with Launcher(out / "logs") as children:
        say(f"adapt benchmark in {out}: three warm-up axes at --speed 0 on {endpoint}; load {load[0]:.2f}")
        # the recorder first, listening: it joins at once (no publisher yet to answer its hellos, which a
        # loaded machine may answer late) and every bridge that connects afterwards knows its subscriber
        recorder = children.start(
            "recorder", "record", "-o", str(recording), "--listen", endpoint, ready=True
        )
        children.wait_ready(recorder, READY_TIMEOUT_S)
        bridges = []
        for way in WAYS:
            bridges.append(
                children.start(
                    f"bridge-{way}",
                    "bridge",
                    "--sim",
                    "--axis",
                    way,
                    "--plant-profile",
                    "warm-up",
                    "--speed",
                    "0",
                    "--connect",
                    endpoint,
                    ready=True,
                )
            )
            children.wait_ready(bridges[-1], READY_TIMEOUT_S)
        with open_session(ZenohOptions(connect=(endpoint,))) as session:
            import socket

            token = recorder_token(socket.gethostname(), recorder.pid)
            if not wait_for_token(session, token, READY_TIMEOUT_S):
                raise AxisflowError(f"the recorder was ready, but its token {token} never came")
            # 1. the same excitation on every axis
            t0 = time.monotonic()
            plan = design_excitation(nominal)
            say(
                f"excitation on all three axes: {len(plan.bursts)} bursts, {plan.duration_s:.0f} s of axis "
                "time"
            )
            excitations = _each_way(
                lambda way: run_excitation(session, AxisKeys(way), nominal, plan, stop=stop)
            )
            wall["excitation"] = time.monotonic() - t0
            # 2. the one-time refit, from the refit axis's excitation
            t0 = time.monotonic()
            refit_settings = IdentifySettings(
                topic="/axisflow/refit/state", window=excitations["refit"].window()
            )
            _ident, report = identify_to(out / "refit", [recording], nominal, refit_settings)
            refit = load_params(out / "refit" / "params.toml")
            wall["identification"] = time.monotonic() - t0
            say(
                "one-time refit: "
                + ", ".join(f"{n} {p['value']:.4g}" for n, p in report["parameters"].items())
            )
            # 3. the adaptive node, from its starting set
            start_file = out / "refit" / "params.toml" if settings.adapt_from == "refit" else None
            adapt_args = ["--params", str(start_file)] if start_file else []
            adapter = children.start(
                "adapt", "adapt", "--axis", "adapt", "--connect", endpoint, *adapt_args, ready=True
            )
            children.wait_ready(adapter, READY_TIMEOUT_S)
            # 4. the way points, three planners at once
            t0 = time.monotonic()
            params = {"nominal": nominal, "refit": refit, "adapt": refit if start_file else nominal}
            say(
                f"way points: {n_passes} passes of {len(waypoints)} (min-time, {'/'.join(LAWS)} in turn), "
                "then one of min-time-energy (ω 0.9, poly5), on each axis"
            )
            watches = {way: DriveWatch(session, AxisKeys(way)) for way in WAYS}
            done = threading.Event()
            ticker = threading.Thread(target=_ticker, args=(watches, done, say, t0), name="ticker")
            ticker.start()
            try:
                reports = _each_way(
                    lambda way: _planner(session, way, params[way], way == "adapt", waypoints, n_passes, stop)
                )
                wall["way points"] = time.monotonic() - t0
                _tail(watches, reports, say)
            finally:
                done.set()
                ticker.join()
                for w in watches.values():
                    w.close()
            children.stop(adapter)
        # the recorder before the bridges: its stop's hello needs them alive to prove nothing is missing
        end = children.stop(recorder)
        for bridge in bridges:
            children.stop(bridge)
        if end.returncode != 0:
            raise AxisflowError(f"the recorder exited with {end.returncode}: see {out / 'logs'}")
    t0 = time.monotonic()
    results = _results(recording, out, settings.minutes)
    results["equal_time"] = _equal_time(recording, waypoints, nominal, out)
    for way in WAYS:
        late = [k for r in reports[way] for k in r.late_moves]
        results["ways"][way]["late_moves"] = len(late)
    results["passes"] = n_passes
    results["waypoints"] = settings.waypoints
    results["seed"] = settings.seed
    results["adapt_from"] = settings.adapt_from
    wall["analysis"] = time.monotonic() - t0
    if settings.rrd:
        t0 = time.monotonic()
        from ..viz.session import write_session_rrd

        write_session_rrd([recording], out / "session.rrd", nominal)
        wall["rerun view"] = time.monotonic() - t0
    results["wall_time_s"] = time.monotonic() - t_start
    results["phases_s"] = wall
    results["load_average"] = {"start": list(load), "end": list(os.getloadavg())}
    _write(out, results, settings)
    return results


def _passes(minutes: float, waypoints: Any, nominal: Any) -> int:
    """Passes of min-time moves for ``minutes`` of axis time (estimated with the nominal parameters,
    poly7 the slowest law, with :data:`PASS_MARGIN`)."""
    import itertools

    from ..planner import Case, ExactBackend, MoveProblem

    backend = ExactBackend()
    seconds = 0.0
    for a, b in itertools.pairwise(waypoints):
        result = backend.solve(MoveProblem(float(a), float(b), "poly5", Case.MIN_TIME), nominal)
        seconds += result.duration_s
    return max(1, math.ceil(PASS_MARGIN * minutes * 60.0 / seconds))


def _each_way(work: Any) -> dict[str, Any]:
    """``work(way)`` for the three ways at once, one thread each; the first error is raised."""
    results: dict[str, Any] = {}
    errors: list[BaseException] = []

    def one(way: str) -> None:
        try:
            results[way] = work(way)
        except BaseException as exc:
            errors.append(exc)

    threads = [threading.Thread(target=one, args=(way,), name=f"way-{way}") for way in WAYS]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        raise errors[0]
    return results


def _planner(
    session: Any, way: str, params: Any, adapt: bool, waypoints: Any, n_passes: int, stop: threading.Event
) -> Any:
    from ..acquisition.wire.keys import AxisKeys
    from ..nodes.planner_node import NodeRun, NodeSettings, PlannerNode
    from ..planner import DEFAULT_OMEGA, Case, ExactBackend

    runs = tuple(NodeRun(Case.MIN_TIME, LAWS[k % len(LAWS)]) for k in range(n_passes))
    runs += (NodeRun(Case.MIN_TIME_ENERGY, "poly5"),)
    # a busy machine may hold this process back longer than the queue lasts: an idle stretch is counted
    settings = NodeSettings(
        AxisKeys(way), runs, DEFAULT_OMEGA, 1, LOOKAHEAD_S, way, adapt, stop_when_late=False
    )
    with PlannerNode(session, settings, params, ExactBackend(), None, stop) as node:
        return node.run(waypoints)


def _tail(watches: dict[str, Any], reports: dict[str, Any], say: Any) -> None:
    """Let every bridge run :data:`TAIL_S` of drive time past its last move, so that the recorder (which
    trails the bridges) has the whole experiment before it stops."""
    last = {}
    for way, runs in reports.items():
        ends = [m.accepted.stamp_of(m.accepted.end_tick) for r in runs for m in r.moves if m.accepted]
        last[way] = max(ends)
    say(f"  the bridges run on {TAIL_S:g} s of drive time, for the recorder to catch up")
    deadline = time.monotonic() + TAIL_WAIT_S

    def caught_up() -> bool:
        infos = {way: watch.latest() for way, watch in watches.items()}
        return all(i is not None and i.stamp_ns >= last[w] + TAIL_S * 1e9 for w, i in infos.items())

    while not caught_up() and time.monotonic() < deadline:
        time.sleep(0.2)


def _ticker(watches: dict[str, Any], done: threading.Event, say: Any, t0: float) -> None:
    """Every :data:`TICKER_S` of wall time: how far each axis has come (drive time since it began)."""
    first: dict[str, int] = {}
    while not done.wait(TICKER_S):
        parts = []
        for way, watch in watches.items():
            info = watch.latest()
            if info is None:
                continue
            first.setdefault(way, info.stamp_ns)
            parts.append(f"{way} {(info.stamp_ns - first[way]) / 60e9:.1f}")
        if not parts:
            continue
        say(f"  {time.monotonic() - t0:.0f} s: axis minutes since the way points began: {', '.join(parts)}")


# ---- the results, from the recording alone ----------------------------------------------------------
def _results(recording: Path, out: Path, minutes: float) -> dict[str, Any]:
    from ..acquisition.wire.keys import AxisKeys
    from ..experiment.per_move import write_move_energies
    from ..experiment.table2 import move_energies, recorded_runs
    from ..model.files import write_atomic
    from ..viz.adaptation_figure import EnergyErrorSeries, adaptation_png

    whole = math.floor(minutes)
    ways: dict[str, Any] = {}
    series = {}
    for way in WAYS:
        runs, _accounting = recorded_runs(recording, AxisKeys(way), way)
        moves = move_energies(runs)
        write_move_energies(moves, out, f"moves-{way}")
        timed = [m for m in moves if m.case == "min-time" and m.start_ns >= 0]
        start = timed[0].start_ns
        at = np.array([(m.start_ns - start) / 60e9 for m in timed])
        error = np.array([np.nan if m.energy_error_pct is None else m.energy_error_pct for m in timed])
        per_minute = []
        for k in range(whole):
            inside = (at >= k) & (at < k + 1)
            e = error[inside]
            e = e[np.isfinite(e)]
            planned = sum(
                m.energy_planned_j
                for m, i in zip(timed, inside, strict=True)
                if i and m.energy_measured_j is not None
            )
            measured = sum(m.energy_measured_j or 0.0 for m, i in zip(timed, inside, strict=True) if i)
            per_minute.append(
                {
                    "minute": k,
                    "moves": int(np.count_nonzero(inside)),
                    "measured": int(e.size),
                    "median_abs_pct": float(np.median(np.abs(e))) if e.size else None,
                    "max_abs_pct": float(np.max(np.abs(e))) if e.size else None,
                    "median_pct": float(np.median(e)) if e.size else None,
                    "sum_pct": energy_error_pct(planned, measured),
                }
            )
        medians = np.array(
            [np.nan if r["median_abs_pct"] is None else r["median_abs_pct"] for r in per_minute]
        )
        series[way] = EnergyErrorSeries(at, error, medians)
        versions = [m.params_version for m in moves]
        ways[way] = {
            "moves": len(moves),
            "minutes": per_minute,
            "axis_time_min": float(at[-1]) if at.size else 0.0,
            "params_versions": [min(versions), max(versions)],
            "energy_pass": _energy_pass([m for m in moves if m.case == "min-time-energy"]),
        }
    ways["adapt"]["decisions"] = _decisions(recording)
    title = f"E% per move on a warming axis: nominal, one-time refit, online adaptation ({recording.name})"
    write_atomic(out / "adapt.png", adaptation_png(series, title))
    return {"ways": ways, "goals": _goals(ways), "recording": str(recording)}


def _energy_pass(moves: list[Any]) -> dict[str, Any]:
    """The min-time-energy pass: total time, energies, E% and eq. (3) with the measured energy."""
    from ..planner import DEFAULT_OMEGA

    measured = [m for m in moves if m.energy_measured_j is not None]
    planned = math.fsum(m.energy_planned_j for m in measured)
    real = math.fsum(m.energy_measured_j for m in measured)
    total = math.fsum(m.duration_s for m in measured)  # over the measured moves, as the energies
    return {
        "moves": len(moves),
        "measured": len(measured),
        "omega": DEFAULT_OMEGA,
        "total_time_s": total,
        "energy_planned_j": planned,
        "energy_measured_j": real,
        "energy_error_pct": energy_error_pct(planned, real),
        "objective_measured": DEFAULT_OMEGA * total + (1.0 - DEFAULT_OMEGA) * real,
        "median_abs_pct": float(np.median([abs(m.energy_error_pct) for m in measured])) if measured else None,
    }


def _equal_time(recording: Path, waypoints: Any, nominal: Any, out: Path) -> dict[str, Any]:
    """The energy the accurate model (the adaptive node's last accepted set) saves against the stale
    one-time refit at equal cycle time: the refit's last pass (its poly5 durations) against the accurate
    model's plans at the ω that matches its cycle time, both judged by the accurate model."""
    from ..acquisition.logs.reader import read_messages
    from ..acquisition.wire.keys import AxisKeys, topic_for_key
    from ..acquisition.wire.params_estimate import PARAMS_ESTIMATE_TYPE, ParamsEstimate
    from ..experiment.per_move import read_move_energies
    from ..savings.cycle_moves import moves_of_waypoints
    from ..savings.study import equal_time_saving

    records = [
        ParamsEstimate.decode(m.data)
        for m in read_messages(recording, topic_for_key(AxisKeys("adapt").params), PARAMS_ESTIMATE_TYPE)
    ]
    last = max((r for r in records if r.accepted and r.version > 0), key=lambda r: r.version, default=None)
    if last is None:
        return {"saving_pct": None, "why": "no accepted parameter set"}
    stale = [m for m in read_move_energies(out / "moves-refit.json") if m.case == "min-time-energy"]
    durations = {m.waypoint_index: m.duration_s for m in stale}
    moves = moves_of_waypoints(waypoints)
    if sorted(durations) != list(range(1, len(moves) + 1)):
        return {"saving_pct": None, "why": "the refit's last pass is incomplete"}
    got = equal_time_saving(
        moves, "poly5", [durations[k] for k in range(1, len(moves) + 1)], last.applied_to(nominal)
    )
    return got | {"accurate_version": last.version}


def _decisions(recording: Path) -> dict[str, Any]:
    from ..acquisition.logs.reader import read_messages
    from ..acquisition.wire.keys import AxisKeys, topic_for_key
    from ..acquisition.wire.params_estimate import PARAMS_ESTIMATE_TYPE, ParamsEstimate

    records = [
        ParamsEstimate.decode(m.data)
        for m in read_messages(recording, topic_for_key(AxisKeys("adapt").params), PARAMS_ESTIMATE_TYPE)
    ]
    counts = Counter(r.decision.value for r in records if r.decision.value != "initial")
    last = max((r for r in records if r.accepted), key=lambda r: r.version, default=None)
    return {
        "counts": dict(counts),
        "last_version": last.version if last is not None else 0,
        "last_values": dict(last.value_of) if last is not None else {},
        "first_values": next((dict(r.value_of) for r in records if r.decision.value == "initial"), {}),
    }


def _goals(ways: dict[str, Any]) -> dict[str, Any]:
    after = [r["median_abs_pct"] for r in ways["adapt"]["minutes"] if r["minute"] >= GOAL_SETTLE_MIN]
    after = [v for v in after if v is not None]
    drift = next(
        (r["minute"] for r in ways["refit"]["minutes"] if (r["median_abs_pct"] or 0.0) > GOAL_DRIFT_PCT), None
    )
    return {
        "adapt_worst_median_after_settling_pct": max(after) if after else None,
        "adapt_met": bool(after) and max(after) <= GOAL_ADAPT_PCT,
        "refit_first_minute_past_3pct": drift,
        "refit_drifts_past_3pct": drift is not None,
    }


def adaptation_markdown(results: dict[str, Any], settings: AdaptationSettings) -> str:
    """The results as a Markdown page (adapt.md), headed by the benchmark's command line."""
    ways = results["ways"]
    lines = [
        f"# axisflow bench adapt --minutes {settings.minutes:g} --waypoints {settings.waypoints} "
        f"--seed {settings.seed} --adapt-from {settings.adapt_from}",
        "",
        f"{results['passes']} passes of min-time moves per axis (poly3/poly5/poly7 in turn), then one pass "
        f"of min-time-energy; wall time {results['wall_time_s']:.0f} s, load average "
        f"{results['load_average']['start'][0]:.2f} at the start, {results['load_average']['end'][0]:.2f} at "
        "the end.",
        "",
        "median / max |E%| per minute of axis time since the way points began:",
        "",
        "| minute | " + " | ".join(f"{w} median | {w} max" for w in WAYS) + " |",
        "|---:|" + "---:|" * (2 * len(WAYS)),
    ]
    for k in range(len(ways["nominal"]["minutes"])):
        cells = []
        for w in WAYS:
            r = ways[w]["minutes"][k]
            cells += [_pct(r["median_abs_pct"]), _pct(r["max_abs_pct"])]
        lines.append(f"| {k} | " + " | ".join(cells) + " |")
    lines += [
        "",
        "the last pass, minimum time-energy (ω = 0.9, poly5), the same way points:",
        "",
        "| way | moves measured | T [s] | E_th [J] | E_exp [J] | E% | median abs E% | ω·T + (1−ω)·E_exp |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for w in WAYS:
        e = ways[w]["energy_pass"]
        lines.append(
            f"| {w} | {e['measured']}/{e['moves']} | {e['total_time_s']:.1f} | {e['energy_planned_j']:.0f} | "
            f"{e['energy_measured_j']:.0f} | {_pct(e['energy_error_pct'], signed=True)} | "
            f"{_pct(e['median_abs_pct'])} | {e['objective_measured']:.1f} |"
        )
    late = {w: ways[w].get("late_moves", 0) for w in WAYS}
    if any(late.values()):
        lines += [
            "",
            "moves that started after the move before had ended (this process held back on a busy machine: "
            "the axis idled): " + ", ".join(f"{w} {n}" for w, n in late.items()) + ".",
        ]
    eq = results.get("equal_time", {})
    if eq.get("saving_pct") is not None:
        lines += [
            "",
            f"at equal cycle time ({eq['cycle_time_s']:.1f} s, the refit's last pass), judged by the adapted "
            f"model (version {eq['accurate_version']}): the refit's plans {eq['energy_stale_j']:.2f} J, the "
            f"adapted model's at ω = {eq['omega']:.4f} {eq['energy_accurate_j']:.2f} J: "
            f"{eq['saving_pct']:.3f} % saved.",
        ]
    d = ways["adapt"]["decisions"]
    g = results["goals"]
    counts = ", ".join(f"{n} {k}" for k, n in sorted(d["counts"].items()))
    drift = g["refit_first_minute_past_3pct"]
    lines += [
        "",
        f"adaptation: {counts}; version {d['last_version']} in force at the end; plans used versions "
        f"{ways['adapt']['params_versions'][0]}…{ways['adapt']['params_versions'][1]}.",
        f"goal, adapt: median |E%| ≤ {GOAL_ADAPT_PCT:g} % in every minute from minute {GOAL_SETTLE_MIN}: "
        f"worst {_pct(g['adapt_worst_median_after_settling_pct'])} — "
        f"{'met' if g['adapt_met'] else 'NOT met'}.",
        f"goal, refit: median |E%| past {GOAL_DRIFT_PCT:g} %: "
        + (f"from minute {drift}." if drift is not None else "never, within this run."),
    ]
    return "\n".join(lines)


def _pct(value: float | None, signed: bool = False) -> str:
    if value is None:
        return "–"
    return f"{value:+.2f} %" if signed else f"{value:.2f} %"


def _write(out: Path, results: dict[str, Any], settings: AdaptationSettings) -> None:
    from ..model.files import write_atomic_files

    write_atomic_files(
        out,
        {
            "adapt.json": json.dumps(results, indent=1, allow_nan=False) + "\n",
            "adapt.md": adaptation_markdown(results, settings) + "\n",
        },
    )
