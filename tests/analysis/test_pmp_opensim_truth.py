"""The passive-parameter estimator on trials OpenSim made (independent truth, OpenSim in a subprocess).

The trials' passive moments come from OpenSim's DeGrooteFregly2016 muscles on Rajagopal 2016
with drawn parameters (``benchmarks/opensim_truth.py``); nothing of the estimator's path
polynomials or curve code made them. Coverage over many seeds is measured by
``python -m benchmarks pmp_opensim``; here a few seeds hold the claims.
"""

from __future__ import annotations

import pytest

from tests.opensim_reference import have_opensim

pytestmark = pytest.mark.skipif(not have_opensim(), reason="OpenSim (test extra) is the independent truth")

@pytest.fixture(scope="module")
def generic():
    from benchmarks.opensim_truth import MODEL, generic_parameters

    if not MODEL.exists():
        pytest.skip(f"{MODEL} (the generic model, beside the repo) is not here")
    return generic_parameters()


def _fit(seed: int, generic, variant: str):
    from benchmarks.pmp_opensim import fit_subject

    truth, made, res, idf, _ = fit_subject(seed, generic, variant, intervals=24)
    return truth, made, res, idf


@pytest.mark.timeout(600)
@pytest.mark.parametrize("seed", [1, 2])
def test_determined_parameters_are_within_3_5_percent_and_inside_their_intervals(generic, seed: int) -> None:
    truth, _, res, idf = _fit(seed, generic, "base")
    assert res.success and idf.determined, idf.not_determined_because
    for name in idf.determined:
        muscle, what = name.split(".")
        true = truth[muscle][what]
        lo, hi = idf.ci95[name]
        assert abs(res.parameters[name] / true - 1) < 0.035, (name, res.parameters[name], true)
        assert lo <= true <= hi, (name, lo, true, hi)


@pytest.mark.timeout(600)
def test_the_forward_model_matches_opensim_at_the_true_parameters(generic) -> None:
    from benchmarks.opensim_truth import draw_truth, make_trials
    from benchmarks.pmp_opensim import SHANK_M, forward_model_rmse

    truth = draw_truth(4, generic)
    made = make_trials(truth, 4, shank_m=SHANK_M)
    rmse = dict(zip([t.name for t in made], forward_model_rmse(made, truth)))
    # measured over 10 seeds with the B-spline paths: knee median 0.004, worst 0.021 N·m RMS; ankle
    # < 0.0001 N·m (the global polynomials before: knee 0.11–0.29, ankle ≤ 0.12). The target is 0.1
    assert all(v < 0.01 for k, v in rmse.items() if k.startswith("ankle")), rmse
    assert all(v < 0.1 for v in rmse.values()), rmse


@pytest.mark.timeout(600)
def test_the_extended_muscles_match_opensim_with_compliant_knee_tendons_and_activation(generic) -> None:
    """The model extensions' muscle physics (knee tendons compliant, a tonic activation with the active
    force–length curve) against OpenSim's muscles doing the same, at the true parameters."""
    import numpy as np

    from analysis.pmp.estimator import PmpTrial
    from analysis.pmp.model import moment_function
    from analysis.pmp.model_diagnosis import RIGID_TENDONED
    from analysis.pmp.muscles import LegMuscles, MuscleParameters, scale_for_subject
    from benchmarks.opensim_truth import draw_truth, make_trials
    from benchmarks.pmp_opensim import SHANK_M

    truth = draw_truth(5, generic)
    made = make_trials(truth, 5, shank_m=SHANK_M, variant="realistic")  # compliant knee tendons, activation 0.01
    leg = LegMuscles(length_scale=scale_for_subject(SHANK_M))
    for m, p in truth.items():
        leg.params[m] = MuscleParameters(p["tendon_slack_length_m"], p["passive_strain"], p["tendon_strain"])
    strains = {m: truth[m]["tendon_strain"] for m in RIGID_TENDONED}
    for t in made:
        step = max(t.passive_nm.size // 40, 1)
        q = t.true_angle_rad[::step]
        trial = PmpTrial(t.joint, t.fixed_rad, t.time_s, t.angle_rad, t.velocity_rad_s, t.torque_nm, t.name)
        extended = np.asarray(moment_function(leg, trial, {}, activation=0.01, tendon_strain=strains)
                              .map(q.size)(q[None, :])).ravel()
        plain = np.asarray(moment_function(leg, trial, {}).map(q.size)(q[None, :])).ravel()
        ours, theirs = np.sqrt(np.mean((extended - t.passive_nm[::step]) ** 2)), \
            np.sqrt(np.mean((plain - t.passive_nm[::step]) ** 2))
        assert ours < 0.1 and ours < 0.2 * theirs, (t.name, ours, theirs)


@pytest.mark.timeout(900)
def test_compliant_knee_tendons_and_a_tonic_activation_opensim_made_are_both_named(generic) -> None:
    """OpenSim's subject with compliant knee tendons and activation 0.01 in every muscle (the plain model
    determines nothing on it: residual 4–5× the noise): the model-level diagnosis names both extensions
    together and predicts the held-out blocks at under 0.81 of the plain model's error (measured 0.37). The
    ankle's activation is OpenSim's 0.01 within 20 % (measured 0.0088); the knee's trades with the knee
    muscles' passive parameters (co-contracting quadriceps and hamstrings leave a small net moment; one
    tendon strain stands for eight drawn ±25 %): measured 0.026 with a jackknife interval [0.024, 0.028]
    that misses 0.01, so only its order (0.005–0.04) is held here: the extension's own intervals are the
    folds' spread, not the trade-off."""
    import numpy as np

    from analysis.pmp.estimator import PmpTrial, Subject
    from analysis.pmp.model_diagnosis import RIGID_TENDONED, diagnose_model
    from analysis.pmp.muscles import LegMuscles, scale_for_subject
    from benchmarks.opensim_truth import draw_truth, make_trials
    from benchmarks.pmp_opensim import SHANK_M

    truth = draw_truth(0, generic)
    made = make_trials(truth, 0, shank_m=SHANK_M, variant="realistic")
    trials = [PmpTrial(t.joint, t.fixed_rad, t.time_s, t.angle_rad, t.velocity_rad_s, t.torque_nm, t.name) for t in made]
    d = diagnose_model(trials, Subject(75.0, SHANK_M, 0.26), leg=LegMuscles(length_scale=scale_for_subject(SHANK_M)),
                       intervals=12, candidates=["tonic_activation", "knee_tendon_compliance"])
    assert set(d.cause.split("+")) == {"tonic_activation", "knee_tendon_compliance"}, d.text()
    found = d.winner()
    assert found is not None
    assert abs(found.parameters["ankle_activation"] / 0.01 - 1.0) < 0.2, found.parameters
    assert 0.005 < found.parameters["knee_activation"] < 0.04, found.parameters
    strains = [truth[m]["tendon_strain"] for m in RIGID_TENDONED]
    assert 0.75 * min(strains) <= found.parameters["knee_tendon_strain"] <= 1.25 * max(strains), (strains, found.parameters)
    assert np.isfinite(found.heldout_rmse_nm) and found.heldout_ratio < 0.81


@pytest.mark.timeout(900)
def test_the_model_level_diagnosis_names_a_torque_offset_in_trials_opensim_made(generic) -> None:
    """Each of the six conditions recorded twice (repeats are left out in turn), a 1.5 N·m torque
    offset added to OpenSim's trials: the diagnosis names ``torque_offset`` and the knee's size."""
    from analysis.pmp.estimator import PmpTrial, Subject
    from analysis.pmp.model_diagnosis import diagnose_model
    from analysis.pmp.muscles import LegMuscles, scale_for_subject
    from benchmarks.opensim_truth import draw_truth, make_trials
    from benchmarks.pmp_opensim import SHANK_M

    truth = draw_truth(1, generic)
    made = make_trials(truth, 1, shank_m=SHANK_M) + make_trials(truth, 101, shank_m=SHANK_M)
    offset_nm = 1.5  # measured torque = −(moment) + offset: the model's moment is off by −1.5 N·m
    trials = [PmpTrial(t.joint, t.fixed_rad, t.time_s, t.angle_rad, t.velocity_rad_s, t.torque_nm + offset_nm, t.name)
              for t in made]
    d = diagnose_model(trials, Subject(75.0, SHANK_M, 0.26), leg=LegMuscles(length_scale=scale_for_subject(SHANK_M)),
                       intervals=12, candidates=["viscous_damping", "limb_mass_error", "torque_offset"])
    assert d.conclusive and d.cause == "torque_offset", d.text()
    found = d.winner()
    assert found is not None and found.heldout_ratio < 0.85  # measured 0.73
    # measured (2026-11-29): knee −1.37 N·m [−2.15, −0.59] (covers the truth); ankle −1.58 [−1.99, −1.16]:
    # the calf tendons' strains move with the offset and take part of it
    assert found.parameters["knee_offset_Nm"] == pytest.approx(-offset_nm, rel=0.15)
    assert found.parameters["ankle_offset_Nm"] == pytest.approx(-offset_nm, rel=0.15)
    lo, hi = found.ci95["knee_offset_Nm"]
    assert lo <= -offset_nm <= hi


@pytest.mark.timeout(600)
def test_a_thigh_scaled_unlike_the_shank_gets_honest_intervals_measured_or_not(generic) -> None:
    """OpenSim scales Rajagopal 2016's thigh (pelvis, femur, patella) by 1.06 and its shank by 0.98 with its own
    ``Model.scale`` (the Scale Tool's manual factors), the subject's slack lengths drawn about the scaled ones.
    With the thigh's length entered as a tape reads it (2 mm long) every determined parameter is inside its
    interval and within 3.5 %; without it the leg is scaled by the shank alone, 8 % short on the thigh, and
    whatever is still determined is inside its interval (the thigh's muscles carry the proportions' spread)."""
    from analysis.pmp.estimator import PmpTrial, Subject
    from analysis.pmp.geometry import model_segment_lengths_m
    from analysis.pmp.report import analyse
    from benchmarks.opensim_truth import draw_truth, make_trials
    from benchmarks.pmp_opensim import SHANK_M, determined_against_truth

    seed, thigh, shank = 7, 1.06, 0.98
    scales = {"pelvis": thigh, "femur_r": thigh, "patella_r": thigh, "tibia_r": shank}
    truth = draw_truth(seed, generic)
    simulated: dict[str, float] = {}
    made = make_trials(truth, seed, shank_m=SHANK_M * shank, segment_scales=scales, simulated_slack_m=simulated)
    scaled_truth = {m: {**row, "tendon_slack_length_m": simulated[m]} for m, row in truth.items()}
    trials = [PmpTrial(t.joint, t.fixed_rad, t.time_s, t.angle_rad, t.velocity_rad_s, t.torque_nm, t.name) for t in made]
    measured = analyse(trials, Subject(75.0, SHANK_M * shank, 0.26, thigh_length_m=model_segment_lengths_m()[
        "thigh_length_m"] * thigh + 0.002), intervals=16)
    rows = determined_against_truth(measured.result, measured.identifiability, scaled_truth)
    assert rows and all(r["covered"] and abs(r["error_pct"]) < 3.5 for r in rows), rows
    unmeasured = analyse(trials, Subject(75.0, SHANK_M * shank, 0.26), intervals=16)
    rows = determined_against_truth(unmeasured.result, unmeasured.identifiability, scaled_truth)
    assert all(r["covered"] for r in rows), rows
    assert len(rows) <= len(measured.identifiability.determined)
