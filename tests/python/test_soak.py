# SPDX-License-Identifier: GPL-3.0-or-later
"""The soak (hapticfluid.bench.soak, issue 19): its period-by-period checks find what they look for,
and a short run (20 s; the 10-minute one is in docs/BENCHMARKS.md) passes them all."""

import numpy as np
import pytest

from hapticfluid.bench import soak


def chunk(times, forces):
    return {"time": np.asarray(times, dtype=float), "commanded_force": np.asarray(forces, dtype=float)}


def test_the_trace_check_finds_a_force_above_max_and_a_slew_violation():
    check = soak.TraceCheck(max_force_n=2.0, slew_rate_n_s=200.0)
    t = np.arange(10) * 1e-3
    ramp = np.zeros((10, 3))
    ramp[:, 0] = 0.2 * np.arange(10)              # 200 N/s exactly: at the limit, allowed
    check.add(chunk(t, ramp))
    assert check.ok() and check.periods == 10
    assert check.worst_step_ratio == pytest.approx(1.0, rel=1e-6)
    # The next chunk continues from the last sample: 1.8 N -> 2.3 N in 1 ms is 500 N/s, and above max.
    check.add(chunk([10e-3], [[2.3, 0.0, 0.0]]))
    assert check.slew_violations == 1 and check.over_max == 1 and not check.ok()
    assert check.worst_step_ratio == pytest.approx(2.5, rel=1e-4)


def test_the_trace_check_allows_hard_stops_and_caps_a_late_period():
    check = soak.TraceCheck(max_force_n=8.0, slew_rate_n_s=200.0)
    # 5 N to zero at once (not homed or NaN: by design) is not a slew violation ...
    check.add(chunk([0.0, 1e-3], [[5.0, 0.0, 0.0], [0.0, 0.0, 0.0]]))
    assert check.ok()
    # ... and a period 10 ms late may step at most two nominal periods' worth (0.4 N), as the loop does.
    check.add(chunk([11e-3, 12e-3], [[0.4, 0.0, 0.0], [0.5, 0.0, 0.0]]))
    assert check.ok()
    check.add(chunk([22e-3], [[1.0, 0.0, 0.0]]))
    assert check.slew_violations == 1


def test_a_short_soak_passes_every_check():
    result = soak.soak(20.0, seed=3, log=lambda line: None)
    assert result["failures"] == [], result["failures"]
    lanes = result["lanes"]
    for lane in lanes.values():
        assert lane.alive_at_end
        assert lane.check.periods > 2000           # ~1 kHz, fewer under load
        assert lane.check.largest_n <= 8.0 + 1e-5
        assert lane.sim_steps > 0
    assert lanes["falcon"].check.largest_n > 0.0   # the force was on
    assert lanes["host"].rejected > 0              # NaN, inf, 1e30 and time going back, refused
    assert lanes["replug"].sessions >= 3           # unplugged and plugged in again
    assert all("nplug" in e or "device" in e.lower() for e in lanes["replug"].errors)
    assert result["rss_peak_growth_mib"] <= soak.RSS_GROWTH_BOUND_MIB
    table = soak.section(result)
    assert len(table["rows"]) == 3 and table["notes"][-1] == "every check passed"
