"""Where each signal of an axis lives in a rerun recording: the entity paths and the one timeline.

Every axis found in a log or on the network gets a subtree ``axes/<label>`` (``<label>`` is the axis
name for the default key prefix ``axisflow``, else ``<prefix>/<axis>``), one entity per signal, grouped
by the plot that shows it::

    axes/<label>/position/measured     carriage position x [m], state            Scalars
    axes/<label>/position/setpoint     commanded position [m], setpoint            Scalars
    axes/<label>/position/stroke       0 and L [m] (two series)                    Scalars
    axes/<label>/position/waypoints    each planned move's end position [m]        Scalars (points)
    axes/<label>/velocity/measured     cart velocity [m/s], state                  Scalars
    axes/<label>/velocity/setpoint     commanded velocity [m/s]                    Scalars
    axes/<label>/velocity/limits       ±v_max [m/s]                                Scalars
    axes/<label>/torque/measured       motor torque τ_m [N·m], state               Scalars
    axes/<label>/torque/feedforward    the setpoint's model feed-forward τ_ff [N·m] Scalars
    axes/<label>/torque/limits         ±tau_max [N·m]                              Scalars
    axes/<label>/tracking_error        setpoint − measured position [m]            Scalars
    axes/<label>/power/measured        τ_m·ω_m [W]                                 Scalars
    axes/<label>/energy/measured       ∫ g(τ_m·ω_m) dt over each move's ticks [J]  Scalars (points)
    axes/<label>/energy/planned        the plan's model energy E_th [J]            Scalars (points)
    axes/<label>/energy_error          E% = (E_th − E_exp)/E_th of each move [%]   Scalars (points)
    axes/<label>/params/<name>         an adaptive node's accepted M_eq, a1…a4, f0,
                                       da1, da2 (those not 0 in its version 0), in
                                       % of version 0, with ±σ (three series)      Scalars
    axes/<label>/params/rejected/<name> estimates it turned down, the same units   Scalars (points)
    axes/<label>/friction/now          F_c(ẋ) [N] over ±v_max of the accepted set
                                       (both directions, f0 at rest)               LineStrips2D
    axes/<label>/friction/start        F_c(ẋ) [N] of version 0                     LineStrips2D
    axes/<label>/events                the bridge's move statuses                  TextLog

Everything is on one timeline, :data:`TIMELINE`: the drive time of the sample (the JointState
``header.stamp``, the move status's ``header.stamp``) as a rerun timestamp with integer nanoseconds
since the Unix epoch — the same instant has the same time in every entity.
"""

from __future__ import annotations

from dataclasses import dataclass

TIMELINE = "stamp"
"""the one timeline: drive time [ns since the Unix epoch]"""
ROOT = "axes"


@dataclass(frozen=True)
class AxisEntities:
    """The entity paths of one axis (see the module docstring)."""

    label: str

    @property
    def root(self) -> str:
        return f"{ROOT}/{self.label}"

    def plot(self, name: str) -> str:
        """The subtree of one plot: ``position``, ``velocity``, ``torque``, ``tracking_error``,
        ``power``, ``energy``."""
        return f"{self.root}/{name}"

    @property
    def position_measured(self) -> str:
        return f"{self.root}/position/measured"

    @property
    def position_setpoint(self) -> str:
        return f"{self.root}/position/setpoint"

    @property
    def stroke(self) -> str:
        return f"{self.root}/position/stroke"

    @property
    def waypoints(self) -> str:
        return f"{self.root}/position/waypoints"

    @property
    def velocity_measured(self) -> str:
        return f"{self.root}/velocity/measured"

    @property
    def velocity_setpoint(self) -> str:
        return f"{self.root}/velocity/setpoint"

    @property
    def velocity_limits(self) -> str:
        return f"{self.root}/velocity/limits"

    @property
    def torque_measured(self) -> str:
        return f"{self.root}/torque/measured"

    @property
    def torque_feedforward(self) -> str:
        return f"{self.root}/torque/feedforward"

    @property
    def torque_limits(self) -> str:
        return f"{self.root}/torque/limits"

    @property
    def tracking_error(self) -> str:
        return f"{self.root}/tracking_error"

    @property
    def power(self) -> str:
        return f"{self.root}/power/measured"

    @property
    def energy_measured(self) -> str:
        return f"{self.root}/energy/measured"

    @property
    def energy_planned(self) -> str:
        return f"{self.root}/energy/planned"

    @property
    def energy_error(self) -> str:
        return f"{self.root}/energy_error"

    def parameter(self, name: str) -> str:
        """an accepted parameter with its σ band, in % of the adaptive node's version 0"""
        return f"{self.root}/params/{name}"

    def rejected_parameter(self, name: str) -> str:
        return f"{self.root}/params/rejected/{name}"

    @property
    def friction(self) -> str:
        return f"{self.root}/friction"

    @property
    def friction_now(self) -> str:
        return f"{self.root}/friction/now"

    @property
    def friction_start(self) -> str:
        return f"{self.root}/friction/start"

    @property
    def events(self) -> str:
        return f"{self.root}/events"
