"""axisflow: fast, energy-aware point-to-point motion for a belt-driven linear axis.

Layers (imports only go downwards):

* ``axisflow.model``: the axis (parameters, eq. (1) dynamics, motion laws, energy, limits)
* ``axisflow.planner``, ``axisflow.acquisition``, ``axisflow.identification``: beside each other
* ``axisflow.viz`` and the command line (``axisflow.cli``, ``axisflow.experiment``): on top
"""

__version__ = "0.1.0"
