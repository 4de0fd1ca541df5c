"""Zenoh: sessions from the command line's flags (:mod:`.session`), the numbered publisher of the wire
contract (:mod:`.publisher`), the move sender that planners use (:mod:`.move_sender`) and the latest
sample of an axis (:mod:`.axis_state`). Import the modules themselves: this package's import loads no
Zenoh."""
