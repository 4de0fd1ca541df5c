"""The bridge's stack from typed settings: refused settings, and a simulated axis run through it on a
real Zenoh session on loopback, its hooks called in order with the report."""

import threading

import pytest
from axisflow.acquisition import ZenohOptions
from axisflow.model import AxisflowError, default_params

from axisflow.nodes.bridge_stack import BridgeStackSettings, StackHooks, run_bridge_stack


def test_an_unknown_drive_is_refused_naming_the_choices():
    with pytest.raises(AxisflowError, match="drive 'servo' is not one of sim, canopen, canopen-sim"):
        BridgeStackSettings(drive="servo")


def test_a_simulated_axis_runs_through_the_stack_and_reports(port):
    said = []
    hooks = StackHooks(
        started=lambda config: said.append(("started", config.keys.axis, config.drive.drive)),
        ready=lambda: said.append(("ready",)),
        reports=lambda reports, bus: said.append(("reports", {a: r.ticks for a, r in reports.items()}, bus)),
    )
    settings = BridgeStackSettings(axis="a3", speed=1.0, duration_s=0.05)
    options = ZenohOptions.loopback(listen_port=port)
    run_bridge_stack(settings, default_params(), options, threading.Event(), hooks)
    assert said == [("started", "a3", "simulated"), ("ready",), ("reports", {"a3": 50}, None)]
