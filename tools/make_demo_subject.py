"""Make the simulated lab's seated subject: passive joint moments computed by OpenSim, written as tables.

    python tools/make_demo_subject.py   # needs the test extra (OpenSim) and ../shared/models/Rajagopal2016.osim

The subject the demo, the GUI's simulated lab and `instrument record --simulate` put on the dynamometer:
Rajagopal 2016's eleven leg muscles with DeGroote–Fregly curves (OpenSim's own, in a subprocess:
:mod:`benchmarks.opensim_passive`), parameters drawn around the generic ones (seed DEMO_SEED; the
hamstrings' slack lengths 8 % longer than the generic model's, whose hamstrings at hip 90° and full knee
extension would hold 650 N·m, far past what a relaxed subject shows and a dynamometer allows; rectus
femoris' 7 % longer, for the same reason at hip 15° and knee 90°), every
other muscle crossing the knee or the ankle, and OpenSim's CoordinateLimitForce at both ends of the
knee's and the ankle's range (capsule and ligaments). None of it is the estimator's model: the tables are
what a lab's subject would be to it, a model it was not built from. Written to
``drivers/simulation/data/demo_subject.json`` with the truth (for validation only).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.opensim_truth import draw_truth, generic_parameters, model_path, opensim  # noqa: E402 - after the repository root is on the path

DEMO_SEED = 77
HAMSTRINGS = ("bflh", "semimem", "semiten")
RECFEM_SLACK_FACTOR = 1.07
HAMSTRING_SLACK_FACTOR = 1.08
LIMIT_FORCES = {"knee": {"upper_deg": 80.0, "upper_stiffness_Nm_per_deg": 0.6, "lower_deg": 8.0,
                         "lower_stiffness_Nm_per_deg": 0.8, "transition_deg": 5.0},
                "ankle": {"upper_deg": 10.0, "upper_stiffness_Nm_per_deg": 0.5, "lower_deg": -25.0,
                          "lower_stiffness_Nm_per_deg": 0.4, "transition_deg": 5.0}}
STEP_DEG = 0.5
CONDITIONS = [("knee", "hip", h, (-5.0, 100.0)) for h in (90.0, 55.0, 15.0)] + \
             [("ankle", "knee", k, (-35.0, 20.0)) for k in (0.0, 45.0, 90.0)]


def main() -> int:
    truth = draw_truth(DEMO_SEED, generic_parameters())
    for m in HAMSTRINGS:
        truth[m]["tendon_slack_length_m"] *= HAMSTRING_SLACK_FACTOR
    truth["recfem"]["tendon_slack_length_m"] *= RECFEM_SLACK_FACTOR
    poses, grids = [], []
    for joint, other, fixed_deg, (lo, hi) in CONDITIONS:
        grid = np.arange(lo, hi + 1e-9, STEP_DEG)
        grids.append(grid)
        for a in grid:
            pose = {"hip": np.radians(90.0), "knee": 0.0, "ankle": 0.0}
            pose[other] = float(np.radians(fixed_deg))
            pose[joint] = float(np.radians(a))
            poses.append(pose)
    answer = opensim({"model": str(model_path()), "parameters": truth, "poses": poses, "limit_forces": LIMIT_FORCES,
                      "unmodelled_muscles": True})
    tables, i = [], 0
    for (joint, other, fixed_deg, _), grid in zip(CONDITIONS, grids):
        moments = answer["moments_nm"][joint][i:i + grid.size]
        i += grid.size
        tables.append({"joint": joint, f"{other}_deg": fixed_deg, "angle_deg": grid.round(3).tolist(),
                       "moment_nm": [round(float(v), 6) for v in moments]})
    facts = opensim({"what": "facts", "model": str(model_path())})
    out = {"source": "OpenSim (Rajagopal 2016, DeGrooteFregly2016Muscle), tools/make_demo_subject.py",
           "seed": DEMO_SEED, "shank_length_m": facts["shank_length_m"],
           "moment_sign": "toward positive angle (knee flexion, ankle dorsiflexion), N·m",
           "truth": truth, "limit_forces": LIMIT_FORCES, "unmodelled_muscles": True, "tables": tables}
    path = ROOT / "drivers" / "simulation" / "data" / "demo_subject.json"
    path.write_text(json.dumps(out, indent=1))
    for t in tables:
        m = np.array(t["moment_nm"])
        print(f"{t['joint']} {[k for k in t if k.endswith('_deg') and k != 'angle_deg'][0]}: "
              f"{m.min():.1f} .. {m.max():.1f} N·m")
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
