"""The PySINDy peer (:mod:`benchmarks.sindy_peer`) alone on the second and third families' trials.

The peer was rebuilt to the issue's description of a fair one (columns at unit RMS, stop hinges wherever the
diagnosis searches, a cause named by its terms' joint significance, the one-standard-error rule) after the
third family's run; that run's ``sindy_*`` keys are the earlier peer's. This benchmark runs the rebuilt peer on
the same trials (seeds and scoring as :mod:`benchmarks.diagnosis_family_b`) and prints the engine's committed
figures beside it. Keys per family: ``sindy_accuracy``, ``sindy_pair_accuracy``, ``sindy_false_alarm_rate``
and their ``sindy_1se_*`` twins, ``engine_*`` from ``benchmarks/results/diagnosis_family_<f>.json``.
"""

from __future__ import annotations

import json
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

from .diagnosis_family_b import FAMILIES, _trial, jobs

RESULTS = Path(__file__).parent / "results"


def _peer(job: tuple[str, tuple[str, ...], int, str]) -> dict[str, Any]:
    from threadpoolctl import threadpool_limits

    from .sindy_peer import diagnose_sparse

    kind, effects, seed, family = job
    g = FAMILIES[family][0](kind, effects, seed)
    with threadpool_limits(1):
        peer = diagnose_sparse(_trial(g))
    expected = set(effects) - (set(peer.untestable) & {"gravity_error"})
    return {"kind": kind, "effects": list(effects), "seed": seed, "named": sorted(peer.named),
            "named_1se": sorted(peer.named_1se), "right": set(peer.named) == expected,
            "right_1se": set(peer.named_1se) == expected}


def run(quick: bool = False) -> dict[str, Any]:
    out: dict[str, Any] = {"quick": quick}
    print(f"{'':<10}{'':<26}{'engine':>8}{'peer':>8}{'peer 1SE':>10}")
    for family in ("b", "c"):
        with ProcessPoolExecutor(2) as pool:
            rows = list(pool.map(_peer, jobs(quick, family), chunksize=4))
        engine_file = RESULTS / f"diagnosis_family_{family}.json"
        engine = json.loads(engine_file.read_text()) if engine_file.exists() else {}
        groups = {"accuracy": [r for r in rows if len(r["effects"]) == 1],
                  "pair_accuracy": [r for r in rows if len(r["effects"]) == 2],
                  "false_alarm_rate": [r for r in rows if not r["effects"]]}
        fam: dict[str, Any] = {"trials": len(rows)}
        for key, group in groups.items():
            for suffix, field in (("", "right"), ("_1se", "right_1se")):
                share = float(np.mean([r[field] for r in group])) if group else float("nan")
                fam[f"sindy{suffix}_{key}"] = 1.0 - share if key == "false_alarm_rate" else share
            fam[f"engine_{key}"] = engine.get(key)
            e = fam[f"engine_{key}"]
            print(f"family {family:<3}{key:<26}{(e if e is not None else float('nan')):>8.3f}"
                  f"{fam[f'sindy_{key}']:>8.3f}{fam[f'sindy_1se_{key}']:>10.3f}")
        fam["cases"] = rows
        out[family] = fam
    return out
