"""Recordings: the MCAP writer (:mod:`.mcap_writer`), reading logs (:mod:`.reader`, in three layers:
framing → messages → columns; :mod:`.joint_state_layout` for JointState payloads in bulk),
:mod:`.recover` for a file whose writer was killed or whose chunks are damaged, and
:mod:`.synthetic_log` (a recording of one axis written fast, for tests and benchmarks) — none of them
loads Zenoh — and the two Zenoh ends of a log: :mod:`.recorder` (keys → MCAP) and :mod:`.replay`
(MCAP → keys)."""
