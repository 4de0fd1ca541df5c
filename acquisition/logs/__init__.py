"""Recordings: the MCAP writer (:mod:`.mcap_writer`), reading logs (:mod:`.recording`,
:mod:`.log_reader`, :mod:`.joint_state_layout`), :mod:`.recover` for a file whose writer was killed —
none of them loads Zenoh — and the two Zenoh ends of a log: :mod:`.recorder` (keys → MCAP) and
:mod:`.replay` (MCAP → keys)."""
