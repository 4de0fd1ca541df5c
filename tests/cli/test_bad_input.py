"""Bad input, catalogued: every command, as a new user would get it wrong.

Each case must end with exit code 2 and exactly one error line on stderr that names the value (and,
where there is one, the limit and its unit); no traceback, nothing on stdout, and the output it
would have written absent or unchanged — errors found by argparse (a value that is not a number, an
unknown choice) too: the command line turns them into one line (axisflow/cli/__init__.py). The same
list is docs/refusals.md, generated from this one (:func:`refusals_page`).

Beyond the line, every case checks that the input folder is byte for byte what it was and that the
working folder holds exactly what it held: nothing written, no stray temporary (``.part``) file.

The table runs in-process (``axisflow.cli.main``); the three slips our issue found, and piping into
``head``, run as real processes.
"""

from __future__ import annotations

import json
import math
import os
import signal
import struct
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest
from axisflow.acquisition import AxisSample
from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter
from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec
from axisflow.acquisition.wire.messages import JOINT_STATE_TYPE, MOVE_TYPE
from axisflow.model import default_params

from axisflow.cli import main
from axisflow.security import SecurityPlan, init_security

from ..acquisition.logs.cell_log import write_cell_log

CLI = [sys.executable, "-c", "import sys; from axisflow.cli import main; sys.exit(main())"]
LOOPBACK = ("--listen", "tcp/127.0.0.1:0")  # a session that reaches for nobody else's peers
T0_NS = 1_700_000_000_000_000_000


@dataclass(frozen=True)
class Case:
    id: str
    args: tuple[str, ...]
    says: tuple[str, ...]
    """fragments the one error line must contain: the value, the limit, the unit"""
    untouched: tuple[str, ...] = ()
    """paths (in the working folder) that must be absent afterwards, or unchanged if they existed"""


def case(name: str, *args: str, says: tuple[str, ...], untouched: tuple[str, ...] = ()) -> Case:
    return Case(name, args, says, untouched)


CASES = [
    # parameters
    case(
        "params: missing file", "params", "--params", "missing.toml", says=("missing.toml", "does not exist")
    ),
    case(
        "params: unknown key",
        "params",
        "--params",
        "unknown.toml",
        says=("unknown.toml", "unknown key(s) foo"),
    ),
    case(
        "params: negative mass",
        "params",
        "--params",
        "negative.toml",
        says=("m = -3.0 kg", "outside the physical range [0.001, 10000] kg"),
    ),
    case(
        "params: mass 1e308",
        "params",
        "--params",
        "huge-mass.toml",
        says=("m = 1e+308 kg", "outside the physical range [0.001, 10000] kg"),
    ),
    case(
        "params: stroke in millimetres",
        "params",
        "--params",
        "stroke-mm.toml",
        says=("L = 800.0 m", "outside the physical range [0.01, 50] m"),
    ),
    case(
        "params: a motor weaker than Coulomb friction",
        "params",
        "--params",
        "weak-motor.toml",
        says=("tau_max = 0.25 N·m", "F_max = tau_max·i_r/r = 62.5 N", "Coulomb friction a1 = 72.0 N"),
    ),
    case(
        "params: motor speed beyond any motor",
        "params",
        "--params",
        "fast-motor.toml",
        says=("v_max = 20.0 m/s", "v_max·i_r/r = 200000 rad/s", "60000 rpm"),
    ),
    case("params: NaN friction", "params", "--params", "nan.toml", says=("a1 = nan N", "not finite")),
    case("params: not TOML", "params", "--params", "garbage.toml", says=("garbage.toml", "not valid TOML")),
    # one move
    case(
        "plan: x1 out of the stroke",
        "plan",
        "0.1",
        "0.95",
        says=("x1_m = 0.95 m", "outside the stroke [0, 0.8] m"),
    ),
    case("plan: x1 not a number", "plan", "0.1", "abc", says=("x1", "'abc' is not a number")),
    case("plan: x1 NaN", "plan", "0.1", "nan", says=("x1", "'nan' is not a finite number")),
    case(
        "plan: omega > 1",
        "plan",
        "0.1",
        "0.5",
        "--case",
        "min-time-energy",
        "--omega",
        "1.2",
        says=("omega = 1.2", "outside [0, 1]"),
    ),
    case(
        "plan: empty duration bounds",
        "plan",
        "0.1",
        "0.5",
        "--t-min",
        "5",
        "--t-max",
        "1",
        says=("t_min_s = 5.0 s > t_max_s = 1.0 s",),
    ),
    case(
        "plan: negative mass",
        "plan",
        "0.1",
        "0.5",
        "--params",
        "negative.toml",
        says=("m = -3.0 kg", "[0.001, 10000] kg"),
    ),
    case(
        "plan: mass 1e308",
        "plan",
        "0",
        "0.5",
        "--params",
        "huge-mass.toml",
        says=("m = 1e+308 kg", "outside the physical range [0.001, 10000] kg"),
    ),
    # the experiment, the sweep
    case(
        "experiment: one way point",
        "experiment",
        "--out",
        "exp",
        "--waypoints",
        "1",
        says=("1 way points", "at least 2"),
        untouched=("exp",),
    ),
    case(
        "experiment: omega < 0",
        "experiment",
        "--out",
        "exp",
        "--omega",
        "-0.5",
        says=("omega = -0.5", "outside [0, 1]"),
        untouched=("exp",),
    ),
    case(
        "experiment: too many way points",
        "experiment",
        "--out",
        "exp",
        "--waypoints",
        "200000",
        says=("waypoints = 200000", "[2, 100000]"),
        untouched=("exp",),
    ),
    case(
        "experiment: --out under /proc",
        "experiment",
        "--out",
        "/proc/x",
        says=("output directory /proc/x cannot be created", "/proc is not writable"),
        untouched=("/proc/x",),
    ),
    case(
        "bench all: --out under /proc, refused before the benchmarks run",
        "bench",
        "all",
        "--out",
        "/proc/x",
        says=("output directory /proc/x cannot be created", "/proc is not writable"),
        untouched=("/proc/x",),
    ),
    case(
        "experiment: --out is a file",
        "experiment",
        "--out",
        "notes.txt",
        "--waypoints",
        "3",
        says=("notes.txt", "exists and is not a directory"),
        untouched=("notes.txt",),
    ),
    case(
        "pareto: omega > 1",
        "pareto",
        "--out",
        "par",
        "--omega",
        "1.5",
        says=("omega = 1.5", "outside [0, 1]"),
        untouched=("par",),
    ),
    case(
        "pareto: unknown law",
        "pareto",
        "--out",
        "par",
        "--law",
        "poly9",
        says=("--law", "'poly9'"),
        untouched=("par",),
    ),
    # benchmarks
    case(
        "bench: zero moves",
        "bench",
        "planner",
        "--moves",
        "0",
        says=("--moves", "0 must be >= 1"),
    ),
    case(
        "bench: an endless idle window",
        "bench",
        "pipeline",
        "--idle-seconds",
        "inf",
        says=("--idle-seconds", "'inf' is not a finite number"),
    ),
    case(
        "bench: zero payloads",
        "bench",
        "faults",
        "--payloads",
        "0",
        says=("--payloads", "0 must be >= 1"),
    ),
    # the bridge
    case(
        "bridge: impossible address",
        "bridge",
        "--sim",
        "--connect",
        "tcp/999.1.1.1:1",
        says=("'tcp/999.1.1.1:1'", "'999.1.1.1'", "IPv4 parts 0…255"),
    ),
    case(
        "bridge: port out of range",
        "bridge",
        "--sim",
        "--listen",
        "tcp/127.0.0.1:99999",
        says=("'99999'", "not in 0…65535"),
    ),
    case("bridge: negative speed", "bridge", "--sim", "--speed", "-1", says=("speed = -1.0", "must be >= 0")),
    case(
        "bridge: zero duration",
        "bridge",
        "--sim",
        "--duration",
        "0",
        says=("duration = 0.0 s", "must be > 0 s"),
    ),
    case(
        "bridge: real-time priority above SCHED_FIFO's",
        "bridge",
        "--sim",
        "--rt-priority",
        "100",
        says=("real-time priority 100", "outside 1…99"),
    ),
    case(
        "bridge: a core this machine lacks",
        "bridge",
        "--sim",
        "--cpus",
        "0,4096",
        says=("CPUs 0,4096", "not all available"),
    ),
    case(
        "bridge: cores that are not numbers",
        "bridge",
        "--sim",
        "--cpus",
        "first",
        says=("'first'", "not a comma-separated list of CPU numbers"),
    ),
    case(
        "bridge: negative jump tolerance",
        "bridge",
        "--sim",
        "--jump-tolerance",
        "-1",
        says=("jump tolerance = -1.0 m", ">= 0 m"),
    ),
    case(
        "bridge: missing plant file",
        "bridge",
        "--sim",
        "--plant",
        "missing.toml",
        says=("plant file missing.toml", "does not exist"),
    ),
    case(
        "bridge: plant scaled beyond any cart",
        "bridge",
        "--sim",
        "--plant",
        "heavy-plant.toml",
        says=("heavy-plant.toml", "m = 90000.0 kg", "[0.001, 10000] kg"),
    ),
    case(
        "bridge: plant state is someone's file",
        "bridge",
        "--sim",
        "--plant-state",
        "notes.txt",
        says=("notes.txt holds 6 bytes", "16 bytes"),
        untouched=("notes.txt",),
    ),
    case(
        "bridge: plant state outside the stroke",
        "bridge",
        "--sim",
        "--plant-state",
        "far.state",
        says=("far.state holds x = 5 m", "outside the stroke [0, 0.8] m"),
        untouched=("far.state",),
    ),
    case(
        "bridge: plant state beyond the speed limit",
        "bridge",
        "--sim",
        "--plant-state",
        "fast.state",
        says=("fast.state holds v = 100 m/s", "beyond ±1.65 m/s", "v_max 1.5 m/s"),
        untouched=("fast.state",),
    ),
    case(
        "bridge: plant file out of range",
        "bridge",
        "--sim",
        "--plant",
        "lossy-plant.toml",
        says=("lossy-plant.toml", "sample_clock.drop_fraction = 0.9", "must be <= 0.5"),
    ),
    case(
        "bridge: unknown plant profile",
        "bridge",
        "--sim",
        "--plant-profile",
        "cold",
        says=("--plant-profile", "'cold'", "ideal", "warm-up"),
    ),
    case(
        "bridge: a plant file and a profile",
        "bridge",
        "--sim",
        "--plant",
        "lossy-plant.toml",
        "--plant-profile",
        "realistic",
        says=("--plant-profile", "not allowed with argument --plant"),
    ),
    case("bridge: bad key prefix", "bridge", "--sim", "--prefix", "a/*", says=("key prefix 'a/*'", "'*'")),
    case(
        "demo: unknown plant profile", "demo", "--plant-profile", "tidy", says=("--plant-profile", "'tidy'")
    ),
    case(
        "identify: a cogging order that is not a number",
        "identify",
        "still.mcap",
        "--out",
        "refit",
        "--cogging",
        "24,x",
        says=("--cogging 24,x", "'x' is not a whole number of cycles per motor revolution"),
        untouched=("refit",),
    ),
    case(
        "identify: too many stroke terms",
        "identify",
        "still.mcap",
        "--out",
        "refit",
        "--stroke-terms",
        "20",
        says=("stroke terms = 20", "0…12"),
        untouched=("refit",),
    ),
    case(
        "bridge: invalid zenoh config",
        "bridge",
        "--sim",
        "--zenoh-config",
        "bad.json5",
        says=("zenoh config file bad.json5 is invalid",),
    ),
    # the bridge with CANopen drives (docs/drives.md)
    case(
        "bridge: missing drive config",
        "bridge",
        "--drive-config",
        "missing-drive.toml",
        says=("drive configuration file missing-drive.toml", "does not exist"),
    ),
    case(
        "bridge: unknown key in the drive config",
        "bridge",
        "--drive-config",
        "drive-unknown.toml",
        says=("drive-unknown.toml", "unknown key(s) speed in [drive]", "allowed: node_id"),
    ),
    case(
        "bridge: node id out of range",
        "bridge",
        "--drive-config",
        "drive-node200.toml",
        says=("[drive] node_id = 200", "must be in 1…127"),
    ),
    case(
        "bridge: CAN interface unknown",
        "bridge",
        "--drive-config",
        "drive-nope.toml",
        *LOOPBACK,
        says=("CAN interface 'pcan2'", "is not a python-can interface"),
    ),
    case(
        "bridge: CAN interface cannot open",
        "bridge",
        "--drive-config",
        "drive-socketcan.toml",
        *LOOPBACK,
        says=("CAN interface 'socketcan' channel 'nocan7' cannot be opened",),
    ),
    case(
        "bridge: no drive at the node id",
        "bridge",
        "--drive-config",
        "drive-nobody.toml",
        *LOOPBACK,
        says=("no answer from drive node 9 (axis a0)", "node id 9"),
    ),
    case(
        "bridge: wall pacing faster than real time",
        "bridge",
        "--drive-config",
        "drive-wall.toml",
        "--speed",
        "0",
        says=("pacing = wall", "--speed must be 1, not 0"),
    ),
    case(
        "bridge: canopen without a config",
        "bridge",
        "--drive",
        "canopen",
        says=("--drive canopen needs --drive-config FILE",),
    ),
    # the simulated CANopen drive
    case(
        "drive-sim: an in-process bus",
        "drive-sim",
        "--drive-config",
        "drive-wall.toml",
        says=("CAN interface 'virtual' reaches only its own process", "udp_multicast"),
    ),
    case(
        "drive-sim: error code not hexadecimal",
        "drive-sim",
        "--drive-config",
        "drive-sock.toml",
        "--fault-at",
        "1:zz",
        says=("--fault-at '1:zz'", "error code 'zz' is not hexadecimal"),
    ),
    case(
        "drive-sim: no drive at that node",
        "drive-sim",
        "--drive-config",
        "drive-sock.toml",
        "--node",
        "4",
        says=("--node 4", "has no drive at that node id (it has 5)"),
    ),
    # the recorder
    case(
        "record: bad key expression",
        "record",
        "-o",
        "rec.mcap",
        "--keys",
        "a/**/**",
        says=("--keys 'a/**/**'", "not a valid Zenoh key expression"),
        untouched=("rec.mcap",),
    ),
    case(
        "record: not .mcap",
        "record",
        "-o",
        "rec.txt",
        says=("rec.txt", "must end in .mcap"),
        untouched=("rec.txt",),
    ),
    case("record: missing folder", "record", "-o", "nowhere/rec.mcap", says=("nowhere", "does not exist")),
    case(
        "record: existing file",
        "record",
        "-o",
        "existing.mcap",
        "--duration",
        "1",
        says=("existing.mcap already exists", "--overwrite"),
        untouched=("existing.mcap",),
    ),
    case(
        "record: zero duration",
        "record",
        "-o",
        "rec.mcap",
        "--duration",
        "0",
        says=("duration = 0.0 s", "must be > 0 s"),
        untouched=("rec.mcap",),
    ),
    case(
        "record: zero split size",
        "record",
        "-o",
        "rec.mcap",
        "--split-size",
        "0",
        says=("'0'", "must be >= 1 byte"),
        untouched=("rec.mcap",),
    ),
    case(
        "record: negative flush interval",
        "record",
        "-o",
        "rec.mcap",
        "--flush-interval",
        "-1",
        says=("flush interval = -1.0 s", "must be > 0 s"),
        untouched=("rec.mcap",),
    ),
    # excitation and identification
    case(
        "excite: too short",
        "excite",
        "--plan-only",
        "--duration",
        "1",
        says=("duration = 1.0 s", "outside [5.0, 3600.0] s"),
    ),
    case(
        "excite: torque margin > 1",
        "excite",
        "--plan-only",
        "--torque-margin",
        "1.5",
        says=("1.5 of tau_max", "[0.1, 1.0]"),
    ),
    case(
        "identify: a cell's recording without --axis",
        "identify",
        "cell.mcap",
        "--out",
        "ident",
        says=("cell.mcap holds 3 axes (a0, a1, a2)", "choose one with --axis"),
        untouched=("ident",),
    ),
    case(
        "identify: an axis the recording does not hold",
        "identify",
        "cell.mcap",
        "--axis",
        "a7",
        "--out",
        "ident",
        says=("--axis a7", "holds no such axis", "3 axes (a0, a1, a2)"),
        untouched=("ident",),
    ),
    case(
        "identify: missing log",
        "identify",
        "missing.mcap",
        "--out",
        "ident",
        says=("missing.mcap",),
        untouched=("ident",),
    ),
    case(
        "identify: empty file",
        "identify",
        "empty.mcap",
        "--out",
        "ident",
        says=("empty.mcap is not an MCAP file", "first 0 bytes"),
        untouched=("ident",),
    ),
    case(
        "identify: not MCAP",
        "identify",
        "notes.txt",
        "--out",
        "ident",
        says=("notes.txt is not an MCAP file",),
        untouched=("ident",),
    ),
    case(
        "identify: wrong schema",
        "identify",
        "wrong-schema.mcap",
        "--out",
        "ident",
        says=("'axisflow_msgs/msg/Move'", "not sensor_msgs/msg/JointState"),
        untouched=("ident",),
    ),
    case(
        "identify: NaN in the samples",
        "identify",
        "nan-samples.mcap",
        "--out",
        "ident",
        says=("non-finite values", "more than 1%"),
        untouched=("ident",),
    ),
    case(
        "identify: truncated before any message",
        "identify",
        "truncated.mcap",
        "--out",
        "ident",
        says=("truncated.mcap",),
        untouched=("ident",),
    ),
    case(
        "identify: holdout > 0.9",
        "identify",
        "still.mcap",
        "--out",
        "ident",
        "--holdout",
        "1.5",
        says=("holdout = 1.5", "[0, 0.9)"),
        untouched=("ident",),
    ),
    # the views
    case(
        "view: web port out of range",
        "view",
        "still.mcap",
        "--serve",
        "--web-port",
        "99999",
        says=("--web-port", "99999 is not a TCP port (0…65535; 0 = a free one)"),
    ),
    # the planner node, the quick stop
    case(
        "planner: missing way points",
        "planner",
        "--waypoints",
        "missing.txt",
        says=("way point file missing.txt does not exist",),
    ),
    case(
        "planner: way point out of the stroke",
        "planner",
        "--waypoints",
        "outside.txt",
        says=("line 2", "0.9 m is outside the stroke [0, 0.8] m"),
    ),
    case(
        "planner: way point not a number",
        "planner",
        "--waypoints",
        "words.txt",
        says=("line 2", "'abc' is not a number (in m)"),
    ),
    case(
        "planner: too few way points", "planner", "--waypoints", "one.txt", says=("has 1 way points", "2 to")
    ),
    case(
        "planner: omega > 1",
        "planner",
        "--random",
        "5",
        "--omega",
        "2",
        says=("--omega 2.0", "outside [0, 1]"),
    ),
    case(
        "planner: mass 1e308",
        "planner",
        "--random",
        "5",
        "--params",
        "huge-mass.toml",
        says=("m = 1e+308 kg", "outside the physical range [0.001, 10000] kg"),
    ),
    case(
        "planner: a1 beyond any belt",
        "planner",
        "--waypoints",
        "tiny.txt",
        "--params",
        "huge-friction.toml",
        says=("a1 = 1000000.0 N", "[0, 100000] N"),
    ),
    case(
        "planner: negative lookahead",
        "planner",
        "--random",
        "5",
        "--lookahead-s",
        "-1",
        says=("lookahead = -1.0 s", "[0, 600] s"),
    ),
    case("stop: negative timeout", "stop", "--timeout", "-1", says=("--timeout -1 s", "must be > 0 s")),
    # the adaptive node, and reading its parameters back
    case("adapt: window too short", "adapt", "--window", "1", says=("window = 1.0 s", "[2, 3600] s")),
    case(
        "adapt: hold-out over half the window",
        "adapt",
        "--window",
        "10",
        "--holdout",
        "6",
        says=("hold-out = 6 s", "at most half the window = 10 s"),
    ),
    case("adapt: unknown term", "adapt", "--terms", "M_eq,a9", says=("unknown a9", "choose from M_eq")),
    case(
        "adapt: coulomb with a1",
        "adapt",
        "--terms",
        "a1,coulomb",
        says=("coulomb scales a1 and a3 together",),
    ),
    case("adapt: zero duration", "adapt", "--duration", "0", says=("--duration 0 s", "must be > 0 s")),
    case(
        "params: --out without --from",
        "params",
        "--out",
        "p.toml",
        says=("--out and --version", "--from LOG.mcap"),
        untouched=("p.toml",),
    ),
    case(
        "params: a recording without estimates",
        "params",
        "--from",
        "still.mcap",
        "--out",
        "p.toml",
        says=("still.mcap", "no accepted parameter estimate"),
        untouched=("p.toml",),
    ),
    case(
        "params: --out not a .toml",
        "params",
        "--from",
        "still.mcap",
        "--out",
        "p.txt",
        says=("p.txt must end in .toml",),
        untouched=("p.txt",),
    ),
    # the ROS 2 node: refused before any ROS 2 call (no DDS discovery starts)
    case("ros2: rate 0", "ros2", "--rate", "0", says=("rate = 0.0 Hz", "(0, 1000] Hz")),
    case("ros2: rate above the drive's", "ros2", "--rate", "5000", says=("rate = 5000.0 Hz", "(0, 1000] Hz")),
    case("ros2: axis not a ROS 2 name", "ros2", "--axis", "a-0", says=("axis name 'a-0'", "ROS 2 name")),
    case("ros2: omega > 1", "ros2", "--omega", "2", says=("omega = 2.0", "outside [0, 1]")),
    # Table 2 from a recording, replay, recover
    case(
        "table2: no plan records",
        "table2",
        "still.mcap",
        "--out",
        "t2",
        says=("still.mcap", "no plan records"),
        untouched=("t2",),
    ),
    case(
        "table2: a cell's recording without --axis",
        "table2",
        "cell.mcap",
        "--out",
        "t2",
        says=("cell.mcap holds 3 axes (a0, a1, a2)", "choose one with --axis"),
        untouched=("t2",),
    ),
    case(
        "view: an axis the recording does not hold",
        "view",
        "cell.mcap",
        "--axis",
        "b1",
        says=("--axis b1", "not in cell.mcap", "it holds a0, a1, a2"),
        untouched=("cell.rrd",),
    ),
    case(
        "view: --live with two axes",
        "view",
        "--live",
        "--axis",
        "a0",
        "--axis",
        "a1",
        says=("--live views one --axis or all", "--axis a0 --axis a1"),
    ),
    case(
        "table2: not MCAP",
        "table2",
        "notes.txt",
        "--out",
        "t2",
        says=("not an MCAP file",),
        untouched=("t2",),
    ),
    case(
        "replay: no complete message",
        "replay",
        "truncated.mcap",
        "--no-wait",
        *LOOPBACK,
        says=("truncated.mcap", "no complete message"),
    ),
    case(
        "replay: missing file",
        "replay",
        "missing.mcap",
        "--no-wait",
        *LOOPBACK,
        says=("missing.mcap", "does not exist"),
    ),
    case(
        "replay: negative speed",
        "replay",
        "still.mcap",
        "--speed",
        "-2",
        "--no-wait",
        *LOOPBACK,
        says=("speed = -2.0", "must be >= 0"),
    ),
    case(
        "replay: bad key expression",
        "replay",
        "still.mcap",
        "--keys",
        "a/**/**",
        "--no-wait",
        *LOOPBACK,
        says=("--keys 'a/**/**'",),
    ),
    case(
        "recover: no complete message",
        "recover",
        "truncated.mcap",
        says=("truncated.mcap", "no complete message"),
        untouched=("truncated.recovered.mcap",),
    ),
    case(
        "recover: not MCAP",
        "recover",
        "notes.txt",
        "-o",
        "out.mcap",
        says=("not an MCAP file",),
        untouched=("out.mcap",),
    ),
    case(
        "recover: existing output",
        "recover",
        "still.mcap",
        "-o",
        "existing.mcap",
        says=("existing.mcap already exists", "--overwrite"),
        untouched=("existing.mcap",),
    ),
    case(
        "recover: output is the source",
        "recover",
        "still.mcap",
        "-o",
        "still.mcap",
        says=("output still.mcap is the input still.mcap", "must never write over an input"),
        untouched=("still.mcap",),
    ),
    # security, the router, the demo
    case(
        "security: zero days",
        "security",
        "init",
        "sec",
        "--days",
        "0",
        says=("--days", "0 must be >= 1"),
        untouched=("sec",),
    ),
    case(
        "security: unknown role",
        "security",
        "init",
        "sec",
        "--roles",
        "pilot",
        says=("role 'pilot'",),
        untouched=("sec",),
    ),
    case(
        "security: impossible host",
        "security",
        "init",
        "sec",
        "--host",
        "999.1.1.1",
        says=("'999.1.1.1'", "IPv4 parts 0…255"),
        untouched=("sec",),
    ),
    case(
        "security: port out of range",
        "security",
        "init",
        "sec",
        "--listen-port",
        "70000",
        says=("70000", "1…65535"),
        untouched=("sec",),
    ),
    case(
        "security add: role already there",
        "security",
        "add",
        "secure",
        "--roles",
        "recorder",
        says=("role 'recorder' is already in secure", "not reissuing"),
        untouched=("secure",),
    ),
    case(
        "security add: no such folder",
        "security",
        "add",
        "nowhere",
        "--roles",
        "recorder-2",
        says=("nowhere does not exist or is not a folder",),
        untouched=("nowhere",),
    ),
    case("router: nothing to listen on", "router", says=("needs --zenoh-config FILE", "--listen EP")),
    case("router: zero duration", "router", "--duration", "0", *LOOPBACK, says=("duration = 0.0 s", "> 0 s")),
    case(
        "demo: negative speed",
        "demo",
        "--out",
        "dm",
        "--speed",
        "-1",
        says=("--speed -1.0", ">= 0"),
        untouched=("dm",),
    ),
    case(
        "cell: a launch file with an unknown key",
        "cell",
        "up",
        "bad-cell.toml",
        says=("bad-cell.toml", "unknown key(s) routers", "allowed: router, listen"),
        untouched=("logs",),
    ),
    case(
        "demo: a cell of more axes than processes fit",
        "demo",
        "--out",
        "dm",
        "--axes",
        "99",
        says=("--axes 99", "1…32"),
        untouched=("dm",),
    ),
    case(
        "demo: session folder not empty",
        "demo",
        "--out",
        "full",
        says=("full", "not empty"),
        untouched=("full",),
    ),
]


LONG = "x" * 300
"""a file name longer than any file system takes (255 bytes): ENAMETOOLONG wherever it is used"""

FILE_CASES = [
    # files: names too long, directories, links, one file named twice, earlier outputs, damaged chunks
    case(
        "record: a name too long",
        "record",
        "-o",
        f"{LONG}.mcap",
        "--duration",
        "1",
        says=(f"{LONG}.mcap cannot be written", "File name too long"),
    ),
    case(
        "view: a log name too long",
        "view",
        f"{LONG}.mcap",
        says=(f"recording {LONG}.mcap cannot be read", "File name too long"),
    ),
    case(
        "view: an output name too long",
        "view",
        "still.mcap",
        "-o",
        f"{LONG}.rrd",
        says=(f"output {LONG}.rrd cannot be written", "File name too long"),
    ),
    case(
        "view: a directory as the log",
        "view",
        "full",
        says=("recording full is a directory, not a file",),
        untouched=("full",),
    ),
    case(
        "view: the log as its output",
        "view",
        "still.mcap",
        "-o",
        "still.mcap",
        says=("output still.mcap must end in .rrd",),
    ),
    case(
        "view: the output a link to the log",
        "view",
        "still.mcap",
        "-o",
        "still-link.rrd",
        "--overwrite",
        says=("output still-link.rrd is the input still.mcap under another name", "never write over"),
    ),
    case(
        "view: the same log twice",
        "view",
        "still.mcap",
        "still-hard.mcap",
        says=("log still.mcap and log still-hard.mcap are the same file",),
    ),
    case(
        "view: an earlier view without --overwrite",
        "view",
        "viewed.mcap",
        says=("output viewed.rrd already exists", "--overwrite"),
        untouched=("viewed.rrd",),
    ),
    case(
        "identify: a log name too long",
        "identify",
        f"{LONG}.mcap",
        "--out",
        "ident",
        says=(f"recording {LONG}.mcap cannot be read", "File name too long"),
        untouched=("ident",),
    ),
    case(
        "identify: an output folder name too long",
        "identify",
        "still.mcap",
        "--out",
        LONG,
        says=(f"output directory {LONG} cannot be created", "File name too long"),
    ),
    case(
        "identify: a directory as the log",
        "identify",
        "full",
        "--out",
        "ident",
        says=("recording full is a directory, not a file",),
        untouched=("ident", "full"),
    ),
    case(
        "identify: the same log twice",
        "identify",
        "still.mcap",
        "still.mcap",
        "--out",
        "ident",
        says=("log still.mcap and log still.mcap are the same file",),
        untouched=("ident",),
    ),
    case(
        "identify: the same log twice, by a hard link",
        "identify",
        "still.mcap",
        "still-hard.mcap",
        "--out",
        "ident",
        says=("log still.mcap and log still-hard.mcap are the same file",),
        untouched=("ident",),
    ),
    case(
        "identify: the same log to fit and to validate, by a symbolic link",
        "identify",
        "still.mcap",
        "--validate",
        "still-link.mcap",
        "--out",
        "ident",
        says=("log still.mcap and log still-link.mcap are the same file",),
        untouched=("ident",),
    ),
    case(
        "identify: an earlier refit without --overwrite",
        "identify",
        "still.mcap",
        "--out",
        "refit",
        says=("refit/params.toml already exists", "--overwrite"),
        untouched=("refit",),
    ),
    case(
        "identify: every chunk damaged",
        "identify",
        "all-damaged.mcap",
        "--out",
        "ident",
        says=("all-damaged.mcap", "holds no message", "could not be read", "chunk 1 at byte 43"),
        untouched=("ident",),
    ),
    case(
        "table2: a log name too long",
        "table2",
        f"{LONG}.mcap",
        "--out",
        "t2",
        says=("cannot be read", "File name too long"),
        untouched=("t2",),
    ),
    case(
        "table2: a directory as the recording",
        "table2",
        "full",
        "--out",
        "t2",
        says=("recording full is a directory, not a file",),
        untouched=("t2", "full"),
    ),
    case(
        "table2: an earlier table without --overwrite",
        "table2",
        "still.mcap",
        "--out",
        "tables",
        says=("tables/table2.md already exists", "--overwrite"),
        untouched=("tables",),
    ),
    case(
        "recover: a name too long",
        "recover",
        f"{LONG}.mcap",
        says=("cannot be read", "File name too long"),
    ),
    case(
        "recover: an output name too long",
        "recover",
        "still.mcap",
        "-o",
        f"{LONG}.mcap",
        says=(f"output {LONG}.mcap cannot be written", "File name too long"),
    ),
    case(
        "recover: the output a symbolic link to the source, --overwrite",
        "recover",
        "still.mcap",
        "-o",
        "still-link.mcap",
        "--overwrite",
        says=("output still-link.mcap is the input still.mcap under another name", "never write over"),
    ),
    case(
        "recover: the output a hard link to the source, --overwrite",
        "recover",
        "still.mcap",
        "-o",
        "still-hard.mcap",
        "--overwrite",
        says=("output still-hard.mcap is the input still.mcap under another name", "never write over"),
    ),
    case(
        "recover: every chunk damaged",
        "recover",
        "all-damaged.mcap",
        says=("no complete message to recover", "chunk(s) could not be read", "chunk 1 at byte 43"),
        untouched=("all-damaged.recovered.mcap",),
    ),
    case(
        "replay: every chunk damaged",
        "replay",
        "all-damaged.mcap",
        "--no-wait",
        *LOOPBACK,
        says=("no complete message to replay", "chunk(s) could not be read"),
    ),
    case(
        "replay: a directory",
        "replay",
        "full",
        "--no-wait",
        *LOOPBACK,
        says=("recording full is a directory, not a file",),
    ),
    case(
        "figures: an output folder name too long",
        "figures",
        "--out",
        LONG,
        says=(f"output directory {LONG} cannot be created", "File name too long"),
    ),
    case(
        "figures: earlier figures without --overwrite",
        "figures",
        "--out",
        "figs",
        says=("figs/fig4a.png already exists", "--overwrite"),
        untouched=("figs",),
    ),
    case(
        "figures: a directory as the recording",
        "figures",
        "--out",
        "fg",
        "--recording",
        "full",
        says=("recording full is a directory, not a file",),
        untouched=("fg",),
    ),
    case(
        "experiment: an output folder name too long",
        "experiment",
        "--offline",
        "--out",
        LONG,
        says=(f"output directory {LONG} cannot be created", "File name too long"),
    ),
    case(
        "pareto: an output folder name too long",
        "pareto",
        "--out",
        LONG,
        says=(f"output directory {LONG} cannot be created", "File name too long"),
    ),
    case(
        "bridge: a Zenoh config name too long",
        "bridge",
        "--sim",
        "--zenoh-config",
        f"{LONG}.json5",
        says=(f"{LONG}.json5", "File name too long"),
    ),
    case(
        "security: a folder name too long",
        "security",
        "init",
        LONG,
        says=(LONG, "File name too long"),
    ),
]
CASES += FILE_CASES


def _recording(path: Path, *, schema: str = JOINT_STATE_TYPE, nan: bool = False, finish: bool = True) -> None:
    """A 2 s recording of /axisflow/a0/state: the axis at rest (or NaN torques in every other sample)."""
    writer = Ros2McapWriter(path)
    channel = writer.channel_for("/axisflow/a0/state", schema)
    for k in range(2000):
        torque = math.nan if nan and k % 2 else 0.05
        sample = AxisSample(T0_NS + k * 1_000_000, "a0", 0.4, 0.0, 12.0, 80.0, 0.0, torque)
        writer.add(channel, T0_NS + k * 1_000_000, T0_NS + k * 1_000_000, k + 1, sample.encode())
    if finish:
        writer.finish()


def _params_file(path: Path, **changes: object) -> None:
    data = default_params().to_dict()
    data.pop("M_eq")
    data.update(changes)
    path.write_text("".join(f"{k} = {v!r}\n".replace("'", '"') for k, v in data.items()))


@pytest.fixture(scope="module")
def inputs(tmp_path_factory, damage) -> Path:
    """The bad (and a few good) input files every case may name, in one folder."""
    d = tmp_path_factory.mktemp("inputs")
    _params_file(d / "unknown.toml", foo=1)
    _params_file(d / "negative.toml", m=-3.0)
    _params_file(d / "nan.toml", a1=math.nan)
    _params_file(d / "huge-mass.toml", m=1e308)
    _params_file(d / "stroke-mm.toml", L=800.0)
    _params_file(d / "weak-motor.toml", tau_max=0.25)
    _params_file(d / "fast-motor.toml", v_max=20.0, r=0.001)
    _params_file(d / "huge-friction.toml", a1=1e6)
    (d / "heavy-plant.toml").write_text("[scale]\nm = 1000.0\n")
    (d / "tiny.txt").write_text("0.1\n0.1\n1e-310\n5e-324\n0.4\n")
    (d / "garbage.toml").write_text("m = = 3\n[[[\n")
    (d / "bad.json5").write_text("{ mode: 'peer',\n")
    (d / "notes.txt").write_text("hello\n")
    (d / "far.state").write_bytes(struct.pack("<dd", 5.0, 0.0))  # x [m], v [m/s] as a bridge writes them
    (d / "fast.state").write_bytes(struct.pack("<dd", 0.4, 100.0))
    (d / "lossy-plant.toml").write_text('base = "realistic"\n[sample_clock]\ndrop_fraction = 0.9\n')
    (d / "outside.txt").write_text("0.1\n0.9\n")
    (d / "words.txt").write_text("0.1\nabc\n")
    (d / "one.txt").write_text("0.1\n")
    (d / "empty.mcap").write_bytes(b"")
    (d / "full").mkdir()
    (d / "full" / "keep.txt").write_text("a session\n")
    _recording(d / "still.mcap")
    (d / "bad-cell.toml").write_text(
        'router = "tcp/127.0.0.1:7447"\nrouters = 2\n[machine.a]\nrouter = true\n'
    )
    write_cell_log(
        d / "cell.mcap", [SyntheticLogSpec(duration_s=0.2, axis=f"a{k}", seed=k) for k in range(3)]
    )
    _recording(d / "existing.mcap")
    _recording(d / "wrong-schema.mcap", schema=MOVE_TYPE)
    _recording(d / "nan-samples.mcap", nan=True)
    (d / "truncated.mcap").write_bytes((d / "still.mcap").read_bytes()[:40])  # magic and header only
    init_security(SecurityPlan(d / "secure", days=2))
    (d / "still-link.mcap").symlink_to("still.mcap")
    (d / "still-link.rrd").symlink_to("still.mcap")
    os.link(d / "still.mcap", d / "still-hard.mcap")
    _recording(d / "viewed.mcap")
    (d / "viewed.rrd").write_text("an earlier view\n")
    for folder, name in (("refit", "params.toml"), ("tables", "table2.md"), ("figs", "fig4a.png")):
        (d / folder).mkdir()
        (d / folder / name).write_text("an earlier result\n")
    for k in range(len(damage.chunks(d / "still.mcap"))):  # every chunk's CRC wrong
        damage.damage(d / ("still.mcap" if k == 0 else "all-damaged.mcap"), d / "all-damaged.mcap", k, "crc")
    drive = "[drive]\nnode_id = {node}\nencoder_counts_per_rev = 131072\n{extra}"
    for name, can, node, extra in (
        ("drive-unknown", 'interface = "virtual"\nchannel = "bad-1"', 5, "speed = 3\n"),
        ("drive-node200", 'interface = "virtual"\nchannel = "bad-2"', 200, ""),
        ("drive-nope", 'interface = "pcan2"\nchannel = "x"', 5, ""),
        ("drive-socketcan", 'interface = "socketcan"\nchannel = "nocan7"', 5, ""),
        ("drive-nobody", 'interface = "virtual"\nchannel = "bad-nobody"', 9, 'pacing = "lockstep"\n'),
        ("drive-wall", 'interface = "virtual"\nchannel = "bad-3"', 5, 'pacing = "wall"\n'),
        ("drive-sock", 'interface = "socketcan"\nchannel = "nocan8"', 5, ""),
    ):
        (d / f"{name}.toml").write_text(f"[can]\n{can}\n" + drive.format(node=node, extra=extra))
    return d


def _snapshot(folder: Path, names: tuple[str, ...]) -> dict[str, bytes | None]:
    """The bytes of each file (a folder: its listing), None if absent."""
    out: dict[str, bytes | None] = {}
    for name in names:
        p = folder / name
        if p.is_dir():
            out[name] = "\n".join(sorted(str(q.relative_to(p)) for q in p.rglob("*"))).encode()
        else:
            out[name] = p.read_bytes() if p.exists() else None
    return out


def _error_line(err: str, command: str) -> str:
    """The one line of stderr, an error of ``axisflow COMMAND``."""
    lines = err.strip("\n").splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"axisflow {command}") and ": error: " in lines[0], err
    return lines[0]


@pytest.mark.parametrize("bad", CASES, ids=[c.id for c in CASES])
@pytest.mark.slow
def test_a_bad_input_is_one_line_exit_2_and_nothing_written(bad, inputs, tmp_path, capfd, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    for p in inputs.iterdir():  # what a case must not touch is a copy of its own; the rest, links
        if p.name in bad.untouched:
            _copy(p, work / p.name)
        else:
            (work / p.name).symlink_to(p)
    monkeypatch.chdir(work)
    before = _snapshot(work, bad.untouched)
    inputs_before, work_before = _tree(inputs), _tree(work)
    t0 = time.monotonic()
    try:
        code = main(list(bad.args))
    except SystemExit as exc:  # argparse
        code = exc.code
    elapsed = time.monotonic() - t0
    out, err = capfd.readouterr()
    assert code == 2, err
    assert "Traceback" not in err and out == ""
    line = _error_line(err, bad.args[0])
    for fragment in bad.says:
        assert fragment in line, line
    assert _snapshot(work, bad.untouched) == before
    assert _tree(inputs) == inputs_before  # every file that was there is byte-identical, nothing new
    assert _tree(work) == work_before  # nothing written, no stray temporary (.part) file
    assert elapsed < 10.0  # refused at once, not after the work


def _tree(folder: Path) -> dict[str, bytes | str]:
    """Every entry under ``folder``, links not followed: a file's bytes, a link's target, "/" for a
    folder."""
    out: dict[str, bytes | str] = {}
    for root, folders, files in os.walk(folder):
        for name in folders + files:
            p = Path(root) / name
            rel = str(p.relative_to(folder))
            if p.is_symlink():
                out[rel] = f"-> {os.readlink(p)}"
            elif p.is_dir():
                out[rel] = "/"
            else:
                out[rel] = p.read_bytes()
    return out


# a listen endpoint whose port another process holds: one line naming it, for every command that listens
PORT_IN_USE = [
    ("bridge", "--sim", "--duration", "1"),
    ("record", "-o", "new.mcap", "--duration", "1"),
    ("replay", "still.mcap", "--no-wait"),
    ("view", "--live", "-o", "new.rrd", "--duration", "1"),
    ("router",),
]


@pytest.mark.parametrize("args", PORT_IN_USE, ids=[a[0] for a in PORT_IN_USE])
def test_a_port_in_use_is_one_line_naming_it(args, inputs, tmp_path, capfd, monkeypatch):
    import socket

    monkeypatch.chdir(tmp_path)
    for name in ("still.mcap",):
        (tmp_path / name).symlink_to(inputs / name)
    with socket.socket() as holder:
        holder.bind(("127.0.0.1", 0))
        holder.listen()
        endpoint = f"tcp/127.0.0.1:{holder.getsockname()[1]}"
        code = main([*args, "--listen", endpoint])
    out, err = capfd.readouterr()
    assert code == 2 and out == "" and "Traceback" not in err, err
    line = _error_line(err, args[0])
    assert line == f"axisflow {args[0]}: error: {endpoint} is in use"  # no repr, no Rust source path
    assert sorted(p.name for p in tmp_path.iterdir()) == ["still.mcap"]  # nothing written


@pytest.mark.slow
def test_a_second_bridge_on_an_axis_is_refused_naming_where_the_first_runs(cli, port):
    first = cli.start("bridge", "--sim", "--listen", f"tcp/127.0.0.1:{port}", ready=True)
    cli.wait_ready(first)
    second = cli.run("bridge", "--sim", "--connect", f"tcp/127.0.0.1:{port}", "--duration", "5", timeout=60)
    assert second.returncode == 2 and second.stdout == "" and "Traceback" not in second.stderr
    line = _error_line(second.stderr, "bridge")
    for fragment in (
        "axis 'a0' already has a bridge (it holds axisflow/a0/alive)",
        f"pid {first.pid} on host ",
        f"reached at tcp/127.0.0.1:{port}",
        "give this bridge another --axis",
    ):
        assert fragment in line, line
    other_axis = cli.run(
        "bridge", "--sim", "--axis", "a1", "--connect", f"tcp/127.0.0.1:{port}", "--duration", "0.1"
    )
    assert other_axis.returncode == 0, other_axis.stderr  # another axis is free
    assert first.poll() is None  # the first runs on


def _copy(src: Path, dst: Path) -> None:
    import shutil

    if src.is_dir():
        shutil.copytree(src, dst)
    else:
        shutil.copy2(src, dst)


def test_the_catalogue_covers_every_command():
    from axisflow.cli import COMMAND_MODULES

    commands = {m.removesuffix("_cmd").replace("_", "-") for m in COMMAND_MODULES}
    assert commands <= {c.args[0] for c in CASES}
    assert len(CASES) >= 30


# ---- as real processes: the slips of the issue, and pipes --------------------------------------------


def _run(*args: str, cwd: Path, timeout: float = 60.0) -> subprocess.CompletedProcess:
    return subprocess.run([*CLI, *args], capture_output=True, text=True, timeout=timeout, cwd=cwd)


@pytest.mark.slow
def test_the_three_slips_of_the_issue_fail_at_once_as_processes(inputs, tmp_path):
    # a bridge that cannot connect used to run deaf and exit 0
    t0 = time.monotonic()
    bridge = _run("bridge", "--sim", "--connect", "tcp/999.1.1.1:1", "--duration", "1", cwd=tmp_path)
    assert bridge.returncode == 2 and bridge.stdout == "" and len(bridge.stderr.splitlines()) == 1, (
        bridge.stderr
    )
    assert "'999.1.1.1' is neither an IP address" in bridge.stderr
    # a replay of a file with no complete message used to report "replayed 0 messages", exit 0
    replay = _run("replay", str(inputs / "truncated.mcap"), "--no-wait", *LOOPBACK, cwd=tmp_path)
    assert replay.returncode == 2 and replay.stdout == "" and len(replay.stderr.splitlines()) == 1, (
        replay.stderr
    )
    assert "holds no complete message to replay" in replay.stderr
    # an experiment into /proc/x used to plan for ~20 s before failing
    t0 = time.monotonic()
    exp = _run("experiment", "--out", "/proc/x", cwd=tmp_path)
    assert exp.returncode == 2 and exp.stdout == "" and len(exp.stderr.splitlines()) == 1, exp.stderr
    assert "output directory /proc/x cannot be created: /proc is not writable" in exp.stderr
    assert time.monotonic() - t0 < 10.0  # the 100-way-point experiment takes ~20 s: it did not run
    assert not Path("/proc/x").exists()


@pytest.mark.parametrize(
    "args",
    [
        ("params",),
        ("plan", "0.1", "0.5", "--json"),
        ("--help",),
        ("excite", "--plan-only"),
        ("experiment", "--out", "exp", "--waypoints", "3", "--solver", "exact"),
    ],
    ids=["params", "plan", "help", "excite", "experiment"],
)
@pytest.mark.slow
def test_a_reader_that_goes_away_is_not_an_error(args, tmp_path):
    """``axisflow … | head -1``: the reader closes the pipe; here before the first write, so the command
    always meets the broken pipe (with head it may not, for output smaller than the pipe's buffer)."""
    proc = subprocess.Popen(
        [*CLI, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path
    )
    proc.stdout.close()
    err = proc.stderr.read()
    proc.stderr.close()
    assert proc.wait(60) == 0, err
    assert err == ""


def test_head_gets_the_first_line(tmp_path):
    done = subprocess.run(
        f"{sys.executable} -m axisflow params | head -1",
        shell=True,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.stdout.split()[:3] == ["m", "=", "90"] and done.stderr == ""


# ---- moves shorter than one encoder count: planned at once as zero moves, never a spin -------------


@pytest.mark.timeout(60)
@pytest.mark.parametrize("x1", ["1e-310", "1e-320", "5e-324", "1e-6"])
@pytest.mark.parametrize(
    ("law", "case_", "solver"),
    [
        ("poly5", "min-time", "exact"),
        ("poly3", "min-time-energy", "exact"),
        ("poly7", "min-time", "ipopt"),
        ("poly5", "min-time-energy", "ipopt"),
        ("bang", "min-time", "exact"),
        ("least-energy", "min-time-energy", "exact"),
    ],
)
def test_a_move_below_one_encoder_count_is_a_zero_move(x1, law, case_, solver, capfd):
    """The issue: ``plan 0 1e-310`` spun at 100 % CPU. One count is 2π·0.04 m/131072 = 1.917 µm."""
    code = main(["plan", "0", x1, "--law", law, "--case", case_, "--solver", solver, "--json"])
    out, err = capfd.readouterr()
    assert code == 0 and err == ""
    plan = json.loads(out)
    assert plan["duration_s"] == 0.0 and plan["energy_j"] == 0.0 and plan["objective"] == 0.0
    if law.startswith("poly"):
        assert plan["message"].startswith("zero move: |x1 - x0| = ") and "(1.917e-06 m)" in plan["message"]


@pytest.mark.timeout(60)
def test_the_issue_s_tiny_move_returns_at_once_as_a_process(tmp_path):
    done = _run("plan", "0", "1e-310", "--json", cwd=tmp_path, timeout=30)
    assert done.returncode == 0 and done.stderr == "", done.stderr
    assert json.loads(done.stdout)["duration_s"] == 0.0


@pytest.mark.timeout(120)
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
@pytest.mark.slow
@pytest.mark.heavy  # a bound in wall time: alone, not beside another test's processes
def test_the_planner_with_tiny_way_points_ends_within_2_s_of_a_signal(cli, tmp_path, sig):
    """Way points within a count of each other (zero moves, not sent) among real moves, on a bridge at
    real time: mid-run (a plan record seen), the signal ends the planner within 2 s."""
    import zenoh
    from axisflow.acquisition import AxisKeys, ZenohOptions, open_session

    port = cli.free_port()
    bridge = cli.start("bridge", "--sim", "--listen", f"tcp/127.0.0.1:{port}", "--speed", "1")
    points = tmp_path / "tiny.txt"
    points.write_text("0.1\n0.1\n0.1000000000001\n0.5\n5e-324\n1e-310\n0.6\n0.2\n0.7\n0.3\n0.7\n0.1\n")
    with open_session(ZenohOptions.loopback(connect_port=port)) as session:
        plans = session.declare_subscriber(AxisKeys("a0").plan, zenoh.handlers.FifoChannel(1000))
        planner = cli.start("planner", "--waypoints", str(points), "--connect", f"tcp/127.0.0.1:{port}")
        deadline = time.monotonic() + 60.0
        while plans.try_recv() is None:  # the fact: the planner is mid-run
            assert planner.poll() is None, cli.finish(planner)
            assert time.monotonic() < deadline, "no plan record within 60 s"
            time.sleep(0.02)
        plans.undeclare()
    t0 = time.monotonic()
    planner.send_signal(sig)
    try:
        planner.wait(timeout=2.0)
    except subprocess.TimeoutExpired:
        pytest.fail(f"the planner still ran 2 s after {sig.name}")
    elapsed = time.monotonic() - t0
    err = planner.stderr_text()
    bridge.send_signal(signal.SIGTERM)
    cli.finish(bridge)
    assert elapsed < 2.0
    assert "Traceback" not in err, err
    assert planner.returncode == 130, err


# ---- the page of refusals, docs/refusals.md: generated from this catalogue ------------------------------

REFUSALS_PAGE = Path(__file__).resolve().parents[2] / "docs" / "refusals.md"


def refusals_page() -> str:
    """docs/refusals.md as the catalogue says it (``python tools/write_refusals_page.py`` writes it)."""
    lines = [
        "# What axisflow refuses, and why",
        "",
        "Generated from the catalogue of bad inputs, `tests/cli/test_bad_input.py` (write it again with",
        "`python tools/write_refusals_page.py`; a test fails when it is out of date). Every input below is",
        "refused with exit code 2 and exactly one line on stderr, no traceback, nothing on stdout, and",
        "every file that existed before byte for byte what it was, with no stray temporary file; the",
        "test checks each of these, and that the line names what the last column lists (the value, the",
        "limit and its unit, where there are some). How the catalogue is run, and the faults injected",
        "beside it: [trust.md](trust.md).",
        "",
        f"{len(CASES)} inputs over {len({c.args[0] for c in CASES})} commands.",
    ]
    for command in sorted({c.args[0] for c in CASES}):
        lines += ["", f"## axisflow {command}", "", "| what | input | the line names |", "|---|---|---|"]
        for c in (c for c in CASES if c.args[0] == command):
            what = c.id.split(": ", 1)[-1]
            shown = " ".join(a if len(a) <= 40 else a[:37] + "…" for a in c.args)
            names = "; ".join(f"`{s}`" for s in c.says)
            row = [what, f"`axisflow {shown}`", names]
            lines.append(
                "| " + " | ".join(cell.replace("|", "\\|").replace("\n", " ") for cell in row) + " |"
            )
    return "\n".join(lines) + "\n"


def test_the_refusals_page_is_the_catalogue():
    assert REFUSALS_PAGE.read_text(encoding="utf-8") == refusals_page(), (
        "docs/refusals.md is out of date: run python tools/write_refusals_page.py"
    )
