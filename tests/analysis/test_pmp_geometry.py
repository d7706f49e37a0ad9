"""Fitted muscle paths against OpenSim's own geometry of Rajagopal 2016, at points the fit never saw."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from analysis.pmp.geometry import MUSCLES, load_paths
from tests.opensim_reference import run_opensim

MODEL = Path(__file__).resolve().parents[3] / "shared" / "models" / "Rajagopal2016.osim"
#: stated accuracy of the committed fit (mm): lengths, and moment arms except the gastrocnemii,
#: whose wrapping surface puts a kink in the path that a polynomial smooths (see the JSON's fit block)
LENGTH_MAX_MM = 0.5
ARM_RMS_MM, ARM_MAX_MM = 1.0, 2.0
GASTROC_ARM_RMS_MM = 5.0


def test_paths_ship_all_eleven_muscles_with_generic_parameters() -> None:
    paths = load_paths()
    assert tuple(paths) == MUSCLES
    assert paths["soleus"].joints == ("ankle",) and paths["vasint"].joints == ("knee",)
    assert set(paths["recfem"].joints) == {"hip", "knee"} and set(paths["gasmed"].joints) == {"knee", "ankle"}
    assert paths["soleus"].max_isometric_force_n == pytest.approx(6194.8, abs=0.1)
    for m, p in paths.items():
        assert p.fit["length_max_mm"] < LENGTH_MAX_MM, m
        limit = (GASTROC_ARM_RMS_MM, 20.0) if m.startswith("gas") else (ARM_RMS_MM, ARM_MAX_MM)
        assert p.fit["moment_arm_rms_mm"] < limit[0] and p.fit["moment_arm_max_mm"] < limit[1], m


def test_moment_arms_are_the_length_derivatives_in_numpy_and_casadi() -> None:
    import casadi as ca

    p = load_paths()["recfem"]
    q = {"hip": np.array([0.3, 1.2]), "knee": np.array([0.2, 1.4]), "ankle": np.zeros(2)}
    h = 1e-6
    num = -(p.length_m(**{**q, "knee": q["knee"] + h}) - p.length_m(**{**q, "knee": q["knee"] - h})) / (2 * h)
    np.testing.assert_allclose(p.moment_arm_m("knee", **q), num, rtol=1e-6)
    assert p.moment_arm_m("knee", **q)[0] < 0  # the rectus femoris extends the knee
    hip, knee = ca.SX.sym("hip"), ca.SX.sym("knee")
    f = ca.Function("f", [hip, knee], [ca.jacobian(p.length_m(hip=hip, knee=knee, ankle=0.0), knee)])
    assert -float(f(0.3, 0.2)) == pytest.approx(float(p.moment_arm_m("knee", hip=0.3, knee=0.2, ankle=0.0)), rel=1e-12)


def test_fit_against_opensim_at_random_postures() -> None:
    if not MODEL.exists():
        pytest.skip(f"{MODEL} (the generic model, not part of the repo) is not here")
    rng = np.random.default_rng(7)
    pts = np.column_stack([rng.uniform(np.deg2rad(-5), np.deg2rad(95), 40), rng.uniform(0.02, np.deg2rad(105), 40),
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
                out[mu].append(m.getMuscles().get(mu + "_r").getLength(s))
        print(json.dumps(out))
    """, timeout_s=300)
    paths = load_paths()
    for mu in MUSCLES:
        ours = paths[mu].length_m(hip=pts[:, 0], knee=pts[:, 1], ankle=pts[:, 2])
        err_mm = np.abs(np.asarray(ours) - np.array(ref[mu])) * 1e3
        assert err_mm.max() < LENGTH_MAX_MM, (mu, err_mm.max())
