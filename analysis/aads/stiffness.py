"""AFO stiffness: linear torque–angle fits in the fit window, hysteresis, the stop; theory from the spring (eqs 2.1–2.9).

Angles are in degrees here (the stiffness is reported in N·m/°, the unit of the dissertation);
torques in N·m, energies in J.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np

from ..errors import FitError
from ..fit import FitStatus
from .model import BRANCHES

#: a branch fit needs this many frames and this fraction of the window's angle span
MIN_FRAMES = 10
MIN_SPAN_FRACTION = 0.5


@dataclass(frozen=True)
class LineFit:
    """Torque = slope · angle + intercept over ``frames`` frames spanning ``span_deg``.

    A closed-form least-squares line, with SciPy's result names beside its own: ``x`` is
    (slope N·m/°, intercept N·m), ``success`` always (a line that cannot be fitted raises
    :class:`~analysis.errors.FitError` with the reason instead), ``nit`` 0 (no iterations).
    """

    slope_nm_per_deg: float
    intercept_nm: float
    r_squared: float
    frames: int
    span_deg: float
    rms_residual_nm: float

    @property
    def x(self) -> np.ndarray:
        """(slope N·m/°, intercept N·m), SciPy's name for the solution."""
        return np.array([self.slope_nm_per_deg, self.intercept_nm])

    @property
    def success(self) -> bool:
        return True

    @property
    def status(self) -> FitStatus:
        return FitStatus.CONVERGED

    @property
    def message(self) -> str:
        return f"least-squares line through {self.frames} frames"

    @property
    def nit(self) -> int:
        return 0

    def as_dict(self) -> dict[str, float]:
        return asdict(self)


def line_fit(angle_deg: np.ndarray, torque_nm: np.ndarray, window_deg: tuple[float, float],
             bin_deg: float | None = 0.5) -> LineFit:
    """Least-squares line of torque against angle for the frames given (already selected).

    With ``bin_deg`` the frames are first averaged in angle bins of that width and the line is
    fit to the bin means with equal weight, so the slope describes the torque–angle curve over
    the angles visited and not where the operator happened to linger (the curve is slightly
    nonlinear because the spring's moment arm changes with angle). ``None`` fits the frames
    directly. R² and the RMS residual are always those of the frames about the line.

    :raises FitError: fewer than ``MIN_FRAMES`` frames, or they cover less than half the window.
    """
    ok = np.isfinite(angle_deg) & np.isfinite(torque_nm)
    x, y = angle_deg[ok], torque_nm[ok]
    width = window_deg[1] - window_deg[0]
    span = float(np.ptp(x)) if x.size else 0.0
    if x.size < MIN_FRAMES:
        raise FitError(f"{x.size} frames in the {window_deg[0]:g}–{window_deg[1]:g}° window; a fit needs {MIN_FRAMES}")
    if span < MIN_SPAN_FRACTION * width:
        raise FitError(f"the frames span {span:.1f}° of the {width:g}° window; a fit needs {MIN_SPAN_FRACTION * width:.1f}°")
    if bin_deg:
        idx = np.floor((x - window_deg[0]) / bin_deg).astype(int)
        idx -= idx.min()
        count = np.bincount(idx)
        used = count > 0
        xf = np.bincount(idx, x)[used] / count[used]
        yf = np.bincount(idx, y)[used] / count[used]
    else:
        xf, yf = x, y
    slope, icpt = np.polyfit(xf, yf, 1)
    resid = y - (slope * x + icpt)
    ss_tot = float(np.sum((y - y.mean()) ** 2))
    r2 = 1.0 - float(np.sum(resid**2)) / ss_tot if ss_tot > 0 else float("nan")
    return LineFit(float(slope), float(icpt), r2, int(x.size), span, float(np.sqrt(np.mean(resid**2))))


def branch_masks(angle_deg: np.ndarray, velocity_deg_s: np.ndarray, window_deg: tuple[float, float],
                 min_speed_deg_s: float) -> dict[str, np.ndarray]:
    """Frames in the window: loading (dorsiflexing faster than ``min_speed``), unloading, and both (all of them)."""
    with np.errstate(invalid="ignore"):
        inside = (angle_deg >= window_deg[0]) & (angle_deg <= window_deg[1]) & np.isfinite(velocity_deg_s)
        return {"loading": inside & (velocity_deg_s > min_speed_deg_s),
                "unloading": inside & (velocity_deg_s < -min_speed_deg_s), "both": inside}


def hysteresis_area_j(angle_deg: np.ndarray, torque_nm: np.ndarray, masks: dict[str, np.ndarray],
                      window_deg: tuple[float, float], bin_deg: float = 0.5) -> tuple[float, float]:
    """Area between the loading and unloading curves in the window (J) and the angle span it covers (°).

    Each branch is averaged in ``bin_deg`` bins; the area sums (loading − unloading) × bin over the
    bins both branches visit. It is the energy the AFO dissipates per bend within the window.
    """
    edges = np.arange(window_deg[0], window_deg[1] + bin_deg / 2, bin_deg)
    means = []
    for name in ("loading", "unloading"):
        m = masks[name] & np.isfinite(torque_nm)
        idx = np.digitize(angle_deg[m], edges) - 1
        keep = (idx >= 0) & (idx < edges.size - 1)
        s = np.bincount(idx[keep], torque_nm[m][keep], minlength=edges.size - 1)
        c = np.bincount(idx[keep], minlength=edges.size - 1)
        with np.errstate(invalid="ignore", divide="ignore"):
            means.append(s / c)
    both = np.isfinite(means[0]) & np.isfinite(means[1])
    if not both.any():
        return float("nan"), 0.0
    return float(np.sum(means[0][both] - means[1][both]) * np.deg2rad(bin_deg)), float(both.sum() * bin_deg)


@dataclass(frozen=True)
class StiffnessResult:
    """Stiffness of one trial from one torque–angle record."""

    fits: dict[str, LineFit | None]
    errors: dict[str, str]
    reported_branch: str
    hysteresis_area_j: float
    hysteresis_span_deg: float
    peak_angle_deg: float
    frames_past_stop: int
    frames_in_window: int
    flags: list[str] = field(default_factory=list)

    @property
    def stiffness_nm_per_deg(self) -> float:
        """Slope of the reported branch (N·m/°); NaN when that fit failed (see ``errors``)."""
        f = self.fits.get(self.reported_branch)
        return f.slope_nm_per_deg if f is not None else float("nan")

    def as_dict(self) -> dict:
        return {"stiffness_nm_per_deg": self.stiffness_nm_per_deg, "reported_branch": self.reported_branch,
                "fits": {k: (v.as_dict() if v else None) for k, v in self.fits.items()}, "fit_errors": self.errors,
                "hysteresis_area_j": self.hysteresis_area_j, "hysteresis_span_deg": self.hysteresis_span_deg,
                "peak_angle_deg": self.peak_angle_deg, "frames_past_stop": self.frames_past_stop,
                "frames_in_window": self.frames_in_window, "flags": self.flags}


def stiffness(angle_deg: np.ndarray, velocity_deg_s: np.ndarray, torque_nm: np.ndarray, *,
              window_deg: tuple[float, float] = (6.0, 20.0), stop_deg: float = 21.0, min_speed_deg_s: float = 2.0,
              reported_branch: str = "loading") -> StiffnessResult:
    """Fits of torque against angle in the window, per branch, with hysteresis and the stop.

    Never raises for data that merely misses the window: the failed fits are ``None`` with the
    reason in ``errors`` and in ``flags``, and the stiffness is NaN.
    """
    if reported_branch not in BRANCHES:
        raise ValueError(f"reported_branch must be one of {BRANCHES}")
    masks = branch_masks(angle_deg, velocity_deg_s, window_deg, min_speed_deg_s)
    fits: dict[str, LineFit | None] = {}
    errors: dict[str, str] = {}
    for name in BRANCHES:
        try:
            fits[name] = line_fit(angle_deg[masks[name]], torque_nm[masks[name]], window_deg)
        except FitError as err:
            fits[name] = None
            errors[name] = str(err)
    area, span = hysteresis_area_j(angle_deg, torque_nm, masks, window_deg)
    finite = np.isfinite(angle_deg)
    peak = float(np.max(angle_deg[finite])) if finite.any() else float("nan")
    past = int(np.sum(angle_deg[finite] > stop_deg))
    flags = []
    if fits[reported_branch] is None:
        flags.append(f"no {reported_branch} stiffness: {errors[reported_branch]}")
    if peak < window_deg[1]:
        flags.append(f"the bend peaks at {peak:.1f}°, below the top of the fit window ({window_deg[1]:g}°)")
    if past:
        flags.append(f"{past} frames past the {stop_deg:g}° stop (peak {peak:.1f}°); they are outside the fit window")
    return StiffnessResult(fits, errors, reported_branch, area, span, peak, past, int(masks["both"].sum()), flags)


@dataclass
class SpringTheory:
    """Eqs 2.1–2.8 per frame (SI; the angle in degrees) and the linear fit of eq 2.9 (N·m/°)."""

    length_m: np.ndarray
    extension_m: np.ndarray
    force_n: np.ndarray
    moment_arm_m: np.ndarray
    torque_nm: np.ndarray
    angle_deg: np.ndarray
    fit: LineFit | None
    error: str = ""

    @property
    def stiffness_nm_per_deg(self) -> float:
        return self.fit.slope_nm_per_deg if self.fit is not None else float("nan")


def spring_torque(top_m: np.ndarray, bottom_m: np.ndarray, ankle_m: np.ndarray, rest_length_m: float,
                  stiffness_n_per_m: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Eqs 2.1–2.8: spring length, extension, force, moment arm |AD| and torque from T, B and A (n, 3) in m.

    A spring cannot push: the force is zero below the rest length (the spring is slack there).
    """
    bt = top_m - bottom_m
    length = np.linalg.norm(bt, axis=1)                               # (2.1)
    extension = length - rest_length_m                                # (2.2)
    force = stiffness_n_per_m * np.maximum(extension, 0.0)            # (2.3)
    ab = bottom_m - ankle_m
    q = -np.einsum("ni,ni->n", bt, ab) / length**2                    # (2.7) solved for q
    ad = ab + q[:, None] * bt                                         # (2.5), ⟂ BT by (2.6)
    arm = np.linalg.norm(ad, axis=1)                                  # (2.8)
    return length, extension, force, arm, force * arm                 # (2.4)
