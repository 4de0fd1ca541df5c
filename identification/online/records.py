"""An adaptive node's parameters read back from a recording: the last accepted estimate (or a given
version) as a parameter file every ``--params`` takes (``axisflow params --from LOG.mcap``)."""

from __future__ import annotations

from pathlib import Path

from ...acquisition.logs.reader import read_messages
from ...acquisition.wire.keys import AxisKeys, topic_for_key
from ...acquisition.wire.params_estimate import PARAMS_ESTIMATE_TYPE, ParamsEstimate
from ...model import AxisParams
from ...model.params import params_to_toml
from ..errors import IdentificationError


def recorded_estimates(path: str | Path, keys: AxisKeys) -> list[ParamsEstimate]:
    """Every parameter estimate of the axis ``keys`` in the recording ``path``, in recording order."""
    topic = topic_for_key(keys.params)
    return [ParamsEstimate.decode(m.data) for m in read_messages(path, topic, PARAMS_ESTIMATE_TYPE)]


def accepted_estimate(path: str | Path, keys: AxisKeys, version: int | None = None) -> ParamsEstimate:
    """The accepted estimate of version ``version`` (default: the newest) of the axis ``keys`` recorded
    in ``path``; an :class:`IdentificationError` naming what the recording holds otherwise."""
    records = [r for r in recorded_estimates(path, keys) if r.accepted]
    if not records:
        raise IdentificationError(
            f"{path} holds no accepted parameter estimate on {topic_for_key(keys.params)}: record while "
            "`axisflow adapt` runs (it publishes one per decision)"
        )
    if version is None:
        return max(records, key=lambda r: r.version)
    found = [r for r in records if r.version == version]
    if not found:
        versions = sorted({r.version for r in records})
        raise IdentificationError(
            f"{path}: no accepted estimate of version {version} on {topic_for_key(keys.params)} (versions "
            f"{versions[0]}…{versions[-1]} are there)"
        )
    return found[-1]


def adapted_params_file(record: ParamsEstimate, base: AxisParams, source: str) -> str:
    """A complete parameter file: ``base`` with the record's M_eq (as the cart mass) and friction law
    (the offset and asymmetry on as the record has them)."""
    params = record.applied_to(base)
    window = (record.window_end_ns - record.window_start_ns) * 1e-9
    head = (
        f"# Adapted parameters, version {record.version} of axis {record.axis!r}, read from {source}:\n"
        f"# {record.decision.value} on a window of {window:.1f} s ending at {record.window_end_ns} ns "
        f"(drive time), terms {', '.join(record.fitted) or 'none'}.\n"
        "# M_eq is written as the cart mass m (rotor, gearbox and pulley inertias as in the base file).\n"
    )
    return head + params_to_toml(params)
