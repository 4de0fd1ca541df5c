"""axisflow: fast, energy-aware point-to-point motion for a belt-driven linear axis.

Layers (imports only go downwards; tests/test_layers.py checks every import):

* ``axisflow.model``: the axis (parameters, eq. (1) dynamics, motion laws, energy, limits)
* ``axisflow.planner``, ``axisflow.acquisition``, ``axisflow.identification``: beside each other
* ``axisflow.viz``: the views
* the top floor, in rooms: ``axisflow.experiment`` (the paper's experiment and its records) <
  ``axisflow.nodes`` (the programs that talk to a bridge) < ``axisflow.deploy`` (processes, cells,
  security) < ``axisflow.demo``; then ``axisflow.benchmarks`` and the command line (``axisflow.cli``)

The repository keeps one top-level folder per sub-package (``model/`` installs as ``axisflow.model``,
``benchmarks/`` as ``axisflow.benchmarks``: pyproject.toml maps them); docs/architecture.md draws the
imports between the packages.
"""

__version__ = "0.1.0"
