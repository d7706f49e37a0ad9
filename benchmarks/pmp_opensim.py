"""The passive-parameter estimator on trials OpenSim made: errors, interval coverage, forward model.

For each seed a subject's parameters are drawn around Rajagopal 2016's (slack lengths ±5 %,
strains ±25 %), OpenSim computes the passive moments of the protocol's six sweeps
(:mod:`benchmarks.opensim_truth`), noise is added, and the estimator fits all six trials at
once. Reported: for every parameter the estimator calls determined, whether its 95 % interval
holds the truth (coverage) and its error; the forward model's RMSE against OpenSim at the true
parameters per trial (the estimator's muscle model evaluated at the truth against OpenSim's
moments); and the fit time.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from analysis.pmp.estimator import PmpTrial, Subject, estimate, identifiability
from analysis.pmp.geometry import model_segment_lengths_m
from analysis.pmp.identifiability import Identifiability
from analysis.pmp.muscles import LegMuscles, MuscleParameters, scale_for_subject

from .opensim_truth import draw_truth, generic_parameters, make_trials

#: the subject's shank is the model's own (OpenSim makes the trials with the unscaled model): its
#: knee-to-ankle distance as the path data record it, not a rounded 0.3965 m, which scales every path
#: by 1.00007 (+0.03 mm in semimembranosus: +0.16 % of its 7.7 kN at hip 90°, 0.16 N·m)
SHANK_M = model_segment_lengths_m()["shank_length_m"]


def forward_model_rmse(trials: list[Any], truth: dict[str, dict[str, float]]) -> list[float]:
    """RMS (N·m) of the estimator's passive moment at the true parameters against OpenSim's, per trial."""
    leg = LegMuscles(length_scale=scale_for_subject(SHANK_M))
    for m, p in truth.items():
        leg.params[m] = MuscleParameters(p["tendon_slack_length_m"], p["passive_strain"], p["tendon_strain"])
    out = []
    for t in trials:
        step = max(t.passive_nm.size // 40, 1)
        q_true = t.true_angle_rad[::step]
        fixed = {"hip": t.fixed_rad.get("hip", 0.0), "knee": t.fixed_rad.get("knee", 0.0),
                 "ankle": t.fixed_rad.get("ankle", 0.0)}
        ours = np.array([leg.joint_moment_nm(t.joint, **{**fixed, t.joint: float(q)}) for q in q_true])
        theirs = t.passive_nm[::step]  # OpenSim's moment at those angles
        out.append(float(np.sqrt(np.mean((ours - theirs) ** 2))))
    return out


def fit_subject(seed: int, generic: dict[str, dict[str, float]], variant: str = "base",
                intervals: int = 30) -> tuple[dict[str, dict[str, float]], list[Any], Any, dict[str, Any], float]:
    """Draw a subject, let OpenSim make its six sweeps, fit them: (truth, made trials, result,
    identifiability, fit wall time s)."""
    truth = draw_truth(seed, generic)
    made = make_trials(truth, seed, variant=variant, shank_m=SHANK_M)
    trials = [PmpTrial(t.joint, t.fixed_rad, t.time_s, t.angle_rad, t.velocity_rad_s, t.torque_nm, t.name)
              for t in made]
    subject = Subject(75.0, SHANK_M, 0.26)
    leg = LegMuscles(length_scale=scale_for_subject(SHANK_M))
    t0 = time.perf_counter()
    res = estimate(trials, subject, leg=leg, intervals=intervals)
    idf = identifiability(res, trials, subject, leg=leg)
    return truth, made, res, idf, time.perf_counter() - t0


def determined_against_truth(res: Any, idf: Identifiability, truth: dict[str, dict[str, float]]) -> list[dict[str, Any]]:
    """Each determined parameter against the truth: estimate, error (%), its 95 % interval and whether it holds it."""
    rows = []
    for name in idf.determined:
        muscle, what = name.split(".")
        true = truth[muscle][what]
        lo, hi = idf.ci95[name]
        rows.append({"parameter": name, "truth": true, "estimate": res.parameters[name],
                     "error_pct": 100 * (res.parameters[name] - true) / true, "covered": bool(lo <= true <= hi),
                     "ci95": [lo, hi]})
    return rows


def one_subject(seed: int, generic: dict[str, dict[str, float]], variant: str = "base",
                intervals: int = 30) -> dict[str, Any]:
    truth, made, res, idf, wall = fit_subject(seed, generic, variant, intervals)
    rows = determined_against_truth(res, idf, truth)
    undetermined_err = [abs(100 * (res.parameters[n] - truth[n.split(".")[0]][n.split(".")[1]])
                            / truth[n.split(".")[0]][n.split(".")[1]]) for n in idf.undetermined]
    return {"seed": seed, "variant": variant, "success": res.success, "status": res.solver_status,
            "iterations": res.nit, "fit_s": wall, "determined": rows,
            "undetermined": len(idf.undetermined), "undetermined_median_error_pct":
            float(np.median(undetermined_err)) if undetermined_err else None,
            "residual_rms_nm": idf.residual_rms_nm, "misfit_ratio": idf.misfit_ratio,
            "not_determined_because": idf.not_determined_because,
            "forward_model_rmse_nm": forward_model_rmse(made, truth)}


def run(quick: bool = False) -> dict[str, Any]:
    seeds = range(3) if quick else range(10)
    generic = generic_parameters()
    subjects = []
    print(f"{'seed':>4} {'variant':<10} {'fit s':>6} {'det':>4} {'covered':>8} {'max err %':>9} {'resid':>7} "
          f"{'misfit':>7} {'fwd RMS max':>11}")
    for variant in ("base", "realistic"):
        for seed in seeds:
            r = one_subject(seed, generic, variant)
            subjects.append(r)
            det = r["determined"]
            print(f"{seed:>4} {variant:<10} {r['fit_s']:>6.1f} {len(det):>4} "
                  f"{sum(d['covered'] for d in det):>4}/{len(det):<3} "
                  f"{max((abs(d['error_pct']) for d in det), default=float('nan')):>9.2f} "
                  f"{r['residual_rms_nm']:>7.3f} {r['misfit_ratio']:>7.1f} {max(r['forward_model_rmse_nm']):>11.3f}")
    determined = [d for r in subjects for d in r["determined"]]
    fwd = [x for r in subjects if r["variant"] == "base" for x in r["forward_model_rmse_nm"]]
    out = {"subjects": subjects, "seeds": len(seeds),
           "determined_total": len(determined),
           "coverage_95": (sum(d["covered"] for d in determined) / len(determined)) if determined else None,
           "max_error_determined_pct": max((abs(d["error_pct"]) for d in determined), default=None),
           "forward_model_rmse_vs_opensim_Nm": {"per_trial_max": max(fwd), "per_trial_median": float(np.median(fwd))},
           "fit_s_median": float(np.median([r["fit_s"] for r in subjects]))}
    print(f"determined {out['determined_total']}, coverage {out['coverage_95']}, max error "
          f"{out['max_error_determined_pct']} %, forward model RMS vs OpenSim max {max(fwd):.3f} N·m")
    return out
