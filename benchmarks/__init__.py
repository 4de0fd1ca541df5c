"""Benchmarks: each measures a speed or memory goal against a baseline in the same run."""
