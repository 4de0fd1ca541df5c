"""What a user saves: axisflow's moves against the profiles drives run today (``axisflow savings``).

The moves (:mod:`.cycle_moves`), the comparison planned on the model (:mod:`.comparison`), its runs on
a simulated axis (:mod:`.axis_run`) measured from the recording (:mod:`.measurement`), the report
(:mod:`.report`), and the whole as one call (:mod:`.study`). docs/savings.md has the figures.
"""
