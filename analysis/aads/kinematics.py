"""Segment poses and the hinge angle of the AADS jig from marker trajectories (SI; degrees at the edge).

Per frame, each segment's pose is the least-squares rigid fit (Kabsch/Söderkvist; solved in Horn's
closed form for all frames at once, :mod:`analysis.aads.rotations`) of its
model markers to the measured ones that are present; a segment needs 3 markers that are not on a
line. Then:

1. in frames with a marker missing, a fit on the markers present fills it from the segment's pose;
2. frames where a segment cannot be fit are bridged by linear interpolation when the gap is at
   most ``max_gap_s``; longer gaps stay out (the frames are flagged, never invented);
3. the filled trajectories are low-pass filtered (``analysis.filtering.lowpass``) and the poses
   fit: these are the poses whose derivatives give velocities and accelerations, and the
   distances of the measured markers from them are the residuals that judge the data (the
   dissertation accepts a maximum < 2 cm and an RMS < 1 cm);
4. the hinge angle is the twist of the shank relative to the foot about the hinge axis
   (swing–twist decomposition), positive in dorsiflexion.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..filtering import derivative, derivative_together, finite_runs, lowpass_together
from ..motion import MotionTrial
from .model import JigModel, Segment
from .rotations import best_rotations

#: markers of a segment must spread at least this far (RMS distance from their line, m) to fix a pose
MIN_SPREAD_M = 0.005


def _covariance(model_m: np.ndarray, measured_m: np.ndarray) -> tuple[np.ndarray, ...]:
    """Centroids (frames, 3) of the model and measured markers present, their cross-covariance H
    (frames, 3, 3) = Σ w (x − x̄)(y − ȳ)ᵀ, and the bound (Σw|x−x̄|² + Σw|y−ȳ|²)/2 on Horn's eigenvalue."""
    present = np.all(np.isfinite(measured_m), axis=2)
    y = np.where(present[..., None], measured_m, 0.0)
    complete = present.all(axis=1)
    if np.array_equal(complete, present.any(axis=1)):  # every frame has all its markers or none (filtered data)
        xc0 = model_m - model_m.mean(axis=0)
        cy = y.mean(axis=1)
        yc = y - cy[:, None, :]
        h = np.matmul(xc0.T[None], yc)
        spread = 0.5 * (float(np.sum(xc0 * xc0)) + np.einsum("nmk,nmk->n", yc, yc))
        return present, np.broadcast_to(model_m.mean(axis=0), cy.shape), cy, h, spread
    w = present.astype(float)
    safe = np.maximum(w.sum(axis=1), 1.0)
    cx = (w @ model_m) / safe[:, None]
    cy = np.matmul(w[:, None, :], y)[:, 0, :] / safe[:, None]
    xc = model_m[None, :, :] - cx[:, None, :]
    yc = y - cy[:, None, :]
    h = np.matmul((w[..., None] * xc).transpose(0, 2, 1), yc)
    spread = 0.5 * (np.einsum("nm,nmk,nmk->n", w, xc, xc) + np.einsum("nm,nmk,nmk->n", w, yc, yc))
    return present, cx, cy, h, spread


def fit_poses_together(clusters: list[tuple[np.ndarray, np.ndarray, np.ndarray | None]]) -> list[
        tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """:func:`fit_poses` of several clusters (model markers, measured markers, poseable frames or None),
    their rotations solved in one batch; (rotation, origin, fit-ok) per cluster."""
    parts = [_covariance(model_m, measured_m) for model_m, measured_m, _ in clusters]
    rots = best_rotations(np.concatenate([p[3] for p in parts]), np.concatenate([p[4] for p in parts]))
    out, at = [], 0
    for (model_m, _, known), (present, cx, cy, _, _) in zip(clusters, parts):
        rot = rots[at:at + len(cx)]
        at += len(cx)
        ok = poseable(model_m, present) if known is None else known
        origin = cy - np.matmul(rot, cx[:, :, None])[:, :, 0]
        rot[~ok] = np.nan
        origin[~ok] = np.nan
        out.append((rot, origin, ok))
    return out


def fit_poses(model_m: np.ndarray, measured_m: np.ndarray, residuals: bool = True,
              poseable_frames: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]:
    """Least-squares rigid poses of a marker cluster, every frame at once (Horn's closed form,
    :func:`analysis.aads.rotations.best_rotations`; the same rotations as Kabsch's SVD).

    :param model_m: marker coordinates in the segment frame (markers, 3), m.
    :param measured_m: measured positions (frames, markers, 3) in the lab, m; NaN where missing.
    :param poseable_frames: the frames whose present markers can fix a pose, when the caller knows
        them (default: :func:`poseable`).
    :returns: rotation (frames, 3, 3) segment→lab, origin (frames, 3) m, fit-ok (frames,) and the
        distance of each measured marker from its fitted position (frames, markers) m (NaN if missing;
        ``None`` when ``residuals`` is False).
    """
    ((rot, origin, ok),) = fit_poses_together([(model_m, measured_m, poseable_frames)])
    if not residuals:
        return rot, origin, ok, None
    fitted = np.matmul(model_m[None], rot.transpose(0, 2, 1)) + origin[:, None, :]
    resid = np.linalg.norm(fitted - measured_m, axis=2)
    return rot, origin, ok, resid


@functools.lru_cache(maxsize=256)
def _pattern_poseable(model_bytes: bytes, markers: int, code: int) -> bool:
    """Whether the markers of ``code`` (a bit per marker) of a cluster can fix a pose (asked once per pattern)."""
    model_m = np.frombuffer(model_bytes).reshape(markers, 3)
    pts = model_m[(code >> np.arange(markers)) & 1 == 1]
    if pts.shape[0] < 3:
        return False
    lam = np.linalg.eigvalsh(np.cov(pts.T, bias=True))
    return bool(np.sqrt(max(lam[1], 0.0)) >= MIN_SPREAD_M)


def poseable(model_m: np.ndarray, present: np.ndarray) -> np.ndarray:
    """Frames (n,) whose present markers (n, markers) can fix a pose: 3 or more, not on one line."""
    codes = present.astype(np.int64) @ (1 << np.arange(present.shape[1], dtype=np.int64))
    model_bytes = np.ascontiguousarray(model_m, dtype=float).tobytes()
    unique, inverse = np.unique(codes, return_inverse=True)
    ok = np.array([_pattern_poseable(model_bytes, present.shape[1], int(c)) for c in unique], dtype=bool)
    return ok[inverse.reshape(-1)]


def hinge_twist_rad(rot_foot: np.ndarray, rot_shank: np.ndarray, axis_in_foot: np.ndarray) -> np.ndarray:
    """Twist angle (rad) of the shank relative to the foot about the hinge axis (swing–twist).

    With the relative rotation R as a unit quaternion (w, q), the twist about the unit axis a is
    2·atan2(q·a, w); multiplying both by 4w gives 2·atan2(a·v, 1 + tr R), v = (R₂₁ − R₁₂,
    R₀₂ − R₂₀, R₁₀ − R₀₁), valid for relative rotations below 180°.
    """
    rel = np.matmul(rot_foot.transpose(0, 2, 1), rot_shank)  # shank in foot coordinates
    v = np.stack([rel[:, 2, 1] - rel[:, 1, 2], rel[:, 0, 2] - rel[:, 2, 0], rel[:, 1, 0] - rel[:, 0, 1]], axis=1)
    return 2.0 * np.arctan2(v @ axis_in_foot, 1.0 + np.trace(rel, axis1=1, axis2=2))


def _bridge_gaps(x: np.ndarray, valid: np.ndarray, max_gap: int) -> np.ndarray:
    """Linear interpolation of ``x`` (n, ...) over runs of invalid frames no longer than ``max_gap`` frames."""
    x = x.copy()
    for a, b in finite_runs(~valid):
        if a == 0 or b == valid.size or b - a > max_gap:
            continue
        frac = (np.arange(a, b) - (a - 1)) / (b - (a - 1))
        x[a:b] = x[a - 1] + frac.reshape(-1, *([1] * (x.ndim - 1))) * (x[b] - x[a - 1])
    return x


def _vee(skew: np.ndarray) -> np.ndarray:
    return 0.5 * np.stack([skew[:, 2, 1] - skew[:, 1, 2], skew[:, 0, 2] - skew[:, 2, 0],
                           skew[:, 1, 0] - skew[:, 0, 1]], axis=1)


@dataclass
class SegmentMotion:
    """A segment's filtered pose and its derivatives in the lab frame (SI)."""

    name: str
    rotation: np.ndarray       # (n, 3, 3) segment → lab
    origin_m: np.ndarray       # (n, 3)
    omega_rad_s: np.ndarray    # (n, 3) angular velocity
    alpha_rad_s2: np.ndarray   # (n, 3) angular acceleration
    com_m: np.ndarray          # (n, 3) centre of mass
    com_acc_m_s2: np.ndarray   # (n, 3)

    def point_m(self, local_m: np.ndarray) -> np.ndarray:
        """Lab position (n, 3) of a point fixed in the segment."""
        return self.rotation @ np.asarray(local_m, dtype=float) + self.origin_m


@dataclass
class MarkerQuality:
    """Marker residuals (m) from the fitted segments against the dissertation's acceptance (max < 2 cm, RMS < 1 cm)."""

    rms_m: float
    max_m: float
    per_marker_rms_m: dict[str, float]
    frames_over_max: int
    accepted: bool


@dataclass
class AadsKinematics:
    """Kinematics of one trial at the marker frames."""

    time_s: np.ndarray
    rate_hz: float
    foot: SegmentMotion
    shank: SegmentMotion
    hinge_angle_deg: np.ndarray        # (n,) dorsiflexion positive, filtered
    hinge_velocity_deg_s: np.ndarray   # (n,)
    valid: np.ndarray                  # (n,) both segments posed (measured or bridged) and filtered
    unfit_frames: int                  # frames where a segment could not be fit from its markers
    bridged_frames: int                # of those, frames bridged by interpolation
    quality: MarkerQuality
    hinge_gap_m: np.ndarray            # (n,) distance of the hinge point as the foot and the shank place it
    markers_m: dict[str, np.ndarray]   # filtered trajectories (n, 3) of the markers the analysis uses
    flags: list[str] = field(default_factory=list)


def _segment_columns(trial: MotionTrial, seg: Segment, flags: list[str]) -> tuple[np.ndarray, np.ndarray]:
    have = [k for k in seg.marker_labels if k in trial.marker_labels]
    missing = [k for k in seg.marker_labels if k not in trial.marker_labels]
    if len(have) < 3:
        raise InputError(f"{trial.source or 'trial'}: the {seg.name} needs 3 of its markers {seg.marker_labels}; "
                         f"missing {missing} (the file has {trial.marker_labels})")
    if missing:
        flags.append(f"{seg.name} markers {missing} are not in the file; posed from {have}")
    model = np.array([seg.markers_m[k] for k in have])
    meas = np.stack([trial.marker(k) for k in have], axis=1)
    return model, meas


def _motions(segments: list[Segment], poses: list[tuple[np.ndarray, np.ndarray]], dt: float) -> list[SegmentMotion]:
    """Angular velocity and acceleration, centre-of-mass position and acceleration of each segment
    from its filtered poses (the derivatives of all segments taken together)."""
    rdots = derivative_together([rot for rot, _ in poses], dt)
    omegas = [_vee(np.matmul(rdot, rot.transpose(0, 2, 1))) for rdot, (rot, _) in zip(rdots, poses)]
    coms = [rot @ seg.com_m + origin for seg, (rot, origin) in zip(segments, poses)]
    firsts = derivative_together(omegas + coms, dt)
    alphas, com_vels = firsts[:len(segments)], firsts[len(segments):]
    com_accs = derivative_together(com_vels, dt)
    return [SegmentMotion(seg.name, rot, origin, omega, alpha, com, acc)
            for seg, (rot, origin), omega, alpha, com, acc in zip(segments, poses, omegas, alphas, coms, com_accs)]


def aads_kinematics(trial: MotionTrial, model: JigModel) -> AadsKinematics:
    """Poses, hinge angle and marker quality of one trial.

    :raises InputError: a segment has fewer than 3 of its markers in the file, the marker clock is
        not uniform, or no frame can be fit.
    """
    t = np.asarray(trial.marker_time_s, dtype=float)
    if t.size < 20:
        raise InputError(f"{trial.source or 'trial'}: {t.size} marker frames; the analysis needs at least 20")
    steps = np.diff(t)
    dt = float(np.median(steps))
    if not dt > 0 or np.max(np.abs(steps - dt)) > 0.01 * dt:
        raise InputError(f"{trial.source or 'trial'}: marker frames are not uniformly spaced")
    rate = 1.0 / dt
    flags: list[str] = []
    max_gap = int(round(model.max_gap_s * rate))
    filtered: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    raw_ok_all = np.ones(t.size, dtype=bool)
    bridged_all = np.ones(t.size, dtype=bool)
    residuals, labels = [], []
    segments = (model.foot, model.shank)
    columns, bridged_of = [], []
    for seg in segments:
        x_model, meas = _segment_columns(trial, seg, flags)
        present = np.all(np.isfinite(meas), axis=2)
        ok = poseable(x_model, present)
        filled = meas.copy()
        partial = np.flatnonzero(ok & ~present.all(axis=1))
        if partial.size:  # fill a missing marker from its segment's pose on the markers present
            rot, origin, _, _ = fit_poses(x_model, meas[partial], residuals=False, poseable_frames=ok[partial])
            fill = np.matmul(x_model[None], rot.transpose(0, 2, 1)) + origin[:, None, :]
            filled[partial] = np.where(present[partial, :, None], meas[partial], fill)
        filled[~ok] = np.nan
        bridged = _bridge_gaps(filled, ok, max_gap)
        raw_ok_all &= ok
        bridged_all &= np.all(np.isfinite(bridged), axis=(1, 2))
        columns.append((x_model, meas, present))
        bridged_of.append(bridged)
    # the spring hooks' markers (for the theory) are bridged the same way and filtered with the segments
    hook_names = [n for n in (model.spring_top_marker, model.spring_bottom_marker) if n in trial.marker_labels]
    hooks_raw = [trial.marker(n) for n in hook_names]
    hooks_bridged = [_bridge_gaps(raw, np.all(np.isfinite(raw), axis=1), max_gap) for raw in hooks_raw]
    smoothed = lowpass_together(bridged_of + hooks_bridged, rate, model.filter_cutoff_hz)
    # a filtered frame has every marker or none: poseable where it has them (the whole cluster is)
    clusters = [(x_model, smooth, poseable(x_model, np.ones((1, x_model.shape[0]), dtype=bool))[0]
                 & np.all(np.isfinite(smooth), axis=(1, 2))) for (x_model, _, _), smooth in zip(columns, smoothed)]
    for seg, (x_model, meas, present), (rot_f, origin_f, _) in zip(segments, columns, fit_poses_together(clusters)):
        # residual of each measured marker from the fitted (filtered) rigid segment
        fitted = np.matmul(x_model[None], rot_f.transpose(0, 2, 1)) + origin_f[:, None, :]
        residuals.append(np.where(present, np.linalg.norm(fitted - meas, axis=2), np.nan))
        labels += [k for k in seg.marker_labels if k in trial.marker_labels]
        filtered[seg.name] = (rot_f, origin_f)
    hooks = dict(zip(hook_names, smoothed[len(segments):]))
    if not bridged_all.any():
        raise InputError(f"{trial.source or 'trial'}: no frame has enough markers to pose both segments")
    res = np.concatenate(residuals, axis=1)
    with np.errstate(invalid="ignore"):
        rms = float(np.sqrt(np.nanmean(res**2))) if np.isfinite(res).any() else float("nan")
        mx = float(np.nanmax(res)) if np.isfinite(res).any() else float("nan")
        per = {k: float(np.sqrt(np.nanmean(res[:, i] ** 2))) if np.isfinite(res[:, i]).any() else float("nan")
               for i, k in enumerate(labels)}
        over = int(np.sum(np.nanmax(np.where(np.isfinite(res), res, -1.0), axis=1) > model.max_marker_error_m))
    quality = MarkerQuality(rms, mx, per, over, bool(mx < model.max_marker_error_m and rms < model.rms_marker_error_m))
    if not quality.accepted:
        flags.append(f"marker fit outside acceptance: max {mx * 1e3:.1f} mm (limit {model.max_marker_error_m * 1e3:.0f}), "
                     f"RMS {rms * 1e3:.1f} mm (limit {model.rms_marker_error_m * 1e3:.0f})")
    foot, shank = _motions([model.foot, model.shank], [filtered["foot"], filtered["shank"]], dt)
    angle = np.rad2deg(hinge_twist_rad(foot.rotation, shank.rotation, model.hinge_axis_in_foot))
    valid = (np.isfinite(angle) & np.all(np.isfinite(foot.com_acc_m_s2), axis=1)
             & np.all(np.isfinite(shank.com_acc_m_s2), axis=1) & np.all(np.isfinite(shank.alpha_rad_s2), axis=1)
             & np.all(np.isfinite(foot.alpha_rad_s2), axis=1))
    unfit = int(np.sum(~raw_ok_all))
    if unfit:
        flags.append(f"{unfit} frames could not be fit from their markers; {int(np.sum(bridged_all & ~raw_ok_all))} "
                     f"bridged (gaps ≤ {model.max_gap_s * 1e3:.0f} ms), {int(np.sum(~valid))} left out")
    gap = np.linalg.norm(foot.point_m(model.hinge_in_foot_m) - shank.point_m(model.hinge_in_shank_m), axis=1)
    return AadsKinematics(t, rate, foot, shank, angle, derivative(angle, dt), valid, unfit,
                          int(np.sum(bridged_all & ~raw_ok_all)), quality, gap, hooks, flags)
