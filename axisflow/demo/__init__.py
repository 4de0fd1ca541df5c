"""The demo: the whole loop on one simulated axis (``axisflow demo``), its settings, and the demo of a
cell of several axes."""
