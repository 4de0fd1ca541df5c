"""Bad payloads for a bridge's trajectory key (catalogued and generated, seeded), and a sender that
puts raw bytes there."""

from __future__ import annotations

import struct
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ...acquisition import AxisKeys
from ...model import AxisParams
from .rig import KEYS

_F64 = struct.Struct("<d")
_U32 = struct.Struct("<I")


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
