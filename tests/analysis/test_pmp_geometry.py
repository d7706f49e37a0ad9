"""Fitted muscle paths against OpenSim's own geometry of Rajagopal 2016, at points the fit never saw."""

from __future__ import annotations

import numpy as np
import pytest

from analysis.pmp.geometry import MUSCLES, load_paths
from benchmarks.opensim_truth import MODEL  # the one place that finds the generic model
from tests.opensim_reference import run_opensim

#: stated accuracy of the committed paths against OpenSim (mm): lengths, and moment arms from
#: computeMomentArm, tabulated on 1° grids (2.5° over the hip) and interpolated by cubic B-splines.
#: Measured between the nodes by tools/fit_muscle_paths.py: lengths ≤ 0.03 mm, moment arms RMS
#: ≤ 0.008 mm and ≤ 0.074 mm worst (the global polynomials they replace: moment arms up to 0.18 mm RMS)
LENGTH_MAX_MM = 0.05
ARM_RMS_MM, ARM_MAX_MM = 0.02, 0.1


def test_paths_ship_all_eleven_muscles_with_generic_parameters() -> None:
    paths = load_paths()
    assert tuple(paths) == MUSCLES
    assert paths["soleus"].joints == ("ankle",) and paths["vasint"].joints == ("knee",)
    assert set(paths["recfem"].joints) == {"hip", "knee"} and set(paths["gasmed"].joints) == {"knee", "ankle"}
    assert paths["soleus"].max_isometric_force_n == pytest.approx(6194.8, abs=0.1)
    for m, p in paths.items():
        assert p.fit["length_max_mm"] < LENGTH_MAX_MM, m
        limit = (ARM_RMS_MM, ARM_MAX_MM)
        assert p.fit["moment_arm_rms_mm"] < limit[0] and p.fit["moment_arm_max_mm"] < limit[1], m


def test_length_derivative_moment_arms_in_numpy_and_casadi() -> None:
    import casadi as ca

    p = load_paths()["recfem"]
    q = {"hip": np.array([0.3, 1.2]), "knee": np.array([0.2, 1.4]), "ankle": np.zeros(2)}
    h = 1e-6
    num = -(p.length_m(**{**q, "knee": q["knee"] + h}) - p.length_m(**{**q, "knee": q["knee"] - h})) / (2 * h)
    np.testing.assert_allclose(p.length_derivative_moment_arm_m("knee", **q), num, rtol=1e-6)
    assert p.moment_arm_m("knee", **q)[0] < 0  # the rectus femoris extends the knee
    hip, knee = ca.SX.sym("hip"), ca.SX.sym("knee")
    f = ca.Function("f", [hip, knee], [ca.jacobian(p.length_m(hip=hip, knee=knee, ankle=0.0), knee)])
    assert -float(f(0.3, 0.2)) == pytest.approx(
        float(p.length_derivative_moment_arm_m("knee", hip=0.3, knee=0.2, ankle=0.0)), rel=1e-12)
    # the model's moment arm is OpenSim's computeMomentArm, fitted on its own: same in CasADi and numpy
    g = ca.Function("g", [hip, knee], [p.moment_arm_m("knee", hip=hip, knee=knee, ankle=0.0)])
    assert float(g(0.3, 0.2)) == pytest.approx(float(p.moment_arm_m("knee", hip=0.3, knee=0.2, ankle=0.0)), rel=1e-12)


def test_fit_against_opensim_at_random_postures() -> None:
    if not MODEL.exists():
        pytest.skip(f"{MODEL} (the generic model, not part of the repo) is not here")
    rng = np.random.default_rng(7)
    pts = np.column_stack([rng.uniform(np.deg2rad(-5), np.deg2rad(95), 40), rng.uniform(0.02, np.deg2rad(94), 40),
                           rng.uniform(np.deg2rad(-35), np.deg2rad(25), 40)])
    ref = run_opensim(f"""
        osim.Logger.setLevelString("error")
        m = osim.Model({str(MODEL)!r}); s = m.initSystem(); cs = m.getCoordinateSet()
        names = ["hip_flexion_r", "knee_angle_r", "ankle_angle_r"]
        out = {{mu: [] for mu in {list(MUSCLES)}}}
        for p in {pts.tolist()}:
            for n, v in zip(names, p):
                cs.get(n).setValue(s, v, False)
            m.assemble(s); m.realizePosition(s)
            for mu in out:
                muscle = m.getMuscles().get(mu + "_r")
                out[mu].append([muscle.getLength(s)] + [muscle.computeMomentArm(s, cs.get(n)) for n in names])
        print(json.dumps(out))
    """, timeout_s=300)
    paths = load_paths()
    for mu in MUSCLES:
        ref_mu = np.array(ref[mu])
        q = {"hip": pts[:, 0], "knee": pts[:, 1], "ankle": pts[:, 2]}
        ours = paths[mu].length_m(**q)
        err_mm = np.abs(np.asarray(ours) - ref_mu[:, 0]) * 1e3
        assert err_mm.max() < LENGTH_MAX_MM, (mu, err_mm.max())
        for j, joint in enumerate(("hip", "knee", "ankle")):
            if joint not in paths[mu].joints:
                continue
            arm_err_mm = (np.asarray(paths[mu].moment_arm_m(joint, **q)) - ref_mu[:, 1 + j]) * 1e3
            assert np.sqrt(np.mean(arm_err_mm**2)) < ARM_RMS_MM and np.abs(arm_err_mm).max() < ARM_MAX_MM, \
                (mu, joint, np.sqrt(np.mean(arm_err_mm**2)), np.abs(arm_err_mm).max())
