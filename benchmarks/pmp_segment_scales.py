"""Subjects scaled by OpenSim with unequal segment factors: are the passive parameters' intervals still honest?

The estimator scales every muscle path, optimal fibre length and tendon slack length by one factor, the
subject's measured shank over the generic model's (:func:`analysis.pmp.muscles.scale_for_subject`). A real
subject's thigh, shank and foot are not in one proportion. Here OpenSim's own ``Model.scale`` (the Scale
Tool's manual factors; :mod:`benchmarks.opensim_passive`) scales Rajagopal 2016 per body before a subject's
muscle parameters are drawn about the scaled ones:

* ``uniform``: one factor U(0.93, 1.07) for every body (the estimator's own assumption: the control);
* ``unequal``: the thigh (pelvis, femur, patella), the shank (tibia) and the foot (talus, calcaneus, toes) each
  by its own factor U(0.93, 1.07), the thigh not measured (its muscles scaled as the shank's, their intervals
  carrying an assumed 3 % SD of the thigh's scale over the shank's);
* ``unequal_thigh_measured``: the same, the thigh's length (hip to knee joint centre) entered as a tape reads it,
  within ±5 mm (uniform).

The lab enters the subject's true shank and foot lengths (the generic model's × the tibia's and the foot's
factors: no tape error on them, to see the scaling alone); the six protocol sweeps (knee at hip 90/55/15°, ankle
at knee 0/45/90°, 5 °/s, a 150 N·m ceiling) come from :func:`benchmarks.opensim_truth.make_trials`; the
estimator fits them as ``instrument analyze pmp`` does (plain model, 16 intervals). The truth of a slack length
is the scaled model's, as OpenSim simulated it.

Keys: ``subjects`` (per subject: factors, determined parameters with truth, interval, error, misfit),
``by_variant`` (per variant: ``determined``, ``covered``, ``coverage_95``, ``max_error_pct``, the median misfit
ratio), ``thigh_over_shank`` (each unequal subject's factor ratio beside its worst thigh-muscle error).
"""

from __future__ import annotations

import time
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

VARIANTS = ("uniform", "unequal", "unequal_thigh_measured")
#: seeds of the measured run (development looked at 40000–40201 with --quick; 41000– measured a version that
#: counted the shank's tape twice in the thigh's muscles: 18 of 18 intervals held, one parameter per subject)
SEED_BASE = 42000
SUBJECTS_PER_VARIANT = 6
FACTOR_RANGE = (0.93, 1.07)
THIGH = ("pelvis", "femur_r", "patella_r")
SHANK = ("tibia_r",)
FOOT = ("talus_r", "calcn_r", "toes_r")
MASS_KG = 75.0
#: muscles whose path runs along the thigh (from the pelvis or the femur)
THIGH_MUSCLES = ("bflh", "bfsh", "semimem", "semiten", "vasint", "vaslat", "vasmed", "recfem", "gaslat", "gasmed")


def one_subject(job: tuple[int, str]) -> dict[str, Any]:
    from analysis.pmp.estimator import PmpTrial, Subject
    from analysis.pmp.geometry import model_segment_lengths_m
    from analysis.pmp.report import analyse

    from .opensim_truth import draw_truth, generic_parameters, make_trials
    from .pmp_opensim import SHANK_M, determined_against_truth
    from .pmp_realistic import FOOT_M

    seed, variant = job
    rng = np.random.default_rng(seed)
    if variant == "uniform":  # (the three variants draw their factors from separate seeds)
        thigh = shank = foot = float(rng.uniform(*FACTOR_RANGE))
    else:
        thigh, shank, foot = (float(f) for f in rng.uniform(*FACTOR_RANGE, 3))
    scales = {**dict.fromkeys(THIGH, thigh), **dict.fromkeys(SHANK, shank), **dict.fromkeys(FOOT, foot)}
    truth = draw_truth(seed, generic_parameters())
    simulated: dict[str, float] = {}
    shank_m, foot_m = SHANK_M * shank, FOOT_M * foot
    thigh_m = (model_segment_lengths_m()["thigh_length_m"] * thigh + float(rng.uniform(-0.005, 0.005))
               if variant == "unequal_thigh_measured" else None)
    made = make_trials(truth, seed, shank_m=shank_m, mass_kg=MASS_KG, foot_m=foot_m, segment_scales=scales,
                       simulated_slack_m=simulated)
    scaled_truth = {m: {**row, "tendon_slack_length_m": simulated[m]} for m, row in truth.items()}
    trials = [PmpTrial(t.joint, t.fixed_rad, t.time_s, t.angle_rad, t.velocity_rad_s, t.torque_nm, t.name) for t in made]
    t0 = time.perf_counter()
    report = analyse(trials, Subject(MASS_KG, shank_m, foot_m, thigh_length_m=thigh_m), intervals=16)
    rows = determined_against_truth(report.result, report.identifiability, scaled_truth)
    return {"seed": seed, "variant": variant, "factors": {"thigh": thigh, "shank": shank, "foot": foot},
            "thigh_entered_m": thigh_m, "determined": rows, "misfit": report.identifiability.misfit_ratio,
            "thigh_would_determine": report.identifiability.thigh_would_determine,
            "not_determined_because": report.identifiability.not_determined_because,
            "seconds": time.perf_counter() - t0}


def run(quick: bool = False) -> dict[str, Any]:
    per = 2 if quick else SUBJECTS_PER_VARIANT
    jobs = [(SEED_BASE + 100 * i + k, v) for i, v in enumerate(VARIANTS) for k in range(per)]
    with ProcessPoolExecutor(2) as pool:
        subjects = list(pool.map(one_subject, jobs))
    print(f"{'seed':>6} {'variant':<23}{'thigh':>7}{'shank':>7}{'foot':>7}{'misfit':>8}  determined (error %, covered)")
    for s in subjects:
        f = s["factors"]
        det = ", ".join(f"{r['parameter']} {r['error_pct']:+.2f}{'' if r['covered'] else ' MISSED'}" for r in s["determined"])
        print(f"{s['seed']:>6} {s['variant']:<23}{f['thigh']:>7.3f}{f['shank']:>7.3f}{f['foot']:>7.3f}{s['misfit']:>8.2f}  "
              f"{det or '-'}", flush=True)
    by_variant = {}
    for v in VARIANTS:
        rows = [r for s in subjects if s["variant"] == v for r in s["determined"]]
        by_variant[v] = {"subjects": sum(s["variant"] == v for s in subjects), "determined": len(rows),
                         "covered": sum(r["covered"] for r in rows),
                         "coverage_95": float(np.mean([r["covered"] for r in rows])) if rows else None,
                         "max_error_pct": float(max(abs(r["error_pct"]) for r in rows)) if rows else None,
                         "median_misfit": float(np.median([s["misfit"] for s in subjects if s["variant"] == v]))}
        print(f"{v:<23} determined {by_variant[v]['determined']}, covered {by_variant[v]['covered']}, "
              f"worst {by_variant[v]['max_error_pct']}, median misfit {by_variant[v]['median_misfit']:.2f}")
    ratio = [{"seed": s["seed"], "thigh_over_shank": s["factors"]["thigh"] / s["factors"]["shank"],
              "worst_thigh_muscle_error_pct": max((abs(r["error_pct"]) for r in s["determined"]
                                                   if r["parameter"].split(".")[0] in THIGH_MUSCLES), default=None)}
             for s in subjects if s["variant"] != "uniform"]
    return {"quick": quick, "factor_range": FACTOR_RANGE, "subjects": subjects, "by_variant": by_variant,
            "thigh_over_shank": ratio}
