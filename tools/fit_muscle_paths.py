"""Fit muscle-tendon lengths of the leg muscles as polynomials of hip, knee and ankle angle, from any .osim.

    python tools/fit_muscle_paths.py MODEL.osim [-o analysis/pmp/data/rajagopal2016_paths.json]

Needs OpenSim (``pip install 'afo-gait-instrument[opensim]'``). For each muscle, the coordinates
it crosses are found from its moment arms; its length is sampled on a grid over the seated
ranges (hip −10…100°, knee 0…94° flexion — below the kink the patella mechanism puts in the
moment arms at 95.5°, which a polynomial would ring around — ankle −40…30° dorsiflexion) and
fitted by least squares with a polynomial of total degree ``--degree`` in those angles (radians), to the
lengths, and each moment arm from ``computeMomentArm`` by its own polynomial on the same basis:
OpenSim's moment arm is not −∂L/∂q of its ``getLength`` where the coupled knee or a wrapping
surface kinks the path (the gastrocnemius near full extension: up to 17 mm apart), and OpenSim's
joint moment is tendon force × ``computeMomentArm``, which the model reproduces. The fit is
checked on a second grid, offset by half a step, against OpenSim's own lengths and
``computeMomentArm``; the errors (mm) go into the JSON with the muscles' generic parameters as
the model states them once its muscles are ``DeGrooteFregly2016Muscle`` (maximum isometric
force, optimal fibre length, tendon slack length, pennation, passive fibre and tendon strain)
and the model's own segment lengths between joint centres (the scaling reference).
"""

from __future__ import annotations

import argparse
import itertools
import json
import sys
from pathlib import Path

import numpy as np

MUSCLES = ["bflh", "bfsh", "gaslat", "gasmed", "soleus", "semimem", "semiten", "vasint", "vaslat", "vasmed", "recfem"]
COORDS = {"hip": ("hip_flexion_r", -10.0, 100.0, 12), "knee": ("knee_angle_r", 0.0, 94.0, 24),
          "ankle": ("ankle_angle_r", -40.0, 30.0, 11)}



#: a one-joint polynomial is cheap, and the patella-coupled vasti need it
SINGLE_JOINT_DEGREE = 10


def exponents(n_vars: int, degree: int) -> list[tuple[int, ...]]:
    return [e for e in itertools.product(range(degree + 1), repeat=n_vars) if sum(e) <= degree]


def design(q: np.ndarray, exps: list[tuple[int, ...]]) -> np.ndarray:
    return np.column_stack([np.prod(q ** np.array(e), axis=1) for e in exps])


def derivative_design(q: np.ndarray, exps: list[tuple[int, ...]], j: int) -> np.ndarray:
    """∂/∂q_j of every column of :func:`design`."""
    cols = []
    for e in exps:
        if e[j] == 0:
            cols.append(np.zeros(q.shape[0]))
            continue
        e2 = np.array(e)
        e2[j] -= 1
        cols.append(e[j] * np.prod(q ** e2, axis=1))
    return np.column_stack(cols)


def segment_lengths(model: object, state: object) -> dict[str, float]:
    """The model's thigh (hip to knee centre) and shank (knee to ankle centre) lengths (m)."""
    joints = model.getJointSet()  # type: ignore[attr-defined]
    model.realizePosition(state)  # type: ignore[attr-defined]

    def at(frame: object) -> np.ndarray:
        p = frame.getPositionInGround(state)  # type: ignore[attr-defined]
        return np.array([p.get(i) for i in range(3)])

    knee, ankle, hip = joints.get("walker_knee_r"), joints.get("ankle_r"), joints.get("hip_r")
    return {"shank_length_m": float(np.linalg.norm(at(knee.getChildFrame()) - at(ankle.getParentFrame()))),
            "thigh_length_m": float(np.linalg.norm(at(hip.getChildFrame()) - at(knee.getParentFrame())))}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model", type=Path)
    ap.add_argument("-o", "--output", type=Path, default=Path("analysis/pmp/data/rajagopal2016_paths.json"))
    ap.add_argument("--degree", type=int, default=5)
    args = ap.parse_args(argv)
    import opensim as osim

    osim.Logger.setLevelString("error")
    model = osim.Model(str(args.model))
    osim.DeGrooteFregly2016Muscle.replaceMuscles(model)
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
           "dorsiflexion positive, as the .osim", "script": "tools/fit_muscle_paths.py",
           "segments": segment_lengths(model, state), "muscles": {}}
    for m in MUSCLES:
        spans = [k for k in COORDS if np.max(np.abs(train_r[m][k])) > 1e-3]  # a moment arm over 1 mm somewhere
        idx = [list(COORDS).index(k) for k in spans]
        exps = exponents(len(spans), args.degree if len(spans) > 1 else SINGLE_JOINT_DEGREE)
        basis = design(train_q[:, idx], exps)
        coef, *_ = np.linalg.lstsq(basis, train_l[m], rcond=None)
        # OpenSim's moment arm (computeMomentArm) is not −∂L/∂q of its own getLength where a
        # coupled or wrapped path kinks it: each is fitted on its own, as OpenSim uses each
        arm_coef = {k: np.linalg.lstsq(basis, train_r[m][k], rcond=None)[0] for k in spans}
        pred = design(test_q[:, idx], exps) @ coef
        err_l = (pred - test_l[m]) * 1e3
        test_basis = design(test_q[:, idx], exps)
        err_r = np.concatenate([(test_basis @ arm_coef[k] - test_r[m][k]) * 1e3 for k in spans])
        err_dl = np.concatenate([(-derivative_design(test_q[:, idx], exps, j) @ coef - test_r[m][k]) * 1e3
                                 for j, k in enumerate(spans)])
        mus = osim.DeGrooteFregly2016Muscle.safeDownCast(model.getMuscles().get(f"{m}_r"))
        out["muscles"][m] = {
            "coordinates": spans, "exponents": [list(e) for e in exps], "coefficients_m": coef.tolist(),
            "moment_arm_coefficients_m": {k: arm_coef[k].tolist() for k in spans},
            "max_isometric_force_n": mus.getMaxIsometricForce(), "optimal_fiber_length_m": mus.getOptimalFiberLength(),
            "tendon_slack_length_m": mus.getTendonSlackLength(),
            "pennation_at_optimal_rad": mus.getPennationAngleAtOptimalFiberLength(),
            "passive_strain": mus.get_passive_fiber_strain_at_one_norm_force(),
            "tendon_strain": mus.get_tendon_strain_at_one_norm_force(),
            "min_length_m": float(min(train_l[m].min(), test_l[m].min())),
            "fit": {"length_rms_mm": float(np.sqrt(np.mean(err_l**2))), "length_max_mm": float(np.max(np.abs(err_l))),
                    "moment_arm_rms_mm": float(np.sqrt(np.mean(err_r**2))),
                    "moment_arm_max_mm": float(np.max(np.abs(err_r))),
                    "minus_dl_dq_vs_moment_arm_max_mm": float(np.max(np.abs(err_dl)))}}
        f = out["muscles"][m]["fit"]
        print(f"{m:<8} {'+'.join(spans):<11} length RMS {f['length_rms_mm']:.3f} max {f['length_max_mm']:.3f} mm; "
              f"moment arm RMS {f['moment_arm_rms_mm']:.3f} max {f['moment_arm_max_mm']:.3f} mm "
              f"(−∂L/∂q off by up to {f['minus_dl_dq_vs_moment_arm_max_mm']:.1f} mm)")
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(out, indent=1))
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
