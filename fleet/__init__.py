"""A fleet of axes over months: a catalog of their logs, every axis identified per window on Dask
distributed, friction and energy trends, wear alarms, a report (docs/fleet.md).

Uses the model, acquisition (the log reader, the simulated plant) and identification (the same
``identify`` as ``axisflow identify``); only the command line, the top floor and the benchmarks use it.
Dask and pyarrow load with the modules that need them.
"""
