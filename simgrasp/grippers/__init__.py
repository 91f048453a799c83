"""Parallel-jaw grippers."""
