"""OpenSim's remembered answers (``benchmarks/data/opensim_answers``) are OpenSim's: asked again, OpenSim gives
the same moments; any change to what is asked, or to the child that asks, misses them."""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest

from tests.opensim_reference import have_opensim

pytestmark = pytest.mark.skipif(not have_opensim(), reason="OpenSim (test extra) made the answers")


def _request_of_a_test_subject(monkeypatch: pytest.MonkeyPatch) -> dict[str, Any]:
    """The request ``make_trials`` sends for seed 4's subject (tests/analysis/test_pmp_opensim_truth.py)."""
    import benchmarks.opensim_truth as truth_module
    from benchmarks.pmp_opensim import SHANK_M

    asked: list[dict[str, Any]] = []
    real = truth_module.remembered_opensim

    def spy(request: dict[str, Any]) -> dict[str, Any]:
        asked.append(request)
        return real(request)

    generic = truth_module.generic_parameters()
    monkeypatch.setattr(truth_module, "remembered_opensim", spy)
    truth_module.make_trials(truth_module.draw_truth(4, generic), 4, shank_m=SHANK_M)
    assert len(asked) == 1
    return asked[0]


@pytest.mark.timeout(300)
def test_a_remembered_answer_is_what_opensim_answers_again(monkeypatch: pytest.MonkeyPatch) -> None:
    from benchmarks.opensim_truth import ANSWERS, MODEL, answer_key, opensim

    if not MODEL.exists():
        pytest.skip(f"{MODEL} (the generic model, beside the repo) is not here")
    request = _request_of_a_test_subject(monkeypatch)
    path = ANSWERS / f"{answer_key(request)}.json"
    assert path.exists(), f"{path.name}: the suite's subject is not remembered (INSTRUMENT_OPENSIM_ANSWERS=write)"
    kept = json.loads(path.read_text())
    fresh = opensim(request)
    for joint in ("hip", "knee", "ankle"):
        np.testing.assert_allclose(kept["moments_nm"][joint], fresh["moments_nm"][joint], rtol=1e-9, atol=1e-9)
    assert kept["tendon_slack_length_m"] == pytest.approx(fresh["tendon_slack_length_m"], rel=1e-12)


def test_a_changed_request_model_or_child_misses_the_remembered_answers(tmp_path, monkeypatch) -> None:
    import benchmarks.opensim_truth as truth_module

    model = tmp_path / "model.osim"
    model.write_text("<OpenSimDocument/>")
    request = {"model": str(model), "parameters": {"soleus": {"tendon_slack_length_m": 0.26}}, "poses": [{"knee": 0.1}]}
    key = truth_module.answer_key(request)
    assert truth_module.answer_key(dict(request, model=str(model))) == key  # the path alone is not the content
    moved = tmp_path / "elsewhere.osim"
    moved.write_text(model.read_text())
    assert truth_module.answer_key(dict(request, model=str(moved))) == key
    assert truth_module.answer_key(dict(request, poses=[{"knee": 0.2}])) != key
    model.write_text("<OpenSimDocument><Model/></OpenSimDocument>")
    assert truth_module.answer_key(request) != key
    model.write_text("<OpenSimDocument/>")
    child = tmp_path / "opensim_passive.py"
    child.write_text("# another child\n")
    monkeypatch.setattr(truth_module, "__file__", str(tmp_path / "opensim_truth.py"))
    assert truth_module.answer_key(request) != key
