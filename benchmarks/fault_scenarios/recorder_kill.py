"""Fault 1: the recorder SIGKILLed mid-session → at most a second of the bridge's samples lost (flush +
fsync every second); ``axisflow recover`` gives a file rosbags and rerun open."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from ...acquisition import is_complete, open_session
from ...deploy.processes import Exited, Launcher
from .outcome import FaultResult, Outcome
from .rig import STATE_TOPIC, Rig, require_bridge
from .ticks import TICK_NS, TickRecord, tick_record


def rerun_rows(recording: Path, rrd: Path, entity: str = STATE_TOPIC + "/position") -> int:
    """Rows of ``entity`` after ``rerun mcap convert`` (rerun's own importer) turned ``recording``
    into ``rrd``, read back with ``rerun.chunk.RrdReader``; -1 if the conversion failed."""
    from rerun.chunk import RrdReader

    done = subprocess.run(
        [sys.executable, "-m", "rerun", "mcap", "convert", str(recording), "-o", str(rrd)],
        capture_output=True,
        env={**os.environ, "CI": "1", "RUST_LOG": "error"},
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
    with Launcher(work, cwd=work) as launcher:
        rig = Rig(launcher, "recorder-kill")
        recorder = rig.start_recorder("--flush-interval", "1")
        bridge = rig.start_bridge("bridge", "--duration", f"{kill_after_s + 2.0}")
        with open_session(rig.options()) as session:
            require_bridge(session)
        time.sleep(kill_after_s)  # the session runs this long before the kill
        killed_ns = time.time_ns()
        recorder.kill()
        launcher.wait(recorder)
        bridge_end = launcher.wait(bridge, 60.0)
        on_disk = tick_record(rig.recording)
        fixed = work / "recorder-kill.recovered.mcap"
        recover_end = launcher.wait(
            launcher.start("recover", "recover", str(rig.recording), "-o", str(fixed)), 120.0
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
