# SPDX-License-Identifier: GPL-3.0-or-later
"""Soak: haptic sessions with the simulated Falcon and an abusive pose stream for minutes, checked
period by period (issue 19).

Three sessions run side by side for ``seconds``, each on its own Simulation:

- ``falcon``: the simulated Falcon (the whole driver behind its simulated USB cable, a 300 N/m
  hand) at force gain 1, far above what it can render, so the passivity controller, the clamp
  and the slew limit work all the time. It must stay alive for the whole run.
- ``host``: a host-driven handle fed an abusive pose stream at about 100 Hz from this thread:
  jumps across the workspace, far poses (up to 100 m: the probe is clamped to the domain),
  floods (hundreds of poses 1 us apart, so velocities of 1e5 m/s), and values the API must refuse
  (NaN, inf, 1e30 m, time going back): each must raise InvalidArgumentError. It must stay alive.
- ``replug``: a simulated Falcon whose cable is pulled after a random 0.5-3 s; the session must
  end with a device error (not a crash, not a hang), then a new Falcon is opened on the same
  Simulation (the claims of the old device and session are released) and so on.

Checked on every traced haptic period of every session: |F| <= max_force; |F(k) - F(k-1)| <=
slew_rate x dt(k) (dt as the loop uses it: at most two nominal periods), except the hard stops
to zero (not homed, NaN). The process's RSS is sampled every few seconds: after a warm-up of a
fifth of the run (at least 5 s) it may grow by at most ``RSS_GROWTH_BOUND_MIB``.

Run: ``python3 -m hapticfluid.bench.soak [--seconds 600] [--json PATH]`` (prints the table, exits
1 if a check failed); a short run is in tests/python/test_soak.py.
"""

from __future__ import annotations

import argparse
import math
import os
import random
import sys
import time
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence

import numpy as np

import hapticfluid as hf
from hapticfluid.bench import report

DEFAULT_SECONDS = 600.0
QUICK_SECONDS = 25.0
RSS_GROWTH_BOUND_MIB = 16.0   # RSS growth allowed after the warm-up, MiB (10 min measured 3.1)
RSS_SAMPLE_S = 2.0            # s between RSS samples
POSE_PUSH_HZ = 100.0
SLEW_RATE_N_S = 200.0         # the session's default slew limit, N/s
NOMINAL_PERIOD_S = 1e-3       # the haptic loop's nominal period, s
SLEW_TOLERANCE_N = 1e-5       # float32 rounding of the commanded force, N

COLUMNS = ["session", "seconds", "sessions", "periods", "max |F| (N)", "max force (N)",
           "over max", "largest step / allowed", "slew violations", "rejected poses",
           "sim steps", "errors", "alive at end"]


def rss_mib() -> float:
    """This process's resident set size, MiB (Linux /proc)."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    raise hf.HapticFluidError("soak: VmRSS not found in /proc/self/status (Linux only)")


@dataclass
class TraceCheck:
    """The force limits checked on a session's trace, chunk by chunk (keeps no samples)."""
    max_force_n: float
    slew_rate_n_s: float = SLEW_RATE_N_S
    periods: int = 0
    largest_n: float = 0.0
    over_max: int = 0
    slew_violations: int = 0
    worst_step_ratio: float = 0.0   # largest |dF| / (slew x dt) over the non-hard-stop periods
    first_violation: Optional[str] = None
    _last_t: Optional[float] = None
    _last_f: Optional[np.ndarray] = None

    def add(self, trace: Dict[str, np.ndarray]) -> None:
        t = np.asarray(trace["time"], dtype=float)
        f = np.asarray(trace["commanded_force"], dtype=float)
        if len(t) == 0:
            return
        self.periods += len(t)
        size = np.linalg.norm(f, axis=1)
        self.largest_n = max(self.largest_n, float(size.max()))
        over = size > self.max_force_n * (1.0 + 1e-6)
        self.over_max += int(over.sum())
        if over.any() and self.first_violation is None:
            self.first_violation = f"|F| = {size[over][0]:.6g} N above {self.max_force_n} N"
        if self._last_t is not None:
            t = np.concatenate([[self._last_t], t])
            f = np.vstack([self._last_f, f])
        if len(t) >= 2:
            step = np.linalg.norm(np.diff(f, axis=0), axis=1)
            dt = np.minimum(np.diff(t), 2.0 * NOMINAL_PERIOD_S)
            allowed = self.slew_rate_n_s * dt
            hard_stop = np.all(f[1:] == 0.0, axis=1)  # not homed or NaN: zero at once, by design
            ratio = np.where(hard_stop | (allowed <= 0.0), 0.0, step / np.maximum(allowed, 1e-12))
            bad = ~hard_stop & (step > allowed * (1.0 + 1e-4) + SLEW_TOLERANCE_N)
            self.slew_violations += int(bad.sum())
            if bad.any() and self.first_violation is None:
                k = int(np.argmax(bad))
                self.first_violation = f"step {step[k]:.6g} N in {dt[k] * 1e3:.4g} ms (allowed {allowed[k]:.6g} N)"
            self.worst_step_ratio = max(self.worst_step_ratio, float(ratio.max()))
        self._last_t, self._last_f = float(t[-1]), f[-1].copy()

    def ok(self) -> bool:
        return self.over_max == 0 and self.slew_violations == 0


@dataclass
class Lane:
    """One of the soak's sessions and what was seen of it."""
    name: str
    check: TraceCheck
    sessions: int = 0
    rejected: int = 0
    sim_steps: int = 0
    errors: List[str] = field(default_factory=list)
    alive_at_end: Optional[bool] = None


class AbusivePoses:
    """The host lane's pose stream: mostly a sweep, with jumps, far poses, floods and refused values."""

    def __init__(self, device: hf.HostDevice, rng: random.Random):
        self.device = device
        self.rng = rng
        self.t = time.monotonic()
        self.refused = 0
        self.accepted = 0

    def _push(self, position: Sequence[float]) -> None:
        self.t = max(self.t + 1e-6, time.monotonic())
        self.device.push_pose(tuple(position), self.t)
        self.accepted += 1

    def _refused(self, position: Sequence[float], t: Optional[float] = None) -> None:
        try:
            self.device.push_pose(tuple(position), self.t + 1e-3 if t is None else t)
        except hf.InvalidArgumentError:
            self.refused += 1
            return
        raise hf.HapticFluidError(f"soak: push_pose accepted {tuple(position)} at {t}: it must refuse it")

    def tick(self) -> None:
        r = self.rng.random()
        if r < 0.70:  # a sweep, 4 s figure of eight in x-z
            w = 2.0 * math.pi * time.monotonic() / 4.0
            self._push((0.04 * math.cos(w), 0.0, 0.02 * math.cos(2.0 * w)))
        elif r < 0.80:  # a jump anywhere in (and a little beyond) the Falcon-sized workspace
            self._push([self.rng.uniform(-0.1, 0.1) for _ in range(3)])
        elif r < 0.85:  # far away: the probe is clamped into the domain
            self._push([self.rng.choice((-1.0, 1.0)) * self.rng.uniform(1.0, 100.0) for _ in range(3)])
        elif r < 0.90:  # a flood: hundreds of poses 1 us apart
            for _ in range(self.rng.randint(100, 500)):
                self.t += 1e-6
                self.device.push_pose(tuple(self.rng.uniform(-0.05, 0.05) for _ in range(3)), self.t)
                self.accepted += 1
        else:  # what the API must refuse (and the stream goes on after)
            kind = self.rng.randrange(4)
            if kind == 0:
                self._refused((math.nan, 0.0, 0.0))
            elif kind == 1:
                self._refused((0.0, math.inf, 0.0))
            elif kind == 2:
                self._refused((0.0, 0.0, 1e30))
            else:
                self._refused((0.0, 0.0, 0.0), t=self.t - 1.0)  # time going back


def _session(sim: hf.Simulation, device: hf.Device, **kw) -> hf.HapticSession:
    return hf.HapticSession(sim, device, workspace_scale=6.0, probe_radius=0.1, ramp_time=0.5,
                            realtime=False, trace=True, trace_seconds=30.0, **kw)


def _simulation(n: int) -> hf.Simulation:
    return hf.Simulation(resolution=(n, n, n), fluid_density=1000.0, gravity=(0.0, 0.0, 0.0),
                         pressure_solver="jacobi", pressure_iterations=20)


def _open_replug_falcon(rng: random.Random) -> hf.FalconDevice:
    # Homing takes ~200 packets (1 ms each); pulled 0.5-3 s of packets later.
    return hf.open_simulated_falcon(hand_stiffness=300.0, unplug_after=rng.randint(700, 3200))


def soak(seconds: float, seed: int = 1, log=report.progress) -> Dict[str, object]:
    """Run the soak for `seconds` (s); returns the lanes, RSS samples and the verdict."""
    if not (math.isfinite(seconds) and seconds > 0):
        raise hf.InvalidArgumentError(f"seconds must be a positive number, got {seconds}")
    rng = random.Random(seed)
    falcon_sim, host_sim, replug_sim = _simulation(20), _simulation(16), _simulation(16)
    falcon = hf.open_simulated_falcon(hand_stiffness=300.0)
    host = hf.host_device(max_force=8.0)
    lanes = {"falcon": Lane("falcon (gain 1)", TraceCheck(8.0)),
             "host": Lane("host (abusive poses)", TraceCheck(8.0)),
             "replug": Lane("falcon unplug/replug", TraceCheck(8.0))}
    sessions = {"falcon": _session(falcon_sim, falcon, force_gain=1.0, allow_unsafe_gain=True),  # abuse, on purpose
                "host": _session(host_sim, host, force_gain=1.0)}
    replug_device = _open_replug_falcon(rng)
    sessions["replug"] = _session(replug_sim, replug_device)
    for name, s in sessions.items():
        s.start()
        lanes[name].sessions += 1
    poses = AbusivePoses(host, rng)
    rss: List[List[float]] = []
    start = time.monotonic()
    next_rss = start
    next_log = start + 30.0
    try:
        while True:
            now = time.monotonic()
            elapsed = now - start
            if elapsed >= seconds:
                break
            poses.tick()
            for name in ("falcon", "host", "replug"):
                lanes[name].check.add(sessions[name].trace())
            for name in ("falcon", "host"):
                if sessions[name].error is not None:
                    raise hf.HapticFluidError(f"soak: the {name} session died after {elapsed:.1f} s: "
                                              f"{sessions[name].error}")
            replug = sessions["replug"]
            if replug.state == "failed":
                lane = lanes["replug"]
                error = replug.error or ""
                lane.errors.append(error)
                if "unplugged" not in error and "device" not in error.lower():
                    raise hf.HapticFluidError(f"soak: the unplugged session failed with {error!r}, "
                                              "not a device error")
                try:
                    replug.stop()
                except hf.HapticFluidError:
                    pass  # stop() raises the error that ended it, once
                lane.check.add(replug.trace())
                lane.sim_steps += int(replug.stats()["sim_steps"])
                replug_device.close()
                replug_device = _open_replug_falcon(rng)  # plugged in again
                sessions["replug"] = replug = _session(replug_sim, replug_device)
                replug.start()
                lane.sessions += 1
                lane.check._last_t = None  # a new session starts from zero force
            if now >= next_rss:
                rss.append([round(elapsed, 2), round(rss_mib(), 2)])
                next_rss += RSS_SAMPLE_S
            if now >= next_log:
                log(f"soak: {elapsed:.0f} s, RSS {rss[-1][1]:.1f} MiB, "
                    + ", ".join(f"{k} {lane.check.periods} periods" for k, lane in lanes.items()))
                next_log += 30.0
            time.sleep(1.0 / POSE_PUSH_HZ)
        for name in ("falcon", "host", "replug"):
            lanes[name].alive_at_end = sessions[name].state == "running"
        # The replug lane may be between plug-ins: alive means running or just unplugged.
        if not lanes["replug"].alive_at_end and sessions["replug"].state == "failed":
            lanes["replug"].alive_at_end = True
        rss.append([round(time.monotonic() - start, 2), round(rss_mib(), 2)])
    finally:
        for name, s in sessions.items():
            try:
                s.stop()
            except hf.HapticFluidError as exc:  # the error that ended it (a replug lane's unplug)
                if name == "replug":
                    lanes[name].errors.append(str(exc))
            lanes[name].check.add(s.trace())
            lanes[name].sim_steps += int(s.stats()["sim_steps"])
        for d in (falcon, host, replug_device):
            d.close()
        for sim in (falcon_sim, host_sim, replug_sim):
            sim.close()
    lanes["host"].rejected = poses.refused
    warm = max(5.0, 0.2 * seconds)
    after = [m for t, m in rss if t >= warm] or [rss[-1][1]]
    growth = after[-1] - after[0]
    peak_growth = max(after) - after[0]
    slope = float(np.polyfit([t for t, _ in rss if t >= warm], after, 1)[0] * 60.0) if len(after) >= 3 else 0.0
    failures = []
    for lane in lanes.values():
        if not lane.check.ok():
            failures.append(f"{lane.name}: {lane.check.first_violation}")
        if not lane.alive_at_end:
            failures.append(f"{lane.name}: not alive at the end")
    if peak_growth > RSS_GROWTH_BOUND_MIB:
        failures.append(f"RSS grew {peak_growth:.1f} MiB after the warm-up (bound {RSS_GROWTH_BOUND_MIB} MiB)")
    return {"seconds": seconds, "lanes": lanes, "rss": rss, "rss_warm_s": warm,
            "rss_growth_mib": growth, "rss_peak_growth_mib": peak_growth, "rss_slope_mib_min": slope,
            "accepted_poses": poses.accepted, "failures": failures}


def section(result: Dict[str, object]) -> dict:
    """The soak's figures in the bench section format."""
    rows = []
    for lane in result["lanes"].values():
        c = lane.check
        rows.append([lane.name, round(result["seconds"], 1), lane.sessions, c.periods, round(c.largest_n, 4),
                     c.max_force_n, c.over_max, round(c.worst_step_ratio, 4), c.slew_violations, lane.rejected,
                     lane.sim_steps, len(lane.errors), lane.alive_at_end])
    rss = result["rss"]
    notes = [f"RSS {rss[0][1]:.1f} MiB at start, {rss[-1][1]:.1f} MiB at the end; after the "
             f"{result['rss_warm_s']:.0f} s warm-up it grew {result['rss_growth_mib']:.2f} MiB "
             f"(peak {result['rss_peak_growth_mib']:.2f} MiB, trend {result['rss_slope_mib_min']:.3f} MiB/min; "
             f"bound {RSS_GROWTH_BOUND_MIB} MiB)",
             f"host lane: {result['accepted_poses']} poses accepted, {result['lanes']['host'].rejected} refused "
             "(NaN, inf, 1e30 m, time going back: each raised InvalidArgumentError)",
             "replug lane: the sessions ended by the pulled cable said: "
             + ("; ".join(sorted(set(e.split(":")[0] + ": " + e.split(":")[-1].strip()
                                     for e in result["lanes"]["replug"].errors))) or "(none ended yet)"),
             "largest step / allowed: the largest |F(k) - F(k-1)| over slew_rate x dt (1 = at the limit; "
             "hard stops to zero excluded)",
             f"{os.cpu_count()} CPUs, load average at the end: "
             + ", ".join(f"{x:.2f}" for x in os.getloadavg())]
    notes += [f"FAILED: {f}" for f in result["failures"]] or ["every check passed"]
    return {"title": "Soak: simulated Falcon and abusive poses, every period checked", "columns": COLUMNS,
            "rows": rows, "notes": notes}


def run(quick: bool = False) -> dict:
    """The bench section: QUICK_SECONDS with quick=True, else DEFAULT_SECONDS."""
    return section(soak(QUICK_SECONDS if quick else DEFAULT_SECONDS))


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m hapticfluid.bench.soak",
                                     description="Soak the haptic sessions (see the module's docstring).")
    parser.add_argument("--seconds", type=float, default=DEFAULT_SECONDS,
                        help="run time in s (default: %(default)s)")
    parser.add_argument("--seed", type=int, default=1, help="random seed of the abuse (default: %(default)s)")
    parser.add_argument("--json", metavar="PATH", help="also write the results to this JSON file")
    args = parser.parse_args(argv)
    try:
        machine = report.machine_info()
        print(report.describe_machine(machine), flush=True)
        result = soak(args.seconds, seed=args.seed)
        table = report.check_section("soak", section(result))
        print(report.format_table(table), flush=True)
        if args.json:
            table["rss_samples_s_mib"] = result["rss"]
            report.write_json_atomic(args.json, report.document({"soak": table}, False, machine))
            print(f"wrote {args.json}")
    except (hf.HapticFluidError, OSError, ValueError) as exc:
        print(f"{parser.prog}: error: {exc}", file=sys.stderr)
        return 1
    return 0 if not result["failures"] else 1


if __name__ == "__main__":
    sys.exit(main())
