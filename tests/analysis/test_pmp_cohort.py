"""The cohort's work items: task keys, bootstrap resamples and interval summaries (no Dask here)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from analysis.pmp.cohort import (
    DETERMINED_HALF_WIDTH_REL,
    DIAGNOSED,
    FitTask,
    _block_resample,
    bootstrap_trials,
    condition_of,
    coverage,
    run_fit_task,
    subject_summary,
)
from analysis.pmp.estimator import PmpTrial, Subject


def _trial(joint: str, fixed_deg: dict[str, float], seed: int, n: int = 200) -> PmpTrial:
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.05
    q = np.deg2rad(5.0 * t)
    return PmpTrial(joint, {k: np.deg2rad(v) for k, v in fixed_deg.items()}, t, q, np.full(n, np.deg2rad(5.0)),
                    np.sin(q) * 10 + rng.normal(0, 0.3, n), f"{joint} {fixed_deg}")


def test_task_key_follows_the_data_and_settings_not_the_start_point() -> None:
    trials = [_trial("knee", {"hip": 90.0, "ankle": 0.0}, 1)]
    a = FitTask("S01", 0, trials, Subject(), 12)
    assert a.key == FitTask("S01", 0, [_trial("knee", {"hip": 90.0, "ankle": 0.0}, 1)], Subject(), 12).key
    assert a.key == FitTask("S01", 0, trials, Subject(), 12, initial={"x": 1.0}).key
    changed = _trial("knee", {"hip": 90.0, "ankle": 0.0}, 1)
    changed.torque_nm[17] += 1e-9
    assert FitTask("S01", 0, [changed], Subject(), 12).key != a.key
    assert FitTask("S01", 1, trials, Subject(), 12).key != a.key
    assert FitTask("S01", 0, trials, Subject(mass_kg=76.0), 12).key != a.key
    assert FitTask("S01", 0, trials, Subject(), 24).key != a.key
    # a model extension is part of the result; the muscle model alone keeps its earlier keys
    assert FitTask("S01", 0, trials, Subject(), 12, extension=None).key == a.key
    assert FitTask("S01", 0, trials, Subject(), 12, extension="torque_offset").key != a.key
    assert FitTask("S01", 0, trials, Subject(), 12, extension=DIAGNOSED).key not in (
        a.key, FitTask("S01", 0, trials, Subject(), 12, extension="torque_offset").key)


def test_repeated_conditions_are_resampled_as_whole_trials_within_the_condition() -> None:
    trials = [_trial("knee", {"hip": 90.0, "ankle": 0.0}, s) for s in (1, 2, 3)] + \
             [_trial("knee", {"hip": 15.0, "ankle": 0.0}, s) for s in (4, 5)]
    fits = [np.zeros(t.time_s.size) for t in trials]
    for b in range(1, 8):
        out = bootstrap_trials(trials, fits, b, seed=3)
        assert [condition_of(t) for t in out].count(condition_of(trials[0])) == 3
        assert [condition_of(t) for t in out].count(condition_of(trials[3])) == 2
        for t in out:  # every drawn trial is one of its condition's recorded repeats, untouched
            same = [r for r in trials if condition_of(r) == condition_of(t)]
            assert any(np.array_equal(t.torque_nm, r.torque_nm) for r in same)
    assert all(np.array_equal(a.torque_nm, b.torque_nm) for a, b in
               zip(bootstrap_trials(trials, fits, 4, seed=3), bootstrap_trials(trials, fits, 4, seed=3)))
    with pytest.raises(ValueError, match="numbered from 1"):
        bootstrap_trials(trials, fits, 0)


def test_a_single_sweep_is_resampled_in_residual_blocks_around_the_fit() -> None:
    trial = _trial("ankle", {"hip": 90.0, "knee": 45.0}, 7, n=300)
    fit = np.sin(trial.angle_rad) * 10
    residual = trial.torque_nm - fit
    draws = [bootstrap_trials([trial], [fit], b, seed=1)[0] for b in range(1, 6)]
    for d in draws:
        new = d.torque_nm - fit
        assert new.size == residual.size
        assert np.isin(np.round(new, 12), np.round(residual, 12)).all()  # only the fit's own residuals
        np.testing.assert_array_equal(d.angle_rad, trial.angle_rad)
        assert "residual blocks of 20" in d.name  # 1 s at 20 Hz: the white residual's own time is shorter
    assert not np.allclose(draws[0].torque_nm, draws[1].torque_nm)


@settings(max_examples=60, deadline=None)
@given(n=st.integers(1, 200), block=st.integers(1, 250), seed=st.integers(0, 2**31))
def test_block_resample_keeps_length_and_draws_runs_of_the_original(n: int, block: int, seed: int) -> None:
    x = np.arange(n, dtype=float)
    y = _block_resample(x, block, np.random.default_rng(seed))
    assert y.size == n
    assert np.isin(y, x).all()
    steps = np.diff(y)  # inside a block the indices run on by one (circularly)
    assert ((steps == 1) | (steps == -(n - 1)) | (np.arange(1, n) % min(block, n) == 0)).all()


def _main(value: float = 1.0, determined: bool = True, bias: float = 0.001) -> dict:
    return {"subject_code": "S01", "success": True, "message": "", "parameters": {"a.tendon_slack_length_m": value},
            "generic": {"a.tendon_slack_length_m": 1.0},
            "identifiability": {"determined": ["a.tendon_slack_length_m"] if determined else [],
                                "model_error_bound_rel": {"a.tendon_slack_length_m": bias}},
            "forward_dynamics": [{"trial": "knee", "angle_rmse_deg": 0.1, "torque_rmse_nm_per_kg": 0.01}]}


def test_interval_is_t_times_the_bootstrap_sd_plus_the_model_error_bound() -> None:
    draws = [1.0, 1.01, 0.99, 1.02, 0.98]
    reps = [{"success": True, "parameters": {"a.tendon_slack_length_m": d}} for d in draws]
    reps.append({"success": False, "parameters": {"a.tendon_slack_length_m": 5.0}})
    s = subject_summary(_main(), reps, truth={"a.tendon_slack_length_m": 1.03})
    row = s["parameters"]["a.tendon_slack_length_m"]
    half = stats.t.ppf(0.975, 4) * np.std(draws, ddof=1) + 0.001
    assert row["ci95"] == pytest.approx([1.0 - half, 1.0 + half])
    assert row["bootstrap_n"] == 5 and s["bootstrap_failed"] == 1
    assert row["determined"] == bool(half <= DETERMINED_HALF_WIDTH_REL)
    assert row["covered"] == bool(1.0 + half >= 1.03)
    assert row["error_pct"] == pytest.approx(-100 * 0.03 / 1.03)
    assert coverage([s])["determined_with_truth"] == (1 if row["determined"] else 0)


def test_the_measured_inputs_share_joins_the_bootstrap_in_quadrature() -> None:
    """Resampling the sweeps does not see the tape's, goniometer's or scale's error: their propagated SE
    (identifiability's measurement_se_rel) joins the bootstrap's in quadrature, the bias bound beside both."""
    draws = [1.0, 1.002, 0.998, 1.001, 0.999]
    reps = [{"success": True, "parameters": {"a.tendon_slack_length_m": d}} for d in draws]
    main = _main(value=1.0)
    plain = subject_summary(main, reps, truth={"a.tendon_slack_length_m": 1.012})["parameters"]["a.tendon_slack_length_m"]
    main["identifiability"]["measurement_se_rel"] = {"a.tendon_slack_length_m": 0.006}
    row = subject_summary(main, reps, truth={"a.tendon_slack_length_m": 1.012})["parameters"]["a.tendon_slack_length_m"]
    boot = stats.t.ppf(0.975, 4) * np.std(draws, ddof=1)
    half = float(np.hypot(boot, 1.96 * 0.006)) + 0.001
    assert row["ci95"] == pytest.approx([1.0 - half, 1.0 + half])
    assert not plain["covered"] and row["covered"]  # a 1.2 % tape-driven error: outside without it, inside with it


def test_with_plausible_models_the_interval_also_holds_the_models_hull() -> None:
    """The bootstrap draws about the named model only; with plausible models beside it the fit's interval is their
    hull (identifiability.with_plausible_models), and the subject's interval is widened to hold it: asymmetrically,
    on the side the other model moves the estimate. Without model alternatives the fit's interval is not used."""
    draws = [1.0, 1.002, 0.998, 1.001, 0.999]
    reps = [{"success": True, "parameters": {"a.tendon_slack_length_m": d}} for d in draws]
    main = _main(value=1.0)
    main["identifiability"]["ci95"] = {"a.tendon_slack_length_m": [0.995, 1.02]}
    alone = subject_summary(main, reps, truth={"a.tendon_slack_length_m": 1.015})["parameters"]["a.tendon_slack_length_m"]
    main["identifiability"]["model_alternatives"] = ["tonic_activation+knee_tendon_compliance"]
    row = subject_summary(main, reps, truth={"a.tendon_slack_length_m": 1.015})["parameters"]["a.tendon_slack_length_m"]
    boot = stats.t.ppf(0.975, 4) * np.std(draws, ddof=1) + 0.001
    assert alone["ci95"] == pytest.approx([1.0 - boot, 1.0 + boot]) and not alone["covered"]
    assert row["ci95"] == pytest.approx([1.0 - boot, 1.02]) and row["covered"]
    assert row["determined"] == bool(0.02 <= DETERMINED_HALF_WIDTH_REL)


def test_a_wide_bootstrap_or_an_undetermined_fit_is_not_called_determined() -> None:
    wide = [{"success": True, "parameters": {"a.tendon_slack_length_m": d}} for d in (0.8, 1.2, 0.9, 1.1)]
    assert not subject_summary(_main(), wide)["parameters"]["a.tendon_slack_length_m"]["determined"]
    tight = [{"success": True, "parameters": {"a.tendon_slack_length_m": d}} for d in (1.0, 1.001, 0.999)]
    assert subject_summary(_main(), tight)["parameters"]["a.tendon_slack_length_m"]["determined"]
    assert not subject_summary(_main(determined=False), tight)["parameters"]["a.tendon_slack_length_m"]["determined"]
    one = subject_summary(_main(), tight[:1])["parameters"]["a.tendon_slack_length_m"]
    assert one["ci95"] is None and not one["determined"]


def test_a_subject_fitted_with_an_extension_is_resampled_about_the_extended_model() -> None:
    """A 1.5 N·m arm-weight error on every trial: fitted with ``torque_offset`` the subject's own fit finds the
    ankle's offset, its fitted torque carries it (the residual about it has no mean left), and a bootstrap
    refit with the same extension finds it again; the summary names the extension and its value."""
    import dataclasses

    from analysis.pmp.cohort import fitted_torque_nm
    from analysis.pmp.cohort_report import text
    from analysis.pmp.muscles import LegMuscles, scale_for_subject
    from analysis.pmp.synthetic import simulated_subject

    _, trials, subject = simulated_subject(3, ("knee", "ankle"))
    offset = [dataclasses.replace(t, torque_nm=t.torque_nm + 1.5) for t in trials]
    main = run_fit_task(FitTask("S01", 0, offset, subject, 10, extension="torque_offset"))
    assert main["success"] and main["extension"] == "torque_offset"
    assert abs(main["extension_parameters"]["ankle_offset_Nm"] + 1.5) < 0.3
    residual_mean = [float(np.mean(t.torque_nm - np.asarray(f))) for t, f in zip(offset, main["fitted_torque_nm"])]
    assert max(abs(r) for r in residual_mean) < 0.25, residual_mean
    # about the same muscles without the extension's terms, the ankle trials would keep the offset
    leg = LegMuscles(length_scale=scale_for_subject(subject.shank_length_m))
    without = [float(np.mean(t.torque_nm - fitted_torque_nm(t, subject, main["parameters"], leg)))
               for t in offset if t.joint == "ankle"]
    assert min(without) > 1.0, without
    resample = bootstrap_trials(offset, main["fitted_torque_nm"], 1)
    again = run_fit_task(FitTask("S01", 1, resample, subject, 10, main["parameters"], extension=main["extension"]))
    assert again["success"] and "identifiability" not in again
    assert abs(again["extension_parameters"]["ankle_offset_Nm"] - main["extension_parameters"]["ankle_offset_Nm"]) < 0.3
    summary = subject_summary(main, [again, again])
    assert summary["extension"] == "torque_offset" and "model_diagnosis" in summary
    assert "S01 with torque_offset (knee_offset_Nm" in text([summary])


def test_a_diagnosed_subject_fits_the_plausible_models_into_its_intervals(monkeypatch) -> None:
    """A study's subject fitted with the model-level diagnosis carries the models it left plausible as the
    single-subject report does: fitted, named in the result, their estimates held by the fit's intervals (the
    diagnosis stubbed: nothing named, a tonic activation plausible)."""
    import dataclasses

    import analysis.pmp.model_diagnosis as md
    from analysis.pmp.cohort import run_fit_task
    from analysis.pmp.synthetic import simulated_subject

    _, trials, subject = simulated_subject(11, ("knee",))
    subject = dataclasses.replace(subject, shank_length_sd_m=0.0, set_angle_sd_rad=0.0, mass_sd_kg=0.0)
    monkeypatch.setattr(md, "diagnose_model", lambda *a, **k: md.ModelDiagnosis(
        "none", 0.3, {}, [], "no extension predicts better", ["blocks 1"], plausible=["tonic_activation"]))
    plain = run_fit_task(FitTask("S01", 0, trials, subject, 12))
    out = run_fit_task(FitTask("S01", 0, trials, subject, 12, extension=DIAGNOSED))
    assert out["model_diagnosis"]["plausible"] == ["tonic_activation"] and out["extension"] is None
    idf = out["identifiability"]
    assert idf["model_alternatives"] == ["tonic_activation"] and plain["identifiability"]["model_alternatives"] == []
    assert set(idf["determined"]) <= set(plain["identifiability"]["determined"]) and idf["determined"]
    for name in idf["determined"]:
        assert idf["ci95"][name][0] <= plain["identifiability"]["ci95"][name][0] + 1e-12
        assert idf["ci95"][name][1] >= plain["identifiability"]["ci95"][name][1] - 1e-12
