"""The simulated lab's subject: OpenSim's passive moments as committed tables (provenance and use)."""

from __future__ import annotations

import numpy as np
import pytest

from drivers.simulation.demo_subject import demo_subject, passive_table, shank_length_m


def test_every_protocol_condition_has_a_smooth_table_and_others_have_none() -> None:
    for joint, fixed in [("knee", h) for h in (90.0, 55.0, 15.0)] + [("ankle", k) for k in (0.0, 45.0, 90.0)]:
        table = passive_table(joint, fixed)
        assert table is not None
        deg, nm = np.array(table[0]), np.array(table[1])
        assert np.all(np.diff(deg) > 0) and np.all(np.isfinite(nm))
        lo, hi = (0.0, 90.0) if joint == "knee" else (-30.0, 15.0)
        assert deg[0] <= lo and deg[-1] >= hi  # the whole sweep is inside the table
        # passive tissue resists toward both ends: the moment falls with angle over the sweep
        inside = (deg >= lo) & (deg <= hi)
        assert nm[inside][0] > nm[inside][-1]
    assert passive_table("knee", 70.0) is None
    assert 0.35 < shank_length_m() < 0.45


@pytest.mark.timeout(300)
def test_the_tables_are_what_opensim_computes_for_the_recorded_truth() -> None:
    """Provenance: OpenSim (in a subprocess) at three poses of the committed truth gives the committed moments."""
    from benchmarks.opensim_truth import model_path, opensim
    from tests.opensim_reference import have_opensim

    if not have_opensim():
        pytest.skip("OpenSim (in the test extra) is the independent reference")
    record = demo_subject()
    poses, expected = [], []
    for table in record["tables"][::2]:
        joint = table["joint"]
        other, fixed = ("hip", table["hip_deg"]) if joint == "knee" else ("knee", table["knee_deg"])
        i = len(table["angle_deg"]) // 3
        pose = {"hip": np.radians(90.0), "knee": 0.0, "ankle": 0.0}
        pose[other] = float(np.radians(fixed))
        pose[joint] = float(np.radians(table["angle_deg"][i]))
        poses.append(pose)
        expected.append((joint, table["moment_nm"][i]))
    answer = opensim({"model": str(model_path()), "parameters": record["truth"], "poses": poses,
                      "limit_forces": record["limit_forces"], "unmodelled_muscles": record["unmodelled_muscles"]})
    for k, (joint, moment) in enumerate(expected):
        assert answer["moments_nm"][joint][k] == pytest.approx(moment, abs=1e-4)
