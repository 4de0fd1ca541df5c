"""The benchmarks' toolkit: the synthetic 1 kHz publisher several benchmarks play axes with
(:mod:`.synthetic_publisher`), and what a process costs, read from Linux's /proc (:mod:`.proc_stats`).
A rig of the benchmarks, not a part of the product."""
