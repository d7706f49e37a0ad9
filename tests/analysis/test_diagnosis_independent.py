"""The diagnosis on trials from a generator it does not share (benchmarks.diagnosis_truth: Riener & Edrich
passive moments, de Leva limb weight, its own effect shapes, noise and nuisances).

Effects, kinds, seeds and nuisances are drawn from one seed per test; sizes are 3–5× the noise
(hard stops 8–12×: their measured detection threshold, see benchmarks/diagnosis). Tolerances are
stated per test and sit below what ``python -m benchmarks diagnosis`` measures, by the margin a
small sample needs.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from analysis.diagnosis import diagnose
from benchmarks.diagnosis import INSEPARABLE, as_trial, is_right, magnitude_errors, named_causes
from benchmarks.diagnosis_truth import EFFECTS, generate

DETECTABLE_AT_3_TO_5 = ("coulomb_friction", "viscous_damping", "time_delay", "activation_burst", "sensor_drift")


def _draw_singles(seed: int, count: int) -> list[tuple[str, str, int, bool]]:
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        kind = str(rng.choice(["afo", "knee", "ankle"]))
        cause = str(rng.choice([c for c in DETECTABLE_AT_3_TO_5 if c in EFFECTS[kind]]))
        out.append((kind, cause, int(rng.integers(1 << 30)), bool(rng.random() < 0.5)))
    return out


def test_single_effects_at_three_to_five_times_the_noise_are_named_and_sized() -> None:
    right, errors, wrong = 0, [], []
    cases = _draw_singles(20261123, 18)
    for kind, cause, seed, nuisances in cases:
        g = generate(kind, (cause,), seed, nuisances=nuisances)
        d = diagnose(as_trial(g))
        if is_right(d, g):
            right += 1
            errors += list(magnitude_errors(d, g).values())
        else:
            wrong.append((kind, cause, seed, nuisances, sorted(named_causes(d))))
    assert right >= 17, wrong  # ≥ 94 % of 18 (the benchmark: see docs/validation.md)
    assert np.mean(np.array(errors) <= 0.15) >= 0.85, errors


def test_hard_stops_above_their_detection_threshold_are_found_at_either_end() -> None:
    rng = np.random.default_rng(7)
    found = 0
    for kind in ("afo", "knee", "ankle"):  # the ankle's stop is at the plantarflexion end (the range's bottom)
        for _ in range(2):
            g = generate(kind, ("hard_stop",), int(rng.integers(1 << 30)), noise_multiple=(8.0, 12.0))
            d = diagnose(as_trial(g))
            found += named_causes(d) == {"hard_stop"}
            if d.cause == "hard_stop":
                assert d.parameters["stop_stiffness_Nm_per_deg"] > 0
                assert abs(d.parameters["stop_angle_deg"] - g.details["stop_deg"]) < 3.0
    assert found >= 5


def test_clean_trials_of_every_kind_raise_no_false_alarm() -> None:
    rng = np.random.default_rng(11)
    alarms = []
    for kind in ("afo", "knee", "ankle"):
        for i in range(4):
            g = generate(kind, (), int(rng.integers(1 << 30)), nuisances=bool(i % 2))
            named = named_causes(diagnose(as_trial(g)))
            if named:
                alarms.append((kind, g.details, named))
    assert len(alarms) <= 0, alarms


def test_both_causes_of_a_pair_are_named() -> None:
    rng = np.random.default_rng(3)
    pairs = [(k, a, b) for k in ("afo", "knee", "ankle") for a, b in itertools.combinations(DETECTABLE_AT_3_TO_5, 2)
             if a in EFFECTS[k] and b in EFFECTS[k] and frozenset({a, b}) not in INSEPARABLE]
    picks = [pairs[i] for i in rng.choice(len(pairs), 8, replace=False)]
    right, wrong = 0, []
    for kind, a, b in picks:
        g = generate(kind, (a, b), int(rng.integers(1 << 30)))
        d = diagnose(as_trial(g))
        if is_right(d, g):
            right += 1
        else:
            wrong.append((kind, a, b, sorted(named_causes(d))))
    # the benchmark measures 0.98 over 51 such pairs; these 8 draws include two bursts at 3.1× the noise,
    # at the burst's detection threshold (ΔBIC −5 and −5.5 against the other cause alone)
    assert right >= 6, wrong


def test_friction_beside_a_drift_is_not_taken_for_damping() -> None:
    """Friction leaves a drift's slow structure in its residual, whose own effective sample size is then the
    smallest: ranked by their own ΔBICs, damping (a worse fit) won 7 of these 8 AFO trials (seeds 62000–62007,
    found by a sweep of fresh seeds; other draws fail less often, about 1 in 8). Ranked at one noise model
    for all causes, all 8 are named right."""
    wrong = []
    for seed in range(62000, 62008):
        g = generate("afo", ("coulomb_friction", "sensor_drift"), seed, nuisances=bool(seed % 2))
        d = diagnose(as_trial(g))
        if not is_right(d, g):
            wrong.append((seed, sorted(named_causes(d))))
    assert len(wrong) <= 1, wrong


def test_a_pair_tried_whole_replaces_a_forward_step_led_astray() -> None:
    """Fast ankle sweeps (20 and 30 °/s) with friction and a drift: the short trial's residual holds ~10
    independent samples beside one cause, damping wins the first step by its one parameter fewer, and the
    drift never passes beside it. Tried as a whole, friction + drift passes (seeds 102000 and 102001, found
    by a sweep of fresh seeds: both were named damping before)."""
    for seed in (102000, 102001):
        g = generate("ankle", ("coulomb_friction", "sensor_drift"), seed, nuisances=bool(seed % 2), fast=True)
        d = diagnose(as_trial(g))
        assert is_right(d, g), (seed, sorted(named_causes(d)))


def test_a_delay_reads_the_angle_the_orthosis_had_below_its_cut() -> None:
    """An AFO trial is diagnosed above 6° only; a delayed angle interpolated across that cut (the angle went
    down to ~0° and back) is wrong for the first ``delay`` of every bend, and a "stop" took the leftovers:
    these three delay trials (250 and 1000 Hz) were named delay + stop. Read from the whole trial, delay alone."""
    for seed in (1001, 11001, 11005):
        g = generate("afo", ("time_delay",), seed, nuisances=True)
        d = diagnose(as_trial(g))
        assert sorted(named_causes(d)) == ["time_delay"], (seed, sorted(named_causes(d)))


def test_a_limb_weight_error_in_one_configuration_is_reported_untestable_not_guessed() -> None:
    g = generate("knee", ("gravity_error",), 5)
    d = diagnose(as_trial(g))
    assert "gravity_error" not in named_causes(d)
    assert any(n.startswith("gravity_error cannot be told") for n in d.notes)


@pytest.mark.parametrize("rate_hz", [250.0, 1000.0])
def test_fast_sampling_gives_the_same_finding(rate_hz: float) -> None:
    g = generate("knee", ("viscous_damping",), 12, rate_hz=rate_hz)
    d = diagnose(as_trial(g))
    assert named_causes(d) == {"viscous_damping"}
    assert magnitude_errors(d, g)["viscous_damping"] <= 0.15


def test_damping_intervals_hold_the_truth_on_trials_with_dropped_rows() -> None:
    """With rows dropped and NaN cells removed, the velocity is taken on an even grid: a derivative over the
    raw rows read a gap as one step, overstated the speed by 2–4 % and put viscous damping 4–12 standard
    errors low (7 of 12 intervals missed the truth at seeds 150001–150011 before)."""
    from benchmarks.diagnosis import interval_hits

    rng = np.random.default_rng(20261125)
    hits, errors = [], []
    for _ in range(10):
        kind = str(rng.choice(["afo", "knee", "ankle"]))
        g = generate(kind, ("viscous_damping",), int(rng.integers(1 << 30)), nuisances=True)
        d = diagnose(as_trial(g))
        hits += list(interval_hits(d, g).values())
        errors += list(magnitude_errors(d, g).values())
    assert len(hits) >= 9 and sum(hits) >= len(hits) - 2, hits
    assert max(errors) < 0.03, errors


def test_stop_and_delay_intervals_are_joint_with_their_nonlinear_parameters() -> None:
    """A stop's stiffness trades against its angle, a delay against the baseline: the 95 % intervals of both
    (the joint covariance of coefficients and nonlinear parameters) hold the truth in most trials. Four trials of each
    since the thirty-eighth stop (six before; the suite's time): measured then 7 of 8 intervals holding the truth (a knee
    delay's the one missed)."""
    from benchmarks.diagnosis import interval_hits

    rng = np.random.default_rng(11251)
    hits = []
    for cause in ("time_delay", "hard_stop"):
        for _ in range(4):
            kind = str(rng.choice(["afo", "knee"]))
            g = generate(kind, (cause,), int(rng.integers(1 << 30)), nuisances=bool(rng.random() < 0.5),
                         noise_multiple=(5.0, 8.0))
            d = diagnose(as_trial(g))
            hits += list(interval_hits(d, g).values())
    assert len(hits) >= 7 and sum(hits) >= len(hits) - 2, hits


def test_shape_averaged_intervals_hold_friction_and_stop_magnitudes() -> None:
    """The generator's friction is an arctan law and its ankle stop sits on Riener's steep plantarflexion term;
    the diagnosis's intervals average over smooth Coulomb laws and over a steeper end beside the stop, so
    they hold the truth (with the tanh law alone 0.57 of AFO friction intervals did, ankle stops 0.68)."""
    from benchmarks.diagnosis import interval_hits

    rng = np.random.default_rng(112526)
    hits = []
    for kind, cause in [("afo", "coulomb_friction")] * 6 + [("ankle", "hard_stop")] * 4:
        g = generate(kind, (cause,), int(rng.integers(1 << 30)), nuisances=bool(rng.random() < 0.5),
                     noise_multiple=(5.0, 8.0) if cause == "hard_stop" else (3.0, 5.0))
        d = diagnose(as_trial(g))
        hits += list(interval_hits(d, g).values())
        assert any("averaged over" in n for n in d.notes) or not interval_hits(d, g), d.notes
    assert len(hits) >= 9 and sum(hits) >= len(hits) - 2, hits


def test_the_friction_law_is_the_likeliest_and_leaves_no_damping_behind() -> None:
    """Fast ankle sweeps with arctan-law friction alone (the generator's law): with the tanh law always, the
    law's slow approach to its amplitude was named damping as well (seed 11001, ΔBIC −25); the search now
    uses the law that fits best beside the baseline."""
    from analysis.diagnosis.causes import FRICTION_LAWS, Prepared
    from analysis.diagnosis.engine import likeliest_law

    g = generate("ankle", ("coulomb_friction",), 11001, nuisances=True, fast=True)
    d = diagnose(as_trial(g))
    assert named_causes(d) == {"coulomb_friction"}, d.text()
    prep = Prepared.of(as_trial(g))
    width = 1.0  # rad/s: every law at one width, to read which one the search took
    law = likeliest_law(prep, "coulomb_friction")[0]
    assert law.n_columns is None, law.description  # the generator's friction has no Stribeck excess
    column = law.columns(prep, (width,))[1][:, 0]
    taken = [name for name, shape in FRICTION_LAWS.items() if np.allclose(column, shape(prep.omega / width))]
    assert taken == ["arctan"], taken


@pytest.mark.timeout(600)
def test_a_wandering_drift_is_named_alone() -> None:
    """A drift outside a constant rate, from the third generator family (a slow wander of period 40–150 s at
    3–5× the noise, on knee and ankle sweeps to 2 kHz): the drift's law (a constant rate or a cubic in time)
    is chosen per trial by BIC, so the wander is not missed or split into a drift and a burst. On these seeds
    (drawn after the change) 3 of 6 were named alone before it, 4 of 6 with it; on dev seeds 400000–400002
    of that family 5 of 9 drifts before, 8 of 9 with it (AFO included)."""
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_c_truth import generate_c

    cases = [(kind, 410000 + s) for kind in ("knee", "ankle") for s in range(3)]
    named = {case: named_causes(diagnose(_trial(generate_c(case[0], ("sensor_drift",), case[1]))))
             for case in cases}
    assert sum(n == {"sensor_drift"} for n in named.values()) >= 4, named


def test_dahl_state_turns_over_its_angle_after_each_reversal_and_holds_at_rest() -> None:
    """Dahl's law of the path: after a reversal the unit state approaches the new direction as
    1 − exp(−travel/w) (exactly, from its value at the reversal) and does not move while the joint is still,
    where a law of the speed falls to zero."""
    from analysis.diagnosis.causes import Prepared, dahl_state
    from analysis.diagnosis.data import DiagnosisTrial

    t = np.arange(0.0, 12.0, 0.01)
    speed = np.deg2rad(10.0)
    omega = np.where(t < 4.0, speed, np.where(t < 6.0, 0.0, -speed))  # out, hold, back
    angle = np.concatenate([[0.0], np.cumsum(omega[1:] * np.diff(t))])
    trial = DiagnosisTrial("knee", t, angle, np.zeros_like(t), {"hip_flexion_deg": 90.0},
                           {"mass_kg": 75.0, "shank_length_m": 0.4, "foot_length_m": 0.26}, "unit", 0.0)
    prep = Prepared.of(trial)
    prep.omega = omega  # the exact speed, not its Savitzky–Golay estimate
    width = np.deg2rad(0.5)
    z = dahl_state(prep, width)
    out, hold, back = t < 4.0, (t >= 4.0) & (t < 6.0), t >= 6.0
    travel_out = np.cumsum(np.abs(omega * np.diff(t, prepend=t[0])))
    np.testing.assert_allclose(z[out], 1.0 - np.exp(-travel_out[out] / width), atol=1e-12)
    assert np.all(z[hold] == z[out][-1]) and z[out][-1] > 0.999
    travel_back = travel_out[back] - travel_out[hold][-1]
    np.testing.assert_allclose(z[back], -1.0 + (z[hold][-1] + 1.0) * np.exp(-travel_back / width), atol=1e-12)
    assert z[back][-1] < -0.999


def test_lugre_friction_on_a_joint_is_named_friction_not_damping() -> None:
    """LuGre friction (bristle state, Stribeck curve; the fourth generator family) on knee and ankle sweeps
    whose speed overshoots at each turnaround: with laws of the speed only it was named damping (10 of 16 in
    that family's run; 1 of 12 on development seeds 600000–600005); with Dahl's law of the path among the
    friction laws, 12 of 12 there. Fresh seeds; at least 5 of 6 named alone, magnitudes within 15 %."""
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_d_truth import generate_d

    named, errors = [], []
    for kind, seed in itertools.product(("knee", "ankle"), (640000, 640001, 640002)):
        g = generate_d(kind, ("coulomb_friction",), seed)
        d = diagnose(_trial(g))
        named.append(named_causes(d))
        if named[-1] == {"coulomb_friction"}:
            errors.append(abs(d.parameters["friction_Nm"] / g.effects["coulomb_friction"] - 1.0))
    assert sum(n == {"coulomb_friction"} for n in named) >= 5, named
    assert max(errors) < 0.15, errors


@pytest.mark.timeout(600)
def test_a_settling_or_wandering_drift_is_judged_where_it_interpolates() -> None:
    """Thermal settling and low-passed random-walk drift (the fourth generator family) on knee and ankle sweeps:
    a drift is a function of time, and a left-out first or last block asked its cubic to extrapolate (a drift
    that halved the RMSE read 1.26× worse held out). Judged on the blocks it interpolates: 6 of 8 on these fresh
    seeds (4 of 8 before); the clean trials of the same seeds still name nothing (at most one of 8). Since the
    thirty-eighth stop (the suite's time) the first two seeds of each kind: measured then 3 of 4 drifts named, 0 of 4
    clean trials naming anything (seeds 650000–650003: 7 of 8 and 1 of 8)."""
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_d_truth import generate_d

    cases = list(itertools.product(("knee", "ankle"), range(650000, 650002)))
    drift = [named_causes(diagnose(_trial(generate_d(k, ("sensor_drift",), s)))) for k, s in cases]
    clean = [named_causes(diagnose(_trial(generate_d(k, (), s)))) for k, s in cases]
    assert sum(n == {"sensor_drift"} for n in drift) >= 3, drift
    assert sum(bool(n) for n in clean) <= 1, clean


def test_relaxed_velocity_is_a_maxwell_elements_lag() -> None:
    """A Maxwell element's force over its damping k·τ is the velocity through a first-order lag of τ: at constant
    speed it reaches the speed (plain damping at low speed), after a step it rises as 1 − e^{−t/τ}."""
    from analysis.diagnosis.causes import Prepared, relaxed_velocity
    from analysis.diagnosis.data import DiagnosisTrial

    t = np.arange(0.0, 10.0, 0.005)
    trial = DiagnosisTrial("knee", t, np.deg2rad(10.0) * t, np.zeros_like(t), {"hip_flexion_deg": 90.0},
                           {"mass_kg": 75.0, "shank_length_m": 0.4, "foot_length_m": 0.26}, "unit", 0.0)
    prep = Prepared.of(trial)
    prep.omega = np.where(t >= 2.0, 1.0, 0.0)
    y = relaxed_velocity(prep, 0.2)
    k = int(np.searchsorted(t, 2.0))
    np.testing.assert_allclose(y[k:k + 200], 1.0 - np.exp(-0.005 * np.arange(1, 201) / 0.2), rtol=1e-9)
    assert y[-1] == pytest.approx(1.0, abs=1e-9) and np.all(y[:k] == 0.0)


def test_viscoelastic_damping_is_sized_at_low_speed_alone() -> None:
    """Damping from a Maxwell element (the fifth generator family's: soft tissue's standard linear solid, relaxation
    0.03–0.3 s) on ankle sweeps: with damping proportional to the velocity only, the lag was left for friction or a
    burst beside it and the damping read 2–27 % low (3 of 4 on development seeds 700000–700003 of that family); with
    the relaxed law among the damping laws, 4 of 4 named alone within 2 %. Fresh seeds: at least 4 of 5 named alone,
    their magnitudes (the low-speed k·τ) within 15 %."""
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_e_truth import generate_e

    named, errors = [], []
    for seed in range(710000, 710005):
        g = generate_e("ankle", ("viscous_damping",), seed)
        d = diagnose(_trial(g))
        named.append(named_causes(d))
        if named[-1] == {"viscous_damping"}:
            errors.append(abs(d.parameters["damping_Nm_s_per_rad"] / g.effects["viscous_damping"] - 1.0))
    assert sum(n == {"viscous_damping"} for n in named) >= 4, named
    assert max(errors) < 0.15, errors


def test_two_folds_judge_a_drift_on_every_block() -> None:
    """With fewer than three held-out blocks there is no interior one: a drift is then judged on all of them (the
    interior rule must not leave it nothing to be judged on)."""
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_d_truth import generate_d

    d = diagnose(_trial(generate_d("knee", ("sensor_drift",), 650001)), folds=2)
    drift = next(c for c in d.candidates if c.cause == "sensor_drift")
    assert np.isfinite(drift.heldout_rmse_nm) and drift.heldout_rmse_nm > 0


def test_a_shear_thinning_damping_is_named_alone_and_sized_at_low_speed() -> None:
    """A saturating viscosity (the seventh generator family's, b·θ̇ / (1 + |θ̇|/v_sat)) on knee and ankle sweeps: with
    plain and relaxing damping only it was split into friction + damping (17 of 24 in that family's run; 7 of 9 on
    development seeds 800000–800002, magnitudes 32–72 % low); with the saturating law among the damping laws, 9 of
    9 named alone. These fresh seeds: 1 of 6 named alone before (magnitudes 0.41–0.82 of the truth), 6 of 6 within
    2 % after. At least 5 of 6 named alone, their low-speed magnitudes within 15 %."""
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_g_truth import generate_g

    named, errors = [], []
    for kind, seed in itertools.product(("knee", "ankle"), (820000, 820001, 820002)):
        g = generate_g(kind, ("viscous_damping",), seed)
        d = diagnose(_trial(g))
        named.append(named_causes(d))
        if named[-1] == {"viscous_damping"}:
            errors.append(abs(d.parameters["damping_Nm_s_per_rad"] / g.effects["viscous_damping"] - 1.0))
    assert sum(n == {"viscous_damping"} for n in named) >= 5, named
    assert max(errors) < 0.15, errors


def test_a_saturating_damping_does_not_swallow_a_friction_beside_a_plain_damping() -> None:
    """A saturating damping bends toward a Coulomb friction: it stands alone only with strong evidence over a
    friction beside a plain damping (policy.LAW_RIVAL_MIN_DELTA_BIC). The second family's friction + damping pairs
    (an arctan friction, a linear damping) on fresh seeds: both named in at least 5 of 6 knee and ankle trials (6 of
    6 with the law and before it; with the law and no such test, development seeds 800000–800002 lost 7 of 54
    friction + damping pairs, all three of this family's ankle pairs among them)."""
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_b_truth import generate_b

    named = [named_causes(diagnose(_trial(generate_b(kind, ("coulomb_friction", "viscous_damping"), seed))))
             for kind, seed in itertools.product(("knee", "ankle"), (820000, 820001, 820002))]
    assert sum(n == {"coulomb_friction", "viscous_damping"} for n in named) >= 5, named


def test_the_sandwich_covariance_grows_with_a_misfit_where_the_regressor_acts_and_not_with_noise() -> None:
    """A straight line fitted to data with a white residual: the block sandwich's variance of the slope is the
    model-based one within sampling error. With an unmodelled curvature where the regressor is large (a shape the
    law lacks), it is larger: the interval accounts for the misfit the model-based one calls noise."""
    from analysis.diagnosis.evidence import _block_sandwich

    rng = np.random.default_rng(0)
    x = np.linspace(-1.0, 1.0, 4000)
    jac = np.column_stack([np.ones_like(x), x])
    bread = np.linalg.inv(jac.T @ jac)
    for residual, larger in ((rng.normal(0.0, 0.1, x.size), False),
                             (0.3 * np.sin(4.0 * np.pi * x) * np.abs(x) + rng.normal(0.0, 0.1, x.size), True)):
        fitted = residual - jac @ (bread @ (jac.T @ residual))  # what least squares leaves of it
        model = bread * float(fitted @ fitted) / (x.size - 2)
        robust = _block_sandwich(jac, fitted, bread, 1.0)
        assert robust is not None
        ratio = robust[1, 1] / model[1, 1]
        assert (ratio > 1.5) if larger else (0.7 < ratio < 1.4), ratio
    assert _block_sandwich(jac[:30], np.zeros(30), bread, 1.0) is None  # too few blocks to estimate it


def test_an_inertia_beside_a_passive_end_outside_the_baselines_family_is_sized_on_either_baseline() -> None:
    """An unaccounted inertia on knee sweeps of the fifth family (a densifying bumper's passive ends) and the sixth
    (Gent-like limiting-extensibility ends): a passive curve outside the parametric baseline's family leaves its
    misfit to the cause beside it. On fresh seeds 820000–820003 of both (8 trials), with the magnitude on the
    parametric baseline alone 4 of 7 named inertias were within 15 % and 4 of 7 intervals held the truth; averaged
    over the parametric and the flexible baseline (evidence.magnitude_variants), 7 of 7 within 5 % and held. These
    are the four that were 13–33 % off before (5.9 for 8.7, 10.9 for 12.5, 3.7 for 5.1, 2.1 for 3.0 kg·m²; two
    intervals missed): each named, within 15 %, its interval holding the truth."""
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_e_truth import generate_e
    from benchmarks.family_f_truth import generate_f

    errors, held = [], []
    for make, seed in ((generate_e, 820002), (generate_e, 820003), (generate_f, 820000), (generate_f, 820001)):
        g = make("knee", ("inertia",), seed)
        d = diagnose(_trial(g))
        assert "inertia" in named_causes(d), d.text()
        params = {k: v for a in d.also for k, v in a["parameters"].items()} | dict(d.parameters)
        fitted, truth = params["inertia_kgm2"], g.effects["inertia"]
        errors.append(abs(fitted / truth - 1.0))
        held.append(abs(fitted - truth) <= 1.96 * d.parameters_se["inertia_kgm2"])
    assert max(errors) < 0.15, errors
    assert all(held), held


def test_a_burst_beside_a_passive_curve_outside_the_baselines_family_is_named_from_the_flexible_baseline() -> None:
    """Bursts of 3–5× the noise (the ninth family's biphasic lobes, the tenth's lognormal pulses) on knee and ankle
    strokes whose passive curve no parametric baseline holds (a fibre-recruitment toe, a tabulated stiffness): the
    parametric fit leaves slow structure that shrinks the effective sample size, and the burst's criterion there was
    ΔBIC −2 to +7. On the flexible baseline (a free curve in angle, which cannot mimic a function of time where the
    strokes revisit their angles) at that fit's own n_eff it is decisive. Fresh seeds 830000–830005 of both families
    (24 trials): 5 named alone before, 13 after. These four were missed before: each named alone, within 15 %, its
    interval holding the truth."""
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_i_truth import generate_i
    from benchmarks.family_j_truth import generate_j

    for make, kind, seed in ((generate_i, "ankle", 830001), (generate_i, "knee", 830002), (generate_j, "knee", 830004),
                             (generate_j, "knee", 830005)):
        g = make(kind, ("activation_burst",), seed)
        d = diagnose(_trial(g))
        assert named_causes(d) == {"activation_burst"}, d.text()
        fitted, truth = abs(d.parameters["burst_amplitude_Nm"]), g.effects["activation_burst"]
        assert abs(fitted / truth - 1.0) < 0.15, (kind, seed, fitted, truth)
        assert abs(fitted - truth) <= 1.96 * d.parameters_se["burst_amplitude_Nm"], (kind, seed, fitted, truth)
        note = next(c.note for c in d.candidates if c.cause == "activation_burst")
        assert "at that fit's own n_eff" in note, note  # the report says which criterion named it


def test_a_passive_end_outside_the_baselines_family_is_not_read_as_a_series_compliance() -> None:
    """Clean ankle strokes of the twelfth family (a power-law end k·x^p, p 2.5–4, outside the baseline's exponentials):
    a series compliance reshapes the baseline's curve by its own torque (the joint turns by θ − c·τ), which a stiff end
    bends most, and against the parametric baseline it was named on 9 of 20 of the family's clean ankle trials. In a
    slow trial its effect is a curve in angle again, so it must also beat the flexible baseline. Fresh seeds
    840000–840011 (12 trials): three named a compliance before, none after; these are the three, each now clean."""
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_l_truth import generate_l

    for seed in (840000, 840002, 840009):
        d = diagnose(_trial(generate_l("ankle", (), seed)))
        assert named_causes(d) == set(), (seed, d.text())
