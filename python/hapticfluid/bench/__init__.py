# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmarks: programs that print tables and write JSON (python3 -m hapticfluid bench)."""
