"""How axisflow's MCAP writers cut a recording into chunks: the compressions a chunk may have, by name,
the default chunk size, and the default bound on the chunks a recording holds in memory before they are
written (its backlog). Names and numbers only, no mcap: the command line offers them before it loads a
writer (:mod:`.mcap_writer`, :mod:`.recording_writer`)."""

COMPRESSION_NAMES: tuple[str, ...] = ("zstd", "lz4", "none")
"""chunk compressions, as ``--compression`` names them (each is mcap's ``CompressionType`` of that name)"""
DEFAULT_CHUNK_SIZE = 512 * 1024
"""chunk size before compression. Smaller chunks shorten the recording thread's compression stalls
(p99 stamp→write at 32 kHz, measured: 2.7 ms with 256 KiB, 4.4 ms with 512 KiB, 26 ms with 4 MiB) at
the cost of ~3 % larger files and more chunk indexes (kept on disk until the summary, see
:class:`~.mcap_writer._ChunkIndexSpill`)."""
DEFAULT_BACKLOG_BYTES = 256 * 1024 * 1024
"""the bytes of chunks received and not yet written that a recording may hold (:mod:`.recording_writer`)"""
