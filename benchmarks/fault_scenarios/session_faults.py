"""Fault 6: a full disk, a second recorder on the same file, 30 Zenoh peers coming and going → a clear
outcome each; the first recording complete."""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from pathlib import Path

import zenoh

from ...acquisition import ZenohOptions, open_session
from ...deploy.processes import Exited, Launcher, wait_until
from .outcome import FaultResult, Outcome
from .rig import KEYS, Rig, RunEnd, require_bridge, stop_rig
from .ticks import Stalls, TickRecord, tick_record


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
    with open_session(ZenohOptions(mode="peer", connect=(bridge_endpoint,))) as session:
        token = session.liveliness().declare_token(KEYS.sender(os.urandom(16)))
        sub = session.declare_subscriber(KEYS.state, zenoh.handlers.RingChannel(4))
        try:
            return wait_until(lambda: sub.try_recv() is not None, timeout_s, 0.005)
        finally:
            sub.undeclare()
            token.undeclare()


JOIN_LOSS_ALLOWANCE = 5
"""samples the full-disk recorder, which joins the running bridge, may lose live: on a loaded machine
telemetry at 1× real time is dropped rather than wait for a consumer (its join itself loses none:
acquisition.bus.readiness); the recovery must add none and misplace none"""


def session_faults(work: Path, peers: int = 30, fsize_limit: int = 400_000) -> SessionFaultsResult:
    """Fault 6, with one bridge at 1× real time and its recorder running throughout: a second recorder
    on the same file; a recorder whose file may not exceed ``fsize_limit`` bytes (uncompressed chunks,
    flushed every 0.25 s), then recovered; ``peers`` Zenoh sessions opened and closed one after the
    other against the bridge. The first recorder is stopped cleanly at the end."""
    with Launcher(work, cwd=work) as launcher:
        rig = Rig(launcher, "session-faults")
        recorder = rig.start_recorder()
        bridge = rig.start_bridge()
        with open_session(rig.options()) as session:
            require_bridge(session)
        bridge_ep = f"tcp/127.0.0.1:{rig.bridge_ports[-1]}"
        joining = ("--connect", bridge_ep)
        # the recorder's first flush (~1 s after its start) has put the file on disk: the file the second
        # recorder must not touch (it may hold only the header yet: the recorder started before the bridge)
        if not wait_until(lambda: rig.recording.stat().st_size > 0, 10.0):
            raise RuntimeError(f"the recorder flushed nothing to {rig.recording} within 10 s")

        def run(name: str, *args: str, fsize_limit_bytes: int | None = None) -> Exited:
            return launcher.wait(launcher.start(name, *args, fsize_limit_bytes=fsize_limit_bytes), 60.0)

        before = rig.recording.stat().st_size
        t0 = time.monotonic()
        twice = {"--overwrite": run("twice", "record", "-o", str(rig.recording), "--overwrite", *joining)}
        twice_s = time.monotonic() - t0
        twice["plain"] = run("twice-plain", "record", "-o", str(rig.recording), *joining)
        after = rig.recording.stat().st_size
        full_path = work / "full.mcap"
        limited = ("-o", str(full_path), "--compression", "none", "--flush-interval", "0.25", *joining)
        full = run("full", "record", *limited, fsize_limit_bytes=fsize_limit)
        fixed = work / "full.recovered.mcap"
        recovered = run("recover-full", "recover", str(full_path), "-o", str(fixed))
        churn_from = time.time_ns()
        t0 = time.monotonic()
        heard = sum(_peer_hears_bridge(bridge_ep) for _ in range(peers))
        churn_s = time.monotonic() - t0
        churn_to = time.time_ns()
        end = stop_rig(rig, bridge, recorder)
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
