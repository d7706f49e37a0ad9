"""AFO model-level diagnosis on trials from the jig physics with the orthosis's imperfections hidden.

For each seed, one AFO's imperfections are drawn — none, hinge friction (0.1–0.4 N·m plus 4–10 %
of the spring torque), a compliant shell (8–20 N·m/°), both, or the markers' plane off the hinge
axis (the angle scaled by 4–10 %, either way), or its hinge stop misadjusted to 14–18° (1–3 N·m/°) —
and the same AFO is bent with the three springs by
operators 3 and 4 (six trials, sampled from ``drivers.simulation.aads_jig``, which the diagnosis
does not share, and analysed by the AADS pipeline). :func:`analysis.diagnosis.aads_model.diagnose_afo_model`
then names what the spring model misses.

A case is right when the named set equals the hidden set (a shell and an axis scale error are
the same on one spring; with three springs they separate). Reported per case kind: the rate
right, each hidden parameter's error and whether its jackknife interval holds it.

Keys: ``accuracy``, ``accuracy_by_case``, ``coverage``, ``coverage_by_parameter``,
``magnitude_median_error_by_parameter``, ``seconds_per_case``, ``cases``.
"""

from __future__ import annotations

import time
from collections import defaultdict
from dataclasses import replace
from typing import Any

import numpy as np

from analysis.diagnosis.aads_model import AfoTrialData, diagnose_afo_model

CASES = ("none", "hinge_friction", "shell_compliance", "both", "axis_misalignment", "early_stop")


def _trials(afo: Any, seed: int, angle_scale: float) -> list[AfoTrialData]:
    from analysis.aads import analyze_trial, load_jig_model
    from instrument.sim.simulate import synthesize_aads_trial

    model = load_jig_model()
    out = []
    for spring in (1, 2, 3):
        for operator in (3, 4):
            res = analyze_trial(synthesize_aads_trial(spring, operator, 1, seed=seed, afo=afo)[0], model,
                                factors={"spring": spring})
            t = AfoTrialData.from_result(res, f"spring {spring} operator {operator}")
            # an axis misalignment: the hinge turns (1 + a)·θ when the markers say θ
            out.append(replace(t, angle_deg=t.angle_deg / (1.0 + angle_scale)) if angle_scale else t)
    return out


def run(quick: bool = False) -> dict[str, Any]:
    from drivers.simulation.aads_jig import AfoProperties

    seeds = 1 if quick else 4
    right: dict[str, list[bool]] = defaultdict(list)
    covered: dict[str, list[bool]] = defaultdict(list)
    errors: dict[str, list[float]] = defaultdict(list)
    cases, seconds = [], []
    print(f"{'case':<20}{'seed':>5}  {'named':<36}{'ratio':>7}  parameters: fitted / true [interval]")
    for seed in range(seeds):
        for i, case in enumerate(CASES):
            rng = np.random.default_rng([seed, i])
            friction = case in ("hinge_friction", "both")
            shell = case in ("shell_compliance", "both")
            afo = AfoProperties(hinge_friction_nm=float(rng.uniform(0.1, 0.4)) if friction else 0.0,
                                hinge_friction_coeff=float(rng.uniform(0.04, 0.1)) if friction else 0.0,
                                shell_stiffness_nm_per_deg=float(rng.uniform(8.0, 20.0)) if shell else 1e9)
            scale = float(rng.choice([-1.0, 1.0]) * rng.uniform(0.04, 0.1)) if case == "axis_misalignment" else 0.0
            if case == "early_stop":  # a stop misadjusted into the fit window, as soft as 1–3 N·m/°
                afo = replace(afo, stop_deg=float(rng.uniform(14.0, 18.0)),
                              stop_stiffness_nm_per_deg=float(rng.uniform(1.0, 3.0)))
            truth: dict[str, float] = {}
            if friction:
                truth = {"friction_Nm": afo.hinge_friction_nm, "friction_per_spring_torque": afo.hinge_friction_coeff}
            if shell:
                truth["compliance_deg_per_Nm"] = 1.0 / afo.shell_stiffness_nm_per_deg
            if scale:
                truth["angle_scale_error"] = scale
            if case == "early_stop":
                truth = {"stop_angle_deg": float(afo.stop_deg or 0.0),
                         "stop_stiffness_Nm_per_deg": afo.stop_stiffness_nm_per_deg}
            hidden = {"none": set(), "both": {"hinge_friction", "shell_compliance"}}.get(case, {case})
            trials = _trials(afo, seed, scale)
            t0 = time.perf_counter()
            d = diagnose_afo_model(trials)
            seconds.append(time.perf_counter() - t0)
            ok = set(d.named) == hidden
            right[case].append(ok)
            found = next((c for c in d.candidates if set(c.names) == set(d.named)), None)
            row: dict[str, Any] = {"case": case, "seed": seed, "named": d.named, "right": ok, "truth": truth,
                                   "stiffness_error_raw_pct": d.stiffness_error_raw_pct,
                                   "stiffness_error_corrected_pct": d.stiffness_error_corrected_pct}
            parts = []
            if found is not None and ok:
                row["parameters"], row["ci95"] = found.parameters, {k: list(v) for k, v in found.ci95.items()}
                for k, v in truth.items():
                    lo, hi = found.ci95[k]
                    covered[k].append(bool(lo <= v <= hi))
                    errors[k].append(abs(found.parameters[k] / v - 1.0))
                    parts.append(f"{k} {found.parameters[k]:.3g} / {v:.3g} [{lo:.3g}, {hi:.3g}]")
            cases.append(row)
            ratio = found.heldout_ratio if found is not None else 1.0
            print(f"{case:<20}{seed:>5}  {' + '.join(d.named) or 'none':<36}{ratio:>7.2f}  {'; '.join(parts)}")
    all_cov = [x for v in covered.values() for x in v]
    out = {"quick": quick, "seeds": seeds,
           "accuracy": float(np.mean([x for v in right.values() for x in v])),
           "accuracy_by_case": {k: float(np.mean(v)) for k, v in right.items()},
           "coverage": float(np.mean(all_cov)) if all_cov else float("nan"),
           "coverage_by_parameter": {k: float(np.mean(v)) for k, v in covered.items()},
           "magnitude_median_error_by_parameter": {k: float(np.median(v)) for k, v in errors.items()},
           "seconds_per_case": float(np.mean(seconds)), "cases": cases}
    print(f"\nright {out['accuracy']:.2f} {out['accuracy_by_case']}; intervals holding the truth {out['coverage']:.2f} "
          f"{out['coverage_by_parameter']}; median |error| {out['magnitude_median_error_by_parameter']}; "
          f"{out['seconds_per_case']:.1f} s per case")
    return out
