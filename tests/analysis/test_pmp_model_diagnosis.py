"""Model-level diagnosis of the passive-parameter fit: extensions fitted inside the estimator, judged by
held-out prediction (leave one repeat out)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from analysis.errors import InputError
from analysis.pmp.estimator import estimate
from analysis.pmp.model_diagnosis import EXTENSIONS, diagnose_model, folds_of, predict_torque_nm
from analysis.pmp.muscles import LegMuscles
from analysis.pmp.synthetic import simulated_subject


def _repeats(seed: int, effect: float) -> tuple[list, object]:
    truth, trials, subject = simulated_subject(seed, ("knee",))
    out = []
    for rep in range(2):
        rng = np.random.default_rng(100 + rep)
        out += [dataclasses.replace(t, name=f"{t.name} r{rep}", torque_nm=t.torque_nm + rng.normal(0, 0.2, t.time_s.size)
                                    + effect * t.velocity_rad_s) for t in trials]
    return out, subject


def test_folds_leave_out_repeats_when_there_are_repeats_else_conditions() -> None:
    trials, _ = _repeats(1, 0.0)
    folds = folds_of(trials)
    assert [label for label, _ in folds] == ["repeat 1", "repeat 2"]
    assert sorted(i for _, left in folds for i in left) == list(range(6))
    single = folds_of(trials[:3])
    assert len(single) == 3 and all(len(left) == 1 for _, left in single)
    with pytest.raises(InputError):
        diagnose_model(trials[:2], _)


def test_an_extension_is_fitted_inside_the_estimator_and_predicts_the_hidden_term() -> None:
    trials, subject = _repeats(2, 0.0)
    b = 12.0  # N·m·s/rad: the dynamometer must overcome b·q̇ on top of the muscles
    trials = [dataclasses.replace(t, torque_nm=t.torque_nm + b * t.velocity_rad_s) for t in trials]
    fit = estimate(trials, subject, intervals=24, extension=EXTENSIONS["viscous_damping"])
    # on one-way sweeps at one speed the damping trades with the muscles (it may sit at its bound):
    # what must hold is that it is a decision variable inside its bounds and the model predicts the data
    assert fit.success and 0.0 <= fit.extension_parameters["damping_Nm_s_per_rad"] <= 20.0 + 1e-6
    assert fit.extension_parameters["damping_Nm_s_per_rad"] > 1.0
    idx, pred = predict_torque_nm(fit, trials[0], subject, LegMuscles(), EXTENSIONS["viscous_damping"])
    assert np.sqrt(np.mean((trials[0].torque_nm[idx] - pred) ** 2)) < 0.6


@pytest.mark.timeout(600)
def test_damping_on_one_way_single_speed_sweeps_is_reported_absorbed_with_the_protocol_that_separates_it() -> None:
    trials, subject = _repeats(3, 15.0)  # 1.3 N·m at 5 °/s: a constant offset on one-way sweeps
    d = diagnose_model(trials, subject, intervals=10, candidates=["viscous_damping"])
    assert d.cause == "none" and "fits to the noise" in d.message
    assert "viscous_damping" in d.message and "second sweep speed" in d.message
    damping = next(c for c in d.candidates if c.name == "viscous_damping")
    assert damping.ci95["damping_Nm_s_per_rad"][0] > 0
    assert max(abs(v) for v in damping.parameter_shift_pct.values()) > 1.0  # the muscles moved to absorb it


def test_a_parameter_is_material_only_when_its_interval_excludes_zero_and_it_has_a_size() -> None:
    from analysis.pmp.model_diagnosis import ExtensionFinding, is_material

    def finding(name: str, key: str, value: float, lo: float, hi: float) -> ExtensionFinding:
        return ExtensionFinding(name, 0.2, 1.0, {key: value}, {key: (lo, hi)}, {}, {})

    # an optimiser's leftover with a tight interval: 1e-7 N·m·s/rad is 1e-8 N·m at 5 °/s
    assert not is_material(finding("viscous_damping", "damping_Nm_s_per_rad", 8.8e-8, 5.8e-8, 1.2e-7))
    assert not is_material(finding("limb_mass_error", "limb_weight_error_fraction", 0.15, -0.02, 0.32))
    assert is_material(finding("limb_mass_error", "limb_weight_error_fraction", 0.15, 0.08, 0.22))
    assert is_material(finding("torque_offset", "knee_offset_Nm", -1.6, -2.7, -0.5))
    # a misalignment below what a lab can set (the clean OpenSim trials' 1.4 mm); a 2 cm offset is one
    assert not is_material(finding("axis_misalignment", "knee_axis_cos_rad", -0.0045, -0.0055, -0.0036))
    assert is_material(finding("axis_misalignment", "knee_axis_sin_rad", 0.075, 0.067, 0.082))


@pytest.mark.timeout(900)
def test_a_knee_axis_offset_in_trials_opensim_made_is_named_with_intervals_holding_it() -> None:
    """OpenSim's passive moments (an independent model, in a subprocess), the knee's axis 1.5–2.5 cm off
    the dynamometer's by exact lever geometry (benchmarks/pmp_model_diagnosis): the diagnosis names
    the misalignment, predicts both left-out repeats better, and its first-order coefficients are
    the geometry's."""
    from analysis.pmp.estimator import PmpTrial, Subject
    from analysis.pmp.muscles import scale_for_subject
    from benchmarks.opensim_truth import draw_truth, generic_parameters, make_trials
    from benchmarks.pmp_model_diagnosis import FOOT_M, MASS_KG, PAD_LEVER_M, misaligned_knee
    from benchmarks.pmp_opensim import SHANK_M
    from tests.opensim_reference import have_opensim

    if not have_opensim():
        pytest.skip("OpenSim (in the test extra) is the independent reference")
    rng = np.random.default_rng(5)
    offset, direction = float(rng.uniform(0.015, 0.025)), float(rng.uniform(-0.5, 0.5))
    truth = draw_truth(2, generic_parameters())
    made = make_trials(truth, 2, shank_m=SHANK_M) + make_trials(truth, 102, shank_m=SHANK_M)
    trials = [misaligned_knee(t, offset, direction) if t.joint == "knee" else
              PmpTrial(t.joint, t.fixed_rad, t.time_s, t.angle_rad, t.velocity_rad_s, t.torque_nm, t.name) for t in made]
    d = diagnose_model(trials, Subject(MASS_KG, SHANK_M, FOOT_M), leg=LegMuscles(length_scale=scale_for_subject(SHANK_M)),
                       intervals=8, candidates=["axis_misalignment"])
    assert d.cause == "axis_misalignment", d.text()
    found = next(c for c in d.candidates if c.name == "axis_misalignment")
    assert found.heldout_ratio < 0.9 and found.every_fold_better
    # the first-order coefficients of the exact geometry, within a tenth of the offset's (d/L); the
    # jackknife intervals over two repeats carry the noise only, not the second-order terms the
    # first-order form leaves out ((d/L)²/2 ≈ 0.003 rad), so they are not asserted to hold it here
    # (on benchmarks/pmp_model_diagnosis's case they do)
    for key, value in (("knee_axis_sin_rad", offset / PAD_LEVER_M * np.cos(direction)),
                       ("knee_axis_cos_rad", -offset / PAD_LEVER_M * np.sin(direction))):
        assert abs(found.parameters[key] - value) < 0.1 * offset / PAD_LEVER_M, (key, value, found.parameters[key])
