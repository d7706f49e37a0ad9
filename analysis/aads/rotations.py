"""The best rotation of a marker cluster, every frame at once, without a per-frame SVD.

Horn's closed form (J. Opt. Soc. Am. A 4:629, 1987): with H = Σ w (x − x̄)(y − ȳ)ᵀ the weighted
cross-covariance of model markers x and measured markers y, the proper rotation R maximising
tr(R H) (the least-squares rigid fit, y ≈ R x) is the unit quaternion that is the eigenvector of
the largest eigenvalue of a symmetric, traceless 4×4 matrix N built from H. The eigenvalue is the
largest root of N's characteristic quartic, found by Newton's method from an upper bound (the
quartic is convex above its largest root, so the iteration descends onto it monotonically, as in
Theobald's QCP, Acta Cryst. A 61:478, 2005); the eigenvector is a column of the adjugate of
N − λI. Everything is elementwise arithmetic on arrays of frames: no LAPACK call per frame.
The result is the Kabsch/SVD rotation (the same maximiser; they agree to ~1e-13 in tests), and a
frame where the eigenvector is not well determined (markers on a line, λ not simple) is reported
so that the caller can solve it by SVD.
"""

from __future__ import annotations

import numpy as np

#: Newton steps at most (from the QCP bound it converges in 2–5 for marker fits)
MAX_NEWTON_STEPS = 50


def _det3(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray, e: np.ndarray, f: np.ndarray,
          g: np.ndarray, h: np.ndarray, i: np.ndarray) -> np.ndarray:
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


def horn_rotations(h: np.ndarray, upper: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Rotations (n, 3, 3) with y ≈ R x from cross-covariances ``h`` (n, 3, 3), and where they are determined.

    :param upper: an upper bound of the largest eigenvalue per frame, e.g. (Σw|x−x̄|² + Σw|y−ȳ|²)/2
        (makes Newton start close to the root); default √tr(N²).
    :returns: rotations, and a mask (n,) of frames whose rotation is determined (elsewhere: solve by SVD).
    """
    sxx, sxy, sxz = h[:, 0, 0], h[:, 0, 1], h[:, 0, 2]
    syx, syy, syz = h[:, 1, 0], h[:, 1, 1], h[:, 1, 2]
    szx, szy, szz = h[:, 2, 0], h[:, 2, 1], h[:, 2, 2]
    n = [[sxx + syy + szz, syz - szy, szx - sxz, sxy - syx],
         [syz - szy, sxx - syy - szz, sxy + syx, szx + sxz],
         [szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy],
         [sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz]]
    stacked = np.stack([np.stack(row, axis=-1) for row in n], axis=-2)  # (frames, 4, 4)
    n2 = np.matmul(stacked, stacked)
    p2 = np.einsum("nii->n", n2)                # tr N²
    p3 = np.einsum("nij,nij->n", n2, stacked)   # tr N³ (N symmetric)
    p4 = np.einsum("nij,nij->n", n2, n2)        # tr N⁴
    det = (p2 * p2 / 2.0 - p4) / 4.0  # Newton's identities (tr N = 0)
    half_p2, third_p3 = p2 / 2.0, p3 / 3.0
    lam = np.sqrt(np.maximum(p2, 0.0))
    if upper is not None:
        lam = np.minimum(lam, np.asarray(upper, dtype=float))
    for _ in range(MAX_NEWTON_STEPS):  # P(λ) = λ⁴ − (p2/2)λ² − (p3/3)λ + det N
        l2 = lam * lam
        value = (l2 - half_p2) * l2 - third_p3 * lam + det
        slope = 4.0 * l2 * lam - 2.0 * half_p2 * lam - third_p3
        step = np.divide(value, slope, out=np.zeros_like(value), where=slope > 0)
        lam = lam - step
        if np.all(np.abs(step) <= 1e-15 * np.maximum(np.abs(lam), 1e-300)):
            break
    a = [[n[i][j] - lam if i == j else n[i][j] for j in range(4)] for i in range(4)]
    others = [[r for r in range(4) if r != k] for k in range(4)]

    def cofactor(m: list[list[np.ndarray]], i: int, j: int) -> np.ndarray:
        r, c = others[i], others[j]
        return float((-1) ** (i + j)) * _det3(*(m[r[p]][c[q]] for p in range(3) for q in range(3)))

    # the adjugate's columns are all ∝ q; its diagonal ∝ q_k²: take the column of the largest
    diag = np.stack([cofactor(a, k, k) for k in range(4)], axis=1)
    pick = np.argmax(np.abs(diag), axis=1)
    q = np.zeros(h.shape[:1] + (4,))
    for j in range(4):
        sel = pick == j
        if not sel.any():
            continue
        whole = bool(sel.all())
        m = a if whole else [[entry[sel] for entry in row] for row in a]
        for i in range(4):
            column = diag[:, j] if i == j else cofactor(m, i, j)
            if whole:
                q[:, i] = column
            else:
                q[sel, i] = column[sel] if i == j else column
    norm = np.linalg.norm(q, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        q = q / norm[:, None]
    w, x, y, z = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    rot = np.empty(h.shape[:1] + (3, 3))
    rot[:, 0, 0] = w * w + x * x - y * y - z * z
    rot[:, 0, 1] = 2.0 * (x * y - w * z)
    rot[:, 0, 2] = 2.0 * (x * z + w * y)
    rot[:, 1, 0] = 2.0 * (x * y + w * z)
    rot[:, 1, 1] = w * w - x * x + y * y - z * z
    rot[:, 1, 2] = 2.0 * (y * z - w * x)
    rot[:, 2, 0] = 2.0 * (x * z - w * y)
    rot[:, 2, 1] = 2.0 * (y * z + w * x)
    rot[:, 2, 2] = w * w - x * x - y * y + z * z
    scale = np.maximum(np.abs(lam), 1e-300)
    determined = np.isfinite(rot).all(axis=(1, 2)) & (norm > 1e-10 * scale**3)
    return rot, determined


def kabsch_rotations(h: np.ndarray) -> np.ndarray:
    """The same rotations by SVD (Kabsch, with the reflection corrected): the reference, and the
    solver for frames :func:`horn_rotations` cannot determine."""
    u, _, vt = np.linalg.svd(h)
    v = vt.transpose(0, 2, 1)
    d = np.sign(np.linalg.det(np.matmul(v, u.transpose(0, 2, 1))))
    d[d == 0] = 1.0
    v[:, :, 2] *= d[:, None]
    return np.matmul(v, u.transpose(0, 2, 1))  # V diag(1, 1, d) Uᵀ


def best_rotations(h: np.ndarray, upper: np.ndarray | None = None) -> np.ndarray:
    """Rotations maximising tr(R H) for every frame: Horn's closed form, SVD where it is not determined."""
    rot, determined = horn_rotations(h, upper)
    if not determined.all():
        rot[~determined] = kabsch_rotations(h[~determined])
    return rot


__all__ = ["best_rotations", "horn_rotations", "kabsch_rotations"]
