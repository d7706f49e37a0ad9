"""Model-level diagnosis on trials OpenSim made, with a model effect hidden in them.

One subject's parameters are drawn around Rajagopal 2016's, OpenSim computes the passive moments
of the protocol's six sweeps twice (two repeats, different noise: :mod:`benchmarks.opensim_truth`),
and one model-level effect, drawn from a seed, is added to the dynamometer torque: nothing, a
torque offset per joint (arm-weight compensation), a limb-weight error (the limb heavier or
lighter than the anthropometric tables say), viscous damping, or the knee's axis 1.5–2.5 cm off the
dynamometer's (exact lever geometry with the pad sliding on the shank, OpenSim's knee moment
reaching the arm by virtual work: not the estimator's first-order form). The model-level diagnosis
(:func:`analysis.pmp.model_diagnosis.diagnose_model`) fits each candidate inside the estimator and
judges it on the left-out repeats.

A case is right when the diagnosis names the hidden extension with its interval holding the truth,
or names it among extensions the trials cannot separate (with the protocol that would); or, for an effect these one-way,
one-speed sweeps cannot separate from the muscles (the diagnosis
then reports it absorbed, with the protocol that would separate it), when it is reported so with
its interval holding the truth; a clean case is right when nothing is named and nothing material
is reported absorbed.

Keys: ``cases`` (per case: hidden, truth, verdict, named, absorbed, interval, covered, held-out
ratio, seconds), ``right``, ``covered``, ``seconds_per_case`` (the fits in :func:`fit_workers` processes),
``seconds_first_case_one_process`` and ``speedup_first_case`` (the first case again with every fit in this
process: the reference, measured in the same run).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from analysis.pmp.estimator import PmpTrial, Subject
from analysis.pmp.model_diagnosis import diagnose_model, fit_workers, is_material
from analysis.pmp.muscles import LegMuscles, scale_for_subject

from .opensim_truth import draw_truth, generic_parameters, limb_weight_nm, make_trials
from .pmp_opensim import SHANK_M

CANDIDATES = ["viscous_damping", "limb_mass_error", "torque_offset", "axis_misalignment"]
#: the parameter each hidden effect is scored on
SCORED = {"torque_offset": "knee_offset_Nm", "limb_mass_error": "limb_weight_error_fraction",
          "viscous_damping": "damping_Nm_s_per_rad", "axis_misalignment": "knee_axis_sin_rad"}
#: where the dynamometer's pad sits on the shank, from the knee (m)
PAD_LEVER_M = 0.30


def misaligned_knee(t: Any, offset_m: float, direction_rad: float) -> PmpTrial:
    """A knee trial as the dynamometer records it when its axis is ``offset_m`` from the knee's.

    Exact lever geometry, not the estimator's first-order form: the arm turns by q about its own
    axis O, its pad at PAD_LEVER_M from O, and the pad slides along the shank, which turns about the
    knee J = O + offset·(cos φ, sin φ); the shank's angle is the direction from J to the pad,
    atan2(L sin q − d sin φ, L cos q − d cos φ). The knee's torque (OpenSim's, at the knee angle)
    reaches the arm by virtual work, × dq_knee/dq_arm. Samples whose knee angle falls outside the
    computed sweep are dropped."""
    q = t.angle_rad
    d, phi, lever = offset_m, direction_rad, PAD_LEVER_M
    knee = np.arctan2(lever * np.sin(q) - d * np.sin(phi), lever * np.cos(q) - d * np.cos(phi))
    ratio = lever * (lever - d * np.cos(q - phi)) / (lever**2 + d**2 - 2 * lever * d * np.cos(q - phi))
    order = np.argsort(q)
    inside = (knee >= q.min()) & (knee <= q.max())
    torque = np.interp(knee, q[order], t.torque_nm[order]) * ratio
    return PmpTrial(t.joint, t.fixed_rad, t.time_s[inside], q[inside], t.velocity_rad_s[inside], torque[inside], t.name)
MASS_KG, FOOT_M = 75.0, 0.26


def hide(made: list[Any], effect: str, rng: np.random.Generator) -> tuple[list[PmpTrial], float]:
    """The trials with ``effect`` added to the dynamometer torque; the true value of its scored parameter."""
    sign = float(rng.choice([-1.0, 1.0]))
    truth = 0.0
    out = []
    size = {"torque_offset": rng.uniform(1.0, 2.0), "limb_mass_error": rng.uniform(0.10, 0.20),
            "viscous_damping": rng.uniform(8.0, 16.0), "axis_misalignment": rng.uniform(0.015, 0.025),
            "none": 0.0}[effect]
    # the offset's direction: mostly along the arm at full extension (where a sin-term shows), either way
    direction = rng.uniform(-0.5, 0.5) + (np.pi if sign < 0 else 0.0)
    for t in made:
        extra = np.zeros_like(t.torque_nm)
        if effect == "torque_offset":  # u = I q̈ − M: the model's moment is off by −offset
            extra += sign * size
            truth = -sign * size
        elif effect == "limb_mass_error":  # the limb weighs (1 + δ) times the tables'
            extra -= sign * size * limb_weight_nm(t.joint, t.angle_rad, t.fixed_rad, MASS_KG, SHANK_M, FOOT_M)
            truth = sign * size
        elif effect == "viscous_damping":  # the dynamometer also overcomes b·q̇
            extra += size * t.velocity_rad_s
            truth = size
        elif effect == "axis_misalignment":  # the knee's axis 1.5–2.5 cm off the dynamometer's
            phi = float(direction)
            truth = float(size / PAD_LEVER_M * np.cos(phi))  # the first-order sin coefficient
            if t.joint == "knee":
                out.append(misaligned_knee(t, size, phi))
                continue
        out.append(PmpTrial(t.joint, t.fixed_rad, t.time_s, t.angle_rad, t.velocity_rad_s, t.torque_nm + extra, t.name))
    return out, truth


def run(quick: bool = False) -> dict[str, Any]:
    generic = generic_parameters()
    seed = 1
    truth_params = draw_truth(seed, generic)
    made = make_trials(truth_params, seed, shank_m=SHANK_M) + make_trials(truth_params, 100 + seed, shank_m=SHANK_M)
    subject = Subject(MASS_KG, SHANK_M, FOOT_M)
    leg = LegMuscles(length_scale=scale_for_subject(SHANK_M))
    effects = ["none", "torque_offset"] if quick else ["none", "torque_offset", "limb_mass_error", "viscous_damping",
                                                       "axis_misalignment"]
    cases = []
    print(f"{'hidden':<18}{'truth':>9}  {'verdict':<10}{'fitted [95 % interval]':<30}{'covered':>8}{'ratio':>7}{'s':>6}")
    for i, effect in enumerate(effects):
        rng = np.random.default_rng([seed, i])
        trials, truth = hide(made, effect, rng)
        t0 = time.perf_counter()
        d = diagnose_model(trials, subject, leg=leg, intervals=10 if quick else 12, candidates=CANDIDATES)
        seconds = time.perf_counter() - t0
        absorbed = [c.name for c in d.candidates if c.heldout_ratio < 1.05 and is_material(c)] if d.cause == "none" else []
        verdict = "named" if d.cause != "none" else ("absorbed" if absorbed else "none")
        row: dict[str, Any] = {"hidden": effect, "truth": truth, "verdict": verdict, "named": d.cause,
                               "absorbed": absorbed, "conclusive": d.conclusive, "seconds": seconds}
        if effect == "none":
            row["right"] = d.conclusive and d.cause == "none" and not absorbed
        else:
            c = next(c for c in d.candidates if c.name == effect)
            lo, hi = c.ci95[SCORED[effect]]
            row.update(fitted=c.parameters[SCORED[effect]], interval=[lo, hi], covered=bool(lo <= truth <= hi),
                       heldout_ratio=c.heldout_ratio)
            row["ambiguous_with"] = d.ambiguous_with
            # right: named; or named as one of extensions these trials cannot separate (the report says so
            # and what would separate them); or reported absorbed by the muscles — with the truth inside its interval
            row["right"] = bool((d.cause == effect or effect in d.ambiguous_with
                                 or (d.cause == "none" and effect in absorbed)) and row["covered"])
        cases.append(row)
        fitted = f"{row['fitted']:.3g} [{row['interval'][0]:.3g}, {row['interval'][1]:.3g}]" if "fitted" in row else "—"
        print(f"{effect:<18}{truth:>9.3g}  {verdict + ('' if d.cause == 'none' else ' ' + d.cause):<10}{fitted:<30}"
              f"{str(row.get('covered', '—')):>8}{row.get('heldout_ratio', 1.0):>7.2f}{seconds:>6.0f}")
        print("    " + d.message[:300])
    # the reference in the same run: the first case again with every fit in this process, one after another
    trials, _ = hide(made, effects[0], np.random.default_rng([seed, 0]))
    t0 = time.perf_counter()
    one = diagnose_model(trials, subject, leg=leg, intervals=10 if quick else 12, candidates=CANDIDATES, workers=1)
    one_s = time.perf_counter() - t0
    out = {"quick": quick, "seed": seed, "cases": cases, "right": sum(c["right"] for c in cases) / len(cases),
           "covered": float(np.mean([c["covered"] for c in cases if "covered" in c])) if len(cases) > 1 else float("nan"),
           "seconds_per_case": float(np.mean([c["seconds"] for c in cases])),
           "fit_workers": fit_workers(), "seconds_first_case_one_process": one_s,
           "speedup_first_case": one_s / cases[0]["seconds"],
           "same_answer_one_process": one.cause == cases[0]["named"]}
    print(f"\nright {out['right']:.2f} of {len(cases)} cases; intervals holding the truth {out['covered']:.2f}; "
          f"{out['seconds_per_case']:.0f} s per case; the first case in one process {one_s:.0f} s "
          f"({out['speedup_first_case']:.2f}× slower than with {out['fit_workers']} workers; same answer: "
          f"{out['same_answer_one_process']})")
    return out
