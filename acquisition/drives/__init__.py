"""The drive side of the bridge (no Zenoh here): the drive interface (:mod:`.drive`) and its
implementations — the built-in simulated axis (:mod:`.sim_axis`, with its plant file) and CiA 402 servo
drives over CANopen, real or simulated (:mod:`.canopen`, docs/drives.md)."""
