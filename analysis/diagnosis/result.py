"""What a diagnosis returns: the candidates it tried and the finding, as data and as the operator reads it."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from .causes import (
    CAUSES,
    Prepared,
)
from .fitting import CauseFit


@dataclass
class Candidate:
    """A cause as tried: its fit on the whole trial, held-out RMSE and criterion."""

    cause: str
    params: dict[str, float]
    rmse_nm: float
    heldout_rmse_nm: float
    bic: float
    delta_bic: float
    heldout_ratio: float
    accepted: bool
    note: str = ""

    def as_dict(self) -> dict[str, Any]:
        def clean(v: Any) -> Any:
            return None if isinstance(v, float) and not math.isfinite(v) else v
        return {k: (clean(v) if not isinstance(v, dict) else {a: clean(b) for a, b in v.items()})
                for k, v in self.__dict__.items()}


@dataclass
class Diagnosis:
    """The finding for one trial."""

    kind: str
    cause: str
    parameters: dict[str, float]
    baseline_rmse_nm: float
    extended_rmse_nm: float
    baseline_heldout_rmse_nm: float
    extended_heldout_rmse_nm: float
    heldout_rmse_ratio: float
    delta_bic: float
    effective_n: float
    candidates: list[Candidate]
    ambiguous_with: list[str] = field(default_factory=list)
    separate_by: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    fits: dict[str, CauseFit] = field(default_factory=dict, repr=False)
    prepared: Prepared | None = field(default=None, repr=False)
    also: list[dict[str, Any]] = field(default_factory=list)  # a second effect found with the first
    parameters_se: dict[str, float] = field(default_factory=dict)
    systematic: list[dict[str, Any]] = field(default_factory=list)  # where the baseline's residual is not noise
    rows_left_out: dict[str, int] = field(default_factory=dict)  # rows not diagnosed, by reason (see notes)

    def as_dict(self) -> dict[str, Any]:
        def clean(v: float) -> float | None:
            return v if math.isfinite(v) else None
        return {"kind": self.kind, "cause": self.cause, "parameters": self.parameters,
                "parameters_se": self.parameters_se, "baseline_systematic_regions": self.systematic,
                "baseline_rmse_Nm": clean(self.baseline_rmse_nm), "extended_rmse_Nm": clean(self.extended_rmse_nm),
                "baseline_heldout_rmse_Nm": clean(self.baseline_heldout_rmse_nm),
                "extended_heldout_rmse_Nm": clean(self.extended_heldout_rmse_nm),
                "heldout_rmse_ratio": clean(self.heldout_rmse_ratio), "delta_bic": clean(self.delta_bic),
                "effective_n": self.effective_n, "ambiguous_with": self.ambiguous_with,
                "separate_by": self.separate_by, "notes": self.notes, "also": self.also,
                "rows_left_out": self.rows_left_out,
                "candidates": [c.as_dict() for c in self.candidates]}

    def text(self) -> str:
        ambiguous = f" (cannot be told from {', '.join(self.ambiguous_with)})" if self.ambiguous_with else ""
        lines = [f"cause: {self.cause}" + ambiguous]
        for k, v in self.parameters.items():
            se = self.parameters_se.get(k)
            lines.append(f"  {k} = {v:.4g}" + (f" ± {se:.2g} (SE)" if se is not None else ""))
        if self.systematic:
            regions = "; ".join(f"{r['branch']} {r['angle_deg'][0]:.0f}–{r['angle_deg'][1]:.0f}° "
                                f"({r['mean_residual_Nm']:+.2f} N·m)" for r in self.systematic[:6])
            lines.append(f"  baseline systematically off at: {regions}" + (" …" if len(self.systematic) > 6 else ""))
        lines.append(f"  RMSE baseline {self.baseline_rmse_nm:.3f} N·m → extended {self.extended_rmse_nm:.3f} N·m; "
                     f"held-out {self.baseline_heldout_rmse_nm:.3f} → {self.extended_heldout_rmse_nm:.3f} "
                     f"(ratio {self.heldout_rmse_ratio:.2f}); ΔBIC {self.delta_bic:.1f} at n_eff {self.effective_n:.0f}")
        for a in self.also:
            lines.append(f"  and also: {a['cause']} " + ", ".join(f"{k} = {v:.4g}" for k, v in a["parameters"].items())
                         + f" (RMSE {a['rmse_Nm']:.3f} N·m, ΔBIC {a['delta_bic_vs_single']:.1f} against the first alone)")
        for s in self.separate_by:
            lines.append(f"  to separate them: {s}")
        for n in self.notes:
            lines.append(f"  note: {n}")
        lines.append(f"  {'candidate':<20}{'RMSE':>8}{'held-out':>10}{'ratio':>7}{'ΔBIC':>10}  accepted")
        for c in sorted(self.candidates, key=lambda c: c.bic):
            lines.append(f"  {c.cause:<20}{c.rmse_nm:>8.3f}{c.heldout_rmse_nm:>10.3f}{c.heldout_ratio:>7.2f}"
                         f"{c.delta_bic:>10.1f}  {'yes' if c.accepted else ''} {c.note}")
        return "\n".join(lines)


def magnitude(d: Diagnosis) -> float:
    """The fitted size of the named cause (the parameter the tests compare), NaN for ``none``."""
    key = CAUSES[d.cause].magnitude_key
    return float(d.parameters.get(key, float("nan"))) if key else float("nan")


__all__ = ["Candidate", "Diagnosis", "magnitude"]
