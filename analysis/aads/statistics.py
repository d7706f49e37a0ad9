"""Experiment statistics: per-spring stiffness against theory (Table 2.1) and the multi-factor ANOVA (Table 2.2).

The ANOVA is ordinary least squares with statsmodels: stiffness ~ spring + operator + trial +
spring × operator, all categorical with sum-to-zero contrasts, and Type III ("partial") sums of
squares, the layout of the dissertation's Table 2.2 (Model, each source, Residual, Total). For a
balanced design (every spring × operator × trial once) Type II and III coincide.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ..errors import FitError

FACTORS = ("spring", "operator", "trial")
FORMULA = "stiffness ~ C(spring, Sum) + C(operator, Sum) + C(trial, Sum) + C(spring, Sum):C(operator, Sum)"
SOURCES = {"C(spring, Sum)": "Spring", "C(operator, Sum)": "Operator", "C(trial, Sum)": "Trial",
           "C(spring, Sum):C(operator, Sum)": "Spring × Operator", "Residual": "Residual"}


@dataclass
class StiffnessRecord:
    """One trial's result as the statistics see it (stiffness in N·m/°)."""

    spring: int
    operator: int
    trial: int
    stiffness_nm_per_deg: float
    theoretical_nm_per_deg: float


@dataclass
class SpringRow:
    """A row of Table 2.1 (N·m/°; percent)."""

    spring: int
    trials: int
    theoretical_nm_per_deg: float
    sop_mean_nm_per_deg: float
    sop_sd_nm_per_deg: float
    percent_difference: float

    def as_dict(self) -> dict[str, float]:
        return asdict(self)


def spring_table(records: Sequence[StiffnessRecord]) -> list[SpringRow]:
    """Mean ± SD (sample SD) of the SOP stiffness per spring, the mean theoretical stiffness, and their % difference.

    Trials without a stiffness (NaN) are left out and not counted.
    """
    rows = []
    for spring in sorted({r.spring for r in records}):
        k = np.array([r.stiffness_nm_per_deg for r in records if r.spring == spring])
        th = np.array([r.theoretical_nm_per_deg for r in records if r.spring == spring])
        k, th = k[np.isfinite(k)], th[np.isfinite(th)]
        mean = float(k.mean()) if k.size else float("nan")
        sd = float(k.std(ddof=1)) if k.size > 1 else float("nan")
        theory = float(th.mean()) if th.size else float("nan")
        rows.append(SpringRow(spring, int(k.size), theory, mean, sd, 100.0 * (mean - theory) / theory))
    return rows


@dataclass
class AnovaRow:
    """A row of Table 2.2: partial SS, DF, MS, F and Prob > F (NaN where the layout leaves it empty)."""

    source: str
    ss: float
    df: int
    ms: float
    f: float
    p: float

    def as_dict(self) -> dict[str, float | str | int | None]:
        return {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in asdict(self).items()}


def anova_frame(records: Sequence[StiffnessRecord]) -> Any:
    """The records as the table statsmodels fits (finite stiffness only)."""
    import pandas as pd

    rows = [{"spring": r.spring, "operator": r.operator, "trial": r.trial, "stiffness": r.stiffness_nm_per_deg}
            for r in records if np.isfinite(r.stiffness_nm_per_deg)]
    return pd.DataFrame(rows, columns=["spring", "operator", "trial", "stiffness"])


def anova_table(records: Sequence[StiffnessRecord]) -> list[AnovaRow]:
    """Multi-factor ANOVA over spring, operator, trial and spring × operator (Table 2.2 layout).

    :raises FitError: fewer than two levels of a factor, or no residual degrees of freedom left.
    """
    import statsmodels.api as sm
    from statsmodels.formula.api import ols

    frame = anova_frame(records)
    for name in FACTORS:
        if frame[name].nunique() < 2:
            seen = [v.item() if hasattr(v, "item") else v for v in sorted(frame[name].unique())]
            raise FitError(f"the ANOVA needs at least two {name}s; the trials have {seen}")
    levels = {name: frame[name].nunique() for name in FACTORS}
    terms = 1 + sum(v - 1 for v in levels.values()) + (levels["spring"] - 1) * (levels["operator"] - 1)
    if len(frame) - terms < 1:
        raise FitError(f"{len(frame)} trials leave no residual degrees of freedom for the ANOVA ({terms} terms)")
    fit = ols(FORMULA, data=frame).fit()
    table = sm.stats.anova_lm(fit, typ=3)
    rows = [AnovaRow("Model", float(fit.ess), int(fit.df_model), float(fit.ess / fit.df_model), float(fit.fvalue),
                     float(fit.f_pvalue))]
    for key, label in SOURCES.items():
        r = table.loc[key]
        df = int(r["df"])
        rows.append(AnovaRow(label, float(r["sum_sq"]), df, float(r["sum_sq"] / df),
                             float(r["F"]) if key != "Residual" else float("nan"),
                             float(r["PR(>F)"]) if key != "Residual" else float("nan")))
    n = len(frame)
    rows.append(AnovaRow("Total", float(fit.centered_tss), n - 1, float(fit.centered_tss / (n - 1)), float("nan"),
                         float("nan")))
    return rows


def format_spring_table(rows: Sequence[SpringRow]) -> str:
    """Table 2.1 as text."""
    out = [f"{'Spring':<7}{'Theoretical (Nm/°)':>20}{'SOP (Nm/°)':>18}{'Difference (%)':>16}{'Trials':>8}"]
    for r in rows:
        out.append(f"{r.spring:<7}{r.theoretical_nm_per_deg:>20.3f}{r.sop_mean_nm_per_deg:>11.3f} ± "
                   f"{r.sop_sd_nm_per_deg:<5.3f}{r.percent_difference:>15.1f}{r.trials:>8}")
    return "\n".join(out)


def format_anova_table(rows: Sequence[AnovaRow]) -> str:
    """Table 2.2 as text."""
    def num(v: float, fmt: str) -> str:
        return "" if math.isnan(v) else format(v, fmt)

    out = [f"{'Source':<19}{'Partial SS':>12}{'DF':>5}{'MS':>12}{'F':>11}{'Prob>F':>9}"]
    for r in rows:
        out.append(f"{r.source:<19}{r.ss:>12.4g}{r.df:>5}{r.ms:>12.4g}{num(r.f, '.4g'):>11}{num(r.p, '.3f'):>9}")
    return "\n".join(out)
