"""The drive side of the bridge (no Zenoh here): the drive interface (:mod:`.drive`) and its
implementations — the built-in simulated axis: its plant file and profiles (:mod:`.plant`), the
mechanics it integrates (:mod:`.mechanics`), its friction over time (:mod:`.friction_drift`) and the
simulated drive in front of them (:mod:`.sim_axis`) — and CiA 402 servo drives over CANopen, real
or simulated (:mod:`.canopen`, docs/drives.md)."""
