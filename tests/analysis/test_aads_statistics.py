"""Table 2.1 and the multi-factor ANOVA of Table 2.2 against statsmodels called directly."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import statsmodels.api as sm
from statsmodels.formula.api import ols

from analysis.aads.statistics import StiffnessRecord, anova_table, format_anova_table, format_spring_table, spring_table
from analysis.errors import FitError


def experiment(seed: int, operator_effect: float = 0.0, n_trials: int = 5) -> list[StiffnessRecord]:
    """3 springs × 4 operators × trials with noise; an operator effect drawn at random when asked."""
    rng = np.random.default_rng(seed)
    springs = {1: 0.68, 2: 1.07, 3: 1.73}
    ops = rng.normal(0.0, operator_effect, 4)
    return [StiffnessRecord(s, o + 1, t + 1, k * (1 + rng.normal(0, 0.02)) + ops[o], k)
            for s, k in springs.items() for o in range(4) for t in range(n_trials)]


def test_anova_matches_statsmodels_directly() -> None:
    recs = experiment(7, operator_effect=0.03)
    rows = {r.source: r for r in anova_table(recs)}
    frame = pd.DataFrame([{"spring": r.spring, "operator": r.operator, "trial": r.trial,
                           "k": r.stiffness_nm_per_deg} for r in recs])
    fit = ols("k ~ C(spring) * C(operator) + C(trial)", data=frame).fit()
    direct = sm.stats.anova_lm(fit, typ=2)  # balanced design: Type II = Type III
    for ours, theirs in (("Spring", "C(spring)"), ("Operator", "C(operator)"), ("Trial", "C(trial)"),
                         ("Spring × Operator", "C(spring):C(operator)"), ("Residual", "Residual")):
        assert rows[ours].ss == pytest.approx(direct.loc[theirs, "sum_sq"], rel=1e-9)
        assert rows[ours].df == direct.loc[theirs, "df"]
        if ours != "Residual":
            assert rows[ours].f == pytest.approx(direct.loc[theirs, "F"], rel=1e-9)
            assert rows[ours].p == pytest.approx(direct.loc[theirs, "PR(>F)"], rel=1e-7, abs=1e-300)
    assert (rows["Model"].df, rows["Residual"].df, rows["Total"].df) == (15, 44, 59)  # Table 2.2's degrees of freedom
    assert rows["Model"].ss + rows["Residual"].ss == pytest.approx(rows["Total"].ss, rel=1e-12)
    assert rows["Model"].f == pytest.approx(fit.fvalue, rel=1e-9)
    assert rows["Operator"].p < 0.01  # the drawn operator effect is found
    assert "Spring × Operator" in format_anova_table(anova_table(recs))


def test_anova_without_an_effect_does_not_find_one_and_refuses_a_degenerate_design() -> None:
    p_values = [{r.source: r.p for r in anova_table(experiment(seed))}["Operator"] for seed in range(20)]
    assert sum(p < 0.05 for p in p_values) <= 3  # 5 % false positives expected; 3 of 20 is p ≈ 0.08
    one_operator = [r for r in experiment(1) if r.operator == 1]
    with pytest.raises(FitError, match="two operators"):
        anova_table(one_operator)
    with pytest.raises(FitError, match="residual degrees of freedom"):
        # each spring × operator once: the interaction uses every degree of freedom
        anova_table([StiffnessRecord(s, o, 1 + (s + o) % 2, 1.0 + 0.1 * s + 0.01 * o, 1.0)
                     for s in (1, 2, 3) for o in (1, 2, 3, 4)])


def test_spring_table_mean_sd_and_percent_difference() -> None:
    recs = experiment(3)
    recs.append(StiffnessRecord(1, 1, 6, float("nan"), 0.68))  # a trial without a stiffness is not counted
    rows = spring_table(recs)
    k1 = np.array([r.stiffness_nm_per_deg for r in recs if r.spring == 1 and np.isfinite(r.stiffness_nm_per_deg)])
    assert rows[0].trials == 20 and rows[0].sop_mean_nm_per_deg == pytest.approx(k1.mean())
    assert rows[0].sop_sd_nm_per_deg == pytest.approx(k1.std(ddof=1))
    assert rows[0].percent_difference == pytest.approx(100 * (k1.mean() - 0.68) / 0.68)
    assert "Theoretical" in format_spring_table(rows)
