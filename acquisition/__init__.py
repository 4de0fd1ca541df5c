"""Data acquisition: the Zenoh drive bridge, the simulated axis and the MCAP recorder (see issue 4)."""
