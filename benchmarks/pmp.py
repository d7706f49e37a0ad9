"""Passive-parameter estimation time: a full-subject fit, a single-trial fit, and OpenSim Moco on a shared problem.

Trials are simulated from the model with perturbed parameters: knee 0→90° at 5 °/s at hip 90,
55 and 15°, ankle 15→−30° at 5 °/s at knee 0, 45 and 90°, with 0.3/0.2 N·m torque noise.
Measured: wall time and IPOPT iterations of the six-trial fit (all parameters of the eleven
muscles at once), of the single-trial fit (knee at hip 55°), and the recovery of the determined
parameters. Moco (``MocoStudy`` + ``MocoParameter``) on the same single-trial problem runs in a
subprocess (its bundled CasADi cannot share a process with ours) when OpenSim is installed and the
shared problem is ``benchmarks.pmp_moco`` (one muscle on one degree of freedom, the slack length
unknown, 50 intervals: the problem the issue timed Moco on); without OpenSim its keys are null
with the reason. The replica-leg fit (four springs from 12 holds) is timed too.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from analysis.pmp.estimator import estimate, identifiability
from analysis.pmp.muscles import LegMuscles
from analysis.pmp.synthetic import simulated_subject


def _recovery(truth: LegMuscles, res: Any, idf: dict[str, Any]) -> float:
    errs = [abs(res.parameters[n] / getattr(truth.params[n.split(".")[0]], n.split(".")[1]) - 1) * 100
            for n in idf.determined]
    return float(max(errs)) if errs else float("nan")


def _moco_comparison() -> dict[str, Any]:
    """The shared single-trial problem (``benchmarks.pmp_moco``) by this estimator and by Moco, same run."""
    import importlib.util

    from . import pmp_moco

    data = pmp_moco.trial(0)
    ours = pmp_moco.solve_ours(data)
    out: dict[str, Any] = {"shared_problem": "1 DOF, 1 DeGroote–Fregly muscle (rigid tendon), slack length, "
                                             "50 Hermite–Simpson intervals", "shared_truth_slack_m": pmp_moco.SLACK_TRUE_M,
                           "ours_shared_s": ours["wall_s"], "ours_shared_iterations": ours["iterations"],
                           "ours_shared_slack_m": ours["slack_m"], "moco_single_trial_s": None, "speedup_vs_moco": None,
                           "max_param_diff_vs_moco_pct": None}
    if importlib.util.find_spec("opensim") is None:
        out["moco_note"] = "not run: OpenSim is not installed (pip install -e '.[opensim]')"
        return out
    try:
        moco = pmp_moco.solve_moco(data)
    except (RuntimeError, OSError) as err:
        out["moco_note"] = f"Moco failed: {str(err)[-300:]}"
        return out
    out.update({"moco_single_trial_s": moco["wall_s"], "moco_iterations": moco["iterations"],
                "moco_status": moco["status"], "moco_slack_m": moco["slack_m"],
                "speedup_vs_moco": moco["wall_s"] / ours["wall_s"],
                "max_param_diff_vs_moco_pct": abs(moco["slack_m"] - ours["slack_m"]) / moco["slack_m"] * 100})
    return out


def _replica_fit() -> dict[str, Any]:
    """The replica leg's four springs from 12 holds (sensor tared), truth drawn from a seed."""
    from analysis.pmp.replica import Holds, estimate_replica, load_replica_model, truth_error_pct

    model = load_replica_model()
    rng = np.random.default_rng(7)
    truth = {n: v * (1 + (rng.uniform(-0.15, 0.15) if n.endswith("stiffness_n_per_m") else rng.uniform(-0.01, 0.01)))
             for n, v in zip(model.parameter_names(), model.nominal())}
    q = np.array(model.hold_angles_rad)
    tau = model.with_parameters(truth).torque_nm(q) + rng.normal(0.0, 0.0016, q.size)
    t0 = time.perf_counter()
    res = estimate_replica(Holds(q, tau, np.full(q.size, 0.01), np.full(q.size, 40)), model, sensor_offset_nm=0.0)
    wall = time.perf_counter() - t0
    err = truth_error_pct(res, truth)
    return {"replica_fit_s": wall, "replica_iterations": res.nit, "replica_starts": res.starts,
            "replica_determined": len(res.determined),
            "replica_max_error_determined_pct": max((abs(err[n]) for n in res.determined), default=float("nan"))}


def _opensim_truth(quick: bool) -> dict[str, Any]:
    """Coverage, errors and the forward model against trials OpenSim made (benchmarks/pmp_opensim.py)."""
    from . import pmp_opensim

    try:
        r = pmp_opensim.run(quick)
    except FileNotFoundError as err:  # the generic .osim is not here
        return {"coverage_95": None, "max_error_determined_pct": None, "forward_model_rmse_vs_opensim_Nm": None,
                "opensim_truth_skipped": str(err)}
    return {"coverage_95": r["coverage_95"], "max_error_determined_pct": r["max_error_determined_pct"],
            "forward_model_rmse_vs_opensim_Nm": r["forward_model_rmse_vs_opensim_Nm"]["per_trial_max"],
            "opensim_truth_determined": r["determined_total"], "opensim_truth_seeds": r["seeds"]}


def run(quick: bool = False) -> dict[str, Any]:
    intervals = 16 if quick else 30
    truth, trials, subject = simulated_subject(1, ("knee", "ankle"))
    knee, ankle = [t for t in trials if t.joint == "knee"], [t for t in trials if t.joint == "ankle"]
    t0 = time.perf_counter()
    full = estimate(knee + ankle, subject, intervals=intervals)
    full_s = time.perf_counter() - t0
    idf_full = identifiability(full, knee + ankle, subject)
    t0 = time.perf_counter()
    single = estimate([knee[1]], subject, intervals=intervals)
    single_s = time.perf_counter() - t0
    idf_single = identifiability(single, [knee[1]], subject)
    replica = _replica_fit()
    moco = _moco_comparison()
    independent = _opensim_truth(quick)
    out = {"quick": quick, "intervals_per_trial": intervals, "trials_full_subject": len(knee + ankle),
           "parameters_full_subject": len(full.parameters), "full_subject_fit_s": full_s,
           "full_subject_iterations": full.nit, "full_subject_ipopt_s": full.solve_time_s,
           "full_subject_determined": len(idf_full["determined"]),
           "full_subject_max_error_determined_pct": _recovery(truth, full, idf_full),
           "single_trial_fit_s": single_s, "single_trial_iterations": single.nit,
           "single_trial_determined": len(idf_single["determined"]),
           "single_trial_max_error_determined_pct": _recovery(truth, single, idf_single), **replica, **moco,
           **independent}
    print(f"{'quantity':<42}{'value':>14}")
    for k, v in out.items():
        print(f"{k:<42}{v!s:>14}" if not isinstance(v, float) else f"{k:<42}{v:>14.4g}")
    return out
