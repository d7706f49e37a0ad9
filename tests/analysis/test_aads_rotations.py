"""Horn's closed-form rotations equal Kabsch's SVD rotations, frame by frame, whatever the cluster."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from analysis.aads.kinematics import fit_poses
from analysis.aads.rotations import best_rotations, horn_rotations, kabsch_rotations
from analysis.filtering import _butter_sos, _sosfiltfilt


def _rotations(seed: int, n: int) -> np.ndarray:
    q = np.random.default_rng(seed).normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack([np.stack([w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z], -1)], -2)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31), markers=st.integers(3, 6), noise_m=st.sampled_from([0.0, 1e-4, 2e-3, 2e-2]))
def test_horn_equals_kabsch_on_marker_clusters(seed: int, markers: int, noise_m: float) -> None:
    rng = np.random.default_rng(seed)
    model = rng.normal(0.0, 0.05, (markers, 3))
    truth = _rotations(seed, 64)
    measured = np.einsum("nij,mj->nmi", truth, model) + rng.normal(0.0, 0.3, (64, 1, 3)) \
        + rng.normal(0.0, noise_m, (64, markers, 3))
    xc = model - model.mean(axis=0)
    yc = measured - measured.mean(axis=1, keepdims=True)
    h = np.einsum("mi,nmj->nij", xc, yc)
    rot, determined = horn_rotations(h)
    assert determined.all()
    # the same rotation to 1e-7 (0.1 µrad): Horn's eigenvector carries round-off ∝ 1/eigengap, which a noisy
    # three-marker cluster makes small (seed 5998: 1.2e-8 apart); exact data agree to 1e-9 below
    np.testing.assert_allclose(rot, kabsch_rotations(h), atol=1e-7)
    if noise_m == 0.0:
        np.testing.assert_allclose(rot, truth, atol=1e-9)


def test_any_covariance_gets_the_best_proper_rotation() -> None:
    """Arbitrary H (reflections included): the same maximiser of tr(R H), a proper rotation."""
    h = np.random.default_rng(5).normal(size=(2000, 3, 3))
    rot = best_rotations(h)
    np.testing.assert_allclose(rot, kabsch_rotations(h), atol=1e-9)
    np.testing.assert_allclose(np.linalg.det(rot), 1.0, atol=1e-12)


def test_a_collinear_cluster_is_not_posed() -> None:
    model = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.2, 0.0, 0.0], [0.05, 0.04, 0.0]])
    measured = np.repeat(model[None], 5, axis=0)
    measured[2:, 3] = np.nan  # three markers on a line
    rot, origin, ok, _ = fit_poses(model, measured)
    assert ok.tolist() == [True, True, False, False, False]
    assert np.isnan(rot[2:]).all() and np.isnan(origin[2:]).all()
    np.testing.assert_allclose(rot[:2], np.repeat(np.eye(3)[None], 2, axis=0), atol=1e-12)


def test_the_filter_with_its_initial_conditions_designed_once_is_scipys() -> None:
    from scipy import signal

    sos, zi = _butter_sos(7.48, 100.0)
    x = np.random.default_rng(2).normal(size=(300, 4)).cumsum(axis=0)
    for padlen in (0, 5, 21):
        np.testing.assert_array_equal(_sosfiltfilt(sos, zi, x, padlen),
                                      signal.sosfiltfilt(sos, x, axis=0, padlen=padlen))
