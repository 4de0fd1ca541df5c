"""A move continues the axis's path: it must start where the axis will be when it starts, within a
tolerance (no jumps; :meth:`~.move_queue.MoveQueue.enqueue` checks it). The default tolerance lives
apart from the queue so that the command line offers it without loading the queue's numerics."""

DEFAULT_JUMP_TOLERANCE_M = 1e-4
"""largest accepted mismatch between a move's start position and where the axis will be [m]"""
