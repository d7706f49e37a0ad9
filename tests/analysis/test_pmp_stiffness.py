"""Eqs 3.11–3.16: representative stiffnesses against the curves' own derivatives."""

from __future__ import annotations

import numpy as np
import pytest

from analysis.pmp.curves import passive_fiber_stiffness, tendon_stiffness
from analysis.pmp.geometry import load_paths
from analysis.pmp.stiffness import (
    achilles_stiffness_kn_per_m,
    dissertation_tendon_constant,
    muscle_stiffness_n_per_m,
    tendon_stiffness_n_per_m,
)


@pytest.mark.parametrize("strain", [0.033, 0.049, 0.08])
def test_tendon_stiffness_is_the_curves_mean_of_its_two_end_slopes(strain: float) -> None:
    f, ls = 3115.5, 0.3987
    ends = tendon_stiffness(np.array([1.0, 1.0 + strain]), strain)
    assert tendon_stiffness_n_per_m(f, ls, strain) == pytest.approx(f / ls * ends.mean(), rel=1e-12)
    # the dissertation's eq 3.13: 1.97 F / (ε L_s)
    assert dissertation_tendon_constant() == pytest.approx(1.97, abs=0.005)
    assert tendon_stiffness_n_per_m(f, ls, strain, "dissertation") == pytest.approx(1.971 * f / (strain * ls), rel=1e-3)


@pytest.mark.parametrize("strain", [0.3, 0.6, 0.9])
def test_muscle_stiffness_is_the_mean_of_the_passive_slopes_at_lmin_and_one_plus_strain(strain: float) -> None:
    f, lo = 1697.4, 0.0993
    ends = passive_fiber_stiffness(np.array([0.2, 1.0 + strain]), strain)
    # eq 3.15 takes the slope at l̃min as 0; the curve's is e^{−k·0.8/ε}-small, under 0.5 % of the mean here
    assert muscle_stiffness_n_per_m(f, lo, strain) == pytest.approx(f / lo * ends.mean(), rel=5e-3)
    assert muscle_stiffness_n_per_m(f, lo, strain) == pytest.approx(2.0 / strain * f / lo, rel=1e-12)


def test_achilles_is_the_calf_tendons_in_parallel() -> None:
    p = load_paths()
    tendons = {m: tendon_stiffness_n_per_m(p[m].max_isometric_force_n, p[m].tendon_slack_length_m, 0.049)
               for m in ("soleus", "gasmed", "gaslat")}
    k = achilles_stiffness_kn_per_m(tendons)
    assert k == pytest.approx(sum(tendons.values()) / 1e3)
    assert 100 < k < 1000  # generic calf tendons at 4.9 % strain: a few hundred kN/m, the range reported in vivo
    with pytest.raises(ValueError, match="gaslat"):
        achilles_stiffness_kn_per_m({"soleus": 1.0, "gasmed": 1.0})
