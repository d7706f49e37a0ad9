"""The simulators' physics against independent calculations and published values."""

from __future__ import annotations

import numpy as np
import pytest

from drivers.simulation.aads_jig import AadsJig, AfoProperties
from drivers.simulation.replica_leg import ReplicaLeg, WrappedSpring
from drivers.simulation.seated_leg import SeatedLeg, riener_ankle_dorsiflexion_moment_nm, riener_knee_flexion_moment_nm


@pytest.mark.parametrize("k,theory", [(9910, 0.67), (15600, 1.07), (25200, 1.69)])
def test_spring_geometry_gives_the_dissertation_stiffness(k: float, theory: float) -> None:
    jig = AadsJig(AfoProperties(spring_n_per_m=k))
    assert jig.theoretical_stiffness_nm_per_deg() == pytest.approx(theory, rel=0.03)  # Table 2.1


def test_plate_sees_the_weight_at_rest() -> None:
    jig = AadsJig(seed=4)
    st = jig.state(np.array([0.0, 0.1]))  # the trial opens with a rest at neutral
    weight = (jig.geometry.foot_mass_kg + jig.geometry.shank_mass_kg) * 9.81
    # at rest the operator only adds its off-axis push; Fz = weight + operator's downward push
    assert st.force_n[0, 2] >= weight


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_foot_free_body_recovers_the_afo_torque(seed: int) -> None:
    """Bottom-up inverse dynamics: plate wrench + foot weight about the hinge axis = AFO torque."""
    jig = AadsJig(AfoProperties(spring_n_per_m=15600), operator=seed + 1, seed=seed)
    t = np.linspace(0.0, jig.profile.duration_s, 2000)
    st = jig.state(t)
    g = jig.geometry
    A = np.asarray(g.ankle_m) - jig.plate_origin_m  # hinge point relative to the plate origin
    m_plate_about_a = st.moment_nm - np.cross(A, st.force_n)
    foot_w = np.array([0.0, 0.0, -9.81 * g.foot_mass_kg])
    m_weight_about_a = np.cross(np.asarray(g.foot_com_m), foot_w)
    # the foot is still: the hinge must balance the plate and the foot's weight about the axis
    afo_torque_from_plate = -(m_plate_about_a[:, 1] + m_weight_about_a[1])
    np.testing.assert_allclose(afo_torque_from_plate, st.afo_torque_nm, atol=1e-6)
    assert st.afo_torque_nm.max() > 10.0  # the test is not trivially satisfied


def test_shell_compliance_tilts_the_shank_beyond_the_hinge() -> None:
    jig = AadsJig(AfoProperties(spring_n_per_m=25200, shell_stiffness_nm_per_deg=27.0), seed=1)
    st = jig.state(np.linspace(0, jig.profile.duration_s, 500))
    extra_deg = np.rad2deg(st.shank_rad - st.hinge_rad)
    np.testing.assert_allclose(extra_deg, st.afo_torque_nm / 27.0, rtol=1e-9, atol=1e-12)


def test_riener_values_from_the_reference_notes() -> None:
    # science notes §2.1 (dorsiflexion positive): ankle +20° → −42.4 N·m at knee 0°, −13.6 at knee 60°
    assert riener_ankle_dorsiflexion_moment_nm(0.0, np.array(20.0)) == pytest.approx(-42.4, abs=0.05)
    assert riener_ankle_dorsiflexion_moment_nm(60.0, np.array(20.0)) == pytest.approx(-13.6, abs=0.05)
    # knee at 0° with hip 0° and ankle 20° dorsiflexion: +19.6 N·m (flexion)
    assert riener_knee_flexion_moment_nm(0.0, np.array(0.0), 20.0) == pytest.approx(19.6, abs=0.1)  # notes round to 0.1


def test_gravity_of_the_shank_vanishes_when_it_hangs() -> None:
    leg = SeatedLeg("knee")
    assert leg.gravity_moment_nm(np.array(90.0)) == pytest.approx(0.0, abs=1e-9)
    assert leg.gravity_moment_nm(np.array(0.0)) > 0  # extended shank: gravity pulls into flexion


def test_wrapped_spring_moment_arm_is_the_pulley_radius() -> None:
    s = WrappedSpring(1000.0, 0.2, 0.18, 0.16, 0.03, True, 3.0)
    th = np.deg2rad(np.array([10.0, 40.0, 80.0]))
    h = 1e-6
    arm = (s.length_m(th + h) - s.length_m(th - h)) / (2 * h)
    np.testing.assert_allclose(arm, 0.03, rtol=1e-6)  # while wrapping, dL/dθ = r exactly


def test_replica_leg_holds_every_8_degrees() -> None:
    leg = ReplicaLeg()
    assert leg.hold_angles_deg == tuple(float(a) for a in range(0, 90, 8))
    assert leg.knee_deg(np.array([0.5 * leg.hold_s])) == pytest.approx(0.0)
