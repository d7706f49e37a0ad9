"""A long, damaged recording through `instrument diagnose`: time and peak memory of a 300,000-row trial.

A lab's 5-min knee recording at 1 kHz (300,000 rows): the independent generator's knee trial with
viscous damping (:mod:`benchmarks.diagnosis_truth`, 1000 Hz, 60 s) repeated five times end to end,
with rows whose time cell is missing (0.1 %), NaN angle and torque cells, written as a trial CSV
with its sidecar. Each measurement is a fresh process (`python -m instrument.cli diagnose FILE
--json`), so the peak resident memory (``ru_maxrss`` of the child) is the whole command's, imports
included. The reference measured in the same run is the generator's own 60-s trial (60,000 rows)
through the same command.

Keys: ``seconds_300k_rows``, ``peak_mb_300k_rows``, ``seconds_60k_rows``, ``peak_mb_60k_rows``,
``seconds_ratio_300k_to_60k``, ``named`` (the cause named on the long trial), ``damping_rel_error``,
``rows_left_out`` (what the diagnosis said it left out) and ``rows_without_time`` (what was damaged).
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.diagnosis_truth import MAGNITUDE_KEY, generate

REPEATS = 5
MISSING_TIME_FRACTION = 0.001
NAN_CELL_FRACTION = 0.002


def _write(path: Path, t: np.ndarray, angle_deg: np.ndarray, torque: np.ndarray, sidecar: dict[str, Any]) -> None:
    cols = np.column_stack([t, angle_deg, torque])
    with path.open("w") as fh:
        fh.write("time_s,angle_deg,torque_Nm\n")
        np.savetxt(fh, cols, delimiter=",", fmt="%.9g")
    path.with_suffix(".json").write_text(json.dumps(sidecar))


def _run(path: Path) -> tuple[float, float, dict[str, Any]]:
    """(wall seconds, peak MB of the child, the JSON result) of one `instrument diagnose` process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "instrument.cli", "diagnose", str(path), "--json"],
                         capture_output=True, text=True, check=True)
    seconds = time.perf_counter() - t0
    peak_kb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    # RUSAGE_CHILDREN is the largest child so far: the runs go smallest first, so it is this one's
    return seconds, max(peak_kb, before) / 1024.0, json.loads(out.stdout)


def run(quick: bool = False) -> dict[str, Any]:
    g = generate("knee", ("viscous_damping",), seed=424242, rate_hz=1000.0)
    truth = g.effects["viscous_damping"]
    rng = np.random.default_rng(7)
    step = float(np.median(np.diff(g.time_s)))
    span = float(g.time_s[-1] - g.time_s[0]) + step
    reps = 1 if quick else REPEATS
    t = np.concatenate([g.time_s + k * span for k in range(reps)])
    angle = np.rad2deg(np.tile(g.angle_rad, reps))
    torque = np.tile(g.torque_nm, reps)
    side = {"kind": "knee", **{k: v for k, v in g.fixed_deg.items()}, "subject": g.subject}
    with tempfile.TemporaryDirectory() as tmp:
        ref = Path(tmp) / "ref.csv"
        _write(ref, g.time_s, np.rad2deg(g.angle_rad), g.torque_nm, side)
        s_ref, mb_ref, _ = _run(ref)
        damaged_t = t.copy()
        missing = rng.choice(t.size, int(MISSING_TIME_FRACTION * t.size), replace=False)
        damaged_t[missing] = np.nan
        for col in (angle, torque):
            col[rng.choice(t.size, int(NAN_CELL_FRACTION * t.size), replace=False)] = np.nan
        long = Path(tmp) / "long.csv"
        _write(long, damaged_t, angle, torque, side)
        s_long, mb_long, res = _run(long)
    named = res["cause"]
    fitted = res["parameters"].get(MAGNITUDE_KEY["viscous_damping"]) if named == "viscous_damping" else None
    out = {"quick": quick, "rows": int(t.size), "rows_without_time": int(missing.size),
           "seconds_300k_rows": s_long, "peak_mb_300k_rows": mb_long, "seconds_60k_rows": s_ref,
           "peak_mb_60k_rows": mb_ref, "seconds_ratio_300k_to_60k": s_long / s_ref, "named": named,
           "damping_true": truth, "damping_fitted": fitted,
           "damping_rel_error": None if fitted is None else fitted / truth - 1.0,
           "rows_left_out": res.get("rows_left_out", {})}
    print(f"{'trial':<34}{'rows':>9}{'seconds':>9}{'peak MB':>9}")
    print(f"{'generator knee, 60 s at 1 kHz':<34}{g.time_s.size:>9}{s_ref:>9.2f}{mb_ref:>9.0f}")
    print(f"{f'{reps} × it, damaged':<34}{t.size:>9}{s_long:>9.2f}{mb_long:>9.0f}")
    print(f"named {named}; damping {fitted} for {truth:.4g} N·m·s/rad; left out {out['rows_left_out']}")
    return out
