"""``estimate`` with a passive model plugged in: the one-muscle problem the Moco benchmark shares."""

from __future__ import annotations

import pytest

from benchmarks.pmp_moco import SLACK_TRUE_M, solve_ours, trial


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_single_muscle_slack_length_is_recovered(seed: int) -> None:
    res = solve_ours(trial(seed))  # 0.3 N·m torque noise, generic start 3.6 % short
    assert res["slack_m"] == pytest.approx(SLACK_TRUE_M, rel=1e-3)
