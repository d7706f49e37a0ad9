"""Passive joint moments: the muscles' moments are −∂U/∂q of the energy their fibres and tendons store."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from analysis.pmp.curves import passive_fiber_force, tendon_force
from analysis.pmp.muscles import COMPLIANT, LegMuscles, MuscleParameters, scale_for_subject


def energy_j(leg: LegMuscles, m: str, q: dict[str, float]) -> float:
    """Elastic energy (J) stored in muscle ``m`` at posture ``q``: fibre ∫F dl_M plus tendon ∫F dl_T."""
    p, par = leg.paths[m], leg.params[m]
    lo = leg.optimal_fiber_length_m(m)
    lm, _, _ = leg.fiber_state(m, float(leg.path_length_m(m, **q)))
    fibre = p.max_isometric_force_n * lo * quad(lambda x: float(passive_fiber_force(x, par.passive_strain)), 0.2,
                                                lm / lo, epsabs=1e-13, epsrel=1e-12)[0]
    tendon = 0.0
    if m in COMPLIANT:
        ls = par.tendon_slack_length_m
        lt = float(leg.path_length_m(m, **q)) - np.sqrt(lm**2 - (lo * np.sin(p.pennation_at_optimal_rad)) ** 2)
        if lt > ls:
            tendon = p.max_isometric_force_n * ls * quad(lambda x: float(tendon_force(x, par.tendon_strain)), 1.0,
                                                         lt / ls, epsabs=1e-13, epsrel=1e-12)[0]
    return fibre + tendon


@pytest.mark.parametrize("muscle,joint,posture", [
    ("bflh", "knee", {"hip": np.deg2rad(90), "knee": np.deg2rad(10), "ankle": 0.0}),
    ("recfem", "knee", {"hip": np.deg2rad(-5), "knee": np.deg2rad(100), "ankle": 0.0}),
    ("vasint", "knee", {"hip": 0.0, "knee": np.deg2rad(105), "ankle": 0.0}),
    ("gasmed", "ankle", {"hip": 0.0, "knee": 0.0, "ankle": np.deg2rad(20)}),
    ("soleus", "ankle", {"hip": 0.0, "knee": np.deg2rad(90), "ankle": np.deg2rad(25)}),
])
def test_moment_is_minus_the_energy_gradient(muscle: str, joint: str, posture: dict[str, float]) -> None:
    leg = LegMuscles()
    # stretch the passive curves (small ε₀, short slack) so every muscle carries load at this posture
    leg.params[muscle] = MuscleParameters(leg.paths[muscle].tendon_slack_length_m * 0.93, passive_strain=0.35,
                                          tendon_strain=0.04)
    force = leg.force_n(muscle, **posture)
    assert force > 20.0, force
    h = 1e-5
    up = energy_j(leg, muscle, {**posture, joint: posture[joint] + h})
    down = energy_j(leg, muscle, {**posture, joint: posture[joint] - h})
    # the force is conservative along the length polynomial: −∂U/∂q = F · (−∂L/∂q); the model's
    # moment uses OpenSim's computeMomentArm instead (held against OpenSim in test_pmp_geometry)
    moment = float(leg.paths[muscle].length_derivative_moment_arm_m(joint, **posture)) * force
    assert moment == pytest.approx(-(up - down) / (2 * h), rel=2e-4, abs=1e-4)


def test_calf_equilibrium_and_the_rigid_tendon_error_it_avoids() -> None:
    leg = LegMuscles()
    q = {"hip": 0.0, "knee": 0.0, "ankle": np.deg2rad(15)}
    m = "gasmed"
    lm, alpha, f_t = leg.fiber_state(m, float(leg.path_length_m(m, **q)))
    p, par = leg.paths[m], leg.params[m]
    f_m = p.max_isometric_force_n * float(passive_fiber_force(lm / leg.optimal_fiber_length_m(m), par.passive_strain))
    assert f_m * np.cos(alpha) == pytest.approx(f_t, rel=1e-9)  # eq 3.2
    stretched = leg.joint_moment_nm("ankle", **q)
    assert stretched < 0  # the calf resists dorsiflexion
    # scaling as OpenSim's scale tool: measured over the model's own knee–ankle distance (0.3965 m)
    assert scale_for_subject(0.3965) == pytest.approx(1.0, abs=2e-4)
    assert scale_for_subject(0.42) == pytest.approx(0.42 / 0.39647, rel=1e-4)


def test_a_thigh_scaled_unlike_the_shank_lengthens_each_muscle_by_its_thigh_fraction() -> None:
    """The vasti's paths follow the thigh's scale by 0.83–0.84 (OpenSim's Model.scale per segment), the
    soleus' not at all; a leg in one proportion is the leg scaled by the shank alone."""
    from analysis.pmp.geometry import model_segment_lengths_m, segment_fractions
    from analysis.pmp.muscles import LegMuscles, thigh_over_shank_for_subject

    fractions = segment_fractions()
    assert 0.8 < fractions["vasint"]["thigh"] < 0.86 and fractions["soleus"]["thigh"] < 0.01
    assert all(abs(sum(row.values()) - 1.0) < 0.02 for row in fractions.values())  # a uniform scale: 1
    plain, longer = LegMuscles(length_scale=1.02), LegMuscles(length_scale=1.02, thigh_over_shank=1.05)
    q = {"hip": 1.0, "knee": 0.8, "ankle": 0.0}
    for m in ("vasint", "recfem", "soleus"):
        expected = 1.0 + fractions[m]["thigh"] * 0.05
        assert longer.path_length_m(m, **q) / plain.path_length_m(m, **q) == pytest.approx(expected, rel=1e-12)
        assert longer.params[m].tendon_slack_length_m / plain.params[m].tendon_slack_length_m == pytest.approx(expected)
    segments = model_segment_lengths_m()
    assert thigh_over_shank_for_subject(None, 0.40) == 1.0
    in_proportion = segments["thigh_length_m"] * 0.40 / segments["shank_length_m"]
    assert thigh_over_shank_for_subject(in_proportion, 0.40) == pytest.approx(1.0)
    assert thigh_over_shank_for_subject(1.05 * in_proportion, 0.40) == pytest.approx(1.05)
