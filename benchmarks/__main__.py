"""Run one benchmark by name: ``python -m benchmarks drivers --quick --json out.json``."""

from __future__ import annotations

import argparse
import importlib
import json
import sys
from pathlib import Path

BENCHMARKS = {"drivers": "benchmarks.drivers", "pmp_opensim": "benchmarks.pmp_opensim", "recording": "benchmarks.recording",
              "aads": "benchmarks.aads",
              "diagnosis": "benchmarks.diagnosis", "pmp": "benchmarks.pmp",
              "relaxation": "benchmarks.relaxation", "gui": "benchmarks.gui", "safety": "benchmarks.safety",
              "cohort": "benchmarks.cohort", "cohort_diagnosed": "benchmarks.cohort_diagnosed",
              "diagnosis_wide": "benchmarks.diagnosis_wide",
              "pmp_model_diagnosis": "benchmarks.pmp_model_diagnosis",
              "afo_model_diagnosis": "benchmarks.afo_model_diagnosis",
              "diagnosis_stops": "benchmarks.diagnosis_stops", "diagnosis_input": "benchmarks.diagnosis_input",
              "diagnosis_family_b": "benchmarks.diagnosis_family_b",
              "diagnosis_family_c": "benchmarks.diagnosis_family_c",
              "diagnosis_family_d": "benchmarks.diagnosis_family_d",
              "diagnosis_family_e": "benchmarks.diagnosis_family_e",
              "diagnosis_family_f": "benchmarks.diagnosis_family_f",
              "diagnosis_family_g": "benchmarks.diagnosis_family_g",
              "diagnosis_family_h": "benchmarks.diagnosis_family_h",
              "diagnosis_family_i": "benchmarks.diagnosis_family_i",
              "diagnosis_family_j": "benchmarks.diagnosis_family_j",
              "diagnosis_family_k": "benchmarks.diagnosis_family_k",
              "diagnosis_family_l": "benchmarks.diagnosis_family_l",
              "diagnosis_family_m": "benchmarks.diagnosis_family_m",
              "diagnosis_family_n": "benchmarks.diagnosis_family_n",
              "diagnosis_family_o": "benchmarks.diagnosis_family_o",
              "diagnosis_family_p": "benchmarks.diagnosis_family_p",
              "diagnosis_family_q": "benchmarks.diagnosis_family_q",
              "diagnosis_family_r": "benchmarks.diagnosis_family_r",
              "diagnosis_family_s": "benchmarks.diagnosis_family_s",
              "diagnosis_family_t": "benchmarks.diagnosis_family_t",
              "diagnosis_family_u": "benchmarks.diagnosis_family_u",
              "diagnosis_family_v": "benchmarks.diagnosis_family_v",
              "diagnosis_family_w": "benchmarks.diagnosis_family_w",
              "diagnosis_family_x": "benchmarks.diagnosis_family_x",
              "diagnosis_family_y": "benchmarks.diagnosis_family_y",
              "diagnosis_family_z": "benchmarks.diagnosis_family_z",
              "diagnosis_family_aa": "benchmarks.diagnosis_family_aa",
             "diagnosis_family_ab": "benchmarks.diagnosis_family_ab",
             "diagnosis_family_ac": "benchmarks.diagnosis_family_ac",
             "diagnosis_family_ad": "benchmarks.diagnosis_family_ad",
             "diagnosis_family_ae": "benchmarks.diagnosis_family_ae",
             "diagnosis_family_af": "benchmarks.diagnosis_family_af",
             "diagnosis_family_ag": "benchmarks.diagnosis_family_ag",
             "diagnosis_family_ah": "benchmarks.diagnosis_family_ah",
              "sindy_peer_families": "benchmarks.sindy_peer_families",
              "pmp_realistic": "benchmarks.pmp_realistic", "lsl": "benchmarks.lsl",
              "pmp_speed": "benchmarks.pmp_speed", "pmp_segment_scales": "benchmarks.pmp_segment_scales"}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks")
    parser.add_argument("name", choices=sorted(BENCHMARKS))
    parser.add_argument("--quick", action="store_true", help="short run (for CI smoke checks)")
    parser.add_argument("--json", type=Path, help="write the results here")
    args = parser.parse_args(argv)
    module = importlib.import_module(BENCHMARKS[args.name])
    result = module.run(quick=args.quick)
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(result, indent=2))
        print(f"wrote {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
