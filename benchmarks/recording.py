"""Sustained recording of all three devices plus motion capture at full rate, and recovery after a kill.

Blocks shaped as the drivers deliver them (force plate 1000 Hz in 16-sample blocks, markers
100 Hz × 10 markers, dynamometer 100 Hz, torque sensor 400 polls/s) are fed to one
``TrialWriter`` paced at ``pace`` × real time, so 10 minutes of simulated time take
10 / pace minutes. Reference in the same run: the raw bytes of the samples (``np.save`` of
the same arrays), for the file-size overhead.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path
from typing import Any

import numpy as np

from drivers.blocks import DynamometerBlock, ForcePlateBlock, MarkerBlock, TorqueBlock
from instrument.live.recording import DeviceSpec, TrialWriter, read_trial, recover_trial_file

RATES = {"force_plate": (1000, 16), "mocap": (100, 2), "dynamometer": (100, 2), "torque_sensor": (400, 4)}


def _layouts() -> dict[str, DeviceSpec]:
    mk = dict(MarkerBlock.LAYOUT)
    mk["position_m"] = ((10, 3), "f8")
    return {"force_plate": DeviceSpec(ForcePlateBlock.LAYOUT), "mocap": DeviceSpec(mk),
            "dynamometer": DeviceSpec(DynamometerBlock.LAYOUT), "torque_sensor": DeviceSpec(TorqueBlock.LAYOUT)}


def _block(spec: DeviceSpec, start: int, n: int, rate: float, rng: np.random.Generator) -> dict[str, np.ndarray]:
    c = np.arange(start, start + n, dtype=np.int64)
    out: dict[str, np.ndarray] = {"counter": c, "time_s": c / rate}
    for k, (shape, dtype) in spec.layout.items():
        if k not in out:
            out[k] = rng.normal(size=(n, *shape)).astype(dtype)
    return out


def sustained(seconds: float, pace: float, path: Path) -> dict[str, Any]:
    specs = _layouts()
    rng = np.random.default_rng(0)
    w = TrialWriter(path, specs, {"benchmark": "recording"})
    counters = {n: 0 for n in specs}
    raw_bytes = 0
    cpu0, t0 = time.process_time(), time.perf_counter()
    step = 0.016  # one force-plate block of simulated time per iteration
    sim_t = 0.0
    while sim_t < seconds:
        sim_t += step
        for name, (rate, _) in RATES.items():
            due = int(sim_t * rate) - counters[name]
            if due > 0:
                b = _block(specs[name], counters[name], due, rate, rng)
                raw_bytes += sum(a.nbytes for a in b.values())
                w.append(name, b)
                counters[name] += due
        lag = sim_t / pace - (time.perf_counter() - t0)
        if lag > 0:
            time.sleep(lag)
    w.close()
    wall = time.perf_counter() - t0
    cpu = time.process_time() - cpu0
    samples = sum(counters.values())
    size = path.stat().st_size
    trial = read_trial(path)
    assert all(trial.devices[n].samples == counters[n] for n in counters), "samples lost"
    return {"simulated_s": seconds, "wall_s": wall, "samples": samples,
            "samples_written_per_s": samples / wall, "cpu_s_per_s_of_data": cpu / seconds,
            "bytes_per_sample": size / samples, "raw_bytes_per_sample": raw_bytes / samples,
            "file_overhead_ratio": size / raw_bytes,
            "max_flush_interval_s": w.stats.max_flush_interval_s, "flushes": w.stats.flushes,
            "writer_cpu_s_per_s_of_data": w.stats.write_cpu_s / seconds}


KILL_SCRIPT = textwrap.dedent("""
    import sys, time, numpy as np
    sys.path.insert(0, {root!r})
    from benchmarks.recording import _layouts, _block, RATES
    from instrument.live.recording import TrialWriter
    specs = _layouts(); rng = np.random.default_rng(1)
    w = TrialWriter({path!r}, specs, {{}})
    counters = {{n: 0 for n in specs}}
    t0 = time.perf_counter()
    while True:
        t = time.perf_counter() - t0
        for name, (rate, _) in RATES.items():
            due = int(t * rate * 10) - counters[name]  # 10x real time
            if due > 0:
                w.append(name, _block(specs[name], counters[name], due, rate, rng)); counters[name] += due
        if t > {run_s}:
            print("ready", flush=True)
        time.sleep(0.005)
""")


def kill_and_recover(path: Path, run_s: float) -> dict[str, Any]:
    root = str(Path(__file__).resolve().parents[1])
    proc = subprocess.Popen([sys.executable, "-c", KILL_SCRIPT.format(root=root, path=str(path), run_s=run_s)],
                            stdout=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    proc.stdout.readline()
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    t0 = time.perf_counter()
    report = recover_trial_file(path)
    elapsed = time.perf_counter() - t0
    return {"recovery_s": elapsed, "recovered_samples": sum(report.samples.values()),
            "recovered_file_bytes": path.stat().st_size, "readable": report.readable}


def run(quick: bool = False) -> dict[str, Any]:
    seconds = 60.0 if quick else 600.0
    pace = 20.0 if quick else 10.0
    with tempfile.TemporaryDirectory() as d:
        s = sustained(seconds, pace, Path(d) / "sustained.h5")
        k = kill_and_recover(Path(d) / "killed.h5", 2.0 if quick else 6.0)
    result = {**s, **k, "pace_x_real_time": pace}
    print(f"recording: {seconds:.0f} s of data (force plate 1000 Hz, markers 100 Hz, dynamometer 100 Hz, "
          f"torque 400 Hz) at {pace:.0f}x real time")
    for key in ("samples_written_per_s", "cpu_s_per_s_of_data", "writer_cpu_s_per_s_of_data", "bytes_per_sample",
                "raw_bytes_per_sample", "file_overhead_ratio", "max_flush_interval_s", "recovery_s",
                "recovered_samples"):
        print(f"  {key:<28} {result[key]:.4g}")
    return result
