"""rerun views of the axis signals, live and from logs."""
