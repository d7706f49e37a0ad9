"""Isokinetic trials simulated from the muscle model with randomly perturbed parameters (the estimator's truth).

Knee trials: 0→90° at 5 °/s at hip 90, 55 and 15° (ankle 0°), 0.3 N·m torque noise. Ankle trials:
15→−30° at 5 °/s at knee 0, 45 and 90° (hip 90°), 0.2 N·m noise. Perturbations: slack lengths
×U(0.96, 1.02) (kept below the no-buckling bound), ε₀ of the non-calf muscles ×U(0.9, 1.1),
ε_T0 of the calf tendons ×U(0.85, 1.15); the calf fibres keep the generic ε₀ (the estimator fits
it too, its prior holding it near generic where the trials do not determine it).
"""

from __future__ import annotations

import numpy as np

from .estimator import PmpTrial, Subject, free_parameters
from .geometry import model_segment_lengths_m
from .muscles import COMPLIANT, LegMuscles, MuscleParameters

KNEE_HIPS_DEG = (90.0, 55.0, 15.0)
ANKLE_KNEES_DEG = (0.0, 45.0, 90.0)


def simulated_subject(seed: int, joints: tuple[str, ...] = ("knee",)) -> tuple[LegMuscles, list[PmpTrial], Subject]:
    """The true muscles, the trials of ``joints`` and the subject, drawn from ``seed``."""
    rng = np.random.default_rng(seed)
    truth = LegMuscles()
    probe = [PmpTrial(j, {}, np.arange(3.0), np.zeros(3), np.zeros(3), np.zeros(3)) for j in ("knee", "ankle")]
    ps = free_parameters(truth, probe)
    upper = {n.split(".")[0]: u for n, u in zip(ps.names, ps.upper) if n.endswith("slack_length_m")}
    for m, p in list(truth.params.items()):
        ls = min(p.tendon_slack_length_m * rng.uniform(0.96, 1.02), 0.99 * upper.get(m, np.inf))
        eps = p.passive_strain if m in COMPLIANT else p.passive_strain * rng.uniform(0.9, 1.1)
        eps_t = p.tendon_strain * rng.uniform(0.85, 1.15) if m in COMPLIANT else p.tendon_strain
        truth.params[m] = MuscleParameters(ls, eps, eps_t)
    # the lab measured the thigh as well as the shank (in the generic model's proportion: its muscles are scaled
    # as the shank's, to within the tapes' SDs)
    generic = model_segment_lengths_m()
    subject = Subject()
    subject.thigh_length_m = generic["thigh_length_m"] * subject.shank_length_m / generic["shank_length_m"]
    trials = []
    if "knee" in joints:
        for hip in KNEE_HIPS_DEG:
            t = np.arange(0.0, 18.0, 0.05)
            q = np.deg2rad(5.0 * t)
            fixed = {"hip": np.deg2rad(hip), "ankle": 0.0}
            moment = np.array([truth.joint_moment_nm("knee", hip=fixed["hip"], knee=x, ankle=0.0) for x in q])
            u = -(moment + subject.gravity_moment_nm("knee", q, fixed)) + rng.normal(0.0, 0.3, t.size)
            trials.append(PmpTrial("knee", fixed, t, q, np.full(t.size, np.deg2rad(5.0)), u, f"knee hip{hip:g}"))
    if "ankle" in joints:
        for knee in ANKLE_KNEES_DEG:
            t = np.arange(0.0, 9.0, 0.05)
            q = np.deg2rad(15.0 - 5.0 * t)
            fixed = {"hip": np.deg2rad(90.0), "knee": np.deg2rad(knee)}
            moment = np.array([truth.joint_moment_nm("ankle", hip=fixed["hip"], knee=fixed["knee"], ankle=x) for x in q])
            u = -(moment + subject.gravity_moment_nm("ankle", q, fixed)) + rng.normal(0.0, 0.2, t.size)
            trials.append(PmpTrial("ankle", fixed, t, q, np.full(t.size, np.deg2rad(-5.0)), u, f"ankle knee{knee:g}"))
    return truth, trials, subject
