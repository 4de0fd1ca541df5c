"""Fault 4: ≥ 1000 malformed, truncated, oversized and random payloads on the trajectory key → each
rejected with a reason; every tick recorded, 1 ms apart."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

from ...acquisition import MoveState, MoveStatus, load_plant, open_session
from ...deploy.processes import Launcher
from ...model import default_params
from .outcome import FaultResult, Outcome
from .payloads import BadPayload, PayloadCatalog, RawSender
from .rig import Rig, RssSampler, RunEnd, StatusWatch, require_bridge, stop_rig
from .ticks import Stalls, phase_stalls


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
    with Launcher(work, cwd=work) as launcher:
        rig = Rig(launcher, "bad-payloads")
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
            time.sleep(1.0)  # a quiet second: the ticks' timing with nothing sent, to compare with
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
            statuses = list(watch.settled())  # and anything after the last rejection (there must be none)
            watch.close()
            for sender in senders.values():
                sender.close()
        end = stop_rig(rig, bridge, recorder)
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
