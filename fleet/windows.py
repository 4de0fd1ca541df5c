"""Windows: what one identification covers — an axis over a day, a session or a fixed stretch of time.

``--window day`` (default) groups an axis's logs by the UTC day their samples fall in; ``session``
makes each log (per axis) a window of its own; ``SECONDS`` cuts time into stretches of that length
(from the Unix epoch, so that every axis shares the boundaries). A log that spans a boundary belongs
to every window it reaches, each fitting only its samples inside ``[start, end)``.

Each window has a **key**: a hash of the axis, the bounds, the content hashes of its logs (with the
topic and joint read) and the identification method (:data:`~.window_fit.METHOD`). Equal keys mean
equal work, so a re-run skips every window whose key is already in the fits table.

A window whose logs show too little motion to identify friction (:class:`MotionRule`: time moving,
reversals, top speed, from the catalog) is not fitted: its row says so.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass

from .catalog import CatalogEntry
from .errors import FleetValueError

NS_PER_S = 1_000_000_000
NS_PER_DAY = 86_400 * NS_PER_S
MIN_WINDOW_S = 10.0


@dataclass(frozen=True)
class WindowSpec:
    """``day``, ``session`` or a length in seconds."""

    kind: str
    seconds: float = 0.0

    @classmethod
    def parse(cls, text: str) -> WindowSpec:
        if text in ("day", "session"):
            return cls(text)
        try:
            seconds = float(text)
        except ValueError:
            raise FleetValueError(f"--window {text!r} must be day, session or a length in seconds") from None
        if not (math.isfinite(seconds) and seconds >= MIN_WINDOW_S):
            raise FleetValueError(f"--window {text} s must be at least {MIN_WINDOW_S:g} s")
        return cls("seconds", seconds)

    def describe(self) -> str:
        return f"{self.seconds:g} s" if self.kind == "seconds" else self.kind


@dataclass(frozen=True)
class MotionRule:
    """The least motion a window needs to be identified (summed over its logs, from the catalog)."""

    moving_s: float = 5.0
    """time moving faster than the catalog's threshold [s]"""
    reversals: int = 4
    speed_high_m_s: float = 0.05
    """the top speed reached (99th percentile while moving) [m/s]"""

    def shortfall(self, moving_s: float, reversals: int, speed_high_m_s: float) -> str:
        """Why a window with this motion cannot be identified ("" if it can)."""
        short = []
        if moving_s < self.moving_s:
            short.append(f"moving {moving_s:.1f} s < {self.moving_s:g} s")
        if reversals < self.reversals:
            short.append(f"{reversals} reversals < {self.reversals}")
        if not speed_high_m_s >= self.speed_high_m_s:
            short.append(f"top speed {speed_high_m_s:.3g} m/s < {self.speed_high_m_s:g} m/s")
        return "too little motion to identify friction: " + ", ".join(short) if short else ""


@dataclass(frozen=True)
class WindowPart:
    """One log of a window."""

    path: str
    topic: str
    joint: str
    joint_kind: str
    content_hash: str


@dataclass(frozen=True)
class Window:
    """One axis over ``[start_ns, end_ns)``, the logs that reach into it and their motion there."""

    axis: str
    start_ns: int
    end_ns: int
    parts: tuple[WindowPart, ...]
    moving_s: float
    reversals: int
    speed_high_m_s: float
    key: str


def plan_windows(entries: Sequence[CatalogEntry], spec: WindowSpec, method: str) -> list[Window]:
    """The windows of the catalog's readable entries, by axis and start (see the module docstring)."""
    groups: dict[tuple[str, int, int], list[CatalogEntry]] = {}
    for e in entries:
        if not e.ok:
            continue
        for start, end in _bounds(e, spec):
            groups.setdefault((e.axis, start, end), []).append(e)
    windows = []
    for (axis, start, end), members in sorted(groups.items()):
        members.sort(key=lambda e: (e.start_ns, e.path))
        parts = tuple(WindowPart(e.path, e.topic, e.joint, e.joint_kind, e.content_hash) for e in members)
        share = [_overlap(e, start, end) for e in members]
        windows.append(
            Window(
                axis=axis,
                start_ns=start,
                end_ns=end,
                parts=parts,
                moving_s=sum(e.moving_s * f for e, f in zip(members, share, strict=True)),
                reversals=round(sum(e.reversals * f for e, f in zip(members, share, strict=True))),
                speed_high_m_s=max(e.speed_high_m_s for e in members),
                key=window_key(axis, start, end, parts, method),
            )
        )
    return windows


def _bounds(e: CatalogEntry, spec: WindowSpec) -> list[tuple[int, int]]:
    if spec.kind == "session":
        return [(e.start_ns, e.end_ns + 1)]
    length = NS_PER_DAY if spec.kind == "day" else round(spec.seconds * NS_PER_S)
    first, last = e.start_ns // length, e.end_ns // length
    return [(k * length, (k + 1) * length) for k in range(first, last + 1)]


def _overlap(e: CatalogEntry, start: int, end: int) -> float:
    """The fraction of the log's span inside ``[start, end)``."""
    span = e.end_ns - e.start_ns
    if span <= 0:
        return 1.0
    return max(0, min(e.end_ns, end) - max(e.start_ns, start)) / span


def window_key(axis: str, start_ns: int, end_ns: int, parts: Sequence[WindowPart], method: str) -> str:
    """BLAKE2b-128 (hex) of what a window's fit depends on."""
    text = json.dumps(
        {
            "axis": axis,
            "start_ns": start_ns,
            "end_ns": end_ns,
            "logs": sorted([p.content_hash, p.topic, p.joint, p.joint_kind] for p in parts),
            "method": method,
        },
        sort_keys=True,
    )
    return hashlib.blake2b(text.encode(), digest_size=16).hexdigest()
