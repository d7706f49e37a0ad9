"""The diagnosis on larger samples of independent trials, on seeds ``benchmarks.diagnosis`` does not use.

``benchmarks.diagnosis`` scores 6 trials per single effect, 3 per pair and 12 clean trials per kind:
enough to compare with the peer, too few to measure a false-alarm rate near 2 %. This one draws
150 clean trials per kind (seeds 8000–8149), 8 per single effect (9000–9007) and 3 per pair
(9500–9502) from the same independent generator (:mod:`benchmarks.diagnosis_truth`), half with
nuisances, and diagnoses them on two processes. A second set has fast isokinetic sweeps (20 and
30 °/s, a third of the protocol's trial length): 30 clean trials per kind (10000–10029), 6 per
single effect (11000–11005) and 2 per pair (12000–12001).

Keys: ``false_alarm_rate``, ``false_alarm_rate_by_kind``, ``accuracy``, ``accuracy_by_cause``,
``pair_accuracy``, ``pair_accuracy_by_pair``, ``misses`` (kind, hidden, seed, named), ``trials``;
``fast_sweeps`` holds the same keys for the fast set.
"""

from __future__ import annotations

import itertools
from collections import defaultdict
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

from benchmarks.diagnosis import INSEPARABLE, KINDS, as_trial, is_right, named_causes
from benchmarks.diagnosis_truth import EFFECTS, generate

CLEAN_SEED, SINGLE_SEED, PAIR_SEED = 8000, 9000, 9500
FAST_CLEAN_SEED, FAST_SINGLE_SEED, FAST_PAIR_SEED = 10000, 11000, 12000


def _one(job: tuple[str, tuple[str, ...], int, bool]) -> tuple[str, tuple[str, ...], int, list[str], bool]:
    from analysis.diagnosis import diagnose

    kind, effects, seed, fast = job
    g = generate(kind, effects, seed, nuisances=bool(seed % 2), fast=fast)
    d = diagnose(as_trial(g))
    return kind, effects, seed, sorted(named_causes(d)), is_right(d, g)


def jobs(clean: int, singles: int, pairs: int, fast: bool = False) -> list[tuple[str, tuple[str, ...], int, bool]]:
    seeds = (FAST_CLEAN_SEED, FAST_SINGLE_SEED, FAST_PAIR_SEED) if fast else (CLEAN_SEED, SINGLE_SEED, PAIR_SEED)
    out: list[tuple[str, tuple[str, ...], int, bool]] = []
    for kind in KINDS:
        out += [(kind, (), seeds[0] + s, fast) for s in range(clean)]
        for cause in EFFECTS[kind]:
            out += [(kind, (cause,), seeds[1] + s, fast) for s in range(singles)]
        for a, b in itertools.combinations(EFFECTS[kind], 2):
            if frozenset({a, b}) in INSEPARABLE or "gravity_error" in (a, b):
                continue
            out += [(kind, (a, b), seeds[2] + s, fast) for s in range(pairs)]
    return out


def run(quick: bool = False) -> dict[str, Any]:
    out = _score(jobs(*((20, 2, 1) if quick else (150, 8, 3))))
    print("\nfast sweeps (20 and 30 °/s):")
    out["fast_sweeps"] = _score(jobs(*((6, 1, 1) if quick else (30, 6, 2)), fast=True))
    out["quick"] = quick
    return out


def _score(todo: list[tuple[str, tuple[str, ...], int, bool]]) -> dict[str, Any]:
    clean: dict[str, list[bool]] = defaultdict(list)
    single: dict[str, list[bool]] = defaultdict(list)
    pair: dict[str, list[bool]] = defaultdict(list)
    misses = []
    with ProcessPoolExecutor(2) as pool:
        for kind, effects, seed, named, right in pool.map(_one, todo, chunksize=4):
            key = f"{kind}/{'+'.join(effects)}"
            (clean[kind] if not effects else single[key] if len(effects) == 1 else pair[key]).append(right)
            if not right:
                misses.append({"kind": kind, "hidden": list(effects), "seed": seed, "named": named})

    def rate(d: dict[str, list[bool]]) -> float:
        return float(np.mean([x for v in d.values() for x in v]))

    out: dict[str, Any] = {"trials": len(todo),
           "false_alarm_rate": 1.0 - rate(clean),
           "false_alarm_rate_by_kind": {k: 1.0 - float(np.mean(v)) for k, v in clean.items()},
           "clean_trials_per_kind": {k: len(v) for k, v in clean.items()},
           "accuracy": rate(single), "accuracy_by_cause": {k: float(np.mean(v)) for k, v in single.items()},
           "pair_accuracy": rate(pair), "pair_accuracy_by_pair": {k: float(np.mean(v)) for k, v in pair.items()},
           "misses": misses}
    for k, v in out["accuracy_by_cause"].items():
        if v < 1.0:
            print(f"  single {k:<32}{v:.2f}")
    for k, v in out["pair_accuracy_by_pair"].items():
        if v < 1.0:
            print(f"  pair   {k:<44}{v:.2f}")
    for m in misses:
        print(f"  miss: {m['kind']} hidden {m['hidden'] or 'nothing'} (seed {m['seed']}) named {m['named'] or 'nothing'}")
    print(f"\nclean trials: false alarms {out['false_alarm_rate']:.3f} {out['false_alarm_rate_by_kind']}; single effects "
          f"{out['accuracy']:.3f}; pairs {out['pair_accuracy']:.3f}; {len(todo)} trials")
    return out
