"""The fifth to thirtieth generator families' shared contract: each cause hidden with its truth in a recording with a
lab's damage, and a seed making the same trial. Each family's own physics is tested in its own module."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from benchmarks.family_aa_truth import generate_aa
from benchmarks.family_ab_truth import generate_ab
from benchmarks.family_ac_truth import generate_ac
from benchmarks.family_ad_truth import generate_ad
from benchmarks.family_ae_truth import generate_ae
from benchmarks.family_af_truth import generate_af
from benchmarks.family_ag_truth import generate_ag
from benchmarks.family_ah_truth import generate_ah
from benchmarks.family_b_truth import EFFECTS, MAGNITUDE_KEY
from benchmarks.family_e_truth import generate_e
from benchmarks.family_f_truth import generate_f
from benchmarks.family_g_truth import generate_g
from benchmarks.family_h_truth import generate_h
from benchmarks.family_i_truth import generate_i
from benchmarks.family_j_truth import generate_j
from benchmarks.family_k_truth import generate_k
from benchmarks.family_l_truth import generate_l
from benchmarks.family_m_truth import generate_m
from benchmarks.family_n_truth import generate_n
from benchmarks.family_o_truth import generate_o
from benchmarks.family_p_truth import generate_p
from benchmarks.family_q_truth import generate_q
from benchmarks.family_r_truth import generate_r
from benchmarks.family_s_truth import generate_s
from benchmarks.family_t_truth import generate_t
from benchmarks.family_u_truth import generate_u
from benchmarks.family_v_truth import generate_v
from benchmarks.family_w_truth import generate_w
from benchmarks.family_x_truth import generate_x
from benchmarks.family_y_truth import generate_y
from benchmarks.family_z_truth import generate_z

GENERATORS = {"e": generate_e, "f": generate_f, "g": generate_g, "h": generate_h, "i": generate_i, "j": generate_j,
              "k": generate_k, "l": generate_l, "m": generate_m, "n": generate_n,
              "o": generate_o, "p": generate_p, "q": generate_q, "r": generate_r, "s": generate_s, "t": generate_t,
              "u": generate_u, "v": generate_v, "w": generate_w, "x": generate_x,
              "y": generate_y, "z": generate_z, "aa": generate_aa, "ab": generate_ab,
              "ac": generate_ac, "ad": generate_ad, "ae": generate_ae, "af": generate_af,
              "ag": generate_ag, "ah": generate_ah}


@pytest.mark.parametrize("family", list(GENERATORS))
@pytest.mark.parametrize("kind", list(EFFECTS))
def test_each_cause_is_hidden_with_its_truth_in_a_recording_with_a_labs_damage(family: str, kind: str) -> None:
    generate: Callable[..., Any] = GENERATORS[family]
    for cause in EFFECTS[kind]:
        g = generate(kind, (cause,), 11)
        assert set(g.effects) == {cause}
        truth = g.effects[cause]
        assert (truth is None) == (MAGNITUDE_KEY[cause] is None)
        assert truth is None or truth > 0
        t = g.time_s[np.isfinite(g.time_s)]
        assert np.all(np.diff(t) > 0) and (~np.isfinite(g.time_s)).sum() < 0.01 * g.time_s.size
    assert np.isfinite(generate(kind, (), 11).torque_nm).mean() > 0.99


@pytest.mark.parametrize("family", list(GENERATORS))
def test_a_seed_makes_the_same_trial(family: str) -> None:
    generate = GENERATORS[family]
    a, b = generate("knee", ("inertia", "time_delay"), 3), generate("knee", ("inertia", "time_delay"), 3)
    assert np.array_equal(a.torque_nm, b.torque_nm, equal_nan=True) and a.effects == b.effects
