"""CiA 402 servo drives over CANopen: the bridge's drive interface for a real drive, and a simulated one.

One concept per module, from the wire up:

* :mod:`.objects` — the object dictionary entries axisflow uses (index, type, unit, why) and the
  PDO layout; :mod:`.cia402` — the drive state machine's bits and transitions;
* :mod:`.config` — ``drive.toml`` (the bus and its drives) as validated data;
* :mod:`.network` — opening a python-can bus under a canopen network;
* :mod:`.startup` — the master's start-up of a drive over SDO and NMT;
* :mod:`.emergency` — the CiA 301 emergency codes: names, classes, error register bits;
* :mod:`.faults` — a drive's health and the typed events it reports;
* :mod:`.adapter` — :class:`CanopenDrive`, the :class:`~axisflow.acquisition.drives.drive.Drive` of one
  drive; :mod:`.clock` and :mod:`.cycle` — the bus's drive time and the cycle owner (one SYNC for every
  drive, wall or lock-step pacing); :mod:`.master` — all of it opened from a configuration;
* :mod:`.sim_slave` — a simulated CiA 301 slave (SDO, NMT, heartbeat, SYNC, PDOs) for a device
  profile; :mod:`.sim_drive` — :class:`SimulatedDrive`, the CiA 402 profile on it, a drive around the
  simulated axis's plant.

No Zenoh here (tests/test_layers.py); docs/drives.md tells how to connect a real drive.
"""
