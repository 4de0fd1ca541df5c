"""Reading MCAP logs, in three layers (in the spirit of the mcap library: bytes → records → messages):

=================  ===================================================================================
module             layer
=================  ===================================================================================
:mod:`.framing`    file, chunks, records: the magic, the summary, the walk over top-level records, a
                   chunk's header, message indexes, decompression and CRC check, the records inside a
                   chunk; truncation (a crash) and chunks that cannot be read (:class:`DamagedChunk`)
:mod:`.messages`   typed messages: schemas and channels (:class:`TopicInfo`), the selected channels'
                   message records a chunk at a time with their raw payloads (:class:`MessageScan`),
                   :func:`list_topics`, :func:`read_messages`, :func:`iter_recording`; chunks that
                   cannot be read are skipped and said (:class:`SkippedChunk`)
:mod:`.columns`    columns: one JointState topic as numpy arrays, vectorised where payloads share one
                   layout (:func:`read_joint_states`, :class:`JointStateColumns` with its holes)
=================  ===================================================================================

Every command that reads a log reads it through these (identify, table2, view, replay, recover,
figures). None of them loads Zenoh.
"""

from .columns import Hole, JointColumns, JointStateColumns, read_joint_states
from .framing import MCAP_MAGIC, DamagedChunk, McapFile, check_mcap, is_complete
from .messages import (
    RawMessage,
    RecordedMessage,
    SkippedChunk,
    TopicInfo,
    iter_recording,
    list_topics,
    read_messages,
)

__all__ = [
    "MCAP_MAGIC",
    "DamagedChunk",
    "Hole",
    "JointColumns",
    "JointStateColumns",
    "McapFile",
    "RawMessage",
    "RecordedMessage",
    "SkippedChunk",
    "TopicInfo",
    "check_mcap",
    "is_complete",
    "iter_recording",
    "list_topics",
    "read_joint_states",
    "read_messages",
]
