"""The benchmarks' toolkit: the synthetic 1 kHz publisher several benchmarks play axes with
(:mod:`.synthetic_publisher`), what a process costs, read from Linux's /proc (:mod:`.proc_stats`), and a
recording of the identification excitation made offline, without the network (:mod:`.offline_excitation`).
A rig of the benchmarks, not a part of the product."""
