"""The orthosis's baseline adopts a steeper end where its data ask for one (analysis.diagnosis.baseline_choice).

Regression cases from the spent thirty-second family (development data: its one held-out run was on 637de28, before
this change): its bands stiffen exponentially in the squared invariant, far outside the quadratic spring, and on 637de28
its frictions and dampings went unnamed (2 and 1 of 11) because the spring's misfit, not the noise, was what they were
judged against. And the development generator's hinge stops on a linear spring are still stops (not an adopted end)."""

from __future__ import annotations

import numpy as np
import pytest

from analysis.diagnosis import Diagnosis, diagnose
from analysis.diagnosis.baseline_choice import adopt_steeper_ends
from analysis.diagnosis.causes import Prepared
from analysis.diagnosis.synthetic import make_trial
from benchmarks.diagnosis_family_b import FAMILIES, _trial


def _diagnosed(effects: tuple[str, ...], seed: int) -> tuple[Diagnosis, set[str]]:
    d = diagnose(_trial(FAMILIES["af"][0]("afo", effects, seed)))
    return d, ({d.cause} - {"none"}) | {a["cause"] for a in d.also}


@pytest.mark.parametrize(("effect", "seed"), [("coulomb_friction", 203), ("viscous_damping", 202)])
def test_a_friction_or_damping_beside_a_steeply_stiffening_band_is_named(effect: str, seed: int) -> None:
    """Named nothing on 637de28 (the band's misfit 2–30 × the noise); named alone now, the adopted end said."""
    d, named = _diagnosed((effect,), seed)
    assert named == {effect}
    assert any(n.startswith("the passive curve stiffens at its high end faster than the baseline's family") for n in d.notes)


@pytest.mark.parametrize("seed", [103, 108])
def test_a_clean_band_names_nothing_beside_its_adopted_end(seed: int) -> None:
    """A stop beside the adopted end was named in these two while the end was adopted without the stop's exclusion."""
    d, named = _diagnosed((), seed)
    assert named == set()


def test_a_hinge_stop_on_a_linear_spring_is_not_taken_into_the_baseline() -> None:
    """The AADS orthosis's hinge stop (the development generator, seed 5002): a kink fits better than any smooth end."""
    trial, hidden = make_trial("afo", "random", 5002)
    assert hidden.cause == "hard_stop"
    _, adopted = adopt_steeper_ends(Prepared.of(trial, 6.0), 5, 10.0, 4.0)
    assert adopted == []
    assert diagnose(trial).cause == "hard_stop"


def test_a_joint_keeps_its_own_baseline() -> None:
    """A joint's baseline has its published end terms and its stop tests the smooth rival: nothing is adopted."""
    g = FAMILIES["af"][0]("knee", (), 100)
    prep = Prepared.of(_trial(g))
    out, adopted = adopt_steeper_ends(prep, 5, 10.0, 4.0)
    assert adopted == [] and out is prep and np.array_equal(out.theta, prep.theta)
