"""An adaptive node's parameters read back from a recording: the library and ``axisflow params --from``."""

import math

import pytest
from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter
from axisflow.acquisition.wire.keys import AxisKeys, topic_for_key
from axisflow.acquisition.wire.params_estimate import PARAMS_ESTIMATE_TYPE, Decision, ParamsEstimate
from axisflow.identification.errors import IdentificationError
from axisflow.identification.fit import FrictionValues
from axisflow.identification.online.records import accepted_estimate, recorded_estimates
from axisflow.model import default_params, load_params

BASE = default_params()
T0 = 1_767_225_600_000_000_000


def _record(k: int, version: int, decision: Decision, a2: float, axis: str = "a0") -> ParamsEstimate:
    base = version if decision is not Decision.ACCEPTED else version - 1
    values = (BASE.M_eq + k, BASE.a1 * 0.9, a2, BASE.a3 * 0.9, BASE.a4)
    return ParamsEstimate(
        T0 + k * 10**9, axis, version, base, decision, f"record {k}", ("M_eq", "a2", "coulomb"), values,
        (0.1, 0.5, 1.0, 1.1, math.nan), T0 + (k - 30) * 10**9, T0 + k * 10**9, 1500, 0.01, 0.011, 0.012,
    )  # fmt: skip


RECORDS = [
    _record(0, 0, Decision.INITIAL, BASE.a2),
    _record(1, 1, Decision.ACCEPTED, 190.0),
    _record(2, 2, Decision.ACCEPTED, 180.0),
    _record(3, 2, Decision.NO_IMPROVEMENT, 120.0),  # turned down: never read back
    _record(4, 5, Decision.ACCEPTED, 100.0, axis="a1"),  # another axis's
]


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    path = tmp_path_factory.mktemp("records") / "adapt.mcap"
    writer = Ros2McapWriter(path)
    channels = {
        a: writer.channel_for(topic_for_key(AxisKeys(a).params), PARAMS_ESTIMATE_TYPE) for a in ("a0", "a1")
    }
    for n, r in enumerate(RECORDS, start=1):
        writer.add(channels[r.axis], r.stamp_ns, r.stamp_ns, n, r.encode())
    writer.finish()
    return path


def test_the_newest_accepted_estimate_or_a_given_version(recording):
    assert [r.version for r in recorded_estimates(recording, AxisKeys("a0"))] == [0, 1, 2, 2]
    newest = accepted_estimate(recording, AxisKeys("a0"))
    assert (newest.version, newest.value_of["a2"]) == (2, 180.0)
    assert accepted_estimate(recording, AxisKeys("a0"), 1).value_of["a2"] == 190.0
    assert accepted_estimate(recording, AxisKeys("a1")).version == 5
    with pytest.raises(IdentificationError, match=r"no accepted estimate of version 7 .* \(versions 0…2"):
        accepted_estimate(recording, AxisKeys("a0"), 7)
    with pytest.raises(
        IdentificationError, match="holds no accepted parameter estimate on /axisflow/a2/params"
    ):
        accepted_estimate(recording, AxisKeys("a2"))


def test_params_from_writes_a_parameter_file_every_params_takes(recording, tmp_path, cli):
    out = tmp_path / "adapted.toml"
    done = cli.run("params", "--from", str(recording), "--out", str(out), "--json")
    assert done.returncode == 0, done.stderr
    params = load_params(out)
    assert params == RECORDS[2].applied_to(BASE)
    assert params.a2 == 180.0 and params.M_eq == pytest.approx(BASE.M_eq + 2, rel=1e-12)
    assert "version 2 of axis 'a0'" in out.read_text().splitlines()[0]
    again = cli.run("params", "--from", str(recording), "--version", "1", "--out", str(out))
    assert again.returncode == 2 and "already exists" in again.stderr and load_params(out).a2 == 180.0
    shown = cli.run("params", "--params", str(out), "--json")
    assert '"a2": 180.0' in shown.stdout


def test_params_from_carries_the_terms_beside_eq1_of_the_record(tmp_path, cli):
    """An adapted ball-screw axis (docs/axes): the file written back has the record's offset and
    asymmetry, and its transmission; a parameter file without them gets them from the record."""
    from pathlib import Path

    axes = Path(__file__).parents[3] / "docs" / "axes"
    axis = load_params(axes / "ball-screw.toml")
    values = (axis.M_eq * 1.01, 38.0, 290.0, 0.0, 0.0, axis.f0, 6.5, 27.0)
    start = tuple(FrictionValues.of(axis).as_dict().values())  # the wire's order: M_eq, a1…a4, f0, da1, da2
    fitted = ("M_eq", "a2", "da1", "da2")
    records = [
        ParamsEstimate(T0, "a0", 0, 0, Decision.INITIAL, "start", values=start),
        ParamsEstimate(T0 + 10**9, "a0", 1, 0, Decision.ACCEPTED, "accepted", fitted, values),
    ]
    path = tmp_path / "screw.mcap"
    writer = Ros2McapWriter(path)
    channel = writer.channel_for(topic_for_key(AxisKeys("a0").params), PARAMS_ESTIMATE_TYPE)
    for n, r in enumerate(records, start=1):
        writer.add(channel, r.stamp_ns, r.stamp_ns, n, r.encode())
    writer.finish()
    out = tmp_path / "adapted.toml"
    done = cli.run(
        "params", "--from", str(path), "--params", str(axes / "ball-screw.toml"), "--out", str(out)
    )
    assert done.returncode == 0, done.stderr
    adapted = load_params(out)
    assert (adapted.kind, adapted.lead) == ("ball-screw", axis.lead)
    assert (adapted.a1, adapted.a2, adapted.f0, adapted.da1, adapted.da2) == (38.0, 290.0, axis.f0, 6.5, 27.0)
    assert adapted.terms == axis.terms and adapted.M_eq == pytest.approx(axis.M_eq * 1.01, rel=1e-12)
