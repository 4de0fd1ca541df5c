"""The wire contract: what crosses Zenoh and lands in MCAP (no Zenoh here).

Key expressions (:mod:`.keys`), the ROS 2 CDR codec (:mod:`.cdr`) and the records built on it — samples
and moves (:mod:`.messages`), move statuses (:mod:`.move_status`), plans (:mod:`.plan_record`), quick
stops (:mod:`.quick_stop`) — and the rmw_zenoh-style attachment every message carries
(:mod:`.attachment`). Each record round-trips through ``encode``/``decode`` (tests/acquisition/wire).
"""
