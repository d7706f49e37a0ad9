"""Fit muscle-tendon lengths of the leg muscles as polynomials of hip, knee and ankle angle, from any .osim.

    python tools/fit_muscle_paths.py MODEL.osim [-o analysis/pmp/data/rajagopal2016_paths.json]

Needs OpenSim (``pip install 'afo-gait-instrument[opensim]'``). For each muscle, the coordinates
it crosses are found from its moment arms; its length is sampled on a grid over the seated
ranges (hip −10…100°, knee 0…110° flexion, ankle −40…30° dorsiflexion) and fitted by least
squares with a polynomial of total degree ``--degree`` in those angles (radians). Moment arms are
the polynomial's derivatives, r = −∂L/∂q, as in De Groote et al. (2016) and Falisse et al.
(2019). The fit is checked on a second grid, offset by half a step, against OpenSim's own
lengths and ``computeMomentArm``; the errors (mm) go into the JSON with the muscles' generic
parameters (maximum isometric force, optimal fibre length, tendon slack length, pennation).
"""

from __future__ import annotations

import argparse
import itertools
import json
import sys
from pathlib import Path

import numpy as np

MUSCLES = ["bflh", "bfsh", "gaslat", "gasmed", "soleus", "semimem", "semiten", "vasint", "vaslat", "vasmed", "recfem"]
COORDS = {"hip": ("hip_flexion_r", -10.0, 100.0, 12), "knee": ("knee_angle_r", 0.0, 110.0, 12),
          "ankle": ("ankle_angle_r", -40.0, 30.0, 9)}


def exponents(n_vars: int, degree: int) -> list[tuple[int, ...]]:
    return [e for e in itertools.product(range(degree + 1), repeat=n_vars) if sum(e) <= degree]


def design(q: np.ndarray, exps: list[tuple[int, ...]]) -> np.ndarray:
    return np.column_stack([np.prod(q ** np.array(e), axis=1) for e in exps])


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model", type=Path)
    ap.add_argument("-o", "--output", type=Path, default=Path("analysis/pmp/data/rajagopal2016_paths.json"))
    ap.add_argument("--degree", type=int, default=5)
    args = ap.parse_args(argv)
    import opensim as osim

    osim.Logger.setLevelString("error")
    model = osim.Model(str(args.model))
    state = model.initSystem()
    cs = model.getCoordinateSet()
    coords = {k: cs.get(v[0]) for k, v in COORDS.items()}

    def grid(offset: float) -> np.ndarray:
        axes = []
        for lo, hi, n in ((v[1], v[2], v[3]) for v in COORDS.values()):
            step = (hi - lo) / (n - 1)
            pts = np.linspace(lo, hi, n) + offset * step
            axes.append(pts[pts <= hi + 1e-9])
        return np.deg2rad(np.array(list(itertools.product(*axes))))

    def sample(points: np.ndarray) -> tuple[dict, dict]:
        lengths = {m: [] for m in MUSCLES}
        arms = {m: {k: [] for k in COORDS} for m in MUSCLES}
        for p in points:
            for (k, c), v in zip(coords.items(), p):
                c.setValue(state, float(v), False)
            model.assemble(state)
            model.realizePosition(state)
            for m in MUSCLES:
                mus = model.getMuscles().get(f"{m}_r")
                lengths[m].append(mus.getLength(state))
                for k, c in coords.items():
                    arms[m][k].append(mus.computeMomentArm(state, c))
        return ({m: np.array(v) for m, v in lengths.items()},
                {m: {k: np.array(v) for k, v in d.items()} for m, d in arms.items()})

    train_q = grid(0.0)
    test_q = grid(0.5)
    train_l, train_r = sample(train_q)
    test_l, test_r = sample(test_q)
    out = {"source": args.model.name, "degree": args.degree, "coordinates": {k: v[0] for k, v in COORDS.items()},
           "ranges_deg": {k: [v[1], v[2]] for k, v in COORDS.items()}, "angles": "radians; knee flexion and ankle "
           "dorsiflexion positive, as the .osim", "script": "tools/fit_muscle_paths.py", "muscles": {}}
    for m in MUSCLES:
        spans = [k for k in COORDS if np.max(np.abs(train_r[m][k])) > 1e-3]  # a moment arm over 1 mm somewhere
        idx = [list(COORDS).index(k) for k in spans]
        exps = exponents(len(spans), args.degree)
        coef, *_ = np.linalg.lstsq(design(train_q[:, idx], exps), train_l[m], rcond=None)
        pred = design(test_q[:, idx], exps) @ coef
        err_l = (pred - test_l[m]) * 1e3
        err_r = []
        for j, k in enumerate(spans):
            d = []
            for e, c in zip(exps, coef):
                if e[j] == 0:
                    d.append(np.zeros(test_q.shape[0]))
                    continue
                e2 = list(e)
                e2[j] -= 1
                d.append(c * e[j] * np.prod(test_q[:, idx] ** np.array(e2), axis=1))
            err_r.append((-np.sum(d, axis=0) - test_r[m][k]) * 1e3)
        err_r = np.concatenate(err_r)
        mus = model.getMuscles().get(f"{m}_r")
        out["muscles"][m] = {
            "coordinates": spans, "exponents": [list(e) for e in exps], "coefficients_m": coef.tolist(),
            "max_isometric_force_n": mus.getMaxIsometricForce(), "optimal_fiber_length_m": mus.getOptimalFiberLength(),
            "tendon_slack_length_m": mus.getTendonSlackLength(),
            "pennation_at_optimal_rad": mus.getPennationAngleAtOptimalFiberLength(),
            "min_length_m": float(min(train_l[m].min(), test_l[m].min())),
            "fit": {"length_rms_mm": float(np.sqrt(np.mean(err_l**2))), "length_max_mm": float(np.max(np.abs(err_l))),
                    "moment_arm_rms_mm": float(np.sqrt(np.mean(err_r**2))),
                    "moment_arm_max_mm": float(np.max(np.abs(err_r)))}}
        f = out["muscles"][m]["fit"]
        print(f"{m:<8} {'+'.join(spans):<11} length RMS {f['length_rms_mm']:.3f} max {f['length_max_mm']:.3f} mm; "
              f"moment arm RMS {f['moment_arm_rms_mm']:.3f} max {f['moment_arm_max_mm']:.3f} mm")
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(out, indent=1))
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
