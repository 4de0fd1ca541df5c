"""Drives: a CiA 402 drive over CANopen against the built-in simulated axis, in lock-step and at wall pacing.

Part 1, lock-step (in this process, no Zenoh): ``--ticks`` ticks of a back-and-forth poly5 move, each
tick the bridge's calls — ``read``, ``status``, ``apply`` — and, for CANopen, the cycle's RPDOs, SYNC
and the wait for the TPDOs, against simulated drives on python-can's in-process ``virtual`` bus (the
master and each drive on a bus of their own, with their own receive threads):

* baseline: the built-in simulated axis (``SimulatedAxis``) — the same plant, no bus;
* one drive: :class:`~axisflow.acquisition.drives.canopen.adapter.CanopenDrive` and a
  :class:`~axisflow.acquisition.drives.canopen.sim_drive.SimulatedDrive`;
* two drives on one bus, one SYNC (ticks of both axes).

Part 2, wall pacing (``--seconds`` each, real processes): ``axisflow bridge`` at ``--speed 1`` with a
recorder process beside it (``axisflow record``), publishing over Zenoh on loopback:

* baseline: ``bridge --sim`` — its late ticks (a tick started more than a period after its deadline);
* ``bridge --drive canopen-sim`` at 1 kHz and at 250 Hz (the drive simulated in the bridge's process,
  so it competes for the same interpreter — harder than a real drive): late ticks, and the SYNC's
  late cycles (an interval over 1.5 periods) and missed cycles (over 2: what a drive's SYNC watch
  counts).

Part 3, tick jitter (``--jitter-seconds`` each; :mod:`.tick_jitter`): how late the ticks of
``axisflow bridge --sim`` start, beside the floor of this machine (a minimal C loop sleeping to absolute
1 ms deadlines, compiled at bench time), as found and beside two busy loops, as ordinary processes and at
real-time priority where allowed: p50, p99, max and the ticks late by more than a period, and the
bridge's p99 over the floor's.

``--json`` prints one object; docs/drives.md has a measured table and the command.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from contextlib import ExitStack
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from axisflow.benchmarks import tick_jitter
from axisflow.benchmarks.pipeline import free_port

from axisflow.arguments import finite_float, positive_int

if TYPE_CHECKING:  # the drives (python-can and canopen too) load when the benchmark runs
    from axisflow.acquisition.drives.canopen.config import DriveConfig
    from axisflow.acquisition.drives.drive import Setpoint
    from axisflow.acquisition.drives.plant import PlantConfig
    from axisflow.model import AxisParams

CLI = [sys.executable, "-c", "import sys; from axisflow.cli import main; sys.exit(main())"]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--ticks", type=positive_int, default=20_000, help="lock-step ticks per run (default 20000)"
    )
    parser.add_argument(
        "--seconds", type=finite_float, default=20.0, help="wall-paced run length [s] (default 20)"
    )
    parser.add_argument("--no-wall", action="store_true", help="no wall-paced part")
    parser.add_argument(
        "--jitter-seconds",
        type=finite_float,
        default=10.0,
        help="length of each tick-jitter run [s] (default 10; 0 = skip the tick-jitter part)",
    )


# ---- part 1: lock-step ------------------------------------------------------------------------------


def _back_and_forth(params: AxisParams) -> list[Setpoint]:
    """A poly5 move 0.1 → 0.6 m and back in 0.8 s each, as 1 kHz setpoints (one period: 1.6 s)."""
    from axisflow.acquisition.drives.drive import Setpoint
    from axisflow.model import Move, cart_force, polynomial_law

    out = []
    for x0, x1 in ((0.1, 0.6), (0.6, 0.1)):
        move = Move(x0, x1, 0.8, polynomial_law("poly5"))
        for k in range(800):
            s = move.sample(k * 1e-3)
            v, a = float(s.velocity_m_s), float(s.acceleration_m_s2)
            out.append(Setpoint(float(s.position_m), v, a, float(cart_force(v, a, params))))
    return out


def _plant(params: AxisParams) -> PlantConfig:
    """The packaged plant, starting where the move does."""
    from axisflow.acquisition.drives.plant import load_plant

    plant = load_plant(None, params)
    return replace(plant, simulation=replace(plant.simulation, initial_position_m=0.1))


def _simulated_axis(params: AxisParams, setpoints: list[Setpoint], ticks: int) -> float:
    from axisflow.acquisition.drives.sim_axis import SimulatedAxis

    plant = _plant(params)
    axis = SimulatedAxis(plant, params, start_stamp_ns=0)
    t0 = time.perf_counter()
    for k in range(ticks):
        axis.read()
        axis.status()
        axis.apply(setpoints[k % len(setpoints)])
    return ticks / (time.perf_counter() - t0)


def _bus(drives: int, channel: str) -> DriveConfig:
    from axisflow.acquisition.drives.canopen.config import config_from_mapping

    # as the packaged simulation: the drives' threads share this process and a loaded machine
    waits = {"pdo_timeout_ms": 2000, "heartbeat_timeout_ms": 2000}
    tables = [
        {"node_id": n, "axis": f"a{n}", "encoder_counts_per_rev": 131072, "pacing": "lockstep", **waits}
        for n in range(1, drives + 1)
    ]
    return config_from_mapping({"can": {"interface": "virtual", "channel": channel}, "drive": tables})


def _canopen(params: AxisParams, setpoints: list[Setpoint], ticks: int, drives: int) -> dict[str, float]:
    from axisflow.acquisition.drives.canopen.master import open_master
    from axisflow.acquisition.drives.canopen.sim_drive import SimulatedDrive

    config = _bus(drives, f"bench-drives-{drives}-{os.getpid()}")
    plant = _plant(params)
    with ExitStack() as stack:
        for i in range(drives):
            stack.enter_context(SimulatedDrive(config.can, config.drives[i], config.cycle_hz, plant, params))
        master = stack.enter_context(open_master(config, params))
        t0 = time.perf_counter()
        for k in range(ticks):
            for drive in master.drives:
                drive.read()
                drive.status()
                drive.apply(setpoints[k % len(setpoints)])
            master.cycle.after_tick()
        rate = ticks / (time.perf_counter() - t0)
        timed_out = master.cycle.waits_timed_out
        events = sum(len(d.events()) for d in master.drives)
    return {"cycles_per_s": rate, "axis_ticks_per_s": rate * drives, "waits_timed_out": timed_out,
            "drive_events": events}  # fmt: skip


def lockstep(ticks: int) -> dict[str, Any]:
    from axisflow.model import default_params

    params = default_params()
    setpoints = _back_and_forth(params)
    base = _simulated_axis(params, setpoints, ticks)
    one = _canopen(params, setpoints, ticks, 1)
    two = _canopen(params, setpoints, ticks, 2)
    return {
        "ticks": ticks,
        "simulated_axis_ticks_per_s": base,
        "canopen_1_drive": {**one, "ratio_to_baseline": one["axis_ticks_per_s"] / base},
        "canopen_2_drives": {**two, "ratio_to_baseline": two["axis_ticks_per_s"] / base},
    }


# ---- part 2: wall pacing ----------------------------------------------------------------------------


def _wall_run(tmp: Path, seconds: float, drive_args: list[str]) -> dict[str, Any]:
    """A bridge at --speed 1 with a recorder process beside it; the bridge's JSON report."""
    port = free_port()
    env = {**os.environ, "RUST_LOG": "error"}
    out = tmp / f"wall-{time.monotonic_ns()}.mcap"
    recorder = subprocess.Popen(
        [*CLI, "record", "-o", str(out), "--listen", f"tcp/127.0.0.1:{port}", "--json"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
    )  # fmt: skip
    try:
        deadline = time.monotonic() + 30.0
        while not (out.exists() and out.stat().st_size > 0):
            if recorder.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(
                    f"the recorder did not start: {recorder.stderr.read() if recorder.stderr else ''}"
                )
            time.sleep(0.05)
        bridge = subprocess.run(
            [*CLI, "bridge", *drive_args, "--speed", "1", "--duration", f"{seconds:g}", "--connect",
             f"tcp/127.0.0.1:{port}", "--wait-subscribers", "10", "--json"],
            capture_output=True, text=True, env=env, timeout=seconds + 120,
        )  # fmt: skip
        if bridge.returncode != 0:
            raise RuntimeError(f"bridge {' '.join(drive_args)} failed: {bridge.stderr.strip()}")
        return json.loads(bridge.stdout)
    finally:
        recorder.send_signal(signal.SIGINT)
        try:
            recorder.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            recorder.kill()
            recorder.communicate()


def _wall_config(tmp: Path, cycle_hz: int) -> Path:
    path = tmp / f"wall-{cycle_hz}.toml"
    path.write_text(
        f'[can]\ninterface = "virtual"\nchannel = "bench-wall"\n[drive]\nnode_id = 1\ncycle_hz = {cycle_hz}\n'
        'encoder_counts_per_rev = 131072\npacing = "wall"\nheartbeat_timeout_ms = 2000\n'
    )
    return path


def wall(seconds: float, progress: Any) -> dict[str, Any]:
    out: dict[str, Any] = {"seconds": seconds}
    with tempfile.TemporaryDirectory(prefix="axisflow-bench-drives-") as tmpdir:
        tmp = Path(tmpdir)
        runs = {
            "simulated_axis_1khz": ["--sim"],
            "canopen_1khz": ["--drive", "canopen-sim", "--drive-config", str(_wall_config(tmp, 1000))],
            "canopen_250hz": ["--drive", "canopen-sim", "--drive-config", str(_wall_config(tmp, 250))],
        }
        for name, drive_args in runs.items():
            report = _wall_run(tmp, seconds, drive_args)
            bus = report.get("bus") or {}
            out[name] = {
                "ticks": report["ticks"],
                "late_ticks": report["late_ticks"],
                "period_jitter": report["period_jitter"],
                "syncs": bus.get("syncs"),
                "late_cycles": bus.get("late_cycles"),
                "missed_cycles": bus.get("missed_cycles"),
                "drive_faults": report["drive_faults"],
            }
            progress(f"{name}: {report['late_ticks']} of {report['ticks']} ticks late")
    return out


def run(args: argparse.Namespace) -> int:
    def progress(line: str) -> None:
        if not args.json:
            print(f"  {line}", file=sys.stderr, flush=True)

    progress(f"lock-step: {args.ticks} ticks each (simulated axis, one drive, two drives)")
    result: dict[str, Any] = {"lockstep": lockstep(args.ticks)}
    if not args.no_wall:
        progress(f"wall pacing: {args.seconds:g} s each, a recorder beside the bridge")
        result["wall"] = wall(args.seconds, progress)
    if args.jitter_seconds > 0:
        result["tick_jitter"] = tick_jitter.measure(args.jitter_seconds, progress)
    result["load_average"] = os.getloadavg()
    if args.json:
        print(json.dumps(result, indent=1))
    else:
        print(table(result))
    return 0


def table(result: dict[str, Any]) -> str:
    lock = result["lockstep"]
    base = lock["simulated_axis_ticks_per_s"]
    head = (
        f"{'drive':<36}{'cycles/s':>10}{'axis ticks/s':>14}{'ratio':>8}{'waits timed out':>17}{'events':>8}"
    )
    lines = [
        f"lock-step, {lock['ticks']} ticks of a back-and-forth poly5 move",
        head,
        f"{'built-in simulated axis (baseline)':<36}{base:>10.0f}{base:>14.0f}{1.0:>8.3f}{'-':>17}{'-':>8}",
    ]
    for key, label in (("canopen_1_drive", "CANopen, one drive (virtual bus)"),
                       ("canopen_2_drives", "CANopen, two drives, one SYNC")):  # fmt: skip
        r = lock[key]
        lines.append(
            f"{label:<36}{r['cycles_per_s']:>10.0f}{r['axis_ticks_per_s']:>14.0f}{r['ratio_to_baseline']:>8.3f}"
            f"{r['waits_timed_out']:>17}{r['drive_events']:>8}"
        )
    if "wall" in result:
        w = result["wall"]
        lines += [
            "",
            f"wall pacing, {w['seconds']:g} s at --speed 1 with a recorder beside the bridge",
            f"{'drive':<34}{'late ticks':>15}{'p99 jitter':>12}{'late/missed cycles':>20}{'ratio':>8}"
            f"{'faults':>8}",
        ]
        base_late = w["simulated_axis_1khz"]["late_ticks"]
        for key, label in (("simulated_axis_1khz", "built-in simulated axis, 1 kHz"),
                           ("canopen_1khz", "CANopen (canopen-sim), 1 kHz"),
                           ("canopen_250hz", "CANopen (canopen-sim), 250 Hz")):  # fmt: skip
            r = w[key]
            share = f"{r['late_ticks']} ({100 * r['late_ticks'] / max(r['ticks'], 1):.2f} %)"
            cycles = "-" if r["syncs"] is None else f"{r['late_cycles']}/{r['missed_cycles']} of {r['syncs']}"
            ratio = r["late_ticks"] / base_late if base_late else float("nan")
            jitter = r["period_jitter"]["p99_us"] if r["period_jitter"] else float("nan")
            lines.append(
                f"{label:<34}{share:>15}{jitter:>10.0f}µs{cycles:>20}{ratio:>8.2f}{r['drive_faults']:>8}"
            )
    if "tick_jitter" in result:
        lines += ["", tick_jitter.table(result["tick_jitter"])]
    lines.append(f"load average during the run: {', '.join(f'{x:.2f}' for x in result['load_average'])}")
    return "\n".join(lines)
