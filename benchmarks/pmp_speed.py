"""A realistic subject from its CSVs to the report, as a lab runs it: plain, with its extension, diagnosed.

OpenSim makes a subject's six sweeps (:mod:`benchmarks.opensim_truth`: Rajagopal 2016's muscles with
perturbed parameters, in a subprocess) with one mismatch hidden per case: end-range structures
(``CoordinateLimitForce`` at the knee's and the ankle's range ends) and compliant knee tendons with a tone
of 0.01. The trials are written as trial CSVs with their sidecars, and ``instrument analyze pmp`` (the
command line, in this process) reads them and writes the report and its figures three times:

* plain (the muscle model alone), the reference of the same run;
* ``--extension NAME`` with the extension that case's hidden mismatch needs (what an earlier diagnosis named);
* ``--diagnose-model`` (every candidate fitted and judged by held-out prediction, the winner refitted).

Wall times from the command's start to its report on disk. Targets (issue 30): plain ≤ 15 s, a full subject
with its extension ≤ 20 s, the model-level diagnosis ≤ 120 s on a 2-core machine.

Keys: ``cases`` (per case: ``plain_s``, ``extended_s``, ``diagnose_model_s``, ``named``, misfit ratios),
``plain_s_max``, ``extended_s_max``, ``diagnose_model_s_max``, ``extended_over_plain`` (median ratio, same run),
``cpu_count``, ``load_average_1min`` (the machine's at the start and the end: these are wall times, and another
job on the two cores multiplies them: the run committed at 1b4504c read 2.2–2.8× the next stop's, on a quiet
machine, of the same estimator).
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

#: (case, the variant's generator options, the extension the hidden mismatch needs)
CASES: tuple[tuple[str, dict[str, Any], str], ...] = (
    ("end_range", {"limit_forces": "draw"}, "end_range_structures"),
    ("compliant_tone", {"variant": "realistic"}, "tonic_activation+knee_tendon_compliance"),
)
SEED = 31000
INTERVALS = 16


def _write_csvs(trials: list[Any], folder: Path, shank_m: float, mass_kg: float, foot_m: float) -> list[Path]:
    from analysis.trial_csv import TrialTable, write_trial_csv

    from .pmp_realistic import THIGH_M

    files = []
    for t in trials:
        other = {"hip_flexion_deg": float(np.rad2deg(t.fixed_rad.get("hip", 0.0)))}
        if t.joint == "knee":
            other["ankle_dorsiflexion_deg"] = float(np.rad2deg(t.fixed_rad.get("ankle", 0.0)))
        else:
            other["knee_flexion_deg"] = float(np.rad2deg(t.fixed_rad.get("knee", 0.0)))
        table = TrialTable({"time_s": t.time_s, "angle_deg": np.rad2deg(t.angle_rad), "torque_Nm": t.torque_nm,
                            "velocity_deg_s": np.rad2deg(t.velocity_rad_s)},
                           {"kind": t.joint, **other,
                            "subject": {"mass_kg": mass_kg, "shank_length_m": shank_m, "foot_length_m": foot_m,
                                        "thigh_length_m": THIGH_M}})
        files.append(folder / f"{t.name.replace(' ', '_').replace('°', 'deg')}.csv")
        write_trial_csv(files[-1], table)
    return files


def _timed_cli(args: list[str]) -> tuple[float, dict[str, Any]]:
    from instrument.cli import main

    out = io.StringIO()
    t0 = time.perf_counter()
    with contextlib.redirect_stdout(out):
        code = main(args)
    seconds = time.perf_counter() - t0
    if code != 0:
        raise RuntimeError(f"instrument {' '.join(args[:3])} ... exited {code}")
    return seconds, json.loads(out.getvalue())


def one_case(name: str, options: dict[str, Any], extension: str, root: Path) -> dict[str, Any]:
    from .opensim_truth import draw_truth, generic_parameters, make_trials
    from .pmp_opensim import SHANK_M
    from .pmp_realistic import FOOT_M, MASS_KG, _limit_forces

    rng = np.random.default_rng(SEED)
    kwargs = dict(options)
    if kwargs.get("limit_forces") == "draw":
        kwargs["limit_forces"] = _limit_forces(rng)
    trials = make_trials(draw_truth(SEED, generic_parameters()), SEED, shank_m=SHANK_M, mass_kg=MASS_KG,
                         foot_m=FOOT_M, **kwargs)
    folder = root / name
    folder.mkdir(parents=True)
    files = [str(f) for f in _write_csvs(trials, folder, SHANK_M, MASS_KG, FOOT_M)]
    base = ["analyze", "pmp", *files, "--intervals", str(INTERVALS), "--json"]
    plain_s, plain = _timed_cli([*base, "--out", str(folder / "plain")])
    extended_s, ext = _timed_cli([*base, "--out", str(folder / "extended"), "--extension", extension])
    diagnosed_s, diag = _timed_cli([*base, "--out", str(folder / "diagnosed"), "--diagnose-model"])
    row = {"case": name, "extension": extension, "plain_s": plain_s, "extended_s": extended_s,
           "diagnose_model_s": diagnosed_s, "named": (diag.get("model_diagnosis") or {}).get("cause"),
           "plain_misfit": plain["identifiability"]["misfit_ratio"],
           "extended_misfit": ext["identifiability"]["misfit_ratio"],
           "determined_plain": len(plain["identifiability"]["determined"]),
           "determined_extended": len(ext["identifiability"]["determined"])}
    print(f"{name:<16}{plain_s:>9.1f}{extended_s:>12.1f}{diagnosed_s:>12.1f}  {row['named']}", flush=True)
    return row


def run(quick: bool = False) -> dict[str, Any]:
    load_start = os.getloadavg()[0]
    root = Path(tempfile.mkdtemp(prefix="pmp-speed-"))
    print(f"{'case':<16}{'plain s':>9}{'extended s':>12}{'diagnose s':>12}  named", flush=True)
    cases = [one_case(n, o, e, root) for n, o, e in (CASES[:1] if quick else CASES)]
    out = {"quick": quick, "intervals_per_trial": INTERVALS, "cases": cases,
           "plain_s_max": max(c["plain_s"] for c in cases), "extended_s_max": max(c["extended_s"] for c in cases),
           "diagnose_model_s_max": max(c["diagnose_model_s"] for c in cases),
           "extended_over_plain": float(np.median([c["extended_s"] / c["plain_s"] for c in cases])),
           "targets_s": {"plain": 15.0, "extended": 20.0, "diagnose_model": 120.0}, "cpu_count": os.cpu_count(),
           "load_average_1min": {"start": load_start, "end": os.getloadavg()[0]}}
    for k in ("plain_s_max", "extended_s_max", "diagnose_model_s_max", "extended_over_plain"):
        print(f"{k:<24}{out[k]:>8.2f}")
    return out
