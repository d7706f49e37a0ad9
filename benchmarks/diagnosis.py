"""Diagnosis on trials it did not make: single effects, pairs and clean trials from an independent generator.

Every trial comes from :mod:`benchmarks.diagnosis_truth` (Riener & Edrich passive moments, de
Leva limb weight, its own effect shapes and noise), which shares nothing with the diagnosis. For
each kind (AFO, knee, ankle): clean trials, every single effect at 3–5× the noise, every pair of
effects, half of them with nuisances (100/250/1000 Hz, AR(1) noise of random correlation,
offsets, NaN cells, dropped rows, uneven speed). A hard stop is also measured at larger sizes
(its detection threshold). The same trials go through a peer, PySINDy's sequentially thresholded
least squares over a library of the same candidate terms with its threshold chosen by blocked
cross-validation (:mod:`benchmarks.sindy_peer`), at the CV minimum and with the one-standard-error
rule, so the numbers have a reference measured in the same run.

A trial counts as right when the set of named causes equals the hidden set. A limb-weight error
in one configuration is right when it is reported as untestable (the baseline absorbs it: the
report says so and names the trial that would separate it). Magnitudes: |fitted / true − 1|.

Keys: ``accuracy`` (single effects), ``pair_accuracy``, ``false_alarm_rate`` (clean trials), the
peer's ``sindy_accuracy``, ``sindy_pair_accuracy``, ``sindy_false_alarm_rate`` and their
``sindy_1se_*`` twins, ``seconds_per_trial`` (and ``sindy_seconds_per_trial``),
``magnitude_within_15pct``, ``magnitude_interval_coverage`` (how often the reported 95 % interval of a
named cause's magnitude holds the truth, singles and pairs, and per cause), ``seconds_100hz_60s``, ``seconds_1000hz_60s``,
per-cause and per-pair
tables for both.
"""

from __future__ import annotations

import itertools
import time
from collections import defaultdict
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

from analysis.diagnosis import DiagnosisTrial, diagnose
from benchmarks.diagnosis_truth import EFFECTS, MAGNITUDE_KEY, IndependentTrial, generate

KINDS = ("afo", "knee", "ankle")
#: pairs a single trial cannot separate (the diagnosis reports them as ambiguous with the protocol
#: change that would): not scored as pairs
INSEPARABLE = {frozenset({"viscous_damping", "time_delay"}), frozenset({"coulomb_friction", "viscous_damping"}),
               frozenset({"coulomb_friction", "time_delay"})}


def as_trial(g: IndependentTrial) -> DiagnosisTrial:
    return DiagnosisTrial(g.kind, g.time_s, g.angle_rad, g.torque_nm, g.fixed_deg, g.subject, "independent")


def named_causes(d: Any) -> set[str]:
    """The causes a diagnosis names (the winner and a second effect)."""
    return ({d.cause} - {"none"}) | {a["cause"] for a in d.also}


def is_right(d: Any, g: IndependentTrial) -> bool:
    hidden = set(g.effects)
    untestable = {n.split(" ")[0] for n in d.notes if "cannot be told from the baseline" in n}
    expected = hidden - (untestable & {"gravity_error"})
    return named_causes(d) == expected


def _named_magnitudes(d: Any, g: IndependentTrial) -> list[tuple[str, str, float, float]]:
    """(cause, magnitude key, fitted magnitude, true magnitude) for every hidden cause the diagnosis named."""
    params = dict(d.parameters)
    for a in d.also:
        params.update(a["parameters"])
    return [(cause, MAGNITUDE_KEY[cause], abs(params[MAGNITUDE_KEY[cause]]), truth) for cause, truth in g.effects.items()
            if cause in named_causes(d) and MAGNITUDE_KEY[cause] in params and truth]


def magnitude_errors(d: Any, g: IndependentTrial) -> dict[str, float]:
    """|fitted / true − 1| per named hidden cause."""
    return {cause: abs(fitted / truth - 1.0) for cause, _, fitted, truth in _named_magnitudes(d, g)}


def interval_hits(d: Any, g: IndependentTrial, z: float = 1.96) -> dict[str, bool]:
    """Per named hidden cause: whether the reported 95 % interval (± ``z`` standard errors) of its
    magnitude holds the truth. A cause reported without a finite standard error counts as a miss."""
    out = {}
    for cause, key, fitted, truth in _named_magnitudes(d, g):
        se = float(d.parameters_se.get(key, float("nan")))
        out[cause] = bool(np.isfinite(se) and abs(fitted - truth) <= z * se)
    return out


def _peer(job: tuple[str, tuple[str, ...], int, bool]) -> Any:
    from threadpoolctl import threadpool_limits  # scikit-learn's, which PySINDy needs

    from benchmarks.sindy_peer import diagnose_sparse

    kind, effects, seed, nuisances = job
    with threadpool_limits(1):  # two worker processes on two cores: one BLAS thread each
        return diagnose_sparse(as_trial(generate(kind, effects, seed, nuisances=nuisances)))


def peer_is_right(named: frozenset[str], untestable: frozenset[str], g: IndependentTrial) -> bool:
    """The peer's answer scored as the diagnosis's: the hidden set, a limb-weight error its library
    had to leave out (the baseline reproduces it) counted as reported untestable."""
    return set(named) == set(g.effects) - (untestable & {"gravity_error"})


def _speed(rate_hz: float) -> float:
    g = generate("knee", ("coulomb_friction",), 7, rate_hz=rate_hz)
    n = int(60.0 * rate_hz)
    t = np.arange(n) / rate_hz
    trial = DiagnosisTrial("knee", t, np.interp(t, g.time_s, g.angle_rad, period=g.time_s[-1]),
                           np.interp(t, g.time_s, g.torque_nm, period=g.time_s[-1]), g.fixed_deg, g.subject)
    t0 = time.perf_counter()
    diagnose(trial)
    return time.perf_counter() - t0


def run(quick: bool = False) -> dict[str, Any]:
    seeds = 2 if quick else 6
    pair_seeds = 1 if quick else 3
    t_total = 0.0
    n_trials = 0
    singles: dict[str, list[bool]] = defaultdict(list)
    sindy: dict[str, list[bool]] = defaultdict(list)
    mags: dict[str, list[float]] = defaultdict(list)
    covered: dict[str, list[bool]] = defaultdict(list)
    clean: dict[str, list[bool]] = defaultdict(list)
    pairs: dict[str, list[bool]] = defaultdict(list)

    def one(g: IndependentTrial) -> Any:
        nonlocal t_total, n_trials
        t0 = time.perf_counter()
        d = diagnose(as_trial(g))
        t_total += time.perf_counter() - t0
        n_trials += 1
        return d

    todo: list[tuple[str, tuple[str, ...], int, bool]] = []
    for kind in KINDS:
        todo += [(kind, (), 500 + s, bool(s % 2)) for s in range(seeds * 2)]
        todo += [(kind, (cause,), 1000 + s, bool(s % 2)) for cause in EFFECTS[kind] for s in range(seeds)]
        todo += [(kind, (a, b), 2000 + s, bool(s % 2)) for a, b in itertools.combinations(EFFECTS[kind], 2)
                 if frozenset({a, b}) not in INSEPARABLE and "gravity_error" not in (a, b) for s in range(pair_seeds)]
    t_peer = time.perf_counter()
    with ProcessPoolExecutor(2) as pool:
        peer_results = list(pool.map(_peer, todo, chunksize=2))
    t_peer = (time.perf_counter() - t_peer) * 2 / len(todo)  # two processes
    sindy_clean: dict[str, list[bool]] = defaultdict(list)
    sindy_clean_1se: dict[str, list[bool]] = defaultdict(list)
    sindy_1se: dict[str, list[bool]] = defaultdict(list)
    sindy_pairs: dict[str, list[bool]] = defaultdict(list)
    sindy_pairs_1se: dict[str, list[bool]] = defaultdict(list)
    for (kind, effects, seed, nuisances), peer in zip(todo, peer_results, strict=True):
        g = generate(kind, effects, seed, nuisances=nuisances)
        d = one(g)
        at_min = peer_is_right(peer.named, peer.untestable, g)
        at_1se = peer_is_right(peer.named_1se, peer.untestable, g)
        if not effects:
            clean[kind].append(not named_causes(d))
            sindy_clean[kind].append(at_min)
            sindy_clean_1se[kind].append(at_1se)
            continue
        key = f"{kind}/{'+'.join(effects)}"
        if len(effects) == 1:
            singles[key].append(is_right(d, g))
            sindy[key].append(at_min)
            sindy_1se[key].append(at_1se)
        else:
            pairs[key].append(is_right(d, g))
            sindy_pairs[key].append(at_min)
            sindy_pairs_1se[key].append(at_1se)
        for c, e in magnitude_errors(d, g).items():
            mags[f"{kind}/{c}" + (" (pair)" if len(effects) == 2 else "")].append(e)
        for c, hit in interval_hits(d, g).items():
            covered[f"{kind}/{c}"].append(hit)
    stop_threshold: dict[str, dict[str, float]] = {}
    for kind in KINDS:
        stop_threshold[kind] = {}
        for lo, hi in ((3.0, 5.0), (5.0, 8.0), (8.0, 12.0)):
            hits = [named_causes(one(g)) == {"hard_stop"} for g in
                    (generate(kind, ("hard_stop",), 3000 + s, noise_multiple=(lo, hi)) for s in range(seeds))]
            stop_threshold[kind][f"{lo:g}-{hi:g}x_noise"] = float(np.mean(hits))

    def rate(d: dict[str, list[bool]]) -> float:
        v = [x for xs in d.values() for x in xs]
        return float(np.mean(v)) if v else float("nan")

    all_mags = [x for xs in mags.values() for x in xs]
    s100 = _speed(100.0)
    s1000 = _speed(1000.0)
    out: dict[str, Any] = {
        "quick": quick, "trials": n_trials,
        "accuracy": rate(singles), "pair_accuracy": rate(pairs), "false_alarm_rate": 1.0 - rate(clean),
        "sindy_accuracy": rate(sindy), "sindy_pair_accuracy": rate(sindy_pairs),
        "sindy_false_alarm_rate": 1.0 - rate(sindy_clean),
        "sindy_1se_accuracy": rate(sindy_1se), "sindy_1se_pair_accuracy": rate(sindy_pairs_1se),
        "sindy_1se_false_alarm_rate": 1.0 - rate(sindy_clean_1se),
        "false_alarm_rate_by_kind": {k: 1.0 - float(np.mean(v)) for k, v in clean.items()},
        "sindy_false_alarm_rate_by_kind": {k: 1.0 - float(np.mean(v)) for k, v in sindy_clean.items()},
        "sindy_1se_false_alarm_rate_by_kind": {k: 1.0 - float(np.mean(v)) for k, v in sindy_clean_1se.items()},
        "accuracy_by_cause": {k: float(np.mean(v)) for k, v in singles.items()},
        "sindy_accuracy_by_cause": {k: float(np.mean(v)) for k, v in sindy.items()},
        "sindy_1se_accuracy_by_cause": {k: float(np.mean(v)) for k, v in sindy_1se.items()},
        "pair_accuracy_by_pair": {k: float(np.mean(v)) for k, v in pairs.items()},
        "sindy_pair_accuracy_by_pair": {k: float(np.mean(v)) for k, v in sindy_pairs.items()},
        "sindy_1se_pair_accuracy_by_pair": {k: float(np.mean(v)) for k, v in sindy_pairs_1se.items()},
        "magnitude_within_15pct": float(np.mean(np.array(all_mags) <= 0.15)) if all_mags else float("nan"),
        "magnitude_median_error": float(np.median(all_mags)) if all_mags else float("nan"),
        "magnitude_error_by_cause": {k: float(np.median(v)) for k, v in mags.items()},
        "magnitude_interval_coverage": rate(covered),
        "magnitude_interval_coverage_by_cause": {k: float(np.mean(v)) for k, v in sorted(covered.items())},
        "hard_stop_detection_by_size": stop_threshold,
        "seconds_per_trial": t_total / n_trials, "sindy_seconds_per_trial": t_peer,
        "seconds_100hz_60s": s100, "seconds_1000hz_60s": s1000, "seconds_ratio_1000_to_100hz": s1000 / s100,
    }
    print(f"{'cause':<32}{'diagnosis':>10}{'SINDy':>8}{'SINDy 1SE':>10}{'|mag err| median':>18}")
    for k in out["accuracy_by_cause"]:
        m = out["magnitude_error_by_cause"].get(k)
        print(f"{k:<32}{out['accuracy_by_cause'][k]:>10.2f}{out['sindy_accuracy_by_cause'][k]:>8.2f}"
              f"{out['sindy_1se_accuracy_by_cause'][k]:>10.2f}{(f'{m:.3f}' if m is not None else '—'):>18}")
    print(f"\n{'pair':<50}{'diagnosis':>10}{'SINDy':>8}{'SINDy 1SE':>10}")
    for k, v in out["pair_accuracy_by_pair"].items():
        print(f"  {k:<48}{v:>10.2f}{out['sindy_pair_accuracy_by_pair'][k]:>8.2f}"
              f"{out['sindy_1se_pair_accuracy_by_pair'][k]:>10.2f}")
    print(f"\n{'':<24}{'diagnosis':>10}{'SINDy':>8}{'SINDy 1SE':>10}")
    for label, key in (("single effects", "accuracy"), ("both causes of a pair", "pair_accuracy"),
                       ("false alarms (clean)", "false_alarm_rate")):
        print(f"{label:<24}{out[key]:>10.3f}{out['sindy_' + key]:>8.3f}{out['sindy_1se_' + key]:>10.3f}")
    print(f"\n95 % intervals of the magnitudes holding the truth: {out['magnitude_interval_coverage']:.3f}")
    for k, v in out["magnitude_interval_coverage_by_cause"].items():
        print(f"  {k:<30}{v:>6.2f}  ({len(covered[k])})")
    print(f"\nhard stop found, by size: {stop_threshold}")
    print(f"\nsingle effects {out['accuracy']:.3f} (SINDy {out['sindy_accuracy']:.3f}); pairs {out['pair_accuracy']:.3f}; "
          f"false alarms {out['false_alarm_rate']:.3f} {out['false_alarm_rate_by_kind']}; magnitudes within 15 %: "
          f"{out['magnitude_within_15pct']:.3f}; {out['seconds_per_trial']:.2f} s per trial; 60 s knee trial: "
          f"{s100:.2f} s at 100 Hz, {s1000:.2f} s at 1000 Hz")
    return out
