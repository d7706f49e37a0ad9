"""Relaxation check: detection delay, sensitivity and false alarms on simulated isokinetic trials.

Trials come from the simulated seated subject (Riener & Edrich passive moments, limb and arm
weight, damping) moved at 5 °/s through the knee (0→90°) or ankle (15→−30°) range, with the
dynamometer's 0.05 N·m torque noise at 100 Hz. Half of the trials carry one activation burst
(half-sine, 0.3–0.8 s) of a drawn amplitude at a random time; the others are relaxed. A burst
is caught if an alarm falls within its duration + 0.5 s; the delay is from the burst's start.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from drivers.simulation.seated_leg import Burst, SeatedLeg
from instrument.live.relaxation import RelaxationMonitor

RATE_HZ = 100.0
NOISE_NM = 0.05


def trial(seed: int, amplitude_nm: float | None) -> tuple[np.ndarray, np.ndarray, np.ndarray, Burst | None]:
    rng = np.random.default_rng(seed)
    joint = "knee" if seed % 2 else "ankle"
    start, end = (0.0, 90.0) if joint == "knee" else (15.0, -30.0)
    t = np.arange(0.0, abs(end - start) / 5.0, 1.0 / RATE_HZ)
    angle = start + np.sign(end - start) * 5.0 * t
    burst = None
    if amplitude_nm is not None:
        burst = Burst(float(rng.uniform(2.0, t[-1] - 2.0)), float(amplitude_nm * rng.choice([-1, 1])),
                      float(rng.uniform(0.3, 0.8)))
    leg = SeatedLeg(joint=joint, hip_flexion_deg=float(rng.choice([90.0, 55.0, 15.0])), bursts=[burst] if burst else [])
    velocity = np.full(t.size, 5.0 * np.sign(end - start))
    torque = leg.shaft_torque_nm(t, angle, velocity, np.zeros(t.size)) + rng.normal(0.0, NOISE_NM, t.size)
    return t, angle, torque, burst


def run(quick: bool = False) -> dict[str, Any]:
    n = 60 if quick else 300
    amplitudes = (0.5, 1.0, 2.0, 4.0)
    delays, caught = [], {a: 0 for a in amplitudes}
    counts = {a: 0 for a in amplitudes}
    false_alarms = extra_alarms = 0
    t0 = time.perf_counter()
    samples = 0
    for i in range(n):
        amp = amplitudes[i % len(amplitudes)]
        for amplitude in (None, amp):
            t, angle, torque, burst = trial(1000 + i, amplitude)
            mon = RelaxationMonitor()
            for k in range(0, t.size, 5):  # blocks of 50 ms, as the dynamometer driver delivers them
                mon.update(t[k:k + 5], angle[k:k + 5], torque[k:k + 5])
            samples += t.size
            if burst is None:
                false_alarms += bool(mon.alarms)
                continue
            counts[amp] += 1
            # an alarm outside the burst (before it, or after its hold-off) is a false alarm in a burst trial
            extra_alarms += sum(not (burst.start_s <= a.time_s <= burst.start_s + burst.duration_s + 0.5)
                                for a in mon.alarms)
            hits = [a.time_s for a in mon.alarms if burst.start_s <= a.time_s <= burst.start_s + burst.duration_s + 0.5]
            if hits:
                caught[amp] += 1
                delays.append(hits[0] - burst.start_s)
    elapsed = time.perf_counter() - t0
    sens = {f"{a:g}Nm": caught[a] / counts[a] for a in amplitudes}
    out = {"quick": quick, "relaxed_trials": n, "burst_trials": n,
           "median_delay_ms": float(np.median(delays) * 1e3) if delays else None,
           "p95_delay_ms": float(np.percentile(delays, 95) * 1e3) if delays else None,
           "sensitivity": float(sum(caught[a] for a in amplitudes if a >= 1.0) / sum(counts[a] for a in amplitudes if a >= 1.0)),
           "sensitivity_by_amplitude": sens, "false_alarm_rate": false_alarms / n,
           "alarms_outside_the_burst_per_burst_trial": extra_alarms / n,
           "cpu_us_per_sample": elapsed / samples * 1e6}
    for k, v in out.items():
        print(f"{k:<28}{v}")
    return out
