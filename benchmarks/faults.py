"""Faults: the data path's processes killed, fuzzed, flooded and starved; what survives, counted.

Every scenario runs real processes — ``axisflow bridge --sim``, ``record``, ``planner``, ``recover`` as
subprocesses on free loopback ports — with real Zenoh sessions and real MCAP files, measures what
happened, and returns a result object: the numbers, the contract it checks (:attr:`Outcome.passed`)
and the command that reproduces it. tests/faults asserts on the same objects; ``axisflow bench
faults [--json]`` prints them as one table (docs/trust.md has a measured one).

===================  ==========================================================================
scenario             fault → what must hold
===================  ==========================================================================
``recorder_kill``    recorder SIGKILL mid-session → ≤ 1 s of the bridge's samples lost (flush +
                     fsync every second), ``axisflow recover`` gives a file rosbags and rerun open
``bridge_kill``      bridge SIGKILL mid-move → the recording so far complete; the recorder lists
                     the restarted bridge as a new publisher; the restart (same ``--plant-state``)
                     starts at rest where the axis coasted to
``planner_kill``     planner SIGKILL → its queued moves dropped, the axis at rest within [0, L]
                     (the test is tests/top/test_planner_restart.py)
``bad_payloads``     ≥ 1000 malformed, truncated, oversized, random payloads on the trajectory key
                     from a live sender and from a session that is not one → each rejected with a
                     reason; every tick recorded, 1 ms apart
``move_flood``       thousands of valid moves → the queue holds MAX_QUEUED_MOVES, the rest "queue
                     is full"; the bridge's memory flat; telemetry complete
``session_faults``   a full disk, a second recorder on the same file, 30 Zenoh peers coming and
                     going → a clear outcome each; the first recording complete
``quick_stop``       a quick stop at full speed → distance and time against the physical minimum
===================  ==========================================================================
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from axisflow.acquisition import (
    AxisKeys,
    MoveState,
    MoveStatus,
    ZenohOptions,
    is_complete,
    load_plant,
    open_session,
    read_joint_states,
)
from axisflow.benchmarks.pipeline import free_port
from axisflow.model import AxisflowError, AxisParams, default_params, stop_profile

CLI = [sys.executable, "-c", "import sys; from axisflow.cli import main; sys.exit(main())"]
ENV = {**os.environ, "CI": "1", "RUST_LOG": "error"}
KEYS = AxisKeys()
STATE_TOPIC = "/" + KEYS.state
SETPOINT_TOPIC = "/" + KEYS.setpoint
TICK_NS = 1_000_000
_F64 = struct.Struct("<d")
_U32 = struct.Struct("<I")
_PLANT_STATE = struct.Struct("<dd")
"""the plant state file of ``bridge --plant-state``: x [m], v [m/s] (acquisition/drives/sim_axis.py)"""


# ---- results ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Outcome:
    """One row of the fault table."""

    fault: str
    passed: bool
    outcome: str
    """what happened, with the measured numbers"""
    command: str
    """how to reproduce it"""
    measured: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return {
            "fault": self.fault,
            "passed": self.passed,
            "outcome": self.outcome,
            "command": self.command,
            "measured": self.measured,
        }


class FaultResult:
    """What a scenario measured; :meth:`outcomes` are its rows of the fault table."""

    def outcome(self) -> Outcome:
        raise NotImplementedError

    def outcomes(self) -> list[Outcome]:
        return [self.outcome()]


# ---- processes -------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Exited:
    """A finished process: its exit code and output."""

    returncode: int
    stdout: str
    stderr: str

    def json(self) -> dict[str, Any]:
        """The JSON object a ``--json`` command printed (a :class:`RuntimeError` with its exit code and
        stderr if it printed none: killed after a hang, or crashed)."""
        try:
            return json.loads(self.stdout)
        except json.JSONDecodeError:
            raise RuntimeError(
                f"exit code {self.returncode}, no JSON on stdout ({self.stdout[-300:]!r}); "
                f"stderr ends: {self.stderr[-1500:]}"
            ) from None


class Fleet:
    """The processes of one scenario (a context manager: every one still running is killed on exit).

    Output goes to files in ``work`` (never to pipes nobody reads: a bridge logging a thousand
    rejections must not block on a full pipe)."""

    def __init__(self, work: Path) -> None:
        self.work = work
        self._procs: list[tuple[subprocess.Popen, str]] = []

    def start(self, name: str, *args: str, fsize_limit: int | None = None) -> subprocess.Popen:
        """``axisflow ARGS`` in the background; ``fsize_limit``: RLIMIT_FSIZE [bytes] of the process (a
        disk that fills up; Python ignores SIGXFSZ, so a write past it fails with EFBIG)."""
        command = CLI
        if fsize_limit is not None:
            command = [
                sys.executable,
                "-c",
                "import resource, sys; "
                f"resource.setrlimit(resource.RLIMIT_FSIZE, ({fsize_limit}, {fsize_limit})); "
                "from axisflow.cli import main; sys.exit(main())",
            ]
        with open(self.work / f"{name}.out", "w") as out, open(self.work / f"{name}.err", "w") as err:
            proc = subprocess.Popen([*command, *args], stdout=out, stderr=err, env=ENV, cwd=self.work)
        self._procs.append((proc, name))
        return proc

    def wait(self, proc: subprocess.Popen, timeout_s: float = 30.0) -> Exited:
        """Wait for ``proc`` to exit (killed after ``timeout_s``: a hang is a failure, not a wait)."""
        try:
            proc.wait(timeout_s)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        name = next(n for p, n in self._procs if p is proc)
        return Exited(
            proc.returncode,
            (self.work / f"{name}.out").read_text(errors="replace"),
            (self.work / f"{name}.err").read_text(errors="replace"),
        )

    def run(self, name: str, *args: str, timeout_s: float = 60.0, fsize_limit: int | None = None) -> Exited:
        """``axisflow ARGS`` to its end (see :meth:`start` and :meth:`wait`)."""
        return self.wait(self.start(name, *args, fsize_limit=fsize_limit), timeout_s)

    def stop(self, proc: subprocess.Popen, timeout_s: float = 30.0) -> Exited:
        """SIGINT (a clean stop: summary, footer) and wait."""
        proc.send_signal(signal.SIGINT)
        return self.wait(proc, timeout_s)

    def __enter__(self) -> Fleet:
        return self

    def __exit__(self, *_exc: object) -> None:
        for proc, _name in self._procs:
            if proc.poll() is None:
                proc.kill()
                proc.wait()


def _listens(port: int) -> bool:
    with socket.socket() as s:
        return s.connect_ex(("127.0.0.1", port)) == 0


def rss_mb(pid: int) -> float:
    """Resident set size of process ``pid`` [MB] (from /proc/<pid>/status)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    raise RuntimeError(f"no VmRSS for process {pid}")


def wait_until(predicate: Callable[[], bool], timeout_s: float, poll_s: float = 0.02) -> bool:
    deadline = time.monotonic() + timeout_s
    while not predicate():
        if time.monotonic() >= deadline:
            return False
        time.sleep(poll_s)
    return True


# ---- a bridge and a recorder on loopback -----------------------------------------------------------


class Rig:
    """A recorder (listening) and bridges (connecting to it, each listening on a port of its own) as
    processes, and the Zenoh options for this process's own sessions (connected to both)."""

    def __init__(self, fleet: Fleet, name: str) -> None:
        self.fleet = fleet
        self.recording = fleet.work / f"{name}.mcap"
        self.recorder_port = free_port()
        self.bridge_ports: list[int] = []

    @property
    def recorder_endpoint(self) -> str:
        return f"tcp/127.0.0.1:{self.recorder_port}"

    def start_recorder(self, *extra: str) -> subprocess.Popen:
        """``axisflow record`` of ``axisflow/**`` into :attr:`recording`, started before the bridge."""
        proc = self.fleet.start(
            "recorder",
            "record",
            "-o",
            str(self.recording),
            "--listen",
            self.recorder_endpoint,
            "--json",
            *extra,
        )
        if not wait_until(lambda: _listens(self.recorder_port) or proc.poll() is not None, 30.0):
            raise RuntimeError(f"the recorder did not listen on {self.recorder_endpoint} within 30 s")
        if proc.poll() is not None:
            raise RuntimeError(f"the recorder exited: {self.fleet.wait(proc).stderr.strip()}")
        return proc

    def start_bridge(self, name: str = "bridge", *extra: str) -> subprocess.Popen:
        """``axisflow bridge --sim --json`` at 1× real time, waiting for the recorder's subscription."""
        self.bridge_ports.append(free_port())
        return self.fleet.start(
            name,
            "bridge",
            "--sim",
            "--json",
            "--wait-subscribers",
            "10",
            "--connect",
            self.recorder_endpoint,
            "--listen",
            f"tcp/127.0.0.1:{self.bridge_ports[-1]}",
            *extra,
        )

    def options(self) -> ZenohOptions:
        """A peer of this process, connected to the recorder (it learns the bridges by gossip)."""
        return ZenohOptions(mode="peer", connect=(self.recorder_endpoint,))


class StatusWatch:
    """The move statuses a bridge publishes on ``<prefix>/<axis>/event``, as typed records."""

    def __init__(self, session: Any, keys: AxisKeys = KEYS) -> None:
        import zenoh

        self._sub = session.declare_subscriber(keys.event, zenoh.handlers.FifoChannel(1 << 18))
        self.statuses: list[MoveStatus] = []

    def drain(self) -> list[MoveStatus]:
        while (sample := self._sub.try_recv()) is not None:
            self.statuses.append(MoveStatus.decode(sample.payload.to_bytes()))
        return self.statuses

    def count(self, state: MoveState, sender: str | None = None) -> int:
        self.drain()
        return sum(s.state is state and (sender is None or s.sender == sender) for s in self.statuses)

    def wait(self, state: MoveState, count: int, timeout_s: float, sender: str | None = None) -> bool:
        return wait_until(lambda: self.count(state, sender) >= count, timeout_s)

    def close(self) -> None:
        self._sub.undeclare()


def require_bridge(session: Any, timeout_s: float = 30.0, keys: AxisKeys = KEYS) -> None:
    """Return once a bridge holds its liveliness token ``<prefix>/<axis>/alive``; a
    :class:`RuntimeError` (the scenario cannot run) if none does within ``timeout_s``."""
    if not wait_until(lambda: bool(list(session.liveliness().get(keys.alive, timeout=1.0))), timeout_s, 0.1):
        raise RuntimeError(f"the bridge did not come up within {timeout_s:g} s")


@dataclass(frozen=True)
class Stalls:
    """How late the ticks of a stretch of drive time started."""

    ticks: int
    late: int
    """ticks that started more than a period (1 ms) after their deadline"""
    max_ms: float
    """the latest tick start [ms after its deadline]"""

    def __str__(self) -> str:
        return f"{self.late} of {self.ticks} ticks late, longest stall {self.max_ms:.1f} ms"


@dataclass(frozen=True, eq=False)
class TickRecord:
    """The 1 kHz samples of one topic in a recording, split by publisher (a restarted bridge numbers
    its samples from 1 again).

    A sample's ``publish_time`` is the wall time at which the bridge published it and its header stamp
    the tick's drive time, which at 1× real time advances with the wall clock: publish − stamp, less
    its median, is how late that tick ran (:attr:`late_ns`) — a tick-by-tick record of the loop's
    timing, from the file alone."""

    runs: tuple[tuple[int, int, int, int], ...]
    """per publisher, in file order: (messages, first sequence, last sequence, first stamp [ns])"""
    bad_steps: int
    """consecutive samples of one publisher whose stamps are not exactly 1 ms apart"""
    sequence_gaps: int
    """sequence numbers skipped within one publisher"""
    misplaced: int
    """consecutive samples of one publisher whose stamp step is not their sequence step × 1 ms (a
    sample out of order, doubled or mislabelled; a lost one is a sequence gap, not this)"""
    last_stamp_ns: tuple[int, ...]
    """per publisher, its last stamp [ns]"""
    stamp_ns: np.ndarray
    late_ns: np.ndarray
    """per sample, how late its tick ran [ns] (see the class docstring)"""
    position_m: np.ndarray
    velocity_m_s: np.ndarray
    """the carriage joint of each sample"""

    @property
    def messages(self) -> int:
        return sum(r[0] for r in self.runs)

    @property
    def contiguous(self) -> bool:
        """No tick missing between the first and the last of each publisher: no sequence gap, stamps
        exactly 1 ms apart."""
        return bool(self.runs) and self.bad_steps == 0 and self.sequence_gaps == 0

    @property
    def consistent(self) -> bool:
        """Every sample where its sequence number puts it (lost samples allowed: see ``sequence_gaps``)."""
        return bool(self.runs) and self.misplaced == 0

    @property
    def every_tick(self) -> bool:
        """Every tick there, once, in order, from each publisher's first: :attr:`contiguous` and the
        sequences start at 1."""
        return self.contiguous and all(r[1] == 1 for r in self.runs)

    def stalls(self, t0_ns: int | None = None, t1_ns: int | None = None) -> Stalls:
        """Late ticks between drive times ``t0_ns`` and ``t1_ns`` (default: all)."""
        keep = np.ones(len(self.stamp_ns), bool)
        if t0_ns is not None:
            keep &= self.stamp_ns >= t0_ns
        if t1_ns is not None:
            keep &= self.stamp_ns < t1_ns
        late = self.late_ns[keep]
        return Stalls(int(late.size), int(np.count_nonzero(late > TICK_NS)), float(late.max(initial=0)) / 1e6)


def tick_record(path: Path, topic: str = STATE_TOPIC) -> TickRecord:
    """:class:`TickRecord` of ``topic`` in ``path`` (complete or cut off by a crash)."""
    cols = read_joint_states(path, topic)
    seq = cols.sequence.astype(np.int64)
    stamps = cols.stamp_ns.astype(np.int64)
    delay = cols.publish_time_ns.astype(np.int64) - stamps
    late = np.empty_like(delay)
    starts = [0, *(np.flatnonzero(np.diff(seq) < 0) + 1).tolist(), len(seq)]
    runs, last, bad, gaps, misplaced = [], [], 0, 0, 0
    for a, b in itertools.pairwise(starts):
        if a == b:
            continue
        s, t = seq[a:b], stamps[a:b]
        runs.append((b - a, int(s[0]), int(s[-1]), int(t[0])))
        last.append(int(t[-1]))
        bad += int(np.count_nonzero(np.diff(t) != TICK_NS))
        gaps += int(np.sum(np.maximum(np.diff(s) - 1, 0)))
        misplaced += int(np.count_nonzero(np.diff(t) != np.diff(s) * TICK_NS))
        late[a:b] = delay[a:b] - np.median(delay[a:b])
    carriage = cols.joint("carriage")
    return TickRecord(
        tuple(runs), bad, gaps, misplaced, tuple(last), stamps, late, carriage.position, carriage.velocity
    )


def phase_stalls(state: TickRecord, marks: dict[str, int]) -> dict[str, Stalls]:
    """:meth:`TickRecord.stalls` between consecutive ``marks`` (name → wall time [ns] its phase began;
    the last mark ends the last phase)."""
    edges = list(marks.values())
    return {name: state.stalls(t0, t1) for name, t0, t1 in zip(marks, edges, edges[1:], strict=False)}


def true_axis(nominal: AxisParams | None = None) -> AxisParams:
    """The simulated plant's true parameters (the packaged plant file on the nominal ones)."""
    return load_plant(None, nominal or default_params()).axis


# ---- bad payloads on the trajectory key -----------------------------------------------------------


@dataclass(frozen=True)
class BadPayload:
    """A payload no bridge may run; ``reason`` is a fragment of the rejection it must get ("" when
    any reason will do: random bytes fail wherever they fail)."""

    kind: str
    """named (a catalogued case), random, truncated, flipped or oversized"""
    name: str
    data: bytes
    move_id: int = 0
    """the move id it carries when it decodes (0 otherwise)"""
    reason: str = ""


def _patched(data: bytes, old: bytes, new: bytes) -> bytes:
    """``data`` with the one occurrence of ``old`` replaced by ``new`` (same length)."""
    if data.count(old) != 1 or len(old) != len(new):
        raise ValueError("the field to patch must occur exactly once")
    return data.replace(old, new)


class PayloadCatalog:
    """Bad payloads for the trajectory key of an axis resting at ``hold_m`` (seeded).

    The named cases are moves that break one rule each (law, duration, stroke, limits, timing, axis,
    encoding, knots, size), built from a valid move that starts where the axis rests so that the rule
    is what rejects them. The generated ones — random bytes, valid moves cut short, valid moves with
    bytes flipped — are kept only if they cannot be a move the bridge would run (checked here with
    the bridge's own decoder and validation: either fails, or the move starts more than 1 mm from the
    axis and so jumps)."""

    STAMP_NS = 1_800_000_000_000_000_000
    """the send stamp of every move (fixed: a seed gives the same bytes)"""
    SENTINEL = 0.123456789012345
    """a float whose bytes are found and replaced in an encoded move (NaN and inf cannot be encoded)"""

    def __init__(self, params: AxisParams, hold_m: float, seed: int = 0, axis: str = KEYS.axis) -> None:
        self.params = params
        self.hold_m = hold_m
        self.axis = axis
        self.rng = np.random.default_rng(seed)
        self._next_id = 1000

    # -- building moves
    def move(self, **changes: Any) -> Any:
        """A valid 1 s poly5 move from the rest position (``changes`` override its fields), with a
        fresh move id."""
        from axisflow.acquisition.wire.messages import MoveCommand

        fields_ = {
            "stamp_ns": self.STAMP_NS,
            "axis": self.axis,
            "move_id": self._next_id,
            "start_ns": 0,
            "law": "poly5",
            "start_position_m": self.hold_m,
            "end_position_m": min(self.hold_m + 0.1, self.params.L),
            "duration_s": 1.0,
        }
        self._next_id += 1
        return MoveCommand(**{**fields_, **changes})

    def sampled(self, n: int, duration_s: float = 2.0, **arrays: np.ndarray) -> Any:
        """A sampled move of ``n`` knots at rest at ``hold_m`` (``arrays`` override t_s, position_m,
        velocity_m_s, acceleration_m_s2)."""
        from axisflow.acquisition.wire.messages import SAMPLED_LAW, Knots

        knots = {
            "t_s": np.linspace(0.0, duration_s, n),
            "position_m": np.full(n, self.hold_m),
            "velocity_m_s": np.zeros(n),
            "acceleration_m_s2": np.zeros(n),
        } | arrays
        k = Knots(knots["t_s"], knots["position_m"], knots["velocity_m_s"], knots["acceleration_m_s2"])
        t = np.asarray(knots["t_s"])
        x = np.asarray(knots["position_m"])
        return self.move(
            law=SAMPLED_LAW,
            knots=k,
            duration_s=float(t[-1]) if t.size else duration_s,
            start_position_m=float(x[0]) if x.size else self.hold_m,
            end_position_m=float(x[-1]) if x.size else self.hold_m,
        )

    def excursion(self, n: int, duration_s: float) -> Any:
        """A slow sampled move of ``n`` knots from the rest position out to 0.1 m beyond the stroke
        and back, x = x0 + A·sin²(πt/T), within v_max and tau_max: only its path breaks a rule."""
        t = np.linspace(0.0, duration_s, n)
        w = np.pi / duration_s
        amplitude = self.params.L + 0.1 - self.hold_m
        x = self.hold_m + amplitude * np.sin(w * t) ** 2
        v = amplitude * w * np.sin(2.0 * w * t)
        a = 2.0 * amplitude * w * w * np.cos(2.0 * w * t)
        v[0] = v[-1] = 0.0
        x[-1] = self.hold_m
        return self.sampled(n, duration_s, t_s=t, position_m=x, velocity_m_s=v, acceleration_m_s2=a)

    def named(self, oversized: bool = True) -> list[BadPayload]:
        """The catalogued cases; with ``oversized`` also a 10 MB random payload and sampled moves of 2
        and 3.6 million knots (64 and 115 MB)."""
        out = self._bad_moves() + self._bad_encodings() + self._bad_knots()
        return out + self.oversized() if oversized else out

    def _bad_moves(self) -> list[BadPayload]:
        """Moves that decode but break one rule of the validation or of the queue."""
        x0, L = self.hold_m, self.params.L
        cases = [
            ("unknown law poly9", self.move(law="poly9"), "poly9"),
            ("empty law", self.move(law=""), "law"),
            ("law sampled without knots", self.move(law="sampled"), "needs knots"),
            ("law poly5 with knots", replace(self.sampled(5), law="poly5"), "takes no knots"),
            ("duration 0 s", self.move(duration_s=0.0), "duration"),
            ("duration -1 s", self.move(duration_s=-1.0), "duration"),
            ("duration 1e9 s", self.move(duration_s=1e9), "duration"),
            ("end beyond the stroke", self.move(end_position_m=L + 0.15), "outside the stroke"),
            ("end below 0 m", self.move(end_position_m=-0.1), "outside the stroke"),
            ("too fast for v_max", self.move(end_position_m=L, duration_s=0.3), "exceeds v_max"),
            ("too short for tau_max", self.move(end_position_m=x0 + 0.05, duration_s=0.1), "tau_max"),
            ("another axis", self.move(axis="a1"), "addressed to axis"),
            ("timed start in 1970", self.move(start_ns=1_000_000_000), "before the end of the queued"),
            (
                "start 0.4 m from the axis",
                self.move(start_position_m=x0 + 0.4, end_position_m=x0 + 0.3),
                "jumps",
            ),
        ]
        out = [BadPayload("named", name, cmd.encode(), cmd.move_id, reason) for name, cmd, reason in cases]
        for name, value in (
            ("start_position_m", float("nan")),
            ("end_position_m", float("inf")),
            ("duration_s", float("nan")),
            ("duration_s", float("-inf")),
        ):
            out.append(
                BadPayload("named", f"{name} = {value}", self._with_float(name, value), 0, "not finite")
            )
        return out

    def _with_float(self, name: str, value: float) -> bytes:
        """An encoded move whose field ``name`` is ``value`` (which the encoder refuses to write)."""
        cmd = self.move(**{name: self.SENTINEL})
        return _patched(cmd.encode(), _F64.pack(self.SENTINEL), _F64.pack(value))

    def _bad_encodings(self) -> list[BadPayload]:
        """Bytes that are no ``axisflow_msgs/msg/Move`` (a valid move's encoding, damaged)."""
        good = self.move().encode()
        # layout: CDR header 0:4, stamp sec 4:8, nanosec 8:12, axis length 12:16, …, 4 empty knot
        # arrays (a uint32 count each) in the last 16 bytes
        law_at = good.index(b"poly5")
        cases = [
            ("empty payload", b"", "CDR_LE"),
            ("only the CDR header", good[:4], "truncated"),
            ("big-endian CDR header", b"\x00\x00" + good[2:], "CDR_LE"),
            ("stamp nanosec = 2e9", good[:8] + _U32.pack(2_000_000_000) + good[12:], "nanosec"),
            ("axis string 4 GiB long", good[:12] + _U32.pack(0xFFFFFFFF) + good[16:], "truncated"),
            ("knot count 2^32 - 1", good[:-16] + _U32.pack(0xFFFFFFFF) + good[-12:], "exceeds"),
            ("law not UTF-8", good[:law_at] + b"\xff\xfe\xfd\xfc\xfb" + good[law_at + 5 :], "UTF-8"),
        ]
        return [BadPayload("named", name, data, 0, reason) for name, data, reason in cases]

    def _bad_knots(self) -> list[BadPayload]:
        """Sampled moves whose knots break a rule."""
        n = 50
        t = np.linspace(0.0, 2.0, n)
        t_repeat = t.copy()
        t_repeat[10] = t_repeat[9]
        moving_end = np.r_[np.zeros(n - 1), 0.1]
        cases = [
            ("knot arrays of different lengths", self.sampled(n, velocity_m_s=np.zeros(n - 1)), "differ"),
            ("knot times not increasing", self.sampled(n, t_s=t_repeat), "must increase"),
            ("knots not at rest at the end", self.sampled(n, velocity_m_s=moving_end), "at rest"),
            ("knots beyond the stroke", self.excursion(n, 20.0), "outside the stroke"),
            ("a NaN knot", self.sampled(n, acceleration_m_s2=np.r_[np.zeros(n - 1), np.nan]), "not finite"),
            ("one knot", self.sampled(1), "knots"),
        ]
        return [BadPayload("named", name, cmd.encode(), cmd.move_id, reason) for name, cmd, reason in cases]

    def oversized(self) -> list[BadPayload]:
        """A 10 MB random payload, a sampled move of 2 000 000 knots (64 MB, a legal size) whose path
        leaves the stroke, and one of 4 000 000 knots (128 MB, beyond the largest move)."""
        long_move = self.excursion(2_000_000, 2000.0)
        too_many = self.sampled(4_000_000, 3600.0)
        return [
            BadPayload("oversized", "10 MB of random bytes", self.rng.bytes(10_000_000), 0, "CDR_LE"),
            BadPayload(
                "oversized",
                "2 000 000 knots (64 MB) leaving the stroke",
                long_move.encode(),
                long_move.move_id,
                "outside the stroke",
            ),
            BadPayload("oversized", "4 000 000 knots (128 MB)", too_many.encode(), 0, "exceeds the largest"),
        ]

    # -- generated cases
    def could_run(self, data: bytes) -> bool:
        """Whether the bridge might run ``data``: it decodes, passes the validation and starts within
        1 mm of the axis."""
        from axisflow.acquisition.bridge.move_queue import validate_move
        from axisflow.acquisition.errors import AcquisitionError
        from axisflow.acquisition.wire.messages import MoveCommand

        try:
            cmd = MoveCommand.decode(data)
            validate_move(cmd, self.params, self.axis)
        except AcquisitionError:
            return False
        return abs(cmd.start_position_m - self.hold_m) <= 1e-3

    def generated(self, count: int) -> list[BadPayload]:
        """``count`` random, truncated and byte-flipped payloads (a third each), none of which the
        bridge may run."""
        out: list[BadPayload] = []
        makers = (self._random, self._truncated, self._flipped)
        while len(out) < count:
            kind, data = makers[len(out) % 3]()
            if not self.could_run(data):
                out.append(BadPayload(kind, kind, data))
        return out

    def _random(self) -> tuple[str, bytes]:
        data = self.rng.bytes(int(self.rng.integers(0, 400)))
        return "random", (b"\x00\x01\x00\x00" + data if self.rng.random() < 0.5 else data)

    def _truncated(self) -> tuple[str, bytes]:
        move = self.rng.random() < 0.5
        good = (self.move(start_position_m=0.5, end_position_m=0.6) if move else self.sampled(20)).encode()
        return "truncated", good[: int(self.rng.integers(0, len(good)))]

    def _flipped(self) -> tuple[str, bytes]:
        data = bytearray(self.move(start_position_m=0.5, end_position_m=0.6).encode())
        for _ in range(int(self.rng.integers(1, 5))):
            data[int(self.rng.integers(0, len(data)))] ^= int(self.rng.integers(1, 256))
        return "flipped", bytes(data)


class RawSender:
    """Puts raw bytes on an axis's trajectory key, numbered like every publisher. ``live``: it also
    holds a move sender's liveliness token, as :class:`~axisflow.acquisition.MoveSender` does, so the
    bridge treats it as a live sender; ``attachment`` False: plain puts with no attachment at all."""

    def __init__(self, session: Any, live: bool, attachment: bool = True, keys: AxisKeys = KEYS) -> None:
        from axisflow.acquisition.bus.publisher import SequencedPublisher, Traffic
        from axisflow.acquisition.wire.messages import MOVE_TYPE

        self._session, self._key = session, keys.trajectory
        self._pub = SequencedPublisher(session, keys.trajectory, MOVE_TYPE, Traffic.COMMAND)
        self._attachment = attachment
        self._token = session.liveliness().declare_token(keys.sender(self._pub.gid)) if live else None
        self.sent = 0

    @property
    def sender_id(self) -> str:
        """How the bridge's statuses name this sender ("" without attachment)."""
        return self._pub.gid.hex() if self._attachment else ""

    def put(self, payload: bytes) -> None:
        if self._attachment:
            self._pub.put(payload)
        else:
            self._session.put(self._key, payload)
        self.sent += 1

    def close(self) -> None:
        if self._token is not None:
            self._token.undeclare()
        self._pub.undeclare()


class RssSampler:
    """The resident memory of a process [MB], sampled on a thread every ``period_s``."""

    def __init__(self, pid: int, period_s: float = 0.05) -> None:
        import threading

        self.pid, self.period_s = pid, period_s
        self.samples: list[tuple[float, float]] = []
        """(monotonic time [s], RSS [MB])"""
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                self.samples.append((time.monotonic(), rss_mb(self.pid)))
            except (OSError, RuntimeError):
                return  # the process is gone
            self._stop.wait(self.period_s)

    def between(self, t0: float, t1: float) -> list[float]:
        return [mb for t, mb in self.samples if t0 <= t <= t1]

    @property
    def peak_mb(self) -> float:
        return max((mb for _t, mb in self.samples), default=float("nan"))

    def __enter__(self) -> RssSampler:
        self._thread.start()
        return self

    def __exit__(self, *_exc: object) -> None:
        self._stop.set()
        self._thread.join()


@dataclass(frozen=True)
class RunEnd:
    """How the bridge and the recorder of a :class:`Rig` ended (both stopped with SIGINT)."""

    bridge: Exited
    recorder: Exited
    state: TickRecord
    setpoint: TickRecord
    complete: bool
    """the recording has its summary and footer"""

    @property
    def report(self) -> dict[str, Any]:
        return self.bridge.json()

    @property
    def summary(self) -> dict[str, Any]:
        return self.recorder.json()

    @property
    def telemetry_intact(self) -> bool:
        """Both processes exited 0 and every tick the bridge ran is in the file, once, 1 ms apart."""
        ticks = self.report["ticks"]
        return (
            self.bridge.returncode == 0
            and self.recorder.returncode == 0
            and self.complete
            and self.state.every_tick
            and self.setpoint.every_tick
            and self.state.messages == ticks == self.setpoint.messages
        )

    def timing(self) -> str:
        r = self.report
        j = r["period_jitter"] or {}
        return (
            f"{r['ticks']} ticks, {r['late_ticks']} late by more than a period, period jitter p99 "
            f"{j.get('p99_us', float('nan')):.0f} µs, max {j.get('max_us', float('nan')) / 1e3:.1f} ms"
        )


def stop_rig(fleet: Fleet, rig: Rig, bridge: subprocess.Popen, recorder: subprocess.Popen) -> RunEnd:
    """SIGINT the bridge, then the recorder (after the last samples arrived); read the recording."""
    bridge_end = fleet.stop(bridge)
    time.sleep(0.3)
    recorder_end = fleet.stop(recorder, 60.0)
    complete = is_complete(rig.recording)
    return RunEnd(
        bridge_end,
        recorder_end,
        tick_record(rig.recording, STATE_TOPIC),
        tick_record(rig.recording, SETPOINT_TOPIC),
        complete,
    )


@dataclass(frozen=True)
class BadPayloadResult(FaultResult):
    sent: dict[str, int]
    """payloads per sender: live (holds a sender token), not live, no attachment"""
    rejected: dict[str, int]
    """REJECTED move statuses per sender"""
    other_statuses: int
    """statuses that are not REJECTED (accepted, started…): must be 0"""
    without_reason: int
    """REJECTED statuses whose text gives no reason"""
    wrong_reason: list[str]
    """catalogued cases whose rejection does not say what they break"""
    largest_payload_mb: float
    answer_s: dict[str, float]
    """per phase (fuzz, oversized): from its first payload sent to its last rejection received [s]"""
    stalls: dict[str, Stalls]
    """per phase (quiet: nothing sent yet; fuzz; oversized): the ticks' lateness, from the recording"""
    bridge_rss_mb: dict[str, float]
    """the bridge's RSS before the payloads and its peak"""
    end: RunEnd

    @property
    def total(self) -> int:
        return sum(self.sent.values())

    @property
    def passed(self) -> bool:
        r = self.end.report
        return (
            self.rejected == self.sent
            and self.other_statuses == 0
            and self.without_reason == 0
            and not self.wrong_reason
            and r["moves_rejected"] == self.total
            and r["moves_accepted"] == 0
            and self.end.telemetry_intact
        )

    def outcome(self) -> Outcome:
        r = self.end.report
        phases = "; ".join(f"{name}: {st}" for name, st in self.stalls.items())
        return Outcome(
            f"{self.total} bad payloads on the trajectory key",
            self.passed,
            f"{', '.join(f'{k} {v}' for k, v in self.sent.items())} "
            f"(largest {self.largest_payload_mb:.0f} MB): "
            f"{sum(self.rejected.values())} REJECTED statuses with a reason, bridge moves_rejected "
            f"{r['moves_rejected']}, accepted {r['moves_accepted']}; answered in "
            f"{self.answer_s['fuzz']:.1f} s (fuzz) and {self.answer_s.get('oversized', 0.0):.1f} s "
            f"(oversized); all {self.end.state.messages} ticks recorded 1 ms apart: "
            f"{self.end.state.every_tick}; {phases}; "
            f"bridge late_ticks {r['late_ticks']}, RSS {self.bridge_rss_mb['before']:.0f} → peak "
            f"{self.bridge_rss_mb['peak']:.0f} MB",
            "axisflow bench faults --only bad_payloads",
            {
                "sent": self.sent,
                "rejected": self.rejected,
                "other_statuses": self.other_statuses,
                "wrong_reason": self.wrong_reason,
                "answer_s": self.answer_s,
                "stalls": {k: vars(v) for k, v in self.stalls.items()},
                "bridge_rss_mb": self.bridge_rss_mb,
                "bridge": {k: v for k, v in r.items() if k != "rejections"},
                "state_samples": self.end.state.messages,
            },
        )


def bad_payloads(
    work: Path, per_sender: int = 1000, oversized: bool = True, seed: int = 0
) -> BadPayloadResult:
    """Fault 4: into a bridge at 1× real time, recorded: 1 s of quiet, then ``per_sender`` bad payloads
    from a live sender and as many from a sender without a token (and 24 with no attachment), then the
    oversized ones from the live sender; each phase ends when every payload is answered."""
    params = default_params()
    catalog = PayloadCatalog(params, hold_m=load_plant(None, params).simulation.initial_position_m, seed=seed)
    fuzz = {name: catalog.named(oversized=False) for name in ("live sender", "no sender token")}
    for payloads in fuzz.values():
        payloads += catalog.generated(per_sender - len(payloads))
    fuzz["no attachment"] = catalog.generated(24)
    big = catalog.oversized() if oversized else []
    with Fleet(work) as fleet:
        rig = Rig(fleet, "bad-payloads")
        recorder = rig.start_recorder()
        bridge = rig.start_bridge()
        with open_session(rig.options()) as session, RssSampler(bridge.pid) as rss:
            require_bridge(session)
            watch = StatusWatch(session)
            senders = {
                "live sender": RawSender(session, live=True),
                "no sender token": RawSender(session, live=False),
                "no attachment": RawSender(session, live=False, attachment=False),
            }
            marks = {"quiet": time.time_ns()}
            time.sleep(1.0)
            before_mb = rss.samples[-1][1]
            answer_s = {}
            for phase, batches in (("fuzz", fuzz), ("oversized", {"live sender": big})):
                marks[phase] = time.time_ns()
                for name, payloads in batches.items():
                    for p in payloads:
                        senders[name].put(p.data)
                watch.wait(MoveState.REJECTED, sum(s.sent for s in senders.values()), timeout_s=120.0)
                answer_s[phase] = (time.time_ns() - marks[phase]) * 1e-9
            marks["end"] = time.time_ns()
            time.sleep(0.6)  # anything after the last rejection (there must be nothing)
            statuses = list(watch.drain())
            watch.close()
            for sender in senders.values():
                sender.close()
        end = stop_rig(fleet, rig, bridge, recorder)
    stalls = phase_stalls(end.state, marks)
    live = senders["live sender"].sender_id
    return BadPayloadResult(
        sent={name: s.sent for name, s in senders.items()},
        rejected={name: _rejected(statuses, s.sender_id) for name, s in senders.items()},
        other_statuses=sum(st.state is not MoveState.REJECTED for st in statuses),
        without_reason=sum(not st.text.partition(": ")[2].strip() for st in statuses),
        wrong_reason=_wrong_reasons(fuzz["live sender"] + big, statuses, live),
        largest_payload_mb=max(len(p.data) for p in fuzz["live sender"] + big) / 1e6,
        answer_s=answer_s,
        stalls=stalls,
        bridge_rss_mb={"before": before_mb, "peak": rss.peak_mb},
        end=end,
    )


def _rejected(statuses: list[MoveStatus], sender: str) -> int:
    return sum(s.sender == sender and s.state is MoveState.REJECTED for s in statuses)


def _wrong_reasons(payloads: list[BadPayload], statuses: list[MoveStatus], sender: str) -> list[str]:
    """The catalogued payloads of ``sender`` whose rejection lacks the reason they were built for: by
    move id where they carry one, else (undecodable: answered as move 0) among that sender's move-0
    rejections."""
    rejected = [s for s in statuses if s.sender == sender and s.state is MoveState.REJECTED]
    by_id = {s.move_id: s.text for s in rejected}
    move0 = [s.text for s in rejected if s.move_id == 0]
    wrong = []
    for p in payloads:
        if p.move_id and p.reason not in by_id.get(p.move_id, ""):
            wrong.append(f"{p.name}: {by_id.get(p.move_id, 'no status')}")
        elif not p.move_id and p.reason and not any(p.reason in text for text in move0):
            wrong.append(f"{p.name}: no move-0 rejection says {p.reason!r}")
    return wrong


# ---- fault 1: the recorder killed ----------------------------------------------------------------


def rerun_rows(recording: Path, rrd: Path, entity: str = STATE_TOPIC + "/position") -> int:
    """Rows of ``entity`` after ``rerun mcap convert`` (rerun's own importer) turned ``recording``
    into ``rrd``, read back with ``rerun.chunk.RrdReader``; -1 if the conversion failed."""
    from rerun.chunk import RrdReader

    done = subprocess.run(
        [sys.executable, "-m", "rerun", "mcap", "convert", str(recording), "-o", str(rrd)],
        capture_output=True,
        env=ENV,
        timeout=120,
    )
    if done.returncode != 0 or not rrd.exists():
        return -1
    return sum(c.num_rows for c in RrdReader(str(rrd)).store().stream() if c.entity_path == entity)


def rosbags_count(recording: Path, topic: str = STATE_TOPIC) -> int:
    """Messages of ``topic`` that rosbags' ``AnyReader`` reads from ``recording`` (decoded)."""
    from rosbags.highlevel import AnyReader

    with AnyReader([recording]) as reader:
        connections = [c for c in reader.connections if c.topic == topic]
        return sum(
            1 for c, _t, raw in reader.messages(connections=connections) if reader.deserialize(raw, c.msgtype)
        )


@dataclass(frozen=True)
class RecorderKillResult(FaultResult):
    published_before_kill: int
    """state samples the bridge published before the kill (1 per ms of drive time since its first)"""
    on_disk: TickRecord
    """what the killed recorder's file holds (read to its last complete chunk)"""
    recover: Exited
    recovered_complete: bool
    recovered_messages: int
    rosbags_messages: int
    rerun_rows: int
    bridge: Exited

    @property
    def lost(self) -> int:
        return self.published_before_kill - self.on_disk.messages

    @property
    def lost_s(self) -> float:
        return self.lost * TICK_NS * 1e-9

    @property
    def passed(self) -> bool:
        n = self.on_disk.messages
        return (
            0 <= self.lost_s <= MAX_CRASH_LOSS_S
            and self.on_disk.every_tick
            and self.recover.returncode == 0
            and self.recovered_complete
            and self.recovered_messages == self.rosbags_messages == self.rerun_rows == n
            and self.bridge.returncode == 0
        )

    def outcome(self) -> Outcome:
        return Outcome(
            "recorder SIGKILL mid-session",
            self.passed,
            f"{self.lost} of {self.published_before_kill} state samples lost ({self.lost_s:.3f} s; the rest "
            f"on disk, sequences 1…{self.on_disk.messages} with no gap: {self.on_disk.every_tick}); "
            f"`axisflow recover` exit {self.recover.returncode}, complete file of {self.recovered_messages} "
            f"state samples; rosbags reads {self.rosbags_messages}, rerun {self.rerun_rows} rows",
            "axisflow bench faults --only recorder_kill",
            {
                "published_before_kill": self.published_before_kill,
                "on_disk": self.on_disk.messages,
                "lost": self.lost,
                "lost_s": self.lost_s,
                "recovered": self.recovered_messages,
                "rosbags": self.rosbags_messages,
                "rerun_rows": self.rerun_rows,
            },
        )


MAX_CRASH_LOSS_S = 1.2
"""the most a SIGKILL may lose: the recorder's 1 s flush interval plus 0.2 s for scheduling"""


def recorder_kill(work: Path, kill_after_s: float = 3.0) -> RecorderKillResult:
    """Fault 1: a bridge at 1× real time recorded; the recorder SIGKILLed ``kill_after_s`` into the
    session; what is on disk counted against what the bridge published, then recovered and opened
    with rosbags and rerun."""
    with Fleet(work) as fleet:
        rig = Rig(fleet, "recorder-kill")
        recorder = rig.start_recorder("--flush-interval", "1")
        bridge = rig.start_bridge("bridge", "--duration", f"{kill_after_s + 2.0}")
        with open_session(rig.options()) as session:
            require_bridge(session)
        time.sleep(kill_after_s)
        killed_ns = time.time_ns()
        recorder.kill()
        fleet.wait(recorder)
        bridge_end = fleet.wait(bridge, 60.0)
        on_disk = tick_record(rig.recording)
        fixed = work / "recorder-kill.recovered.mcap"
        recover_end = fleet.wait(
            fleet.start("recover", "recover", str(rig.recording), "-o", str(fixed)), 120.0
        )
    complete = recover_end.returncode == 0 and is_complete(fixed)
    return RecorderKillResult(
        published_before_kill=(killed_ns - on_disk.runs[0][3]) // TICK_NS + 1 if on_disk.runs else 0,
        on_disk=on_disk,
        recover=recover_end,
        recovered_complete=complete,
        recovered_messages=tick_record(fixed).messages if complete else 0,
        rosbags_messages=rosbags_count(fixed) if complete else 0,
        rerun_rows=rerun_rows(fixed, work / "recorder-kill.rrd") if complete else 0,
        bridge=bridge_end,
    )


# ---- fault 2: the bridge killed mid-move ------------------------------------------------------------


@dataclass(frozen=True)
class BridgeKillResult(FaultResult):
    killed_at: tuple[float, float]
    """the plant's (x [m], v [m/s]) when the first bridge was killed (its state file)"""
    coasts_to_m: float
    """where the model says the cart comes to rest from there on friction alone (true parameters)"""
    last_recorded: tuple[float, float]
    """the last state sample of the first bridge in the recording (x [m], v [m/s])"""
    kill_to_last_sample_ms: float
    restart_first: tuple[float, float]
    """the first state sample of the restarted bridge (x [m], v [m/s])"""
    restart_span_m: float
    """how far the restarted bridge's measured position moved during its run [m] (it holds)"""
    restart_ticks: int
    state: TickRecord
    publishers: list[dict[str, Any]]
    """the recorder's summary of the state topic's publishers (id, first/last sequence, messages)"""
    recorder: Exited
    complete: bool
    count_m: float
    """one encoder count [m]"""

    @property
    def restart_offset_m(self) -> float:
        return self.restart_first[0] - self.coasts_to_m

    @property
    def ticks_after_last_sample(self) -> float:
        """How many ticks of travel lie between the last recorded sample and the plant's state at the
        kill: 1 is a complete recording (a state sample is read before its tick moves the plant; the
        file is written after), more is samples lost before the kill."""
        x, v = self.killed_at
        return (x - self.last_recorded[0]) / (v * TICK_NS * 1e-9) if abs(v) > 0.01 else 0.0

    @property
    def passed(self) -> bool:
        runs = self.state.runs
        return (
            self.recorder.returncode == 0
            and self.complete
            and self.state.every_tick
            and len(runs) == 2
            and [(p["first_sequence"], p["last_sequence"]) for p in self.publishers]
            == [(r[1], r[2]) for r in runs]
            and abs(self.restart_offset_m) <= self.count_m
            and self.restart_first[1] == 0.0
            and self.restart_span_m <= 2 * self.count_m
            and runs[1][0] == self.restart_ticks
            and self.ticks_after_last_sample <= 2.5
        )

    def outcome(self) -> Outcome:
        (x, v), (xr, vr) = self.killed_at, self.restart_first
        n1, n2 = (r[0] for r in self.state.runs[:2]) if len(self.state.runs) >= 2 else (0, 0)
        return Outcome(
            "bridge SIGKILL mid-move, restarted on the same --plant-state",
            self.passed,
            f"killed at x = {x:.4f} m, v = {v:.3f} m/s; recording complete ({self.complete}), last sample "
            f"{self.ticks_after_last_sample:.1f} ticks of travel before the kill point (1 = none lost); "
            f"recorder lists 2 publishers "
            f"(seq 1–{n1}, then 1–{n2}, no gap); restart at rest at {xr:.6f} m, v = {vr:g} m/s, "
            f"{self.restart_offset_m * 1e6:+.1f} µm from the coasting end {self.coasts_to_m:.6f} m "
            f"({(self.coasts_to_m - x) * 1e3:.1f} mm past the kill point), held within "
            f"{self.restart_span_m * 1e6:.1f} µm",
            "axisflow bench faults --only bridge_kill",
            {
                "killed_at": self.killed_at,
                "coasts_to_m": self.coasts_to_m,
                "last_recorded": self.last_recorded,
                "kill_to_last_sample_ms": self.kill_to_last_sample_ms,
                "ticks_after_last_sample": self.ticks_after_last_sample,
                "restart_first": self.restart_first,
                "restart_offset_m": self.restart_offset_m,
                "restart_span_m": self.restart_span_m,
                "publishers": self.publishers,
            },
        )


def fastest_move_s(x0_m: float, x1_m: float, params: AxisParams) -> float:
    """The duration of the minimum-time poly5 move (the planner's exact solver)."""
    from axisflow.planner import Case, MoveProblem, solve_exact

    return solve_exact(MoveProblem(x0_m, x1_m, "poly5", Case.MIN_TIME), params).duration_s


def bridge_kill(work: Path, at_fraction: float = 0.45) -> BridgeKillResult:
    """Fault 2: a minimum-time move over the stroke; the bridge SIGKILLed ``at_fraction`` into it
    (near full speed) while the recorder keeps recording; a new bridge on the same plant state file
    runs 2 s; the recorder is then stopped cleanly."""
    from axisflow.acquisition import MoveSender

    params = default_params()
    plant = load_plant(None, params)
    state_file = work / "plant.state"
    with Fleet(work) as fleet:
        rig = Rig(fleet, "bridge-kill")
        recorder = rig.start_recorder()
        first = rig.start_bridge("bridge-1", "--plant-state", str(state_file))
        with open_session(rig.options()) as session, MoveSender(session, KEYS) as sender:
            sender.require_bridge(30.0)
            duration = fastest_move_s(0.0, params.L, params)
            move = sender.send(0.0, params.L, duration)
            if sender.wait_status(move.move_id, {MoveState.STARTED}, 10.0) is None:
                raise RuntimeError(f"move {move.move_id} did not start: {sender.statuses}")
            time.sleep(at_fraction * duration)
            first.kill()
            killed_ns = time.time_ns()
            fleet.wait(first)
        x_kill, v_kill = _PLANT_STATE.unpack(state_file.read_bytes())
        time.sleep(0.5)
        second_end = fleet.wait(
            rig.start_bridge("bridge-2", "--plant-state", str(state_file), "--duration", "2"), 60.0
        )
        time.sleep(0.3)
        recorder_end = fleet.stop(recorder)
    state = tick_record(rig.recording)
    n1 = state.runs[0][0]
    coast = stop_profile(x_kill, v_kill, plant.axis, force_fraction=0.0).trajectory.x1_m if v_kill else x_kill
    return BridgeKillResult(
        killed_at=(x_kill, v_kill),
        coasts_to_m=min(max(coast, 0.0), params.L),
        last_recorded=(float(state.position_m[n1 - 1]), float(state.velocity_m_s[n1 - 1])),
        kill_to_last_sample_ms=(killed_ns - state.last_stamp_ns[0]) / 1e6,
        restart_first=(float(state.position_m[n1]), float(state.velocity_m_s[n1])),
        restart_span_m=float(np.ptp(state.position_m[n1:])),
        restart_ticks=second_end.json()["ticks"] if second_end.returncode == 0 else -1,
        state=state,
        publishers=recorder_end.json()["topics"][STATE_TOPIC]["publishers"]
        if recorder_end.returncode == 0
        else [],
        recorder=recorder_end,
        complete=is_complete(rig.recording),
        count_m=2.0 * np.pi * plant.axis.r / plant.encoder.counts_per_rev,
    )


# ---- fault 3: the planner killed ---------------------------------------------------------------------


@dataclass(frozen=True)
class PlannerKillResult(FaultResult):
    counts: dict[str, int]
    """the bridge's statuses about the planner's moves, by state"""
    drop_after_s: float
    """from the kill to the bridge's first DROPPED status [s]"""
    rest_setpoint: tuple[float, float]
    """the last setpoint (x [m], v [m/s])"""
    last_completed_end_m: float
    """the end point of the last move that completed"""
    rest_speed_m_s: float
    """the largest measured speed over the last 0.3 s"""
    end: RunEnd
    L: float

    @property
    def passed(self) -> bool:
        c = self.counts
        x, v = self.rest_setpoint
        return (
            c["accepted"] >= 2
            and c["dropped"] == c["accepted"] - c["started"] >= 1
            and c["completed"] == c["started"]
            and c["rejected"] == 0
            and x == self.last_completed_end_m
            and v == 0.0
            and 0.0 <= x <= self.L
            and self.rest_speed_m_s < 0.005
            and self.end.telemetry_intact
        )

    def outcome(self) -> Outcome:
        c = self.counts
        return Outcome(
            "planner SIGKILL with moves queued",
            self.passed,
            f"{c['accepted']} accepted, {c['started']} started and completed, {c['dropped']} dropped "
            f"{self.drop_after_s * 1e3:.0f} ms after the kill; at rest at {self.rest_setpoint[0]:.4f} m (the "
            f"last completed move's end), measured speed ≤ {self.rest_speed_m_s * 1e3:.2f} mm/s; telemetry "
            "complete (test: tests/top/test_planner_restart.py, which also restarts the planner)",
            "axisflow bench faults --only planner_kill",
            {
                "counts": self.counts,
                "drop_after_s": self.drop_after_s,
                "rest_setpoint": self.rest_setpoint,
                "last_completed_end_m": self.last_completed_end_m,
                "rest_speed_m_s": self.rest_speed_m_s,
            },
        )


def planner_kill(work: Path) -> PlannerKillResult:
    """Fault 3: ``axisflow planner`` (lookahead 2) driving a bridge at 1× real time, SIGKILLed once it
    has three moves accepted; the bridge drops the queued ones and the running one ends at rest."""
    from axisflow.acquisition import MoveCommand, read_messages

    points = work / "points.txt"
    points.write_text("0.1\n0.7\n0.2\n0.6\n0.3\n0.5\n")
    names = ("accepted", "started", "completed", "dropped", "rejected")
    with Fleet(work) as fleet:
        rig = Rig(fleet, "planner-kill")
        recorder = rig.start_recorder()
        bridge = rig.start_bridge()
        with open_session(rig.options()) as session:
            require_bridge(session)
            watch = StatusWatch(session)
            args = ("--waypoints", str(points), "--case", "min-time-energy", "--lookahead", "2")
            planner = fleet.start("planner", "planner", *args, "--connect", rig.recorder_endpoint)
            if not watch.wait(MoveState.ACCEPTED, 3, 60.0):
                raise RuntimeError(f"the planner's moves were not accepted: {fleet.wait(planner, 1).stderr}")
            planner.kill()
            killed = time.monotonic()
            fleet.wait(planner)
            watch.wait(MoveState.DROPPED, 1, 30.0)
            drop_after_s = time.monotonic() - killed
            wait_until(lambda: watch.count(MoveState.COMPLETED) == watch.count(MoveState.STARTED), 30.0)
            time.sleep(0.5)
            counts = {name: watch.count(MoveState[name.upper()]) for name in names}
            completed = [s.move_id for s in watch.statuses if s.state is MoveState.COMPLETED]
            watch.close()
        end = stop_rig(fleet, rig, bridge, recorder)
    moves = {
        m.move_id: m
        for m in (MoveCommand.decode(r.data) for r in read_messages(rig.recording, "/" + KEYS.trajectory))
    }
    setpoint, state = end.setpoint, end.state
    return PlannerKillResult(
        counts=counts,
        drop_after_s=drop_after_s,
        rest_setpoint=(float(setpoint.position_m[-1]), float(setpoint.velocity_m_s[-1])),
        last_completed_end_m=moves[completed[-1]].end_position_m if completed else float("nan"),
        rest_speed_m_s=float(np.abs(state.velocity_m_s[-300:]).max()),
        end=end,
        L=default_params().L,
    )


# ---- fault 5: a flood of valid moves -------------------------------------------------------------


@dataclass(frozen=True)
class FloodResult(FaultResult):
    per_sender: list[dict[str, int]]
    """per flooding sender: sent, accepted, rejected, queue_full (rejections that say so), dropped"""
    max_queued: int
    """the most moves queued at once, from the statuses in order (running included)"""
    answer_s: list[float]
    """per flood: from the first move sent to the last answer [s]"""
    rss_mb: dict[str, float]
    """the bridge's RSS: before, after each flood (senders closed), peak"""
    stalls: dict[str, Stalls]
    end: RunEnd
    limit: int
    """MAX_QUEUED_MOVES"""

    @property
    def rss_growth_mb(self) -> float:
        """RSS after the last flood less after the one before: what a flood leaves behind once the
        allocator has settled (the first floods grow it by a few MB that later ones reuse: measured
        3.9, 1.9, 0.2, 0.3, −1.5, 1.2 MB over six floods)"""
        n = len(self.per_sender)
        return self.rss_mb[f"after flood {n}"] - self.rss_mb[f"after flood {n - 1}"]

    @property
    def passed(self) -> bool:
        first, *later = self.per_sender
        return (
            first["accepted"] == self.limit
            # the first sender's running move is still queued
            and all(s["accepted"] == self.limit - 1 for s in later)
            and all(s["rejected"] == s["queue_full"] == s["sent"] - s["accepted"] for s in self.per_sender)
            and all(s["dropped"] == self.limit - 1 for s in self.per_sender)
            and self.max_queued == self.limit
            and abs(self.rss_growth_mb) <= MAX_FLOOD_RSS_GROWTH_MB
            and self.end.telemetry_intact
            and self.end.report["moves_missed"] == 0
        )

    def outcome(self) -> Outcome:
        n = len(self.per_sender)
        rss = " → ".join(
            f"{self.rss_mb[k]:.1f}" for k in ["before", *(f"after flood {i}" for i in range(1, n + 1))]
        )
        return Outcome(
            f"a flood of valid moves ({self.per_sender[0]['sent']} from a sender, its queue dropped; "
            f"{n} senders one after another)",
            self.passed,
            f"accepted {', '.join(str(s['accepted']) for s in self.per_sender)} (at most {self.max_queued} "
            f"queued; limit {self.limit}), the rest rejected 'queue is full' "
            f"({', '.join(str(s['queue_full']) for s in self.per_sender)}); "
            f"answered in {', '.join(f'{a:.1f}' for a in self.answer_s)} s; bridge RSS {rss} MB (peak "
            f"{self.rss_mb['peak']:.1f}; the last flood left {self.rss_growth_mb:+.1f} MB); telemetry: all "
            f"{self.end.state.messages} ticks recorded 1 ms apart: {self.end.telemetry_intact}; "
            + "; ".join(f"{k}: {v}" for k, v in self.stalls.items()),
            "axisflow bench faults --only move_flood",
            {
                "per_sender": self.per_sender,
                "max_queued": self.max_queued,
                "answer_s": self.answer_s,
                "rss_mb": self.rss_mb,
                "stalls": {k: vars(v) for k, v in self.stalls.items()},
                "bridge": {k: v for k, v in self.end.report.items() if k != "rejections"},
            },
        )


MAX_FLOOD_RSS_GROWTH_MB = 5.0
"""the last flood may leave at most this much more resident memory than the one before (a leak of
2.5 kB per accepted move would pass it)"""


def _max_queued(statuses: list[MoveStatus]) -> int:
    queued = peak = 0
    for s in statuses:
        if s.state is MoveState.ACCEPTED:
            queued += 1
            peak = max(peak, queued)
        elif s.state in (MoveState.COMPLETED, MoveState.DROPPED, MoveState.STOPPED):
            queued -= 1
    return peak


def _flood(
    session: Any, watch: StatusWatch, x0_m: float, moves: int, move_s: float
) -> tuple[dict[str, int], float]:
    """One sender sends ``moves`` valid moves from ``x0_m`` (to 0.3 m, then 0.31 m and back), waits until
    each is answered, closes, and waits until its queue is dropped (all but a move that runs). Its
    counts, and the seconds from the first send to the last answer."""
    from axisflow.acquisition import MoveSender

    with MoveSender(session, KEYS) as sender:
        sender.wait_for_bridge(10.0)
        sid = sender.sender_id
        t0 = time.monotonic()
        x = x0_m
        for k in range(moves):
            x1 = 0.3 if k % 2 == 0 else 0.31
            sender.send(x, x1, move_s)
            x = x1

        def answered() -> bool:
            return watch.count(MoveState.ACCEPTED, sid) + watch.count(MoveState.REJECTED, sid) >= moves

        wait_until(answered, 60.0)
        seconds = time.monotonic() - t0
    accepted = watch.count(MoveState.ACCEPTED, sid)
    started = watch.count(MoveState.STARTED, sid)
    watch.wait(MoveState.DROPPED, accepted - started, 30.0, sender=sid)
    rejections = [s for s in watch.drain() if s.sender == sid and s.state is MoveState.REJECTED]
    counts = {
        "sent": moves,
        "accepted": accepted,
        "rejected": len(rejections),
        "queue_full": sum("queue is full" in s.text for s in rejections),
        "dropped": watch.count(MoveState.DROPPED, sid),
    }
    return counts, seconds


def move_flood(work: Path, moves: int = 2000, move_s: float = 30.0, floods: int = 3) -> FloodResult:
    """Fault 5: a sender sends ``moves`` valid moves as fast as the bridge takes them (each ``move_s``
    long, so none ends during the floods), then closes (its queue is dropped; the running move goes
    on); ``floods`` − 1 more senders do the same, one after another. Bridge at 1× real time, recorded,
    its RSS sampled."""
    from axisflow.acquisition.bridge.move_queue import MAX_QUEUED_MOVES

    params = default_params()
    x = load_plant(None, params).simulation.initial_position_m
    per_sender, answer_s, marks, rss_at = [], [], {}, {}
    with Fleet(work) as fleet:
        rig = Rig(fleet, "move-flood")
        recorder = rig.start_recorder()
        bridge = rig.start_bridge()
        with open_session(rig.options()) as session, RssSampler(bridge.pid, 0.1) as rss:
            require_bridge(session)
            watch = StatusWatch(session)
            time.sleep(1.0)
            rss_at["before"] = rss.samples[-1][1]
            for flood in (f"flood {i}" for i in range(1, floods + 1)):
                marks[flood] = time.time_ns()
                counts, seconds = _flood(session, watch, x, moves, move_s)
                per_sender.append(counts)
                answer_s.append(seconds)
                x = 0.3  # where the move that runs (the first sender's first) ends
                time.sleep(1.0)
                rss_at[f"after {flood}"] = rss.samples[-1][1]
            marks["end"] = time.time_ns()
            statuses = list(watch.drain())
            watch.close()
        rss_at["peak"] = rss.peak_mb
        end = stop_rig(fleet, rig, bridge, recorder)
    return FloodResult(
        per_sender=per_sender,
        max_queued=_max_queued(statuses),
        answer_s=answer_s,
        rss_mb=rss_at,
        stalls=phase_stalls(end.state, marks),
        end=end,
        limit=MAX_QUEUED_MOVES,
    )


# ---- fault 6: a full disk, a recorder started twice, peers coming and going -----------------------


@dataclass(frozen=True)
class SessionFaultsResult(FaultResult):
    twice: dict[str, Exited]
    """a second ``record`` on the first one's file: with --overwrite and without"""
    twice_s: float
    """how long the refusal took [s]"""
    size_before_after: tuple[int, int]
    """the first recording's size just before and after the second recorder tried [bytes]"""
    full: Exited
    """a recorder whose file system fills up (RLIMIT_FSIZE)"""
    full_path: Path
    full_size: int
    fsize_limit: int
    full_recovered: Exited
    full_state: TickRecord | None
    """the state samples of the recovered file"""
    peers: int
    peers_heard: int
    """peers that received a state sample before closing"""
    churn_s: float
    stalls: dict[str, Stalls]
    end: RunEnd

    @staticmethod
    def one_line_error(done: Exited, *fragments: str) -> bool:
        lines = done.stderr.strip().splitlines()
        return done.returncode == 2 and len(lines) == 1 and all(f in lines[0] for f in fragments)

    @property
    def twice_ok(self) -> bool:
        before, after = self.size_before_after
        return (
            self.one_line_error(self.twice["--overwrite"], "is being recorded by another process")
            and self.one_line_error(self.twice["plain"], "already exists")
            and after >= before
        )

    @property
    def full_ok(self) -> bool:
        return (
            self.one_line_error(
                self.full, f"writing {self.full_path} failed", f"axisflow recover {self.full_path}"
            )
            and self.full_size <= self.fsize_limit
            and self.full_recovered.returncode == 0
            and self.full_state is not None
            and self.full_state.consistent
            and self.full_state.sequence_gaps <= JOIN_LOSS_ALLOWANCE
            and self.full_state.messages > 0
        )

    @property
    def churn_ok(self) -> bool:
        r = self.end.report
        return self.peers_heard == self.peers and r["moves_dropped"] == r["moves_rejected"] == 0

    @property
    def passed(self) -> bool:
        return self.twice_ok and self.full_ok and self.churn_ok and self.end.telemetry_intact

    def outcomes(self) -> list[Outcome]:
        ow = self.twice["--overwrite"].stderr.strip()
        before, after = self.size_before_after
        intact = f"the first recording complete, every tick 1 ms apart: {self.end.telemetry_intact}"
        full_n = self.full_state.messages if self.full_state is not None else 0
        full_gaps = self.full_state.sequence_gaps if self.full_state is not None else 0
        in_place = self.full_state is not None and self.full_state.consistent
        return [
            Outcome(
                "disk full during recording (RLIMIT_FSIZE)",
                self.full_ok and self.end.telemetry_intact,
                f"recorder exit {self.full.returncode} after {self.full_size} of {self.fsize_limit} bytes: "
                f"'{self.full.stderr.strip()}'; `axisflow recover` exit {self.full_recovered.returncode}: "
                f"{full_n} state samples, {full_gaps} lost while recording, each sample where its sequence "
                f"number puts it: {in_place}; {intact}",
                "axisflow bench faults --only session_faults",
                {"full_size": self.full_size, "fsize_limit": self.fsize_limit, "recovered_state": full_n},
            ),
            Outcome(
                "a second recorder on the same file (with --overwrite; and without)",
                self.twice_ok and self.end.telemetry_intact,
                f"refused in {self.twice_s:.1f} s, exit {self.twice['--overwrite'].returncode}: '{ow}'; "
                f"without --overwrite: '{self.twice['plain'].stderr.strip()}'; the file grew {before} → "
                f"{after} bytes "
                f"meanwhile; {intact}",
                "axisflow bench faults --only session_faults",
                {"size_before_after": self.size_before_after, "twice_s": self.twice_s},
            ),
            Outcome(
                f"{self.peers} Zenoh peers opened and closed against the running bridge",
                self.churn_ok and self.end.telemetry_intact,
                f"{self.peers_heard} of {self.peers} heard the bridge (each also held a sender token) in "
                f"{self.churn_s:.1f} s; bridge: {self.end.report['moves_dropped']} moves dropped, exit "
                f"{self.end.bridge.returncode}; {self.stalls['churn']}; {intact}",
                "axisflow bench faults --only session_faults",
                {
                    "peers_heard": self.peers_heard,
                    "churn_s": self.churn_s,
                    "stalls": vars(self.stalls["churn"]),
                },
            ),
        ]


def _peer_hears_bridge(bridge_endpoint: str, timeout_s: float = 5.0) -> bool:
    """Open a peer on the bridge's endpoint, hold a move sender's token, wait for a state sample,
    close everything."""
    import zenoh

    with open_session(ZenohOptions(mode="peer", connect=(bridge_endpoint,))) as session:
        token = session.liveliness().declare_token(KEYS.sender(os.urandom(16)))
        sub = session.declare_subscriber(KEYS.state, zenoh.handlers.RingChannel(4))
        try:
            return wait_until(lambda: sub.try_recv() is not None, timeout_s, 0.005)
        finally:
            sub.undeclare()
            token.undeclare()


JOIN_LOSS_ALLOWANCE = 5
"""samples a recorder that joins the running bridge may lose live (the full-disk recorder): on a loaded
machine telemetry is dropped rather than wait for a consumer, and a subscriber declared on a new
session could lose a run of samples (docs/acquisition.md; the recorder now settles first); the
recovery must add none and misplace none"""


def session_faults(work: Path, peers: int = 30, fsize_limit: int = 400_000) -> SessionFaultsResult:
    """Fault 6, with one bridge at 1× real time and its recorder running throughout: a second recorder
    on the same file; a recorder whose file may not exceed ``fsize_limit`` bytes (uncompressed chunks,
    flushed every 0.25 s), then recovered; ``peers`` Zenoh sessions opened and closed one after the
    other against the bridge. The first recorder is stopped cleanly at the end."""
    with Fleet(work) as fleet:
        rig = Rig(fleet, "session-faults")
        recorder = rig.start_recorder()
        bridge = rig.start_bridge()
        with open_session(rig.options()) as session:
            require_bridge(session)
        bridge_ep = f"tcp/127.0.0.1:{rig.bridge_ports[-1]}"
        joining = ("--connect", bridge_ep)
        time.sleep(1.0)
        before = rig.recording.stat().st_size
        t0 = time.monotonic()
        twice = {
            "--overwrite": fleet.run("twice", "record", "-o", str(rig.recording), "--overwrite", *joining)
        }
        twice_s = time.monotonic() - t0
        twice["plain"] = fleet.run("twice-plain", "record", "-o", str(rig.recording), *joining)
        after = rig.recording.stat().st_size
        full_path = work / "full.mcap"
        limited = ("-o", str(full_path), "--compression", "none", "--flush-interval", "0.25", *joining)
        full = fleet.run("full", "record", *limited, fsize_limit=fsize_limit)
        fixed = work / "full.recovered.mcap"
        recovered = fleet.run("recover-full", "recover", str(full_path), "-o", str(fixed))
        churn_from = time.time_ns()
        t0 = time.monotonic()
        heard = sum(_peer_hears_bridge(bridge_ep) for _ in range(peers))
        churn_s = time.monotonic() - t0
        churn_to = time.time_ns()
        time.sleep(0.5)
        end = stop_rig(fleet, rig, bridge, recorder)
    return SessionFaultsResult(
        twice=twice,
        twice_s=twice_s,
        size_before_after=(before, after),
        full=full,
        full_path=full_path,
        full_size=full_path.stat().st_size if full_path.exists() else -1,
        fsize_limit=fsize_limit,
        full_recovered=recovered,
        full_state=tick_record(fixed) if recovered.returncode == 0 else None,
        peers=peers,
        peers_heard=heard,
        churn_s=churn_s,
        stalls={"churn": end.state.stalls(churn_from, churn_to)},
        end=end,
    )


# ---- the quick stop ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class QuickStopResult(FaultResult):
    braking_from: tuple[float, float]
    """the measured (x [m], v [m/s]) at the tick braking began"""
    distance_m: float
    """from there to where the measured speed first falls below REST_SPEED_M_S"""
    time_s: float
    minimum: tuple[float, float]
    """the physical minimum from the same state: stop_profile(x, v, true parameters, 1.0) (distance
    [m], time [s])"""
    bridge_text: str
    """the bridge's STOPPED status (its own figures, with the nominal parameters)"""
    rest_m: float
    """where the axis holds at the end (the braking profile's end: the position loop pulls the cart
    back to it after its first stop)"""
    dropped: int
    L: float
    end: RunEnd

    @property
    def passed(self) -> bool:
        d_min, t_min = self.minimum
        return (
            self.braking_from[1] > 1.0
            and d_min * 0.98 <= self.distance_m <= 1.35 * d_min
            and self.time_s <= 1.25 * t_min + 0.005
            and 0.0 < self.rest_m < self.L
            and self.dropped == 1
            and self.end.telemetry_intact
        )

    def outcome(self) -> Outcome:
        (x, v), (d_min, t_min) = self.braking_from, self.minimum
        return Outcome(
            "quick stop (MoveSender.stop()) at full speed",
            self.passed,
            f"from {v:.3f} m/s at {x:.4f} m: stopped in {self.distance_m * 1e3:.1f} mm and "
            f"{self.time_s * 1e3:.0f} ms; physical minimum (true parameters, full force) "
            f"{d_min * 1e3:.1f} mm and {t_min * 1e3:.0f} ms: ×{self.distance_m / d_min:.2f} distance, "
            f"×{self.time_s / t_min:.2f} time; then held at {self.rest_m:.4f} m "
            f"({(x + self.distance_m - self.rest_m) * 1e3:.1f} mm back); the queued move dropped; "
            f"bridge: '{self.bridge_text}'",
            "axisflow bench faults --only quick_stop",
            {
                "braking_from": self.braking_from,
                "distance_m": self.distance_m,
                "time_s": self.time_s,
                "minimum": self.minimum,
                "ratio_distance": self.distance_m / d_min,
                "ratio_time": self.time_s / t_min,
                "rest_m": self.rest_m,
            },
        )


REST_SPEED_M_S = 0.005
"""a measured speed below this (2.6 encoder counts per tick) counts as at rest"""


def quick_stop(work: Path, at_fraction: float = 0.5) -> QuickStopResult:
    """The quick stop: a minimum-time move over the stroke with a second one queued; at
    ``at_fraction`` of it (full speed) the sender requests a quick stop; distance and time to rest
    measured on the recorded samples, against :func:`~axisflow.model.stop_profile` from the measured
    state with the plant's true parameters at full force."""
    from axisflow.acquisition import MoveSender
    from axisflow.acquisition.wire.quick_stop import STOP_MOVE_ID

    params = default_params()
    with Fleet(work) as fleet:
        rig = Rig(fleet, "quick-stop")
        recorder = rig.start_recorder()
        bridge = rig.start_bridge()
        with open_session(rig.options()) as session, MoveSender(session, KEYS) as sender:
            sender.require_bridge(30.0)
            duration = fastest_move_s(0.0, params.L, params)
            move = sender.send(0.0, params.L, duration)
            sender.send(params.L, 0.2, 1.0)
            if sender.wait_status(move.move_id, {MoveState.STARTED}, 10.0) is None:
                raise RuntimeError(f"move {move.move_id} did not start: {sender.statuses}")
            time.sleep(at_fraction * duration)
            sender.stop("axisflow bench faults")
            stopped = sender.wait_status(STOP_MOVE_ID, {MoveState.STOPPED}, 10.0)
            time.sleep(0.5)
            sender.poll_status()
            dropped = sum(s.state is MoveState.DROPPED for s in sender.statuses)
        if stopped is None:
            raise RuntimeError(f"the quick stop was not confirmed: {sender.statuses}")
        end = stop_rig(fleet, rig, bridge, recorder)
    state = end.state
    k0 = stopped.start_tick
    at_rest = np.flatnonzero(np.abs(state.velocity_m_s[k0:]) < REST_SPEED_M_S)
    k_rest = k0 + (int(at_rest[0]) if at_rest.size else len(state.velocity_m_s) - 1 - k0)
    x0, v0 = float(state.position_m[k0]), float(state.velocity_m_s[k0])
    fastest = stop_profile(x0, v0, true_axis(params), 1.0)
    return QuickStopResult(
        braking_from=(x0, v0),
        distance_m=abs(float(state.position_m[k_rest]) - x0),
        time_s=(k_rest - k0) * TICK_NS * 1e-9,
        minimum=(fastest.distance_m, fastest.time_s),
        bridge_text=stopped.text,
        rest_m=float(state.position_m[-1]),
        dropped=dropped,
        L=params.L,
        end=end,
    )


# ---- the benchmark ---------------------------------------------------------------------------------


SCENARIOS: dict[str, Callable[[Path, Any], FaultResult]] = {
    "recorder_kill": lambda work, _args: recorder_kill(work),
    "bridge_kill": lambda work, _args: bridge_kill(work),
    "planner_kill": lambda work, _args: planner_kill(work),
    "bad_payloads": lambda work, args: bad_payloads(work, per_sender=args.payloads),
    "move_flood": lambda work, _args: move_flood(work),
    "session_faults": lambda work, args: session_faults(work, peers=args.peers),
    "quick_stop": lambda work, _args: quick_stop(work),
}
"""the scenarios by the name ``--only`` takes, in the order they run"""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from axisflow.arguments import positive_int

    parser.add_argument(
        "--only",
        action="append",
        choices=list(SCENARIOS),
        metavar="NAME",
        help=f"run only this scenario (repeatable): {', '.join(SCENARIOS)}",
    )
    parser.add_argument(
        "--payloads", type=positive_int, default=1000, help="bad payloads per sender (default 1000)"
    )
    parser.add_argument(
        "--peers", type=positive_int, default=30, help="Zenoh peers opened and closed (default 30)"
    )
    parser.add_argument(
        "--keep",
        metavar="DIR",
        default=None,
        help="keep the recordings and process logs in DIR (default: none)",
    )


def run_scenario(name: str, work: Path, args: argparse.Namespace) -> tuple[list[Outcome], float]:
    """One scenario's rows and its wall time [s]; a scenario that cannot run is one failed row."""
    work.mkdir(parents=True, exist_ok=True)
    t0 = time.monotonic()
    try:
        rows = SCENARIOS[name](work, args).outcomes()
    except Exception as exc:  # a benchmark reports a broken scenario and goes on with the others
        rows = [
            Outcome(
                name,
                False,
                f"could not run: {type(exc).__name__}: {exc}",
                f"axisflow bench faults --only {name}",
            )
        ]
    return rows, time.monotonic() - t0


def run(args: argparse.Namespace) -> int:
    """All (or ``--only``) scenarios; the table, or one JSON object; exit 1 if a contract failed."""
    names = list(dict.fromkeys(args.only or SCENARIOS))
    if args.keep and Path(args.keep).exists() and any(Path(args.keep).iterdir()):
        raise AxisflowError(
            f"--keep {args.keep} is not empty: give a new folder (recordings are never overwritten)"
        )
    rows: list[dict[str, Any]] = []
    plant = load_plant(None, default_params()).describe()  # what every bridge of the scenarios runs
    if not args.json:
        print(f"faults: the bridges drive the simulated axis, plant {plant}", file=sys.stderr, flush=True)
    with tempfile.TemporaryDirectory(prefix="axisflow-faults-") as tmp:
        base = Path(args.keep) if args.keep else Path(tmp)
        for name in names:
            outcomes, seconds = run_scenario(name, base / name, args)
            rows += [{"scenario": name, "seconds": seconds, **o.to_dict()} for o in outcomes]
            if not args.json:
                held = "held" if all(o.passed for o in outcomes) else "FAILED"
                print(f"{name}: {held} ({seconds:.0f} s)", file=sys.stderr, flush=True)
    if args.json:
        summary = {"plant": plant, "faults": rows, "all_held": all(r["passed"] for r in rows)}
        print(json.dumps(summary, indent=1, default=str))
    else:
        print_table(rows)
    return 0 if all(r["passed"] for r in rows) else 1


def print_table(rows: list[dict[str, Any]]) -> None:
    """The fault table in Markdown (docs/trust.md keeps one)."""
    print("| fault | held | outcome (measured) | command |")
    print("|---|---|---|---|")
    for r in rows:
        print(f"| {r['fault']} | {'yes' if r['passed'] else '**no**'} | {r['outcome']} | `{r['command']}` |")
