"""Benchmarks: programs that print tables and write JSON (python3 -m hapticfluid bench)."""
