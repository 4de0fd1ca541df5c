"""Zenoh key expressions of the wire contract and their MCAP topics.

Per axis, under a configurable prefix (default ``axisflow``):

* ``<prefix>/<axis>/state`` — measured samples, ``sensor_msgs/msg/JointState`` at 1 kHz;
* ``<prefix>/<axis>/setpoint`` — what the drive is commanded each tick (same type and joints);
* ``<prefix>/<axis>/trajectory`` — moves sent to the drive, ``axisflow_msgs/msg/Move``;
* ``<prefix>/<axis>/stop`` — quick-stop requests to the bridge (abandon the queue, brake, hold);
* ``<prefix>/<axis>/event`` — the bridge's move status (accepted, rejected with the reason, started,
  completed, dropped), ``axisflow_msgs/msg/MoveStatus``;
* ``<prefix>/<axis>/plan`` — what the planner decided for each move (duration, model energy, solve
  time, certificate), ``axisflow_msgs/msg/PlanResult``;
* ``<prefix>/<axis>/params`` — an adaptive node's parameter estimates, accepted or not
  (``axisflow adapt``), ``axisflow_msgs/msg/ParamsEstimate``;
* ``<prefix>/<axis>/alive`` — a Zenoh liveliness token held by the running bridge (not pub/sub data);
* ``<prefix>/<axis>/sender/<id>`` — a liveliness token held by each move sender while it lives
  (``<id>``: the hex publisher id in its moves' attachments); a bridge runs only moves of live senders;
* ``@axisflow/hello/<key>/<id>`` — the queryable of each publisher on ``<key>``, answering hellos
  (:mod:`.hello`); the verbatim ``@axisflow`` chunk keeps it out of every ``**``;
* ``@axisflow/recorder/<host>/<pid>`` — a liveliness token held by each recorder once it is ready (its
  subscriber has joined: a session that sees the token knows the subscriber too);
* ``@axisflow/receipt/<zid>/<n>`` — the queryable of each joined subscriber that confirms receipt: its
  answer to a publisher's query proves that what the publisher sent before the query has arrived
  (:func:`~axisflow.acquisition.bus.readiness.confirm_delivery`).

The MCAP topic of a key is ``/`` + the key (``/axisflow/a0/state``).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import AcquisitionError

DEFAULT_PREFIX = "axisflow"
HELLO_PREFIX = "@axisflow/hello"
RECORDER_TOKEN_PREFIX = "@axisflow/recorder"
RECEIPT_PREFIX = "@axisflow/receipt"
DEFAULT_AXIS = "a0"
_FORBIDDEN = set("*$#?/ ")


class KeyExprError(AcquisitionError, ValueError):
    """An axis name or key prefix is not a valid Zenoh key chunk."""


def _check_chunk(kind: str, text: str, allow_slash: bool) -> None:
    bad = sorted(c for c in set(text) if c in _FORBIDDEN and not (allow_slash and c == "/"))
    if not text or bad or text.startswith("/") or text.endswith("/") or "//" in text:
        raise KeyExprError(
            f"{kind} {text!r} is not a valid key-expression part (non-empty, no leading/trailing or "
            f"double '/', none of {' '.join(sorted(_FORBIDDEN - {' '}))} or spaces; offending: {bad})"
        )


@dataclass(frozen=True)
class AxisKeys:
    """The key expressions of one axis."""

    axis: str = DEFAULT_AXIS
    prefix: str = DEFAULT_PREFIX

    def __post_init__(self) -> None:
        _check_chunk("axis name", self.axis, allow_slash=False)
        _check_chunk("key prefix", self.prefix, allow_slash=True)

    @property
    def state(self) -> str:
        return f"{self.prefix}/{self.axis}/state"

    @property
    def setpoint(self) -> str:
        return f"{self.prefix}/{self.axis}/setpoint"

    @property
    def trajectory(self) -> str:
        return f"{self.prefix}/{self.axis}/trajectory"

    @property
    def stop(self) -> str:
        """quick-stop requests for the bridge (CiA 402 quick stop: abandon the queue, brake, hold)"""
        return f"{self.prefix}/{self.axis}/stop"

    @property
    def plan(self) -> str:
        """the planner's plan record of each move"""
        return f"{self.prefix}/{self.axis}/plan"

    @property
    def params(self) -> str:
        """an adaptive node's parameter estimates (accepted or not, with the reason)"""
        return f"{self.prefix}/{self.axis}/params"

    @property
    def event(self) -> str:
        return f"{self.prefix}/{self.axis}/event"

    @property
    def drive(self) -> str:
        """what drives the axis (the bridge's DriveInfo, once a second)"""
        return f"{self.prefix}/{self.axis}/drive"

    @property
    def alive(self) -> str:
        """liveliness token of the running bridge"""
        return f"{self.prefix}/{self.axis}/alive"

    def sender(self, publisher_id: bytes) -> str:
        """liveliness token of the move sender whose moves carry ``publisher_id``"""
        return f"{self.prefix}/{self.axis}/sender/{publisher_id.hex()}"

    @property
    def senders(self) -> str:
        """key expression of every move sender's liveliness token"""
        return f"{self.prefix}/{self.axis}/sender/*"


def sender_of_token(key: str) -> bytes | None:
    """The publisher id named by a sender token's key (the inverse of :meth:`AxisKeys.sender`)."""
    try:
        return bytes.fromhex(key.rsplit("/", 1)[-1])
    except ValueError:
        return None


def all_keys(prefix: str = DEFAULT_PREFIX) -> str:
    """The key expression matching every key under ``prefix`` (``axisflow/**``)."""
    _check_chunk("key prefix", prefix, allow_slash=True)
    return f"{prefix}/**"


def key_within(expression: str, chunk: str) -> str:
    """A key (no wildcards) that ``expression`` matches: each ``*`` or ``**`` chunk, and each ``$*``
    inside a chunk, replaced by ``chunk`` (a plain chunk: wildcards do not match a verbatim ``@…``)."""
    _check_chunk("filler chunk", chunk, allow_slash=False)
    if chunk.startswith("@"):
        raise KeyExprError(f"filler chunk {chunk!r} is verbatim (starts with '@'): no wildcard matches it")
    parts = expression.split("/")
    return "/".join(chunk if part in ("*", "**") else part.replace("$*", chunk) for part in parts)


def topic_for_key(key: str) -> str:
    """MCAP topic of a key expression: ``/`` + key."""
    return "/" + key


def key_for_topic(topic: str) -> str:
    """Key expression of an MCAP topic (the inverse of :func:`topic_for_key`)."""
    return topic[1:] if topic.startswith("/") else topic


def hello_key(key: str, publisher_id: bytes) -> str:
    """The key on which the publisher ``publisher_id`` on ``key`` answers hellos."""
    return f"{HELLO_PREFIX}/{key}/{publisher_id.hex()}"


def hello_selector(key_expr: str) -> str:
    """The key expression of the hellos of every publisher whose key matches ``key_expr``."""
    return f"{HELLO_PREFIX}/{key_expr}/*"


def receipt_key(zid: str, number: int) -> str:
    """The key on which subscriber ``number`` of the Zenoh session ``zid`` confirms receipt."""
    return f"{RECEIPT_PREFIX}/{zid}/{number}"


def receipt_selector() -> str:
    """The key expression of every subscriber's receipt queryable."""
    return f"{RECEIPT_PREFIX}/**"


def recorder_token(host: str, pid: int) -> str:
    """The liveliness token of the recorder process ``pid`` on ``host``, held once it is ready."""
    _check_chunk("host name", host, allow_slash=False)
    return f"{RECORDER_TOKEN_PREFIX}/{host}/{pid}"
