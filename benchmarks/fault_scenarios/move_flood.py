"""Fault 5: thousands of valid moves → the queue holds MAX_QUEUED_MOVES (a running move included), the
rest "queue is full"; the bridge's memory flat; telemetry complete."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ...acquisition import MoveState, MoveStatus, load_plant, open_session
from ...deploy.processes import Launcher, wait_until
from ...model import default_params
from .outcome import FaultResult, Outcome
from .rig import KEYS, Rig, RssSampler, RunEnd, StatusWatch, require_bridge, stop_rig
from .ticks import Stalls, phase_stalls


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
        """What every flood leaves behind once the allocator has settled: the least growth of RSS over
        one flood, of those after the first. A leak grows RSS in every flood by the same amount; the
        allocator grows it in steps of a few MB (a new arena of one of the bridge's threads) that come in
        some floods and are reused by later ones, so the least growth is the leak's and not the steps'."""
        n = len(self.per_sender)
        return min(
            self.rss_mb[f"after flood {k}"] - self.rss_mb[f"after flood {k - 1}"] for k in range(2, n + 1)
        )

    @property
    def passed(self) -> bool:
        return (
            # the running move is queued too
            all(s["accepted"] == self.limit - 1 for s in self.per_sender)
            and all(s["rejected"] == s["queue_full"] == s["sent"] - s["accepted"] for s in self.per_sender)
            and all(s["dropped"] == self.limit - 1 for s in self.per_sender)
            and self.max_queued == self.limit
            and self.rss_growth_mb <= MAX_FLOOD_RSS_GROWTH_MB
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
            f"{n} senders one after another, behind a running move)",
            self.passed,
            f"accepted {', '.join(str(s['accepted']) for s in self.per_sender)} (at most {self.max_queued} "
            f"queued; limit {self.limit}), the rest rejected 'queue is full' "
            f"({', '.join(str(s['queue_full']) for s in self.per_sender)}); "
            f"answered in {', '.join(f'{a:.1f}' for a in self.answer_s)} s; bridge RSS {rss} MB (peak "
            f"{self.rss_mb['peak']:.1f}; every later flood left at least {self.rss_growth_mb:+.1f} MB); "
            f"telemetry: all "
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


RUNNING_MOVE_S = 3600.0
"""the move that runs through every flood (sent before them by a sender that stays): the longest move
there is, so that it still runs when the last flood ends on however slow a machine"""
MAX_FLOOD_RSS_GROWTH_MB = 5.0
"""every flood after the first may leave at most this much more resident memory than the one before
(a leak of 2.5 kB per accepted move would pass it)"""


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


def move_flood(work: Path, moves: int = 2000, move_s: float = 30.0, floods: int = 4) -> FloodResult:
    """Fault 5: once a move of :data:`RUNNING_MOVE_S` runs (its sender stays open), a sender sends
    ``moves`` valid moves as fast as the bridge takes them (each ``move_s`` long), then closes (its
    queue is dropped); ``floods`` − 1 more senders do the same, one after another. Bridge at 1× real
    time, recorded, its RSS sampled."""
    from axisflow.acquisition import MoveSender
    from axisflow.acquisition.bridge.move_queue import MAX_QUEUED_MOVES

    params = default_params()
    x = load_plant(None, params).simulation.initial_position_m
    per_sender, answer_s, marks, rss_at = [], [], {}, {}
    with Launcher(work, cwd=work) as launcher:
        rig = Rig(launcher, "move-flood")
        recorder = rig.start_recorder()
        bridge = rig.start_bridge()
        with (
            open_session(rig.options()) as session,
            RssSampler(bridge.pid, 0.1) as rss,
            MoveSender(session, KEYS) as runner,
        ):
            require_bridge(session)
            watch = StatusWatch(session)
            runner.wait_for_bridge(10.0)
            runner.send(x, 0.3, RUNNING_MOVE_S)
            if not watch.wait(MoveState.STARTED, 1, 30.0, sender=runner.sender_id):
                raise RuntimeError("the move that runs through the floods did not start within 30 s")
            rss_at["before"] = rss.after(time.monotonic())
            for flood in (f"flood {i}" for i in range(1, floods + 1)):
                marks[flood] = time.time_ns()
                counts, seconds = _flood(session, watch, 0.3, moves, move_s)  # from where it ends
                per_sender.append(counts)
                answer_s.append(seconds)
                # every move of the flood is answered and its queue dropped: the bridge has freed them
                # (its RSS stays where it is until the next flood)
                rss_at[f"after {flood}"] = rss.after(time.monotonic())
            marks["end"] = time.time_ns()
            statuses = list(watch.drain())
            watch.close()
        rss_at["peak"] = rss.peak_mb
        end = stop_rig(rig, bridge, recorder)
    return FloodResult(
        per_sender=per_sender,
        max_queued=_max_queued(statuses),
        answer_s=answer_s,
        rss_mb=rss_at,
        stalls=phase_stalls(end.state, marks),
        end=end,
        limit=MAX_QUEUED_MOVES,
    )
