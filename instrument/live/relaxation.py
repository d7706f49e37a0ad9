"""Online relaxation check: flag muscle activation in the dynamometer torque while a passive trial runs.

Causal and Qt-free: ``RelaxationMonitor.update(time_s, angle_deg, torque_nm)`` takes each new
sample (or block) as it arrives and returns the alarms raised. Passive tissue gives a torque that
is a smooth function of angle at the slow isokinetic speed; an activation burst adds a transient
the angle does not explain. The monitor

1. predicts each sample from the last ``window_s`` of samples by a quadratic in angle fitted by
   least squares (angle moves 2.5° in 0.5 s at 5 °/s, so the passive curve is locally smooth),
2. scales the prediction error by the noise, estimated as a running median absolute deviation of
   the errors of samples not under alarm (robust to the bursts themselves),
3. after a warm-up of one window (no alarms before the model and the noise estimate exist), runs
   a one-sided CUSUM on |error|/σ − ``drift`` in each direction and raises an alarm when it
   passes ``threshold``; samples under alarm (``hold_off_s``) are left out of the prediction
   window so a burst does not teach the model its own shape, and the window restarts after it.

Delay, sensitivity and false alarms are measured by ``python -m benchmarks relaxation``.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

#: the smallest burst (N·m, peak) the live check is measured to catch every time: 100 % of bursts
#: ≥ 1 N·m, no false alarm in 300 relaxed trials (``python -m benchmarks relaxation``). The offline
#: diagnosis, which sees the whole trial, names smaller ones; the operator is told which check saw what
LIVE_DETECTION_FLOOR_NM = 1.0


@dataclass
class ActivationAlarm:
    """An activation flagged at ``time_s`` (s) at ``angle_deg``; ``excess_nm`` is the torque's prediction error
    then (NaN when the EMG saw it); ``source`` says which check: ``"torque"`` or ``"emg <channel>"``."""

    time_s: float
    angle_deg: float
    excess_nm: float
    source: str = "torque"

    def what(self) -> str:
        """What the check saw, for the operator: the torque's excess (N·m) or the EMG's envelope."""
        return f"{self.excess_nm:+.1f} N·m" if self.source == "torque" else self.source


@dataclass
class RelaxationMonitor:
    """Causal activation detector for the dynamometer torque (see the module docstring)."""

    window_s: float = 0.5
    drift: float = 1.0
    threshold: float = 12.0
    min_sigma_nm: float = 0.02
    hold_off_s: float = 1.0
    alarms: list[ActivationAlarm] = field(default_factory=list)

    def __post_init__(self) -> None:
        self._t: deque[float] = deque()
        self._a: deque[float] = deque()
        self._q: deque[float] = deque()
        self._abs_err: deque[float] = deque(maxlen=400)
        self._pos = 0.0
        self._neg = 0.0
        self._quiet_until = -np.inf

    @property
    def sigma_nm(self) -> float:
        """Current noise estimate (N·m): 1.4826 × median |error|."""
        if len(self._abs_err) < 10:
            return max(self.min_sigma_nm, 0.1)
        return max(self.min_sigma_nm, 1.4826 * float(np.median(self._abs_err)))

    def _predict(self, angle_deg: float) -> float | None:
        if len(self._t) < 10 or np.ptp(self._a) < 1e-6:
            return float(np.mean(self._q)) if self._q else None
        a = np.asarray(self._a) - angle_deg
        x = np.column_stack([np.ones_like(a), a, a * a]) if np.ptp(a) > 0.5 else np.column_stack([np.ones_like(a), a])
        coef, *_ = np.linalg.lstsq(x, np.asarray(self._q), rcond=None)
        return float(coef[0])

    def _reset_window(self) -> None:
        self._t.clear()
        self._a.clear()
        self._q.clear()
        self._pos = self._neg = 0.0

    def update(self, time_s: np.ndarray | float, angle_deg: np.ndarray | float,
               torque_nm: np.ndarray | float) -> list[ActivationAlarm]:
        """Feed samples in time order; returns the alarms they raised."""
        raised = []
        for t, a, q in zip(np.atleast_1d(time_s), np.atleast_1d(angle_deg), np.atleast_1d(torque_nm)):
            t, a, q = float(t), float(a), float(q)
            if self._t and t - self._t[-1] > self.window_s:
                # a pause, or the end of an alarm's hold-off (nothing was kept meanwhile): the window
                # describes where the limb was, not where it is; start the passive model afresh
                self._reset_window()
            warm = len(self._t) >= 10 and (t - self._t[0]) >= 0.8 * self.window_s and len(self._abs_err) >= 30
            pred = self._predict(a)
            err = 0.0 if pred is None else q - pred
            z = err / self.sigma_nm if warm else 0.0
            self._pos = max(0.0, self._pos + z - self.drift)
            self._neg = max(0.0, self._neg - z - self.drift)
            alarmed = warm and max(self._pos, self._neg) > self.threshold
            if alarmed and t >= self._quiet_until:
                alarm = ActivationAlarm(t, a, err)
                self.alarms.append(alarm)
                raised.append(alarm)
                self._quiet_until = t + self.hold_off_s
            if alarmed:
                self._pos = self._neg = 0.0
            if t < self._quiet_until:
                continue  # under alarm: keep the burst out of the passive model and the noise estimate
            self._abs_err.append(abs(err))
            self._t.append(t)
            self._a.append(a)
            self._q.append(q)
            while self._t and self._t[0] < t - self.window_s:
                self._t.popleft()
                self._a.popleft()
                self._q.popleft()
        return raised


@dataclass
class EmgEnvelopeMonitor:
    """Causal activation detector on EMG channels (V), beside the torque check when a lab streams EMG.

    The envelope is each channel's RMS over the last ``window_s``; the relaxed baseline is its median
    over the first ``baseline_s`` of the stream (the trial's set-up and positioning, the subject relaxed
    and strapped in; were they not, the torque check and the operator say so). Alarms are raised only
    while ``armed`` (the runner arms it during the sweep). An alarm is raised when a channel's envelope stays
    above ``ratio`` × its baseline for ``min_duration_s``; then that channel is quiet for ``hold_off_s``.
    ``labels`` name the channels in the alarm's source.
    """

    labels: tuple[str, ...]
    window_s: float = 0.1
    baseline_s: float = 1.0
    ratio: float = 4.0
    min_duration_s: float = 0.05
    hold_off_s: float = 1.0
    alarms: list[ActivationAlarm] = field(default_factory=list)

    def __post_init__(self) -> None:
        k = len(self.labels)
        self._t: deque[float] = deque()
        self._sq: deque[np.ndarray] = deque()
        self._sum_sq = np.zeros(k)
        self._t0: float | None = None
        self._baseline_rms: list[list[float]] = [[] for _ in range(k)]
        self._baseline: np.ndarray | None = None
        self._above_since = np.full(k, np.nan)
        self._quiet_until = np.full(k, -np.inf)

    @property
    def baseline_v(self) -> np.ndarray | None:
        """Each channel's relaxed RMS (V), once the baseline period is over."""
        return self._baseline

    def update(self, time_s: np.ndarray, values: np.ndarray, angle_at: Callable[[float], float], *,
               armed: bool = True) -> list[ActivationAlarm]:
        """Feed samples (``values`` shape (n, channels)) in time order; ``angle_at(t)`` gives the joint angle
        (deg) at time ``t`` for the alarm. Returns the alarms raised (none unless ``armed``)."""
        raised = []
        values = np.asarray(values, dtype=float).reshape(len(time_s), len(self.labels))
        for t, v in zip(np.asarray(time_s, dtype=float), values):
            if not np.all(np.isfinite(v)):
                continue  # a damaged sample: neither in the envelope nor in the baseline
            t = float(t)
            self._t0 = t if self._t0 is None else self._t0
            sq = v * v
            self._t.append(t)
            self._sq.append(sq)
            self._sum_sq += sq
            while self._t and self._t[0] < t - self.window_s:
                self._t.popleft()
                self._sum_sq -= self._sq.popleft()
            if t - self._t0 < self.window_s:
                continue  # the first window is not full yet
            rms = np.sqrt(np.maximum(self._sum_sq, 0.0) / len(self._t))
            if self._baseline is None:
                for channel, r in enumerate(rms):
                    self._baseline_rms[channel].append(float(r))
                if t - self._t0 >= self.baseline_s:
                    self._baseline = np.array([max(float(np.median(b)), 1e-12) for b in self._baseline_rms])
                continue
            above = (rms > self.ratio * self._baseline) & armed
            self._above_since[~above] = np.nan
            for k in (int(i) for i in np.flatnonzero(above)):
                if np.isnan(self._above_since[k]):
                    self._above_since[k] = t
                if t - self._above_since[k] >= self.min_duration_s and t >= self._quiet_until[k]:
                    alarm = ActivationAlarm(t, angle_at(t), float("nan"),
                                            f"emg {self.labels[k]} {rms[k] / self._baseline[k]:.1f}× its relaxed RMS")
                    self.alarms.append(alarm)
                    raised.append(alarm)
                    self._quiet_until[k] = t + self.hold_off_s
        return raised
