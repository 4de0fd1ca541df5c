"""What a planner decided for a move: the typed plan record of the wire contract.

The planner node publishes one :class:`PlanRecord` per move on ``<prefix>/<axis>/plan`` when the plan
is ready, before it sends the move, so that a recording alone holds everything the paper's Table 2
needs (the planned duration and model energy E_th, the objective, the solver's status, iterations
and solve time, the certificate where there is one) next to what the axis did with it (the move
status) and what it cost (the measured torque and speed).

``run`` labels a run of the planner (e.g. ``nominal``, ``refit``); ``waypoint_index`` is k for the
move from way point k − 1 to k, and 0 for a move that only brings the axis to the first way point
(not part of the experiment). The certificate crosses as parallel ``certificate_keys`` and
``certificate_values`` (the planner's ``Certificate.to_dict()``; empty when nothing is proved).

``params_version`` names the parameter set the plan used: 0 for the planner's own (``--params``), N for
version N of an adaptive node's accepted estimates (``axisflow planner --adapt``,
:mod:`.params_estimate`). It was appended to the record: a record written before it existed decodes
with 0.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import WireError
from .cdr import HEADER_DEPENDENCIES, CdrReader, CdrWriter, read_time, schema_with_dependencies, write_time

PLAN_TYPE = "axisflow_msgs/msg/PlanResult"

PLAN_SCHEMA = schema_with_dependencies(
    "# What a planner decided for one move, published when the plan was ready.\n"
    "# header.stamp: when the plan was ready (ns since the Unix epoch); header.frame_id: the axis name.\n"
    "std_msgs/Header header\n"
    "# the move's identifier (the Move message's move_id) and its sender's publisher id (hex), as in\n"
    "# the bridge's MoveStatus\n"
    "uint64 move_id\n"
    "string sender\n"
    "# label of the planner's run, e.g. nominal or refit\n"
    "string run\n"
    "# k for the move from way point k-1 to way point k; 0 for a move to the first way point\n"
    "uint32 waypoint_index\n"
    "# min-time or min-time-energy; poly3, poly5 or poly7; exact or ipopt\n"
    "string case\n"
    "string law\n"
    "string solver\n"
    "float64 omega\n"
    "float64 start_position_m\n"
    "float64 end_position_m\n"
    "float64 duration_s\n"
    "# model energy E_th of the move [J] under energy_accounting, and the objective of eq. (2)/(3)\n"
    "float64 energy_j\n"
    "string energy_accounting\n"
    "float64 objective\n"
    "# worst relative excess over a limit at the 1 kHz samples (0.01 = 1 %)\n"
    "float64 max_violation\n"
    "string status\n"
    "int32 iterations\n"
    "float64 solve_time_s\n"
    "# the certificate's quantities (seconds, joules, J/s), empty when nothing is proved\n"
    "string[] certificate_keys\n"
    "float64[] certificate_values\n"
    "# the parameter set the plan used: 0 the planner's own, N version N of an adaptive node's estimates\n"
    "uint32 params_version\n",
    *HEADER_DEPENDENCIES,
)


@dataclass(frozen=True)
class PlanRecord:
    """``axisflow_msgs/msg/PlanResult`` (see the module docstring)."""

    stamp_ns: int
    axis: str
    move_id: int
    sender: str
    """the hex publisher id of the MoveSender that sent the move (move ids are unique per sender)"""
    run: str
    waypoint_index: int
    case: str
    law: str
    solver: str
    omega: float
    start_position_m: float
    end_position_m: float
    duration_s: float
    energy_j: float
    energy_accounting: str
    objective: float
    max_violation: float
    status: str
    iterations: int
    solve_time_s: float
    certificate: dict[str, float] = field(default_factory=dict)
    params_version: int = 0
    """the parameter set the plan used (0: the planner's own; see the module docstring)"""

    def __post_init__(self) -> None:
        if not 0 <= self.move_id < 2**64:
            raise WireError(f"move_id = {self.move_id} must be in [0, 2**64)")
        if not 0 <= self.waypoint_index < 2**32:
            raise WireError(f"waypoint_index = {self.waypoint_index} must be in [0, 2**32)")
        if not 0 <= self.params_version < 2**32:
            raise WireError(f"params_version = {self.params_version} must be in [0, 2**32)")

    def encode(self) -> bytes:
        w = CdrWriter()
        write_time(w, self.stamp_ns)
        w.string(self.axis)
        w.uint64(self.move_id)
        w.string(self.sender)
        w.string(self.run)
        w.uint32(self.waypoint_index)
        for text in (self.case, self.law, self.solver):
            w.string(text)
        for value in (self.omega, self.start_position_m, self.end_position_m, self.duration_s, self.energy_j):
            w.float64(value)
        w.string(self.energy_accounting)
        w.float64(self.objective)
        w.float64(self.max_violation)
        w.string(self.status)
        w.int32(self.iterations)
        w.float64(self.solve_time_s)
        w.string_sequence(tuple(self.certificate))
        w.float64_sequence(tuple(self.certificate.values()))
        w.uint32(self.params_version)
        return w.to_bytes()

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> PlanRecord:
        r = CdrReader(data, PLAN_TYPE)
        stamp_ns, axis, move_id, sender = read_time(r), r.string(), r.uint64(), r.string()
        run, index = r.string(), r.uint32()
        case, law, solver = r.string(), r.string(), r.string()
        omega, x0, x1, duration, energy = (r.float64() for _ in range(5))
        accounting, objective, violation = r.string(), r.float64(), r.float64()
        status, iterations, solve_time = r.string(), r.int32(), r.float64()
        keys, values = r.string_sequence(), r.float64_sequence()
        if len(keys) != len(values):
            raise WireError(f"{PLAN_TYPE}: {len(keys)} certificate keys but {len(values)} values")
        certificate = dict(zip(keys, values, strict=True))
        version = 0 if r.at_end else r.uint32()  # a record written before the field existed: 0
        return cls(
            stamp_ns, axis, move_id, sender, run, index, case, law, solver, omega, x0, x1, duration, energy,
            accounting, objective, violation, status, iterations, solve_time, certificate, version,
        )  # fmt: skip
