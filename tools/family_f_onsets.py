"""Where the diagnosis's stops on the sixth family's clean trials sit against that generator's passive onsets.

The sixth family's passive law k·x/(1 − (x/x_max)²) starts at its onset with slope k: a kink. This prints, for
the clean trials of ``python -m benchmarks diagnosis_family_f`` (seeds 100–119), the engine's named cause and stop
angle beside the onsets of the generator's own coefficients (the other joint's shift included) and k at each
end. Usage: ``python tools/family_f_onsets.py [ankle|knee ...]``.
"""

from __future__ import annotations

import sys
from typing import Any

import benchmarks.family_f_truth as family_f
from analysis.diagnosis import diagnose
from benchmarks.diagnosis_family_b import _trial


def onsets(kind: str, seed: int) -> tuple[Any, dict[str, float]]:
    """The clean trial of ``seed`` and its passive law's onsets (deg) and slopes at the onsets (N·m/°)."""
    drawn: dict[str, float] = {}
    original = family_f._coefficients

    def spy(rng: Any, k: str) -> dict[str, float]:
        drawn.update(original(rng, k))
        return drawn

    family_f._coefficients = spy
    try:
        trial = family_f.generate_f(kind, (), seed)
    finally:
        family_f._coefficients = original
    other = trial.fixed_deg["hip_flexion_deg"] if kind == "knee" else trial.fixed_deg["knee_flexion_deg"]
    on_lo = drawn["on_lo"] + drawn["shift_lo"] * other if kind == "knee" else drawn["on_lo"]
    on_hi = drawn["on_hi"] if kind == "knee" else drawn["on_hi"] + drawn["shift_lo"] * (other - 45.0)
    return trial, {"onset_low_deg": on_lo, "onset_high_deg": on_hi, "slope_low": drawn["k_lo"],
                   "slope_high": drawn["k_hi"]}


def main(kinds: list[str]) -> None:
    for kind in kinds:
        for seed in range(100, 120):
            trial, law = onsets(kind, seed)
            found = diagnose(_trial(trial))
            stop = found.parameters.get("stop_angle_deg")
            for also in found.also:
                stop = stop if stop is not None else also.get("parameters", also).get("stop_angle_deg")
            print(f"{kind} {seed}: {found.cause:<16} stop {'-' if stop is None else f'{stop:6.2f}°'}  onsets "
                  f"{law['onset_low_deg']:6.2f}° / {law['onset_high_deg']:6.2f}°  slopes {law['slope_low']:.3f} / "
                  f"{law['slope_high']:.3f} N·m/°", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:] or ["ankle", "knee"])
