"""The drive bridge: the 1 kHz loop between a drive and Zenoh (:mod:`.bridge`), the queue of moves it
runs (:mod:`.move_queue`, no Zenoh) and the intake that validates arriving moves off the loop
(:mod:`.move_intake`). Import the modules themselves: this package's import loads no Zenoh."""
