"""The diagnosis benchmark's peer (PySINDy STLSQ over the same candidate terms) works as documented."""

from __future__ import annotations

import numpy as np

from benchmarks.diagnosis import as_trial, peer_is_right
from benchmarks.diagnosis_truth import generate
from benchmarks.sindy_peer import _compressed, _fit, diagnose_sparse, library


def test_stlsq_on_the_compressed_rows_equals_stlsq_on_all_rows() -> None:
    """(R, Qᵀy) stands in for (X, y): the same support and coefficients at every threshold."""
    x, y, _, _, n_base = library(as_trial(generate("afo", ("viscous_damping",), 3)))
    r, z = _compressed(x, y)
    for threshold in (0.0, 0.05, 0.3):
        np.testing.assert_allclose(_fit(r, z, n_base, threshold), _fit(x, y, n_base, threshold), rtol=1e-6, atol=1e-9)


def test_the_peer_names_a_large_effect_and_leaves_a_clean_trial_alone() -> None:
    """Effects at 10–12× the noise on the orthosis (the peer's easiest kind): damping and drift named
    at the cross-validated threshold; a clean trial named nothing under the one-standard-error rule."""
    for cause in ("viscous_damping", "sensor_drift"):
        g = generate("afo", (cause,), 11, noise_multiple=(10.0, 12.0))
        peer = diagnose_sparse(as_trial(g))
        assert cause in peer.named and cause in peer.named_1se
        assert peer.threshold_1se_nm >= peer.threshold_nm
    g = generate("afo", (), 12)
    peer = diagnose_sparse(as_trial(g))
    assert peer_is_right(peer.named_1se, peer.untestable, g), sorted(peer.named_1se)


def test_the_peer_answers_a_trial_shorter_than_its_folds_and_one_without_candidate_terms() -> None:
    """A trial shorter than its five 2 s blocks leaves folds empty: the peer cross-validates over the folds with
    samples; with no candidate term left (each reproduced by the baseline) it fits the baseline and names nothing."""
    import dataclasses

    g = generate("afo", ("viscous_damping",), 3)
    short = g.time_s < g.time_s[0] + 6.0
    trial = as_trial(dataclasses.replace(g, time_s=g.time_s[short], angle_rad=g.angle_rad[short],
                                         torque_nm=g.torque_nm[short]))
    peer = diagnose_sparse(trial)
    assert np.isfinite(peer.threshold_nm) and np.isfinite(peer.threshold_1se_nm)
    x, y, _, _, n_base = library(trial)
    base_only = _fit(x[:, :n_base], y, n_base, 0.1)
    np.testing.assert_allclose(base_only, np.linalg.lstsq(x[:, :n_base], y, rcond=None)[0])
