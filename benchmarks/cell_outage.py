"""What a cell's bridges and recorder do when the router goes away: measured with real processes.

A cell (:class:`axisflow.deploy.cell.Cell`) of N simulated bridges at 1× real time and a recorder, all
clients of one router on loopback; this process is the planner (a client too, one
:class:`~axisflow.acquisition.MoveSender` per axis). On every axis a move runs and another waits
behind it when the router goes:

* **restart**: the router is stopped (SIGINT) and a new one started on the same endpoint — a router
  host rebooted, or ``axisflow router`` restarted to read a new access list. Its clients see their
  links close at once.
* **freeze**: the router is stopped with SIGSTOP — a router that hangs, or a network that fails
  silently: the links stay open and carry nothing, and the clients notice only when the lease runs
  out (``transport/link/tx/lease``, 10 s by default); then SIGCONT.

Measured per outage: when the clients noticed (the planner's session lost its router), per axis the
samples lost (the recorder's sequence gaps: how many, from when), when the recorder wrote samples again
after the new router listened (or after SIGCONT), what each bridge did with its moves (the running one
completed, the queued one dropped with its sender's token), and that a move sent once the router was
back completed.
"""

from __future__ import annotations

import os
import signal
import time
from contextlib import ExitStack
from pathlib import Path

import numpy as np
from axisflow.acquisition import AxisKeys, MoveSender, MoveState, ZenohOptions, open_session
from axisflow.acquisition.logs.reader import read_joint_states
from axisflow.acquisition.wire.keys import topic_for_key

from axisflow.deploy.cell import Cell, CellLayout
from axisflow.deploy.processes import wait_until

RUNNING = {"restart": (0.0, 0.3, 4.0), "freeze": (0.0, 0.3, 16.0)}
"""the move running when the router goes [m, m, s]: it outlasts the outage's detection"""
QUEUED = (0.3, 0.7, 2.0)
"""the move queued behind it (dropped once its sender's token vanishes)"""
AFTER = (0.3, 0.15, 1.0)
"""the move sent once the router is back (from where the running move ended)"""
WAIT_S = 60.0


def measure_outages(tmp: Path, n_axes: int) -> dict[str, dict]:
    """Both outages with ``n_axes`` bridges (see the module docstring)."""
    return {kind: _measure(tmp, n_axes, kind) for kind in ("restart", "freeze")}


def _measure(tmp: Path, n_axes: int, kind: str) -> dict:
    layout = CellLayout.on_loopback(n_axes)
    recording = tmp / f"outage-{kind}.mcap"
    with Cell(layout, tmp / f"logs-{kind}") as cell, ExitStack() as stack:
        cell.start_router()
        cell.start_recorder(recording)
        cell.start_bridges(wait_subscribers_s=10.0)
        session = stack.enter_context(open_session(ZenohOptions(mode="client", connect=(layout.endpoint,))))
        senders = {axis: stack.enter_context(MoveSender(session, AxisKeys(axis))) for axis in layout.axes}
        _start_moves(senders, RUNNING[kind])
        went_wall_ns = time.time_ns()
        went = time.monotonic()
        if kind == "restart":
            restart = cell.restart_router()
            noticed_s = None
            back_from = restart.listening_s
            back_from_wall_ns = went_wall_ns + int((back_from - went) * 1e9)
            router_down_s = restart.down_s
        else:
            assert cell.router is not None
            os.kill(cell.router.pid, signal.SIGSTOP)
            wait_until(lambda: not list(session.info.routers_zid()), WAIT_S)
            noticed_s = time.monotonic() - went
            os.kill(cell.router.pid, signal.SIGCONT)
            back_from, back_from_wall_ns = time.monotonic(), time.time_ns()
            router_down_s = back_from - went
        wait_until(lambda: all(s.bridge_alive for s in senders.values()), WAIT_S)
        planner_back_s = time.monotonic() - back_from
        after_ok = _move_after(senders)
        stack.close()
        bridges = cell.stop_bridges()
        summary = cell.stop_recorder()
        cell.stop_router()
    axes = {
        axis: _axis_outage(recording, axis, summary, bridges[axis], went_wall_ns, back_from_wall_ns)
        for axis in layout.axes
    }
    recording.unlink(missing_ok=True)
    return {
        "axes": n_axes,
        "router_down_s": router_down_s,
        "noticed_after_s": noticed_s,
        "planner_back_after_s": planner_back_s,
        "move_after_completed": after_ok,
        "per_axis": axes,
    }


def _start_moves(senders: dict[str, MoveSender], running: tuple[float, float, float]) -> None:
    first, queued = {}, {}
    for axis, sender in senders.items():
        if not sender.wait_for_bridge(WAIT_S):
            raise RuntimeError(f"the bridge of {axis} did not answer")
        first[axis] = sender.send(*running)
        queued[axis] = sender.send(*QUEUED)
    for axis, sender in senders.items():  # the first runs, the second waits in the bridge's queue
        for move, state in ((first[axis], MoveState.STARTED), (queued[axis], MoveState.ACCEPTED)):
            said = sender.wait_status(move.move_id, {state}, WAIT_S)
            if said is None or said.state is not state:
                raise RuntimeError(f"move {move.move_id} of {axis} was not {state.name.lower()}: {said}")


def _move_after(senders: dict[str, MoveSender]) -> bool:
    """Whether a move sent now (from where the running move ends) completes on every axis."""
    sent = {axis: sender.send(*AFTER) for axis, sender in senders.items()}
    done = [s.wait_status(sent[a].move_id, {MoveState.COMPLETED}, WAIT_S) for a, s in senders.items()]
    return all(d is not None and d.state is MoveState.COMPLETED for d in done)


def _axis_outage(
    path: Path, axis: str, summary: dict, bridge: dict, went_wall_ns: int, back_wall_ns: int
) -> dict:
    """One axis: its bridge's moves, the samples the recorder missed and where, and when samples
    flowed again (the first written after the router was back, by the recorder's clock)."""
    topic = topic_for_key(AxisKeys(axis).state)
    stats = summary["topics"][topic]
    columns = read_joint_states(path, topic)
    seq, stamps = columns.sequence, columns.stamp_ns
    gaps = np.flatnonzero(np.diff(seq) > 1)
    first_gap_ms = (stamps[gaps[0]] - went_wall_ns) / 1e6 if len(gaps) else None
    resumed = columns.log_time_ns[columns.log_time_ns >= back_wall_ns]
    return {
        "ticks": bridge["ticks"],
        "recorded": stats["messages"],
        "missed": stats["missed"],
        "duplicates": stats["duplicates"],
        "gaps": len(gaps),
        "first_gap_after_ms": first_gap_ms,
        "resumed_after_back_ms": (resumed.min() - back_wall_ns) / 1e6 if resumed.size else None,
        "moves_completed": bridge["moves_completed"],
        "moves_dropped": bridge["moves_dropped"],
        "moves_rejected": bridge["moves_rejected"],
    }


def format_outages(outages: dict[str, dict]) -> str:
    lines = ["outages (bridges at 1× real time, a move running and one queued on each axis):"]
    for kind, o in outages.items():
        what = (
            f"router restarted (SIGINT, new router listening {o['router_down_s']:.2f} s later)"
            if kind == "restart"
            else f"router frozen (SIGSTOP; the clients noticed after {o['noticed_after_s']:.2f} s; SIGCONT)"
        )
        lines.append(
            f"  {kind}: {what}; the planner saw every bridge again {o['planner_back_after_s']:.2f} s after "
            f"the router was back; a move sent then completed on every axis: {o['move_after_completed']}"
        )
        for axis, a in o["per_axis"].items():
            lines.append(
                f"    {axis}: {a['recorded']} of {a['ticks']} samples recorded, {a['missed']} missed in "
                f"{a['gaps']} gap(s) (the first from {a['first_gap_after_ms']:.0f} ms after the router "
                f"went), duplicates {a['duplicates']}; written again "
                f"{a['resumed_after_back_ms']:.0f} ms after it was back; moves completed "
                f"{a['moves_completed']}, dropped {a['moves_dropped']}, rejected {a['moves_rejected']}"
            )
    return "\n".join(lines)
