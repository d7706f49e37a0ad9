"""Tabulate and fit muscle-tendon lengths and moment arms of the leg muscles over hip, knee and ankle angle, from any .osim.

    python tools/fit_muscle_paths.py MODEL.osim [-o analysis/pmp/data/rajagopal2016_paths.json]

Needs OpenSim (``pip install 'afo-gait-instrument[opensim]'``), run in a child interpreter
(:mod:`benchmarks.opensim_passive`; its bundled CasADi cannot share a process with the
``casadi`` wheel this script checks the splines with). The model uses, per muscle, OpenSim's
lengths and ``computeMomentArm`` tabulated on a 1° grid (2.5° over the hip) of the coordinates
the muscle crosses, interpolated by cubic B-splines (:class:`analysis.pmp.geometry.SplineGrid`),
checked between the nodes against OpenSim; the polynomials below are kept beside them as the
smooth fallback. For each muscle, the coordinates
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


#: the B-spline grids (deg): lo, hi, nodes; 1° over the knee and ankle (the patella-coupled vasti and the
#: gastrocnemius wrap), 2.5° over the hip
SPLINE_AXES = {"hip": (-10.0, 100.0, 45), "knee": (0.0, 94.0, 95), "ankle": (-40.0, 30.0, 71)}


def _poses(points_rad: np.ndarray, joints: list[str]) -> list[dict[str, float]]:
    """Poses for OpenSim: ``joints`` from ``points_rad`` columns, the other coordinates at 0."""
    out = []
    for p in points_rad:
        pose = {k: 0.0 for k in COORDS}
        pose.update({j: float(v) for j, v in zip(joints, p)})
        out.append(pose)
    return out


def _spline_grid(joints: list[str], offset: float) -> np.ndarray:
    """Grid points (rad) over ``joints``, the first joint varying fastest (CasADi's order); ``offset``
    shifts every axis by that fraction of its step (0.5: the points between the nodes)."""
    axes = []
    for j in joints:
        lo, hi, n = SPLINE_AXES[j]
        pts = np.linspace(lo, hi, n)
        if offset:
            pts = (pts[:-1] + offset * (pts[1] - pts[0]))
        axes.append(np.deg2rad(pts))
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.column_stack([g.ravel(order="F") for g in mesh])


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model", type=Path)
    ap.add_argument("-o", "--output", type=Path, default=Path("analysis/pmp/data/rajagopal2016_paths.json"))
    ap.add_argument("--degree", type=int, default=8)
    args = ap.parse_args(argv)
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from analysis.pmp.geometry import SplineGrid
    from benchmarks.opensim_truth import opensim  # OpenSim in a child interpreter (its CasADi ≠ the wheel's)

    model = str(args.model.resolve())
    facts = opensim({"what": "facts", "model": model})

    def sample(points: np.ndarray, joints: list[str], muscles: list[str]) -> dict:
        return opensim({"what": "paths", "model": model, "poses": _poses(points, joints), "muscles": muscles,
                        "joints": {m: list(COORDS) for m in muscles}}, timeout_s=3600.0)

    def grid(offset: float) -> np.ndarray:
        axes = []
        for lo, hi, n in ((v[1], v[2], v[3]) for v in COORDS.values()):
            step = (hi - lo) / (n - 1)
            pts = np.linspace(lo, hi, n) + offset * step
            axes.append(pts[pts <= hi + 1e-9])
        return np.deg2rad(np.array(list(itertools.product(*axes))))

    train_q, test_q = grid(0.0), grid(0.5)
    train, test = sample(train_q, list(COORDS), MUSCLES), sample(test_q, list(COORDS), MUSCLES)
    out = {"source": args.model.name, "degree": args.degree, "coordinates": {k: v[0] for k, v in COORDS.items()},
           "ranges_deg": {k: [v[1], v[2]] for k, v in COORDS.items()}, "angles": "radians; knee flexion and ankle "
           "dorsiflexion positive, as the .osim", "script": "tools/fit_muscle_paths.py",
           "spline_axes_deg": {k: list(v) for k, v in SPLINE_AXES.items()},
           "segments": {"shank_length_m": facts["shank_length_m"], "thigh_length_m": facts["thigh_length_m"]},
           "muscles": {}}
    spans_of = {}
    for m in MUSCLES:
        arms = {k: np.array(train["moment_arm_m"][m][k]) for k in COORDS}
        spans_of[m] = [k for k in COORDS if np.max(np.abs(arms[k])) > 1e-3]  # a moment arm over 1 mm somewhere
    groups: dict[tuple[str, ...], list[str]] = {}
    for m in MUSCLES:
        groups.setdefault(tuple(spans_of[m]), []).append(m)
    dense, between = {}, {}
    for joints, members in groups.items():
        print(f"sampling OpenSim on the {'×'.join(joints)} grid for {', '.join(members)} ...", flush=True)
        dense[joints] = (_spline_grid(list(joints), 0.0), sample(_spline_grid(list(joints), 0.0), list(joints), members))
        between[joints] = (_spline_grid(list(joints), 0.5), sample(_spline_grid(list(joints), 0.5), list(joints), members))
    for m in MUSCLES:
        spans = spans_of[m]
        idx = [list(COORDS).index(k) for k in spans]
        train_l, test_l = np.array(train["path_length_m"][m]), np.array(test["path_length_m"][m])
        exps = exponents(len(spans), args.degree if len(spans) > 1 else SINGLE_JOINT_DEGREE)
        basis = design(train_q[:, idx], exps)
        coef, *_ = np.linalg.lstsq(basis, train_l, rcond=None)
        # OpenSim's moment arm (computeMomentArm) is not −∂L/∂q of its own getLength where a
        # coupled or wrapped path kinks it: each is fitted on its own, as OpenSim uses each
        arm_coef = {k: np.linalg.lstsq(basis, np.array(train["moment_arm_m"][m][k]), rcond=None)[0] for k in spans}
        test_basis = design(test_q[:, idx], exps)
        poly_err_r = np.concatenate([(test_basis @ arm_coef[k] - np.array(test["moment_arm_m"][m][k])) * 1e3
                                     for k in spans])
        err_dl = np.concatenate([(-derivative_design(test_q[:, idx], exps, j) @ coef
                                  - np.array(test["moment_arm_m"][m][k])) * 1e3 for j, k in enumerate(spans)])
        # the B-spline grid: OpenSim's values at the nodes, checked between the nodes
        key = tuple(spans)
        nodes, at_nodes = dense[key]
        mid, at_mid = between[key]
        values = {"length": np.round(at_nodes["path_length_m"][m], 10).tolist(),
                  **{k: np.round(at_nodes["moment_arm_m"][m][k], 10).tolist() for k in spans}}
        spline = SplineGrid(key, {j: SPLINE_AXES[j] for j in spans}, values)
        cols = [mid[:, i] for i in range(len(spans))]
        err_l = (spline.evaluate("length", cols) - np.array(at_mid["path_length_m"][m])) * 1e3
        err_r = np.concatenate([(spline.evaluate(k, cols) - np.array(at_mid["moment_arm_m"][m][k])) * 1e3
                                for k in spans])
        g = facts["muscles"][m]
        out["muscles"][m] = {
            "coordinates": spans, "exponents": [list(e) for e in exps], "coefficients_m": coef.tolist(),
            "moment_arm_coefficients_m": {k: arm_coef[k].tolist() for k in spans},
            "spline": {"axes_deg": {j: list(SPLINE_AXES[j]) for j in spans}, "length_m": values["length"],
                       "moment_arm_m": {k: values[k] for k in spans}},
            "max_isometric_force_n": g["max_isometric_force_n"], "optimal_fiber_length_m": g["optimal_fiber_length_m"],
            "tendon_slack_length_m": g["tendon_slack_length_m"],
            "pennation_at_optimal_rad": g["pennation_at_optimal_rad"],
            "passive_strain": g["passive_strain"], "tendon_strain": g["tendon_strain"],
            "min_length_m": float(min(train_l.min(), test_l.min(), np.min(at_nodes["path_length_m"][m]))),
            "fit": {"length_rms_mm": float(np.sqrt(np.mean(err_l**2))), "length_max_mm": float(np.max(np.abs(err_l))),
                    "moment_arm_rms_mm": float(np.sqrt(np.mean(err_r**2))),
                    "moment_arm_max_mm": float(np.max(np.abs(err_r))),
                    "polynomial_moment_arm_rms_mm": float(np.sqrt(np.mean(poly_err_r**2))),
                    "minus_dl_dq_vs_moment_arm_max_mm": float(np.max(np.abs(err_dl)))}}
        f = out["muscles"][m]["fit"]
        print(f"{m:<8} {'+'.join(spans):<11} B-spline length RMS {f['length_rms_mm']:.4f} max {f['length_max_mm']:.4f} mm; "
              f"moment arm RMS {f['moment_arm_rms_mm']:.4f} max {f['moment_arm_max_mm']:.4f} mm "
              f"(polynomial {f['polynomial_moment_arm_rms_mm']:.3f}; −∂L/∂q off by up to "
              f"{f['minus_dl_dq_vs_moment_arm_max_mm']:.1f} mm)")
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(out, separators=(",", ":")))
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
