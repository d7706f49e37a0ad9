"""Diagnosis: hidden effects drawn from seeds must be named, sized within 25 %, and 'none' found when absent."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from analysis.diagnosis import DiagnosisTrial, diagnose, magnitude
from analysis.diagnosis.synthetic import make_trial, truth_magnitude
from analysis.trial_csv import TrialTable, write_trial_csv

#: causes each kind's standard protocol can reveal (the others are tested as untestable below)
TESTABLE = {
    "afo": ["coulomb_friction", "viscous_damping", "hard_stop", "time_delay", "sensor_drift"],
    "ankle": ["coulomb_friction", "viscous_damping", "hard_stop", "activation_burst", "time_delay", "sensor_drift"],
    "knee": ["coulomb_friction", "viscous_damping", "hard_stop", "activation_burst", "time_delay", "sensor_drift"],
    "replica": ["hard_stop"],
}
SEEDS = {"afo": 4, "ankle": 2, "knee": 1, "replica": 3}


@pytest.mark.parametrize("kind,cause", [(k, c) for k, cs in TESTABLE.items() for c in cs])
def test_a_hidden_effect_is_named_and_sized(kind: str, cause: str) -> None:
    for seed in range(100, 100 + SEEDS[kind]):
        trial, hidden = make_trial(kind, cause, seed)
        d = diagnose(trial)
        assert d.cause == cause, (seed, hidden, d.text())
        assert abs(magnitude(d) / truth_magnitude(hidden) - 1) < 0.25, (seed, hidden, d.parameters)
        assert d.extended_rmse_nm < d.baseline_rmse_nm
        assert d.heldout_rmse_ratio <= 1.0 or cause == "activation_burst"  # a burst cannot be predicted held out


def test_random_effects_from_seeds_on_afo_trials() -> None:
    right = 0
    for seed in range(20):
        trial, hidden = make_trial("afo", "random", 5000 + seed)
        d = diagnose(trial)
        expected = hidden.cause if hidden.cause in TESTABLE["afo"] + ["none"] else "none"
        right += d.cause == expected
    assert right >= 19, right


def test_without_an_effect_none_comes_out_in_95_percent_of_seeds() -> None:
    """On the first 40 AFO, 20 replica and 10 ankle seeds none was named in 70 of 70 (fortieth stop, the engine with
    the drift's floor as kept); the suite runs the first 20, 10 and 10 of them."""
    for kind, seeds in (("afo", 20), ("replica", 10), ("ankle", 10)):
        found = [diagnose(make_trial(kind, "none", 900 + s)[0]).cause for s in range(seeds)]
        assert found.count("none") >= 0.95 * seeds, (kind, found)


def test_causes_the_trial_cannot_reveal_are_said_not_guessed() -> None:
    d = diagnose(make_trial("afo", "series_compliance", 3)[0])
    assert d.cause == "none" and any("series_compliance cannot be told" in n and "hook markers" in n for n in d.notes)
    d = diagnose(make_trial("ankle", "gravity_error", 3)[0])
    assert d.cause == "none" and any("gravity_error cannot be told" in n for n in d.notes)


def test_one_way_sweeps_and_single_speeds_name_the_missing_protocol() -> None:
    trial, _ = make_trial("ankle", "coulomb_friction", 11)
    one_way = np.flatnonzero(np.diff(trial.angle_rad) < 0)[-1]  # keep the first sweep only
    first = int(np.flatnonzero(np.diff(trial.angle_rad) > 0)[0])
    cut = DiagnosisTrial("ankle", trial.time_s[:first], trial.angle_rad[:first], trial.torque_nm[:first],
                         trial.fixed_deg, trial.subject, "one-way")
    assert one_way > first
    d = diagnose(cut)
    assert d.cause != "coulomb_friction" and any("one way only" in n and "return movement" in n for n in d.notes)
    # flexion and return at one constant speed: friction and damping are the same square wave
    t = np.arange(0, 24.0, 0.01)
    deg = np.where(t < 12, 15 - 45 * t / 12, -30 + 45 * (t - 12) / 12)
    th = np.deg2rad(deg)
    omega = np.gradient(th, t)
    rng = np.random.default_rng(4)
    tau = 2.0 + 20 * th + 5.0 * th**2 + 1.0 * np.tanh(omega / np.deg2rad(1.0)) + rng.normal(0, 0.1, t.size)
    d = diagnose(DiagnosisTrial("ankle", t, th, tau, {"knee_flexion_deg": 0.0}, {}, "one-speed"))
    assert d.cause in ("coulomb_friction", "viscous_damping")
    assert set(d.ambiguous_with) & {"coulomb_friction", "viscous_damping"}
    assert any("second" in s and "speed" in s for s in d.separate_by)


def test_instrument_diagnose_reads_the_trial_csv(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    from instrument.cli import main

    trial, hidden = make_trial("afo", "coulomb_friction", 77)
    table = TrialTable({"time_s": trial.time_s, "angle_deg": np.rad2deg(trial.angle_rad), "torque_Nm": trial.torque_nm},
                       {"kind": "afo"})
    write_trial_csv(tmp_path / "t.csv", table)
    assert main(["diagnose", str(tmp_path / "t.csv"), "--json", "--plot", str(tmp_path / "d.png")]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["cause"] == "coulomb_friction"
    assert abs(out["parameters"]["friction_Nm"] / hidden.magnitude - 1) < 0.25
    assert {"baseline_rmse_Nm", "extended_rmse_Nm", "heldout_rmse_ratio", "candidates"} <= set(out)
    assert {c["cause"] for c in out["candidates"]} >= {"none", "coulomb_friction", "viscous_damping"}
    assert (tmp_path / "d.png").stat().st_size > 10_000
    (tmp_path / "bad.csv").write_text("time_s,angle_deg\n0,1\n")
    assert main(["diagnose", str(tmp_path / "bad.csv"), "--kind", "afo"]) == 1
    assert "missing column" in capsys.readouterr().err


def test_the_seeds_own_case_explains_table_2_1() -> None:
    """Hinge friction and shell compliance, drawn from a seed, explain the AADS stiffness errors."""
    from analysis.aads import analyze_trial, load_jig_model
    from analysis.diagnosis.aads_case import explain_stiffness_error
    from drivers.simulation.aads_jig import AfoProperties
    from instrument.sim.simulate import synthesize_aads_trial

    rng = np.random.default_rng(2026)
    afo = AfoProperties(hinge_friction_nm=float(rng.uniform(0.1, 0.4)), hinge_friction_coeff=float(rng.uniform(0.04, 0.1)),
                        shell_stiffness_nm_per_deg=float(rng.uniform(8.0, 20.0)))
    model = load_jig_model()
    for spring in (1, 3):
        res = analyze_trial(synthesize_aads_trial(spring, 1, 1, afo=afo)[0], model, factors={"spring": spring})
        e = explain_stiffness_error(res.angle_deg, res.velocity_deg_s, res.afo_torque_nm, res.theory.torque_nm,
                                    res.theory.angle_deg)
        assert abs(e.compliance_deg_per_nm * afo.shell_stiffness_nm_per_deg - 1) < 0.25, e
        assert abs(e.friction_per_spring_torque / afo.hinge_friction_coeff - 1) < 0.25, e
        assert abs(e.error_without_both_pct) < 1.0 < abs(e.error_raw_pct) + 1.0
        assert e.error_without_friction_pct < e.error_raw_pct < e.error_without_compliance_pct  # the two pull apart
        assert e.rmse_after_nm < 0.5 * e.rmse_before_nm


def test_two_effects_at_once_are_both_named() -> None:
    """An AFO bent past its stop with a sticky hinge: the stop first, the friction as the second effect."""
    trial, hidden = make_trial("afo", "hard_stop", 31)
    omega = np.gradient(trial.angle_rad, trial.time_s)
    friction = float(np.random.default_rng(31).uniform(0.4, 0.8))
    sticky = DiagnosisTrial("afo", trial.time_s, trial.angle_rad,
                            trial.torque_nm + friction * np.tanh(omega / np.deg2rad(1.0)), {}, {}, "stop+friction")
    d = diagnose(sticky)
    named = {d.cause} | {a["cause"] for a in d.also}
    assert named == {"hard_stop", "coulomb_friction"}, d.text()
    params = {**d.parameters, **{k: v for a in d.also for k, v in a["parameters"].items()}}
    assert abs(params["friction_Nm"] / friction - 1) < 0.25
    assert abs(params["stop_stiffness_Nm_per_deg"] / hidden.magnitude - 1) < 0.25


def test_standard_errors_cover_the_truth_and_systematic_regions_are_marked() -> None:
    inside = 0
    for seed in range(10):
        trial, hidden = make_trial("afo", "coulomb_friction", 300 + seed)
        d = diagnose(trial)
        se = d.parameters_se["friction_Nm"]
        inside += abs(d.parameters["friction_Nm"] - hidden.magnitude) < 3 * se
        # friction puts the loading branch above the baseline and the unloading branch below it
        branches = {r["branch"]: np.sign(r["mean_residual_Nm"]) for r in d.systematic}
        assert branches.get("loading") == 1 and branches.get("unloading") == -1
    assert inside >= 8, inside
    clean = diagnose(make_trial("afo", "none", 300)[0])
    assert len(clean.systematic) <= 1


@pytest.mark.parametrize("delay_s", [0.03, 0.08])
def test_passive_causes_keep_their_physical_sign_on_a_delayed_torque(delay_s: float) -> None:
    """A torque channel lagging the angle leans the loop the way negative damping would; damping,
    friction and a stop are passive, so their fitted coefficients stay ≥ 0 (written here: a
    triangle-wave bend of a plain spring, the torque read late, independent of the diagnosis' own
    generator)."""
    from analysis.diagnosis.causes import CAUSES, Prepared
    from analysis.diagnosis.engine import fit_cause

    rng = np.random.default_rng(3)
    t = np.arange(0.0, 12.0, 0.01)
    angle = np.deg2rad(10.0) * (1 - np.abs(((t / 3.0) % 2) - 1) * 2) + np.deg2rad(10.0)  # 0–20°, 3 s strokes
    late = np.interp(t - delay_s, t, angle)
    torque = 40.0 * late + rng.normal(0.0, 0.05, t.size)  # 0.7 N·m/° spring
    prep = Prepared.of(DiagnosisTrial("afo", t, angle, torque, {}, {}, "delayed spring"))
    for name in ("viscous_damping", "coulomb_friction", "hard_stop"):
        fit = fit_cause(prep, CAUSES[name])
        extension = fit.coef[fit.n_base:]
        assert extension.size == 1 and extension[0] >= 0.0, (name, fit.params)


def _ankle_sweeps(seed: int, extra: str) -> DiagnosisTrial:
    """Ankle sweeps −30..15° at 5 °/s (100 Hz, white noise 0.12 N·m, no limb) whose passive moment has a
    plantarflexion end steeper than the diagnosis's baseline (an exponential of 6–12 /rad, 3–8 N·m there: the
    baseline has none at that end) and, with ``extra == "stop"``, a hinge stop 5–7° inside the dorsiflexion
    end of 20–30× the noise at the end of the range (both drawn from ``seed``)."""
    rng = np.random.default_rng([4711, seed])
    leg = np.linspace(-30.0, 15.0, 901)
    deg = np.concatenate([leg, leg[::-1], leg, leg[::-1]])
    rate = rng.uniform(6.0, 12.0)
    torque = -rng.uniform(3.0, 8.0) * np.exp(-np.radians(deg + 30.0) * rate) + 0.05 * deg
    torque = torque + 2.0 * np.exp(np.radians(deg - 15.0) * 9.0)
    if extra == "stop":
        at = 15.0 - rng.uniform(5.0, 7.0)
        torque = torque + rng.uniform(20.0, 30.0) * 0.12 * np.clip(deg - at, 0.0, None) / (15.0 - at)
    torque = torque + rng.normal(0.0, 0.12, deg.size)
    return DiagnosisTrial("ankle", np.arange(deg.size) / 100.0, np.radians(deg), torque, {"knee_flexion_deg": 0.0}, {})


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_steeper_passive_end_is_not_a_stop_and_a_real_stop_still_is(seed: int) -> None:
    """No rule about where a stop may sit: a plantarflexion end steeper than the baseline is explained by a
    smooth stiffening, which the stop must out-predict on held-out blocks; a hinge stop well above the
    noise does."""
    d = diagnose(_ankle_sweeps(seed, ""))
    assert d.cause != "hard_stop" and all(a["cause"] != "hard_stop" for a in d.also), d.text()
    d = diagnose(_ankle_sweeps(seed, "stop"))
    assert d.cause == "hard_stop", d.text()


def _afo_bends(seed: int, spring: str, stop: bool = False) -> DiagnosisTrial:
    """An orthosis bent 6 times to 17–19° by hand (raised-cosine bends of 2–3 s, 200 Hz, white noise 0.07 N·m), its
    spring engaging at 2°, 15–22 N·m at 15°: ``"stiffening"`` (an exponential of 8–14 /rad), ``"softening"`` (a tanh
    yield over 6–10°) or ``"linear"`` (the AADS test's coil spring); with ``stop``, a hinge stop at 14–16° of 10–14×
    the noise at the largest bend (everything drawn from ``seed``)."""
    rng = np.random.default_rng([4712, seed])
    parts = []
    for _ in range(6):
        u = np.linspace(0.0, 1.0, int(rng.uniform(2.0, 3.0) * 200.0))
        parts += [rng.uniform(17.0, 19.0) * np.sin(np.pi * u) ** 2, np.zeros(int(rng.uniform(0.3, 0.8) * 200.0))]
    deg = np.concatenate(parts)
    bend = np.clip(deg - 2.0, 0.0, None)
    rate, width = np.radians(rng.uniform(8.0, 14.0)), rng.uniform(6.0, 10.0)
    shape = {"stiffening": np.expm1(rate * bend) / np.expm1(rate * 13.0),
             "softening": np.tanh(bend / width) / np.tanh(13.0 / width), "linear": bend / 13.0}[spring]
    torque = rng.uniform(15.0, 22.0) * shape
    if stop:
        at = rng.uniform(14.0, 16.0)
        torque = torque + rng.uniform(10.0, 14.0) * 0.07 * np.clip(deg - at, 0.0, None) / (deg.max() - at)
    torque = torque + rng.normal(0.0, 0.07, deg.size)
    return DiagnosisTrial("afo", np.arange(deg.size) / 200.0, np.radians(deg), torque, {}, {})


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("spring", ["stiffening", "softening"])
def test_an_orthosis_spring_off_the_quadratic_is_not_read_as_a_stop(spring: str, seed: int) -> None:
    """An orthosis's stop meets the joints' test: it must out-predict a smooth curve at its end of the bend on
    held-out blocks. Before, a stiffening spring read as a stop in 20 of 20 clean orthosis trials of the eleventh
    and thirteenth families, a softening one in 16 of 20 of the fourteenth (and these four, written here, were each
    named a stop). A clean trial names nothing and says what would tell a stop from the spring's curve."""
    d = diagnose(_afo_bends(seed, spring))
    assert d.cause != "hard_stop" and all(a["cause"] != "hard_stop" for a in d.also), d.text()


@pytest.mark.parametrize("seed", [0, 1])
def test_a_hinge_stop_on_the_aads_tests_linear_spring_is_still_named(seed: int) -> None:
    """A hinge stop of 10–14× the noise on a linear coil spring (the AADS test's orthosis) beats the smooth curve."""
    d = diagnose(_afo_bends(seed, "linear", stop=True))
    assert d.cause == "hard_stop", d.text()
    assert abs(d.parameters["stop_angle_deg"] - 15.0) < 2.5, d.parameters


def test_a_stop_on_a_curved_orthosis_spring_is_said_to_be_inseparable_not_guessed() -> None:
    """The limit of one trial, measured: the same stop on an exponentially stiffening spring is not named (the smooth
    curve at the bend's end fits the two together better than the stop on the quadratic does); the report says a stop
    or the spring's curve, and which protocol would tell them apart."""
    d = diagnose(_afo_bends(0, "stiffening", stop=True))
    assert d.cause != "hard_stop", d.text()
    assert any("a stop, or the spring's curve" in n for n in d.notes), d.notes
    assert any("bends that go further past the stop" in s for s in d.separate_by), d.separate_by


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**31 - 1), st.floats(0.0, 0.05))
def test_velocity_is_unbiased_by_dropped_rows(seed: int, drop_fraction: float) -> None:
    """The velocity (rad/s) of a sweep with rows missing matches its even-grid derivative: a derivative over
    the raw rows would read each gap as a single step."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 20.0, 0.01)
    angle = np.deg2rad(30.0) * np.sin(2 * np.pi * 0.1 * t)
    keep = rng.random(t.size) >= drop_fraction
    keep[:5] = keep[-5:] = True
    trial = DiagnosisTrial("knee", t[keep], angle[keep], np.zeros(int(keep.sum())), {}, {})
    truth = np.deg2rad(30.0) * 2 * np.pi * 0.1 * np.cos(2 * np.pi * 0.1 * t[keep])
    inner = slice(20, -20)
    # a gap read as one step would be 100 %
    assert np.max(np.abs(trial.velocity_rad_s()[inner] - truth[inner])) < 0.01 * np.max(np.abs(truth))


def test_a_delay_lags_the_limb_weight_too() -> None:
    """A torque channel read late lags all of the torque, the limb's weight included (written here: a knee swept
    at 10 °/s, its passive moment and its weight read 0.12 s late; the delay is the only effect)."""
    rate = 100.0
    t = np.arange(0.0, 60.0, 1.0 / rate)
    knee_deg = 45.0 - 40.0 * np.abs(((t / 16.0) % 1.0) * 2.0 - 1.0) * 2.0 + 40.0  # 5–85°, 10 °/s
    knee = np.deg2rad(knee_deg)
    subject = {"mass_kg": 75.0, "shank_length_m": 0.42, "foot_length_m": 0.26}
    probe = DiagnosisTrial("knee", t, knee, np.zeros_like(t), {"hip_flexion_deg": 90.0}, subject)
    torque = probe.limb_gravity_nm() + 2.0 * np.exp(-3.0 * (knee - 0.1)) + 0.5 * np.exp(3.0 * (knee - 1.5)) + 3.0 * knee
    delay = 0.12
    late = np.interp(t - delay, t, torque) + np.random.default_rng(3).normal(0.0, 0.05, t.size)
    d = diagnose(DiagnosisTrial("knee", t, knee, late, {"hip_flexion_deg": 90.0}, subject, "late knee"))
    assert d.cause == "time_delay", d.text()
    assert abs(d.parameters["delay_s"] - delay) < 0.005, d.parameters


def _filtered_knee(seed: int, pure_delay_s: float = 0.0) -> tuple[DiagnosisTrial, float]:
    """A knee swept 5–85° at 10 °/s whose torque channel runs through a first-order low-pass (its group delay drawn
    from ``seed``, 0.05–0.25 s; written here with scipy, not the engine's filter) or, with ``pure_delay_s``, is read
    that late instead; (the trial, the channel's true delay at low frequency in s)."""
    from scipy.signal import lfilter

    rng = np.random.default_rng(seed)
    rate = 100.0
    t = np.arange(0.0, 64.0, 1.0 / rate)
    knee = np.deg2rad(5.0 + 80.0 * np.abs(((t / 16.0) % 1.0) * 2.0 - 1.0))
    subject = {"mass_kg": 75.0, "shank_length_m": 0.42, "foot_length_m": 0.26}
    probe = DiagnosisTrial("knee", t, knee, np.zeros_like(t), {"hip_flexion_deg": 90.0}, subject)
    torque = probe.limb_gravity_nm() + 2.0 * np.exp(-3.0 * (knee - 0.1)) + 0.5 * np.exp(3.0 * (knee - 1.5)) + 3.0 * knee
    if pure_delay_s > 0.0:
        late, delay = np.interp(t - pure_delay_s, t, torque), pure_delay_s
    else:
        pole = float(np.exp(-1.0 / (rate * rng.uniform(0.05, 0.25))))  # the sampled analogue filter's pole
        late = lfilter([1.0 - pole], [1.0, -pole], torque, zi=[pole * torque[0]])[0]
        delay = pole / (1.0 - pole) / rate
    noisy = late + rng.normal(0.0, 0.05, t.size)
    return DiagnosisTrial("knee", t, knee, noisy, {"hip_flexion_deg": 90.0}, subject, "filtered knee"), delay


@pytest.mark.parametrize("seed", [0, 1, 4])
def test_a_filtered_torque_channel_is_a_delay_whose_interval_holds_its_group_delay(seed: int) -> None:
    """A first-order low-pass on the torque channel is not a pure delay: read as one, its delay was off by up to
    1.3 % with an interval of ±0.8 % (seeds 0, 1, 4 not covered). The delay's magnitude is averaged over both laws
    (a transport delay and a filter's lag, each by its group delay) on the samples both predict."""
    trial, delay = _filtered_knee(seed)
    d = diagnose(trial)
    assert d.cause == "time_delay", d.text()
    est, se = d.parameters["delay_s"], d.parameters_se["delay_s"]
    assert abs(est - delay) <= 1.96 * se and abs(est / delay - 1.0) < 0.02, (est, se, delay)
    assert any("first-order lag" in n for n in d.notes)


def test_a_pure_delay_keeps_the_pure_law() -> None:
    """Beside the lag law a transport delay is still read as one: the weights, compared on the samples both laws
    predict, go to the pure law, and the interval holds the delay."""
    trial, delay = _filtered_knee(7, pure_delay_s=0.15)
    d = diagnose(trial)
    assert d.cause == "time_delay", d.text()
    assert abs(d.parameters["delay_s"] - delay) <= 1.96 * d.parameters_se["delay_s"]
    note = next(n for n in d.notes if n.startswith("time_delay: delay_s averaged"))
    weights = re.findall(r"(pure|first-order lag), (?:parametric|flexible) baseline \(([0-9.]+)\)", note)
    assert len(weights) == 4, note
    assert sum(float(w) for law, w in weights if law == "pure") > 0.5, note


def test_a_delay_that_leaves_the_orthosis_range_for_most_samples_is_no_fit() -> None:
    """An orthosis bent in short bends (1 s each, to 8–14°): a delay of most of a bend puts the delayed angle below the
    spring's engagement at nearly every kept sample. Its mean square over the samples left (none at 1 s) won the
    delay's grid and the diagnosis divided by zero; a model must predict at least half the samples to compete."""
    rate = 200.0
    parts = [np.zeros(80)]
    for peak in np.linspace(8.0, 14.0, 6):
        u = np.linspace(0.0, 1.0, int(rate))
        parts += [peak * np.sin(np.pi * u) ** 2, np.zeros(int(0.3 * rate))]
    deg = np.concatenate(parts)
    t = np.arange(deg.size) / rate
    bend = np.clip(deg - 3.0, 0.0, None)
    torque = 1.2 * bend + 0.01 * bend**2 + np.random.default_rng(2).normal(0.0, 0.07, t.size)
    d = diagnose(DiagnosisTrial("afo", t, np.radians(deg), torque, {}, {}, "short bends"))
    assert d.cause == "none", d.text()
    assert d.fits["time_delay"].n >= 0.5 * d.fits["none"].n


def test_burst_candidates_start_at_their_samples_time_when_rows_are_missing() -> None:
    """The burst's matched filter names a sample; its start is that sample's time, not the first time plus the
    index times the step (with a fifth of the rows missing that put a burst at 30 s some 6 s early)."""
    from analysis.diagnosis.causes import CAUSES, Prepared

    rng = np.random.default_rng(5)
    t = np.arange(0.0, 60.0, 0.01)
    keep = rng.random(t.size) > 0.2
    t = t[keep]
    knee = np.deg2rad(45.0 + 40.0 * np.sin(2 * np.pi * t / 20.0))
    bump = np.where((t > 30.0) & (t < 30.8), np.sin(np.pi * (t - 30.0) / 0.8), 0.0)
    torque = 3.0 * knee + 2.0 * bump + rng.normal(0.0, 0.05, t.size)
    prep = Prepared.of(DiagnosisTrial("knee", t, knee, torque, {"hip_flexion_deg": 90.0}, {}))
    starts = np.array([row[0] for row in CAUSES["activation_burst"].grid(prep)])
    assert np.min(np.abs(starts - 30.0)) < 0.3, np.sort(starts)[:10]


@settings(max_examples=8, deadline=None)
@given(st.sampled_from(["afo", "knee", "ankle"]), st.integers(0, 2**20), st.floats(0.0, 0.4), st.floats(0.0, 0.05))
def test_a_damaged_trial_is_diagnosed_with_finite_intervals_or_refused(kind: str, seed: int, drop: float,
                                                                       nan_fraction: float) -> None:
    """Rows dropped (up to 40 %) and NaN cells (up to 5 %) anywhere: the diagnosis names causes with finite,
    positive standard errors for every magnitude it reports, or refuses with an InputError."""
    from analysis.errors import InputError
    from benchmarks.diagnosis_truth import EFFECTS, generate

    rng = np.random.default_rng(seed)
    effect = str(rng.choice(EFFECTS[kind]))
    g = generate(kind, (effect,), seed)
    keep = rng.random(g.time_s.size) >= drop
    torque = g.torque_nm[keep].copy()
    torque[rng.random(torque.size) < nan_fraction] = np.nan
    try:
        d = diagnose(DiagnosisTrial(kind, g.time_s[keep], g.angle_rad[keep], torque, g.fixed_deg, g.subject))
    except InputError:
        return
    from analysis.diagnosis.causes import CAUSES

    for cause in ({d.cause} | {a["cause"] for a in d.also}) - {"none"}:
        key = CAUSES[cause].magnitude_key
        if key:
            assert np.isfinite(d.parameters_se.get(key, np.nan)) and d.parameters_se[key] > 0, (cause, d.parameters_se)


def test_a_compliance_the_flexible_baseline_absorbs_is_said_untestable_though_the_parametric_one_does_not() -> None:
    # a spent seventeenth-family knee (a cuff whose give creeps): θ − c·τ(θ) is a curve in angle the spline follows
    from analysis.diagnosis.causes import CAUSES, Prepared
    from analysis.diagnosis.fitting import absorbed_by_baseline, fit_cause
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_q_truth import generate_q

    trial = _trial(generate_q("knee", ("series_compliance",), 201))
    prep = Prepared.of(trial.decimated(200.0))
    cause = CAUSES["series_compliance"]
    fit = fit_cause(prep, cause)
    parametric, flexible = absorbed_by_baseline(prep, cause, fit), absorbed_by_baseline(prep, cause, fit, True)
    assert parametric < 0.999 < flexible  # the flexible basis holds the parametric one, and more
    d = diagnose(trial)
    assert any("series_compliance cannot be told" in n for n in d.notes), d.notes
    assert "series_compliance" not in {d.cause, *(a["cause"] for a in d.also)}


def test_a_burst_is_searched_again_on_the_free_curve_where_the_passive_misfit_draws_it_elsewhere() -> None:
    # a spent seventeenth-family knee: its passive end (Veronda–Westmann, steeper than the baseline's) leaves a
    # misfit at the trial's start, where the parametric search put a 6 N·m burst; the sech² pulse is at 26.8 s
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_q_truth import generate_q

    g = generate_q("knee", ("activation_burst",), 202)
    d = diagnose(_trial(g))
    assert d.cause == "activation_burst" and not d.also, d.text()
    centre = d.parameters["burst_start_s"] + 0.5 * d.parameters["burst_duration_s"]
    assert abs(centre - g.details["pulse_centre_s"]) < 0.5
    truth = g.effects["activation_burst"]
    assert truth is not None
    assert abs(abs(d.parameters["burst_amplitude_Nm"]) - truth) <= 1.96 * d.parameters_se["burst_amplitude_Nm"]
