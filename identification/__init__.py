"""Friction identification from recorded logs (SQP refit of a1…a4)."""
