"""The Dask cluster the fleet's work runs on.

:func:`fleet_client` gives a client: of a new :class:`distributed.LocalCluster` of ``workers``
processes (the fit holds the GIL, so threads would not run in parallel) of one thread each, so that
a worker holds one window's samples at a time; scheduler, nannies and workers listen on 127.0.0.1
only, with no dashboard (the scheduler's own HTTP server, health and metrics, on loopback at a free
port). Or a client of a running scheduler (``--scheduler tcp://host:8786``: its workers must have
axisflow installed and see the logs at the catalog's paths: docs/fleet.md). A scheduler that does not
answer within the timeout is a :class:`~.errors.FleetError` naming it. Distributed loads when a client
is made.
"""

from __future__ import annotations

import logging
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from .errors import FleetError, FleetValueError

DEFAULT_WORKERS = 2
MAX_LOCAL_WORKERS = 64
CONNECT_TIMEOUT_S = 10.0
"""how long a running scheduler has to answer [s]"""
LOOPBACK = "127.0.0.1"


@contextmanager
def fleet_client(
    workers: int = DEFAULT_WORKERS, scheduler: str | None = None, timeout_s: float = CONNECT_TIMEOUT_S
) -> Iterator[Any]:
    """A :class:`distributed.Client` (see the module docstring), closed (with its cluster) on exit."""
    from distributed import Client, LocalCluster

    if not (0.0 < timeout_s <= 3600.0):
        raise FleetValueError(f"--connect-timeout {timeout_s} s must be within (0, 3600] s")
    if scheduler is not None:
        try:
            client = Client(scheduler, timeout=f"{timeout_s}s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise FleetError(
                f"scheduler {scheduler} does not answer within {timeout_s:g} s ({type(exc).__name__})"
            ) from None
        with client:
            yield client
        return
    if not 1 <= workers <= MAX_LOCAL_WORKERS:
        raise FleetValueError(f"--workers {workers} must be within [1, {MAX_LOCAL_WORKERS}] workers")
    cluster = LocalCluster(
        n_workers=workers,
        threads_per_worker=1,
        processes=True,
        host=LOOPBACK,
        scheduler_port=0,
        dashboard_address=None,
        worker_dashboard_address=None,
        # no dashboard; the scheduler's own HTTP server (health, metrics) on loopback, any free port
        scheduler_kwargs={"dashboard": False, "dashboard_address": f"{LOOPBACK}:0"},
        silence_logs=logging.ERROR,
    )
    with cluster, Client(cluster) as client:
        yield client
