"""Tabulate how each leg muscle's path length follows the thigh's, the shank's and the foot's scale, from any .osim.

    python tools/fit_segment_fractions.py MODEL.osim [-o analysis/pmp/data/rajagopal2016_segment_fractions.json]

Needs OpenSim, run in a child interpreter (:mod:`benchmarks.opensim_passive`, ``"what": "segment_fractions"``).
Each segment's bodies (thigh: pelvis, femur, patella; shank: tibia; foot: talus, calcaneus, toes) are scaled by
1.02 with OpenSim's ``Model.scale`` (the Scale Tool's manual factors), and each muscle's path length is compared
with the unscaled model's at the seated poses of the protocol (hip 15/55/90°, knee 0/45/90°, ankle −30/0/15°):
the fraction is (ΔL/L)/0.02. The estimator scales a muscle's path, optimal fibre and tendon slack lengths by
the fractions' weighted mean of the segments' factors (:class:`analysis.pmp.muscles.LegMuscles`); the mean over
the poses is kept, and the spread over them (how far one fraction per muscle is from the pose-dependent truth)
beside it.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import sys
from pathlib import Path

import numpy as np

POSES_DEG = [{"hip": h, "knee": k, "ankle": a} for h, k, a in itertools.product((15.0, 55.0, 90.0), (0.0, 45.0, 90.0),
                                                                                 (-30.0, 0.0, 15.0))]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model", type=Path)
    ap.add_argument("-o", "--output", type=Path, default=Path("analysis/pmp/data/rajagopal2016_segment_fractions.json"))
    args = ap.parse_args(argv)
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from benchmarks.opensim_truth import opensim  # OpenSim in a child interpreter (its CasADi ≠ the wheel's)

    poses = [{k: math.radians(v) for k, v in p.items()} for p in POSES_DEG]
    answer = opensim({"what": "segment_fractions", "model": str(args.model.resolve()), "poses": poses, "step": 0.02})
    out = {"source": args.model.name, "script": "tools/fit_segment_fractions.py", "step": answer["step"],
           "bodies": answer["bodies"], "poses_deg": POSES_DEG, "muscles": {}}
    for m, by_segment in answer["fractions"].items():
        out["muscles"][m] = {seg: {"mean": float(np.mean(v)), "min": float(np.min(v)), "max": float(np.max(v))}
                             for seg, v in by_segment.items()}
    args.output.write_text(json.dumps(out, indent=1) + "\n", encoding="utf-8")
    for m, row in out["muscles"].items():
        print(f"{m:<8}" + "  ".join(f"{seg} {r['mean']:.3f} [{r['min']:.3f}, {r['max']:.3f}]" for seg, r in row.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
