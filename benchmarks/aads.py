"""AADS analysis throughput: a 60-trial experiment (3 springs × 4 operators × 5 trials) through the pipeline.

Measured: marker frames per second of the whole per-trial pipeline (kinematics, plate filtering
and resampling, equations of motion, batched static optimisation, stiffness and theory fits).
Reference in the same run: the same static-optimisation problem solved one frame at a time with
``scipy.optimize.minimize`` (SLSQP), as OpenSim's static-optimisation tool works frame by frame;
the reference pipeline is the shared part (everything but the solve) plus the per-frame solves.
``--quick`` times the per-frame reference on every 20th frame (≈2,600 solves) and scales it per
frame; the full run solves every frame of the experiment. Accuracy: the largest difference
between the two solutions, and the SOP stiffness error on ideal-AFO trials against the
simulator's truth (no friction, rigid shell).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from analysis.aads.dynamics import jig_equations, plate_at_markers, static_optimisation, static_optimisation_per_frame
from analysis.aads.kinematics import aads_kinematics
from analysis.aads.model import load_jig_model
from analysis.aads.pipeline import analyze_trial
from analysis.aads.stiffness import line_fit
from drivers.simulation.aads_jig import AfoProperties
from instrument.sim.simulate import synthesize_aads_trial


def run(quick: bool = False) -> dict[str, Any]:
    model = load_jig_model()
    t0 = time.perf_counter()
    trials = [synthesize_aads_trial(s, o, t)[0] for s in (1, 2, 3) for o in (1, 2, 3, 4) for t in range(1, 6)]
    synth_s = time.perf_counter() - t0
    frames = sum(t.marker_time_s.size for t in trials)

    # the product's pipeline, end to end, per trial
    t0 = time.perf_counter()
    results = [analyze_trial(t, model, factors={"spring": 1 + i // 20, "operator": 1 + (i // 5) % 4, "trial": 1 + i % 5})
               for i, t in enumerate(trials)]
    pipeline_s = time.perf_counter() - t0

    # its parts: the shared preparation, and the batched solve alone
    prep_s = solve_s = 0.0
    eqs = []
    for t in trials:
        a = time.perf_counter()
        kin = aads_kinematics(t, model)
        eq = jig_equations(kin, plate_at_markers(t, kin.time_s, model.filter_cutoff_hz), model)
        b = time.perf_counter()
        static_optimisation(eq, model)
        solve_s += time.perf_counter() - b
        prep_s += b - a
        eqs.append(eq)

    # reference: SLSQP frame by frame on the same equations
    stride = 20 if quick else 1
    ref_frames = 0
    ref_s = 0.0
    max_tau = max_wrench = 0.0
    for eq, res in zip(eqs, results):
        idx = np.flatnonzero(eq.valid)[::stride]
        a = time.perf_counter()
        u = static_optimisation_per_frame(eq, model, idx)
        ref_s += time.perf_counter() - a
        ref_frames += idx.size
        max_tau = max(max_tau, float(np.max(np.abs(u[idx, 6] - res.afo_torque_nm[idx]))))
        w = np.hstack([res.sop.operator_force_n, res.sop.operator_moment_nm])
        max_wrench = max(max_wrench, float(np.max(np.abs(u[idx, :6] - w[idx]))))
    per_frame_solve_s = ref_s / ref_frames
    reference_pipeline_s = pipeline_s - solve_s + per_frame_solve_s * frames

    # accuracy on ideal AFOs: SOP stiffness against the simulator's spring torque, same estimator, same frames
    ideal = AfoProperties(hinge_friction_nm=0.0, hinge_friction_coeff=0.0, shell_stiffness_nm_per_deg=1e9)
    errors = []
    for s in (1, 2, 3):
        for o in (1, 2, 4):
            motion, truth = synthesize_aads_trial(s, o, 1, afo=ideal)
            res = analyze_trial(motion, model, factors={"spring": s})
            h = truth["hinge_deg"]
            sel = (h >= 6) & (h <= 20)
            k = line_fit(h[sel], truth["spring_torque_nm"][sel], model.fit_window_deg).slope_nm_per_deg
            errors.append(abs(res.stiffness_nm_per_deg / k - 1) * 100)
    out = {
        "trials": len(trials), "frames": frames, "quick": quick,
        "frames_per_s": frames / pipeline_s,
        "pipeline_s": pipeline_s, "batched_solve_s": solve_s, "shared_preparation_s": prep_s,
        "reference_frames_solved": ref_frames, "reference_s_per_frame": per_frame_solve_s,
        "reference_pipeline_s": reference_pipeline_s,
        "speedup_vs_per_frame": reference_pipeline_s / pipeline_s,
        "solve_speedup_vs_per_frame": per_frame_solve_s * frames / solve_s,
        "max_torque_diff_Nm": max_tau, "max_operator_wrench_diff": max_wrench,
        "ideal_stiffness_error_pct_max": float(max(errors)), "ideal_stiffness_error_pct_mean": float(np.mean(errors)),
        "synthesis_s": synth_s,
    }
    print(f"{'quantity':<40}{'value':>14}")
    for k, v in out.items():
        print(f"{k:<40}{v:>14.6g}" if isinstance(v, float) else f"{k:<40}{v!s:>14}")
    return out
