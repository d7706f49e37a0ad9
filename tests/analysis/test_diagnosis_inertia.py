"""A dynamometer's torque carries the limb's and the arm's inertia: the baseline knows it, so it is
not reported as a cause; an unknown extra mass still is."""

from __future__ import annotations

import numpy as np
import pytest

from analysis.diagnosis import diagnose
from analysis.diagnosis.data import DiagnosisTrial

SUBJECT = {"mass_kg": 75.0, "shank_length_m": 0.42, "foot_length_m": 0.26}
ARM = 1.8 * 0.22**2


def _trial(extra_inertia: float, rig: float | None, seed: int) -> DiagnosisTrial:
    """Knee flexed 7→83° and back (20 s cycles) with a 2°, 1 Hz wobble on top: its accelerations
    (about 1.4 rad/s²) are not a function of the angle, so an inertia can be told from elasticity
    (a smooth sweep's are: there the baseline absorbs any inertia, and the report says so)."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 40.0, 0.01)
    angle = np.deg2rad(45.0 - 36.0 * np.cos(2 * np.pi * t / 20.0) + 2.0 * np.sin(2 * np.pi * t / 1.0))
    probe = DiagnosisTrial("knee", t, angle, np.zeros_like(t), {"hip_flexion_deg": 90.0}, dict(SUBJECT), "probe", rig)
    dt = t[1] - t[0]
    alpha = np.gradient(np.gradient(angle, dt), dt)
    known = probe.known_inertia_kgm2() if rig is not None else 0.0
    torque = (probe.limb_gravity_nm() + (known + extra_inertia) * alpha
              + 2.0 * np.exp(3.0 * (angle - 1.2)) - 1.5 * np.exp(-4.0 * angle) + rng.normal(0.0, 0.05, t.size))
    return DiagnosisTrial("knee", t, angle, torque, {"hip_flexion_deg": 90.0}, dict(SUBJECT), "sim", rig)


@pytest.mark.parametrize("seed", [1, 2])
def test_known_limb_and_arm_inertia_is_not_a_finding(seed: int) -> None:
    trial = _trial(0.0, ARM, seed)
    assert trial.known_inertia_kgm2() == pytest.approx(0.363 + ARM, abs=0.002)
    assert diagnose(trial).cause == "none"


def test_an_unaccounted_mass_is_named_with_its_size() -> None:
    d = diagnose(_trial(0.15, ARM, 3))
    assert d.cause == "inertia", d.text()
    assert d.parameters["inertia_kgm2"] == pytest.approx(0.15, rel=0.15)


def test_a_torque_not_said_to_be_a_dynamometers_has_no_known_inertia() -> None:
    trial = _trial(0.0, None, 4)
    assert trial.known_inertia_kgm2() == 0.0 and diagnose(trial).cause == "none"


def test_a_negative_total_inertia_is_no_moving_mass() -> None:
    """A torque that goes with −(known + 0.3 kg·m²)·q̈ (a lagging channel does that) fits an inertia error
    below minus the known limb's and arm's: no mass is negative, and inertia is not named."""
    probe = _trial(0.0, ARM, 5)
    d = diagnose(_trial(-(probe.known_inertia_kgm2() + 0.3), ARM, 5))
    assert "inertia" not in [d.cause, *(a["cause"] for a in d.also)], d.text()
