"""Diagnose a trial: fit the baseline, try every candidate cause, choose by held-out error and an honest criterion.

Selection, in order:

0. the baseline first: an orthosis's quadratic spring adopts up to two steeper exponential ends where its bend asks
   for them by the same criterion and held-out gain, and only where a smooth end fits better than a hinge would
   (:func:`baseline_choice.adopt_steeper_ends`); a stop at an adopted end is said, not named;
1. every candidate is fitted jointly with the baseline (least squares; nonlinear parameters by a
   grid and a bounded refinement; passive causes keep their physical sign by an active set);
2. held-out error: the trial is cut into ``folds`` contiguous time blocks; each block is
   predicted by the model fitted on the others (neighbouring samples are correlated, so random
   splits would flatter every model). The held-out gain of a larger model over a smaller one is
   n_eff · ln(held-out MSE ratio). A transient cause (a burst) cannot be predicted from other
   blocks, so for it only the criterion decides, at half the threshold;
3. criterion: BIC with the effective sample size n_eff = n / τ, τ the integrated autocorrelation
   time of the *larger* model's own residual at each step (neighbouring samples are not
   independent evidence, and leftover structure of an unmodelled effect must not count as it);
4. a cause is accepted against a reference model when it lowers the criterion by more than
   ``min_delta_bic`` and its held-out gain exceeds ``min_heldout_gain`` — or, by strong held-out
   evidence alone, when the gain exceeds :data:`STRONG_HELDOUT_GAIN` while ΔBIC stays below
   :data:`MAX_DELTA_BIC_WITH_STRONG_HELDOUT` (a local stop); a burst alone also when it lowers the criterion
   against the flexible baseline at that fit's own n_eff, its timing searched again there (a function of time,
   which a free curve in angle cannot mimic where angles are revisited); a hard stop also by its own test, the
   t statistic of its stiffness past a look-elsewhere-corrected level (:data:`LOCAL_STOP_T`) with
   held-out blocks predicted no worse (an orthosis's stop also at a
   lower t with held-out blocks predicted clearly better: :data:`AFO_STOP_T`), and only
   when it predicts held-out blocks better than a smooth curve at its end of the range (a joint's steeper passive term,
   an orthosis's spring off the quadratic: ``_Search.stop_beats_smooth_rival``). Where those tests refuse a joint's
   stop (knee, ankle) that is a kink a free curve in angle cannot follow, judged on the flexible baseline
   (``_Search.stop_is_a_kink``), the report says the end stiffens there (a stop, or a passive end engaging within a
   few degrees) and names neither. A burst, by whichever test, only where the trial also moves through its angles
   at other times (:data:`MIN_REVISITED_BURST_SHARE`): at angles it reaches only then (the outermost strokes of a
   growing protocol) a burst and the passive curve there are the same function of time, said, not named. A
   cause that is not a function of angle alone must also lower the criterion against the *flexible* baseline (a
   spline in angle), and so must a series compliance, which in a slow trial only reshapes the curve in angle;
5. a cause whose effect the baseline can mimic (R² > ``max_absorbed_r2`` of its effect direction
   on the baseline basis; on the flexible baseline's basis for a cause that must also beat that baseline) is not
   testable in this trial: it is never named, and the report says what the trial would need;
6. forward selection: the accepted single cause with the lowest criterion wins, every accepted cause
   judged at one noise model (the best-fitting one's n_eff; see :func:`diagnose`); then every other
   cause is tried beside it and joins when it passes the same tests against the winner alone (and
   the winner stays needed beside it). Then the pairs of the four best-fitting causes are tried
   whole, each cause tested given the other, and replace the forward step's model when the
   criterion at the pair's own noise model prefers them (by ``min_delta_bic`` over a single cause
   or the baseline): one effect can hide another, or lead the first step astray;
7. accepted causes whose fitted effects are nearly the same curve (correlation > 0.9) within
   ``ambiguity_bic`` of the winner, or whose RMSE is within ``ambiguity_rmse`` (5 %) of it, make
   the result ambiguous: the report names them and the protocol change that would separate them,
   rather than guessing.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.optimize import minimize, minimize_scalar

from ..errors import InputError
from ..trial_csv import NOMINAL_RANGE_DEG
from .baseline_choice import adopt_steeper_ends
from .causes import (
    AFO_STOP_OR_SPRING_HINT,
    ARGUMENT_CAUSES,
    BURST_GRID_DURATIONS_S,
    BURST_OR_UNREVISITED_HINT,
    CAUSES,
    LAW_VARIANTS,
    SEPARATE_BY,
    SMOOTH_END_RATES_PER_RAD,
    STOP_OR_STEEPER_END_HINT,
    UNTESTABLE_HINT,
    Cause,
    Prepared,
    _ext_count,
    _nl_count,
    _stop_grid,
    compound,
    rounded_stop_cause,
    toe_onset_cause,
)
from .data import DiagnosisTrial
from .evidence import (
    average_variants,
    averaged_magnitude,
    bic,
    effective_n,
    heldout_block_s,
    heldout_folds,
    heldout_residuals,
    likeliest_law,
    magnitude_variants,
    parameter_se,
    systematic_regions,
)
from .fitting import CauseFit, absorbed_by_baseline, fit_cause
from .policy import (
    AFO_STOP_MAX_DELTA_BIC,
    AFO_STOP_MIN_HELDOUT_GAIN,
    AFO_STOP_NOT_BESIDE,
    AFO_STOP_T,
    ISOLATED_BURST_ALPHA,
    LOCAL_STOP_T,
    MAX_DELTA_BIC_WITH_STRONG_HELDOUT,
    MAX_RATE_HZ,
    MAX_SAMPLES,
    MIN_PEAK_TO_NOISE,
    MIN_RANGE_FRACTION,
    MIN_RATE_HZ,
    MIN_REVISITED_BURST_SHARE,
    MIN_SWING_TO_NOISE,
    REVISIT_BIN_DEG,
    REVISIT_STILL_DEG_S,
    STRONG_HELDOUT_GAIN,
    STRONG_MIN_HELDOUT_IMPROVEMENT,
    SWING_CAUSES,
)
from .result import Candidate, Diagnosis, magnitude
from .transients import TransientScan, isolated_transient, revisit_differenced, revisited_share
from .transients import scan as scan_residual


def mean_stiffness_nm_per_deg(prep: Prepared, base: CauseFit) -> float:
    """The trial's mean stiffness (N·m/°): the slope of the baseline ``base``'s prediction on the angle (0 where it has
    too few predicted samples)."""
    ok = np.isfinite(base.prediction)
    return math.radians(1.0) * float(np.polyfit(prep.theta[ok], base.prediction[ok], 1)[0]) if ok.sum() > 2 else 0.0


def play_alike_text(prep: Prepared, base: CauseFit, friction_nm: float) -> str:
    """What a named friction's loop (``friction_nm`` N·m each way) would be as play in the angle's coupling: the play
    (deg) that shifts the baseline ``base``'s torque by as much at the trial's mean stiffness. Play lags the measured
    angle a fixed amount behind the joint after each reversal, so on a spring of constant stiffness its loop is a
    friction's; only the joint's own curve (stiffer at its ends, where play's loop widens and a friction's does not) or
    the coupling itself tells them apart."""
    slope_nm_per_deg = mean_stiffness_nm_per_deg(prep, base)
    if abs(slope_nm_per_deg) < 1e-9:
        return "coulomb_friction: its loop is also what play in the angle's coupling makes; check the coupling for play"
    play_deg = abs(friction_nm / slope_nm_per_deg)
    return (f"coulomb_friction: its loop ({friction_nm:.3g} N·m each way) is also what play of about {play_deg:.2g}° in the "
            f"angle's coupling makes at this trial's mean stiffness ({abs(slope_nm_per_deg):.3g} N·m/°); check the "
            "coupling for play before reading it as the specimen's friction")


def lag_alike_text(prep: Prepared, base: CauseFit, damping_nm_s_per_rad: float) -> str:
    """What a named damping's loop (b, N·m·s/rad) would be as the angle channel lagging the torque: the lag τ = b / k (s)
    at the trial's mean stiffness k. An angle read τ late, θ(t − τ), under a torque f(θ(t)) shows f(θ_read) + k·τ·θ̇ to
    first order: a viscous loop of b = k·τ. A torque channel lagging the angle makes the opposite loop (a delay, which the
    search tries with τ ≥ 0); an angle lagging the torque is a negative delay, outside it. A skew of a few milliseconds
    between the angle's and the torque's samples makes this loop on fast bends (the spent thirty-third family's clean
    orthosis trials: a damping named in 11 of 20 from the torque sampled 0.2–4.6 ms after the angle)."""
    slope_nm_per_rad = math.degrees(mean_stiffness_nm_per_deg(prep, base))
    if abs(slope_nm_per_rad) < 1e-9:
        return "viscous_damping: its loop is also what an angle channel lagging the torque makes; check the channels' timing"
    lag_ms = 1000.0 * abs(damping_nm_s_per_rad / slope_nm_per_rad)
    return (f"viscous_damping: its loop (b = {damping_nm_s_per_rad:.3g} N·m·s/rad) is also what an angle channel lagging the "
            f"torque by about {lag_ms:.2g} ms makes at this trial's mean stiffness ({abs(math.radians(slope_nm_per_rad)):.3g} "
            "N·m/°; the torque sampled that much after the angle); check the skew between the angle's and the torque's "
            "samples before reading it as the specimen's damping")


def _part_offset(cause: Cause, name: str = "hard_stop") -> int:
    """Index of the first column of the part ``name`` among ``cause``'s extension columns (a pair lists its parts')."""
    offset = 0
    for part in cause.parts or (cause,):
        if part.name == name:
            break
        offset += _ext_count(part)
    return offset




@dataclass
class _Evidence:
    """What adding one cause to a reference model buys, judged at the larger model's own noise model."""

    delta_bic: float         # criterion of the larger model minus the reference's (negative: better)
    heldout_gain: float      # n_eff · ln(held-out MSE ratio): > 0 when held-out blocks are predicted better
    flexible_delta_bic: float  # ΔBIC with the flexible baseline under both (NaN: not hysteretic)
    n_eff: float
    heldout_rmse: float
    accepted: bool
    #: a burst's ΔBIC on the flexible baseline at that fit's own n_eff (NaN: not judged there)
    flexible_own_delta_bic: float = float("nan")
    #: a burst's scan as one isolated event (None: not judged so, :meth:`_Search.burst_scan`)
    isolated: TransientScan | None = None


class _Search:
    """The fits, held-out errors and flexible-baseline checks of one trial, each computed once."""

    def __init__(self, prep: Prepared, folds: int, min_delta_bic: float, min_heldout_gain: float,
                 library: dict[str, Cause] | None = None) -> None:
        self.prep, self.flex = prep, prep.as_flexible()
        self.library = CAUSES if library is None else library  # the causes by name (a trial's friction law)
        self.folds, self.min_delta_bic, self.min_heldout_gain = folds, min_delta_bic, min_heldout_gain
        self.fits: dict[str, CauseFit] = {}
        self.causes: dict[str, Cause] = {}
        self._ho: dict[str, np.ndarray] = {}
        self._flex: dict[str, CauseFit] = {}
        self._smooth: dict[str, tuple[CauseFit, np.ndarray]] = {}
        self._folds: dict[float | None, tuple[str, list[np.ndarray]]] = {}
        #: models whose stop passed every test against its reference but not against a smooth stiffening
        self.stops_not_told_from_smooth: set[str] = set()
        #: the starts (s) of bursts refused because the trial reaches their angles only then (MIN_REVISITED_BURST_SHARE)
        self.bursts_at_unrevisited_angles: list[float] = []
        #: swings (× the residual RMS) of drifts, frictions and dampings the criterion accepted but too small to be
        #: material, by cause
        self.swings_below_noise: dict[str, list[float]] = {}

    def fit(self, names: tuple[str, ...]) -> tuple[Cause, CauseFit]:
        key = "+".join(names)
        if key not in self.fits:
            if len(names) == 1:
                cause = self.library[names[0]]
                self.fits[key] = fit_cause(self.prep, cause)
            else:
                cause = compound(self.library[names[0]], self.library[names[1]])
                a, b = cause.parts
                start = self.fits[a.name].nonlinear + self.fits[b.name].nonlinear
                self.fits[key] = fit_cause(self.prep, cause, start=start)
            self.causes[key] = cause
        return self.causes[key], self.fits[key]

    def folds_of(self, names: tuple[str, ...]) -> tuple[str, list[np.ndarray]]:
        """The held-out folds of the model ``names`` and their label: ``folds`` contiguous time blocks, or the
        round-robin blocks its drift asks for (a wandering drift: :func:`evidence.heldout_folds`)."""
        cause, _ = self.fit(names)
        block_s = heldout_block_s(cause)
        if block_s not in self._folds:  # made once per block length: every held-out comparison asks again
            self._folds[block_s] = (f"blocks of {block_s:.6g} s" if block_s else "contiguous",
                                    heldout_folds(self.prep, cause, self.folds))
        return self._folds[block_s]

    def heldout(self, names: tuple[str, ...], interior: bool = False, folds_from: tuple[str, ...] | None = None
                ) -> float:
        """Held-out RMSE (N·m) of the model ``names`` (:meth:`heldout_residuals`) on the folds of the model
        ``folds_from`` (default its own); ``interior``: without the trial's first and last blocks (where a function of
        time is interpolated, not extrapolated)."""
        label, blocks = self.folds_of(folds_from or names)
        e = self.heldout_residuals(names, folds_from=folds_from)
        if interior and label == "contiguous":  # round-robin folds never leave out the trial's ends
            inner = blocks[1:-1]
            if inner:  # with fewer than three folds every block is an end block: all are used
                e = e[np.concatenate(inner)]
        e = e[np.isfinite(e)]
        return float(np.sqrt(np.mean(e**2))) if e.size else float("nan")

    def heldout_residuals(self, names: tuple[str, ...], flexible: bool = False,
                          folds_from: tuple[str, ...] | None = None) -> np.ndarray:
        """Held-out residuals (N·m) of the model ``names`` on the folds of the model ``folds_from`` (default its own,
        :meth:`folds_of`); ``flexible``: on the flexible baseline, with the nonlinear parameters of the plain
        baseline's fit."""
        label, blocks = self.folds_of(folds_from or names)
        key = "+".join(names) + (" on the flexible baseline" if flexible else "") + f" ({label})"
        if key not in self._ho:
            cause, f = self.fit(names)
            # the nonlinear parameters (a stop's angle, a delay, a burst's timing, a friction width) are
            # held at the whole trial's values in every fold, for every candidate alike. Measured on
            # `python -m benchmarks diagnosis --quick`: searching them again on each fold's training
            # blocks gave the same verdicts (singles 0.947, pairs 0.677, false alarms 0) at 3.1× the
            # time; re-searching singles only (not pairs) favoured pairs and lost 0.026 of the singles
            self._ho[key] = heldout_residuals(self.flex if flexible else self.prep, cause, self.folds,
                                              None if len(names) == 1 and not f.nonlinear else f.nonlinear, blocks)
        return self._ho[key]

    def flexible(self, names: tuple[str, ...], searched: bool = False) -> CauseFit:
        """``names`` fitted on the flexible baseline: at the parametric fit's nonlinear parameters, or (``searched``)
        with them searched again there."""
        key = "+".join(names) + (" searched" if searched else "")
        if key not in self._flex:
            cause, f = self.fit(names)
            self._flex[key] = fit_cause(self.flex, cause) if searched else \
                fit_cause(self.flex, cause, refine=False, start=f.nonlinear)
        return self._flex[key]

    def evidence(self, model: tuple[str, ...], ref: tuple[str, ...]) -> _Evidence:
        """Evidence for ``model`` (the reference plus one cause) against ``ref``."""
        added = self.library[next(n for n in model if n not in ref)]
        _, mf = self.fit(model)
        _, rf = self.fit(ref)
        n_eff = effective_n(self.prep.torque - mf.prediction)
        d = bic(mf, n_eff) - bic(rf, n_eff)
        # a drift is a function of time: a left-out first or last block asks a cubic in time to extrapolate,
        # which it cannot (a settling or wandering offset read 1.26× worse held out at ΔBIC −38); it is judged
        # on the blocks it interpolates, the reference on the same blocks
        # (a wandering drift is judged on blocks of its own resolution dealt round-robin, each predicted from the ones
        # beside it: a contiguous fifth of the trial holds knots no training sample reaches; the reference alike)
        interior = added.name == "sensor_drift"
        ref_ho = self.heldout(ref, interior, folds_from=model)
        ho = self.heldout(model, interior) if not added.transient else float("nan")
        gain = n_eff * math.log(ref_ho ** 2 / ho ** 2) if math.isfinite(ho) and ho > 0 else float("nan")
        d_flex = float("nan")
        if added.hysteretic:
            d_flex = bic(self.flexible(model), n_eff) - bic(self.flexible(ref), n_eff)
        # a transient (a burst) cannot be checked on held-out blocks; its threshold is half the others'
        # (its three parameters already cost 3 ln n_eff, above the largest noise excursion a scan over
        # every start and duration finds: about 2 ln(windows) ≈ 11 on a minute of data)
        need = self.min_delta_bic / 2 if added.transient else self.min_delta_bic
        # a burst is a function of time, not of angle: where a trial revisits its angles a free curve in angle (the
        # flexible baseline) cannot take its place, and it takes the passive curve's misfit out of the residual, which
        # the parametric baseline leaves as slow structure that shrinks n_eff and drowns the burst (a passive end
        # outside the baseline's family: bursts of 3–5× the noise at ΔBIC −2 to +7 on the parametric baseline,
        # −166 to −646 on the flexible one at its own fit's n_eff). So a burst alone is also named when it lowers the
        # criterion against the flexible baseline at that fit's own n_eff. Not beside another cause: there the
        # flexible residual holds the other cause's law mismatch at every reversal, which a burst takes a piece of
        # (development, 2nd–10th families, seeds 800000–800002: beside a single friction, damping or drift 7
        # spurious bursts; the isolated-event test below, tried there too at the thirty-fifth stop with the isolated
        # windows in the burst grid, named 18 more bursts of 168 development pairs but 7 spurious ones beside 168 single
        # causes). And, as a stop, only when material: its peak at least MIN_PEAK_TO_NOISE × the flexible fit's residual
        # RMS (a clean sixth-family knee, Student-t noise, had a 1.5× bump at ΔBIC −103; the bursts
        # found this way were 3.3–7.9×). Development: single bursts 31 → 38 of 54 named, pairs with a burst 50 → 50
        # of 126 right (80 of their bursts named, 76 before), clean knee and ankle trials 158 → 158 of 180
        # Its timing is searched again on the flexible baseline: on the parametric one a passive curve outside the
        # baseline's family leaves a misfit that draws the burst to it (spent seventeenth-family knees: bursts placed
        # at the trial's start, 1–2 s long and 2–6 N·m, against the true 0.4–0.8 N·m at 9–51 s), and the burst the
        # test then weighs on the free curve is not the one in the data. Development, spent families 13–18 (knee and
        # ankle): single bursts 43 → 57 of 96 named, clean trials 184 → 183 of 240, pairs with a burst 24 → 24 of 84
        of_time, d_own, scan = False, float("nan"), None
        if added.name == "activation_burst" and ref == ("none",):
            flex_model = self.flexible(model, searched=True)
            n_flex = effective_n(self.flex.torque - flex_model.prediction)
            peak = abs(flex_model.params["burst_amplitude_Nm"]) / math.sqrt(flex_model.rss / max(flex_model.n, 1))
            d_own = bic(flex_model, n_flex) - bic(self.flexible(ref), n_flex)
            of_time = d_own < -need and peak >= MIN_PEAK_TO_NOISE
            # or when it stands out of that fit's residual as one isolated event at its own time scale (the criterion's
            # n_eff is set by the slowest noise, which a short burst need not stand out of: burst_scan)
            if peak >= MIN_PEAK_TO_NOISE:
                scan = self.burst_scan(flex_model, ref)
                of_time = of_time or scan.isolated
        # (not beside a drift: the differencing tells a function of time from a function of the state, not from the
        # drift law's own misfit, which is a function of time too: an independent family's knocked cable, its step
        # sharper than the drift's spline, was named a drift and a burst)
        if added.name == "activation_burst" and ref != ("none",) and "sensor_drift" not in ref and not of_time:
            scan = self.burst_beside(model, ref, mf)
            of_time = scan is not None and scan.isolated
        # a second way in, by strong out-of-sample evidence: held-out blocks predicted far better
        # (gain > STRONG_HELDOUT_GAIN) while the in-sample criterion does not speak against it. A
        # local effect (a stop over the last degrees) barely moves the whole-trial BIC, whose
        # penalty counts its searched location as a full parameter; the held-out test pays for that
        # search by itself. On clean independent trials the held-out gain of the best spurious stop
        # stayed ≤ 7.1 (24 trials; benchmarks/diagnosis)
        strong = (not added.transient and gain > STRONG_HELDOUT_GAIN and d < MAX_DELTA_BIC_WITH_STRONG_HELDOUT
                  and ho <= (1.0 - STRONG_MIN_HELDOUT_IMPROVEMENT) * ref_ho)
        joint_stop = added.name == "hard_stop" and self.prep.trial.kind in ("knee", "ankle")
        local = added.name == "hard_stop" and gain > 0.0 \
            and self.stop_t(model, n_eff) > LOCAL_STOP_T
        if added.name == "hard_stop" and self.prep.trial.kind == "afo" and not local \
                and not AFO_STOP_NOT_BESIDE.intersection(ref):
            local = gain > AFO_STOP_MIN_HELDOUT_GAIN and d < AFO_STOP_MAX_DELTA_BIC \
                and self.stop_t(model, n_eff) > AFO_STOP_T
        ok = (((d < -need and (added.transient or gain > self.min_heldout_gain)) or strong or local)
              and (not added.hysteretic or d_flex < -need)) or of_time
        if ok and added.name == "activation_burst":
            placed = self.flexible(model, searched=True) if ref == ("none",) else mf
            share = revisited_share(self.prep.t, self.prep.theta, self.prep.omega, placed.params["burst_start_s"],
                                    placed.params["burst_duration_s"], math.radians(REVISIT_BIN_DEG),
                                    math.radians(REVISIT_STILL_DEG_S))
            if share < MIN_REVISITED_BURST_SHARE:
                ok = False
                self.bursts_at_unrevisited_angles.append(placed.params["burst_start_s"])
        if ok and added.name == "inertia":
            # a moving mass adds inertia; an error may take some of the known limb's and arm's away, never more
            # than all of it: a total below zero is no mass (a lagging torque channel fits as one: the demo's
            # ankle sweep read -0.93 kg·m² beside 0.07 known). And material, as a stop: its torque's peak at least
            # MIN_PEAK_TO_NOISE × the residual RMS, on either baseline (a passive curve outside the parametric one's
            # family takes part of an inertia there: a sixth-family knee's 3.0 kg·m² read 2.1, its peak 1.65 × the
            # noise). With the acceleration's window the trial's likeliest (causes.ACCEL_WINDOWS_S) the criterion found
            # the limb tables' own error in clean trials, 0.02–0.14 kg·m² (spent families' segments drawn apart from
            # Winter's fractions; 5 of 192 clean development trials)
            ok = (self.prep.trial.known_inertia_kgm2() + mf.params.get("inertia_kgm2", 0.0) > 0.0
                  and max(self.peak_to_noise(model, "inertia"),
                          self.peak_to_noise(model, "inertia", self.flex, self.flexible(model))) >= MIN_PEAK_TO_NOISE)
        if ok and added.name == "hard_stop":
            ok = self.peak_to_noise(model) >= MIN_PEAK_TO_NOISE
            # a joint's stop against its steeper passive end, an orthosis's against its spring off the quadratic; not
            # the replica leg's, a rig of linear springs whose stops are what it is built to show: the rival there
            # took a stop 200× better in fit at a held-out gain of 11.8 (the first generator, seed 101: a few holds'
            # worth of independent samples), and no development family has replica trials to measure it on
            if ok and self.prep.trial.kind != "replica":
                ok = self.stop_beats_smooth_rival(model) and not self.at_adopted_end(model)
                if ok and joint_stop:  # and a joint's stop not taken up over degrees (a rounded engagement, a toe)
                    ok = not self.stop_taken_up(model, self.prep, self.fit(model)[1], n_eff)
                if not ok:
                    self.stops_not_told_from_smooth.add("+".join(model))
        if ok and added.name in SWING_CAUSES:
            # material: a cause acting through the whole trial must swing (half its peak-to-peak torque: a drift's mean is
            # the baseline's offset, a friction's swing is its level) MIN_SWING_TO_NOISE × the residual RMS on either
            # baseline (a passive curve outside the parametric one's family inflates that fit's residual). A slow nuisance
            # (a gain drifting over the trial, a hum aliased to a slow beat) or play in the angle's coupling (a loop as
            # wide as the play times the stiffness) lowers the criterion at a large n_eff with a fraction of the noise
            swing = max(self.swing_to_noise(model, part=added.name),
                        self.swing_to_noise(model, self.flex, self.flexible(model), part=added.name))
            ok = swing >= MIN_SWING_TO_NOISE
            if not ok:
                self.swings_below_noise.setdefault(added.name, []).append(swing)
        if not ok and joint_stop and self.stop_is_a_kink(model, ref):
            # a kink a free curve in angle cannot follow is said, not named: a stop, or a passive end engaging within a
            # few degrees (a toe region, fibres whose onsets spread over 1–4°), which this trial cannot tell apart. Named,
            # it was a stop in 17 and not one in 27 of 686 development trials (thirty-fourth stop, docs/validation.md)
            self.stops_not_told_from_smooth.add("+".join(model))
        return _Evidence(d, gain, d_flex, n_eff, ho, ok, d_own, scan)

    def burst_scan(self, flex_model: CauseFit, ref: tuple[str, ...]) -> TransientScan:
        """How far the burst of ``flex_model`` (a model with a burst fitted on the flexible baseline, its timing searched
        there) stands out of the residual of ``ref`` on that baseline at its own time scale; ``.isolated`` says whether
        it is one isolated event (:func:`transients.isolated_transient` at :data:`ISOLATED_BURST_ALPHA`, over the burst
        grid's durations)."""
        residual = self.flex.torque - self.flexible(ref).prediction
        return isolated_transient(self.flex.t, residual, flex_model.params["burst_start_s"],
                                  flex_model.params["burst_duration_s"], ISOLATED_BURST_ALPHA,
                                  len(BURST_GRID_DURATIONS_S))

    def burst_beside(self, model: tuple[str, ...], ref: tuple[str, ...], fit: CauseFit) -> TransientScan | None:
        """The burst in ``model`` (``ref``, another cause, plus a burst; ``fit`` its parametric fit) judged as one
        isolated event in what ``ref`` leaves on the flexible baseline once every pass's recurring part is taken out
        (:func:`transients.revisit_differenced`): the likeliest event over the burst grid's durations, which must be
        where the fit put its burst (their centres within the longer of the two durations) and reach
        :data:`MIN_PEAK_TO_NOISE` × the residual RMS of ``model`` on the flexible baseline; None where it is not."""
        on_flexible = self.flexible(model)
        noise = math.sqrt(on_flexible.rss / max(on_flexible.n, 1))
        if noise <= 0.0 or abs(on_flexible.params["burst_amplitude_Nm"]) < MIN_PEAK_TO_NOISE * noise:
            return None
        residual = self.flex.torque - self.flexible(ref).prediction
        differenced = revisit_differenced(self.flex.theta, self.flex.omega, residual, math.radians(REVISIT_BIN_DEG),
                                          math.radians(REVISIT_STILL_DEG_S))
        best: tuple[float, TransientScan, float, float] | None = None
        for duration in BURST_GRID_DURATIONS_S:
            scanned = scan_residual(self.flex.t, differenced, duration)
            if scanned is None:
                continue
            times, z, m = scanned
            start = float(times[min(int(np.argmax(z)) + m, times.size - 1)])
            found = isolated_transient(self.flex.t, differenced, start, duration, ISOLATED_BURST_ALPHA,
                                       len(BURST_GRID_DURATIONS_S))
            ratio = found.z_event / found.z_critical
            if best is None or ratio > best[0]:
                best = (ratio, found, start + 0.5 * duration, duration)
        if best is None:
            return None
        fitted_centre = fit.params["burst_start_s"] + 0.5 * fit.params["burst_duration_s"]
        _, found, centre, duration = best
        return found if abs(fitted_centre - centre) <= max(fit.params["burst_duration_s"], duration) else None

    def stop_is_a_kink(self, model: tuple[str, ...], ref: tuple[str, ...]) -> bool:
        """Whether the joint's stop in ``model`` (``ref`` plus the stop) is a kink in the torque–angle curve that a free
        curve in angle cannot follow: judged on the flexible baseline (the parametric one plus a cubic spline in angle),
        its angle searched there, it must

        - lower the criterion against ``ref`` on that baseline by ``min_delta_bic`` at that fit's own n_eff;
        - predict held-out blocks better than ``ref`` there by strong held-out evidence (n_eff · ln of their MSE ratio
          > :data:`STRONG_HELDOUT_GAIN`: a stop acts over a few degrees of every pass);
        - reach :data:`MIN_PEAK_TO_NOISE` × the fit's residual RMS at its deepest.

        Whether a rounded engagement or a toe's onset fits it better (:meth:`stop_taken_up`) is not asked here: such a
        kink is said, not named, either way.

        A joint's stop is first judged on the parametric baseline (its stiffness's t statistic, the held-out gain over a
        smooth stiffening at its end); where that refuses it and this holds, the report says the end stiffens at the kink
        and names neither a stop nor a passive term (from the thirty-first to the thirty-third stop this named the stop:
        on 686 development trials of seven spent families it named 17 stops that were there and 27 that were not, and
        on the twenty-fourth family, run once, every false alarm was a knee or ankle stop, 10 of 40 clean trials; the
        eight-chain ends there, their fibres' onsets spread over 1–4°, engage within a few degrees). A passive end outside the
        parametric baseline's family leaves a misfit many times a stop's size, which the stop takes: on spent families'
        clean knees and ankles (thirteenth to twenty-second) the hinge stood at the passive ends' onsets (the twenty-
        second's knees: 17–36° into the range, 18–61 × the noise), and beside such a misfit a true stop of 3–5 × the
        noise was named in 15 of 160 trials. The spline takes the smooth misfit and leaves the kink. It is not the only
        test: beside a steep passive end in the parametric family (the first generator's ankle stops on Riener's
        plantarflexion term) the spline bends with the end and takes part of the kink, where the parametric test names
        it (with this test alone that generator's singles fell 0.895 → 0.851 and its pairs 0.753 → 0.634). No rule says
        where in the range a stop may sit or which end is steep. What this cannot tell apart, measured: a passive
        element that goes taut at one angle (a check strap, a chain without a toe region, single collagen fibres) is a
        kink, and a toe region taken up over a few degrees fits a hinge as well as its own onset at a few times the
        noise (docs/validation.md, thirty-first stop)."""
        cause, _ = self.fit(model)
        flex_fit = self.flexible(model, searched=True)
        n_flex = effective_n(self.flex.torque - flex_fit.prediction)
        if bic(flex_fit, n_flex) - bic(self.flexible(ref), n_flex) >= -self.min_delta_bic:
            return False
        resid = heldout_residuals(self.flex, cause, self.folds, flex_fit.nonlinear, self.folds_of(model)[1])
        ref_resid = self.heldout_residuals(ref, flexible=True, folds_from=model)
        ok = np.isfinite(resid) & np.isfinite(ref_resid)
        if ok.sum() < 10:
            return False
        gain = n_flex * math.log(float(np.mean(ref_resid[ok] ** 2)) / float(np.mean(resid[ok] ** 2)))
        return gain > STRONG_HELDOUT_GAIN and self.peak_to_noise(model, "hard_stop", self.flex, flex_fit) >= MIN_PEAK_TO_NOISE

    def stop_taken_up(self, model: tuple[str, ...], signals: Prepared, fit: CauseFit, n_eff: float) -> bool:
        """Whether the stop in ``model``, fitted as ``fit`` on ``signals``' baseline, is fitted clearly better
        (ΔBIC < −``min_delta_bic`` at ``n_eff``) by a stop engaging over a width or by a toe region's onset
        (:meth:`stop_rival`): a stiffening taken up over degrees, as tissue is, not a contact's kink."""
        return any(bic(self.stop_rival(model, fit, rival, signals), n_eff) - bic(fit, n_eff) < -self.min_delta_bic
                   for rival in (rounded_stop_cause(), toe_onset_cause()))

    def stop_rival(self, model: tuple[str, ...], flex_fit: CauseFit, stop_rival: Cause,
                   signals: Prepared | None = None) -> CauseFit:
        """``model`` on ``signals``' baseline (default the flexible one) with its stop replaced by ``stop_rival`` (a
        rounded engagement, :func:`causes.rounded_stop_cause`, or a toe region's onset, :func:`causes.toe_onset_cause`),
        the other cause's parameters held at ``flex_fit``'s (the model's fit on those signals). A rounded engagement's
        angle is searched within two of its widths of the hinge's corner (the width on its grid); a toe's onset over
        the stop's whole grid (a hinge can sit degrees away from the onset it stands in for, where the spline's knots
        leave room); then both refined by Nelder–Mead (on the width's log)."""
        prep_r = self.flex if signals is None else signals
        cause, _ = self.fit(model)
        held: dict[str, tuple[float, ...]] = {}
        i = 0
        for part in cause.parts or (cause,):
            held[part.name] = tuple(flex_fit.nonlinear[i:i + _nl_count(part)])
            i += _nl_count(part)
        others = [n for n in model if n != "hard_stop"]
        rival = compound(self.library[others[0]], stop_rival) if others else stop_rival
        hinge = held["hard_stop"][0]
        rounded = _nl_count(stop_rival) == 2

        def nonlinear(v: tuple[float, ...]) -> tuple[float, ...]:
            out: tuple[float, ...] = ()
            for part in rival.parts or (rival,):
                out += v if part.name == "hard_stop" else held[part.name]
            return out

        def mse(v: tuple[float, ...]) -> float:
            f = fit_cause(prep_r, rival, refine=False, start=nonlinear(v))
            return f.rss / max(f.n, 1) if f.n else math.inf

        rows: list[tuple[float, ...]]
        if rounded:
            rows = [(hinge + k * w, w) for w in stop_rival.grid(prep_r)[1] for k in np.linspace(-2, 2, 9)]
        else:
            rows = [(float(a),) for a in _stop_grid(prep_r)[0]]
        best = min(rows, key=mse)
        x0 = np.array([best[0], math.log(best[1])]) if rounded else np.array(best)

        def unpack(x: np.ndarray) -> tuple[float, ...]:
            return (float(x[0]), math.exp(float(x[1]))) if rounded else (float(x[0]),)

        refined = minimize(lambda x: mse(unpack(x)), x0, method="Nelder-Mead",
                           options={"xatol": 1e-4, "fatol": 1e-12, "maxiter": 120})
        if refined.fun < mse(best):
            best = unpack(refined.x)
        return fit_cause(prep_r, rival, refine=False, start=nonlinear(best))

    def smooth_rival(self, model: tuple[str, ...]) -> tuple[CauseFit, np.ndarray]:
        """``model`` with its stop replaced by a smooth stiffening at the stop's end of the range (one more
        exponential in the baseline, its rate the best of :data:`SMOOTH_END_RATES_PER_RAD`): the rival fit and
        its held-out residuals (N·m). A stop is a kink, the rival a steeper passive end: the same number of
        parameters, told apart by the data."""
        key = "+".join(model)
        if key not in self._smooth:
            end = self.stop_end(model)
            others = tuple(n for n in model if n != "hard_stop")
            rival = self.library[others[0]] if others else self.library["none"]
            start = self.fit(others)[1].nonlinear if others else ()
            def fitted(rate: float) -> tuple[CauseFit, Prepared]:
                p = self.prep.with_end_term(end, rate)
                return fit_cause(p, rival, refine=False, start=start or None), p

            def mse(log_rate: float) -> float:
                f_r = fitted(math.exp(log_rate))[0]
                return f_r.rss / max(f_r.n, 1)

            logs = np.log(SMOOTH_END_RATES_PER_RAD)
            grid = [mse(r) for r in logs]
            i = int(np.argmin(grid))
            refined = minimize_scalar(mse, bounds=(logs[max(i - 1, 0)], logs[min(i + 1, logs.size - 1)]),
                                      method="bounded", options={"xatol": 0.01})
            best, prep = fitted(math.exp(float(refined.x) if refined.fun < grid[i] else float(logs[i])))
            self._smooth[key] = (best, heldout_residuals(prep, rival, self.folds, start or None,
                                                         self.folds_of(model)[1]))
        return self._smooth[key]

    def stop_end(self, model: tuple[str, ...]) -> str:
        """The end of the range (``"low"``/``"high"``) the stop in ``model`` sits nearer."""
        stop = math.radians(self.fit(model)[1].params["stop_angle_deg"])
        return "high" if stop >= 0.5 * (self.prep.lo + self.prep.hi) else "low"

    def at_adopted_end(self, model: tuple[str, ...]) -> bool:
        """Whether the stop in ``model`` sits at an end where the baseline adopted a steeper passive curve
        (baseline_choice, the only source of the signals' end terms): the data there already preferred a smooth
        stiffening, and a stop beside it is the same curve steeper still, which one trial cannot tell from the spring's."""
        end = self.stop_end(model)
        return any(e == end for e, _ in self.prep.end_terms)

    def stop_beats_smooth_rival(self, model: tuple[str, ...]) -> bool:
        """Whether the stop in ``model`` predicts held-out blocks better than a smooth stiffening at its end by
        strong held-out evidence (n_eff · ln of their held-out MSE ratio > :data:`STRONG_HELDOUT_GAIN`, n_eff of
        the stop model's residual, as every held-out gain here) and fits the whole trial better too (the two
        have equal parameter counts), and predicts them better than the model without the stop on the flexible
        baseline (a free curve in angle) does.

        A Diebold–Mariano test of the same held-out errors was tried first: a stop's advantage sits in the few
        samples past it, so the squared-error differences are spiky and their own effective sample size small
        (54 of 2650 samples on a stop at 60× the noise, z = 2.0): it could not name even that stop."""
        _, f = self.fit(model)
        rival, rival_resid = self.smooth_rival(model)
        resid = self.heldout_residuals(model)
        ok = np.isfinite(resid) & np.isfinite(rival_resid)
        if ok.sum() < 10 or f.rss / max(f.n, 1) >= rival.rss / max(rival.n, 1):
            return False
        n_eff = effective_n(self.prep.torque - f.prediction)
        gain = n_eff * math.log(float(np.mean(rival_resid[ok] ** 2)) / float(np.mean(resid[ok] ** 2)))
        if gain <= STRONG_HELDOUT_GAIN:
            return False
        # and a free curve in angle (the flexible baseline's spline, without the stop) must predict the held-out
        # blocks worse: a stop is a kink, which the spline rounds off; a "stop" engaging deep in the range is a
        # passive curve of another shape, which the spline follows (development trials of the second to fifth
        # families, seeds 800000–800002, 288 trials: six spurious stops beside another cause or alone no longer
        # named, 232 → 238 right, every true stop found still found; the development generator's unchanged)
        # Measured and left out (7f36278): asking the flexible baseline *with* the stop to predict better than without
        # it too. False stops on clean development knee and ankle trials 15 → 12 of 180, but the development
        # generator's knee stops 0.50 → 0.33 and stop pairs 4 fewer of 93: the spline follows part of a true kink
        flex_resid = self.heldout_residuals(tuple(n for n in model if n != "hard_stop") or ("none",), flexible=True,
                                            folds_from=model)
        ok = np.isfinite(resid) & np.isfinite(flex_resid)
        return bool(ok.sum() >= 10 and float(np.mean(resid[ok] ** 2)) < float(np.mean(flex_resid[ok] ** 2)))

    def _part_to_noise(self, model: tuple[str, ...], part: str, signals: Prepared | None, fit: CauseFit | None,
                       count: int) -> tuple[np.ndarray, float]:
        """(the torque of ``count`` columns of the cause ``part`` in ``model``, the model's residual RMS): its parametric
        fit, or ``fit`` on ``signals`` (the flexible baseline's)."""
        cause, f = self.fit(model)
        f = f if fit is None else fit
        offset = _part_offset(cause, part)
        _, ext, valid = cause.columns(self.prep if signals is None else signals, f.nonlinear)
        effect = ext[valid][:, offset:offset + count] @ f.coef[f.n_base + offset:f.n_base + offset + count]
        return effect, math.sqrt(f.rss / max(f.n, 1))

    def peak_to_noise(self, model: tuple[str, ...], part: str = "hard_stop", signals: Prepared | None = None,
                      fit: CauseFit | None = None) -> float:
        """The largest torque of the one-column cause ``part`` (a hard stop: at the end of the range) in ``model`` over
        the model's residual RMS: its parametric fit, or ``fit`` on ``signals`` (the flexible baseline's,
        :meth:`stop_is_a_kink`)."""
        effect, noise = self._part_to_noise(model, part, signals, fit, 1)
        return float(np.max(np.abs(effect))) / noise if noise > 0 and effect.size else 0.0

    def swing_to_noise(self, model: tuple[str, ...], signals: Prepared | None = None, fit: CauseFit | None = None,
                       part: str = "sensor_drift") -> float:
        """Half the peak-to-peak torque of the cause ``part`` in ``model`` (all its columns; its mean is the baseline's
        offset) over the model's residual RMS: its parametric fit, or ``fit`` on ``signals`` (the flexible baseline's)."""
        cause = self.fit(model)[0]
        count = _ext_count(next(p for p in cause.parts or (cause,) if p.name == part))
        effect, noise = self._part_to_noise(model, part, signals, fit, count)
        return float(np.ptp(effect)) / 2.0 / noise if noise > 0 and effect.size else 0.0

    def stop_t(self, model: tuple[str, ...], n_eff: float) -> float:
        """t statistic of the hard stop's stiffness in ``model`` (its standard error inflated by n / n_eff)."""
        cause, f = self.fit(model)
        offset = _part_offset(cause)
        base, ext, valid = cause.columns(self.prep, f.nonlinear)
        x = np.hstack([base, ext])[valid]
        scale = np.maximum(np.abs(x).max(axis=0), 1e-12)
        s2 = f.rss / max(f.n - f.n_params, 1) * (f.n / n_eff)
        i = f.n_base + offset
        try:
            var = float(np.linalg.pinv((x / scale).T @ (x / scale))[i, i]) / scale[i] ** 2 * s2
        except np.linalg.LinAlgError:
            return 0.0
        return float(f.coef[i]) / math.sqrt(var) if var > 0 else 0.0


def diagnose(trial: DiagnosisTrial, *, causes: list[str] | None = None, folds: int = 5, min_delta_bic: float = 10.0,
             min_heldout_gain: float = 4.0, ambiguity_bic: float = 10.0, max_absorbed_r2: float = 0.999,
             min_angle_deg: float = 6.0, ambiguity_rmse: float = 0.05, max_rate_hz: float = MAX_RATE_HZ) -> Diagnosis:
    """Name what the baseline model of ``trial`` gets wrong, and a second effect if there is one.

    Forward selection (see the module docstring): every cause is tried against the baseline, then
    every other cause together with the winner; then the pairs of the best-fitting causes are tried
    whole (one effect can mask another, or lead the first step astray). Each step
    judges the larger model at its own residual's effective sample size. AFO trials are diagnosed
    at angles ≥ ``min_angle_deg`` (the spring is slack below its engagement). Trials sampled faster
    than ``max_rate_hz`` (Hz) are averaged down to it first.

    Rows with a missing time or a non-finite angle or torque are left out and counted (a note says so);
    trials longer than :data:`MAX_SAMPLES` at ``max_rate_hz`` are averaged down further (not below
    :data:`MIN_RATE_HZ`).

    :raises InputError: the trial has no usable samples, or its angle barely moves (less than
        :data:`MIN_RANGE_FRACTION` of its protocol's range).
    """
    lo_deg, hi_deg = NOMINAL_RANGE_DEG[trial.kind]
    covered = math.degrees(float(np.subtract(*np.percentile(trial.angle_rad, [99.0, 1.0]))))
    if covered < MIN_RANGE_FRACTION * (hi_deg - lo_deg):
        raise InputError(f"{trial.source or 'trial'}: the angle covers {covered:.2f}° of the {trial.kind} protocol's "
                         f"{hi_deg - lo_deg:g}° (at least {MIN_RANGE_FRACTION * (hi_deg - lo_deg):.1f}° needed): "
                         "nothing to diagnose in a joint that does not move")
    rate_in = trial.rate_hz
    duration = float(trial.time_s[-1] - trial.time_s[0])
    trial = trial.decimated(min(max_rate_hz, max(MIN_RATE_HZ, MAX_SAMPLES / max(duration, 1e-9))))
    prep = Prepared.of(trial, min_angle_deg if trial.kind == "afo" else None)
    names = [c for c in (causes or list(CAUSES)) if trial.kind in CAUSES[c].kinds]
    if "none" not in names:
        names.insert(0, "none")
    notes: list[str] = [trial.left_out_text()] if trial.rows_left_out else []
    # the baseline's own curve first: a steeper end where the data ask for it (baseline_choice), judged as a cause is
    prep, steeper = adopt_steeper_ends(prep, folds, min_delta_bic, min_heldout_gain)
    for end_term in steeper:
        notes.append(f"the passive curve stiffens at its {end_term.end} end faster than the baseline's family: an exponential of "
                     f"{end_term.rate_per_rad:.1f} /rad (an e-folding of {math.degrees(1.0 / end_term.rate_per_rad):.1f}°) was "
                     f"added to the baseline (ΔBIC {end_term.delta_bic:.0f}, held-out gain {end_term.heldout_gain:.0f}); "
                     "every cause is judged against that curve")
    if trial.rate_hz < 0.9 * min(rate_in, max_rate_hz):
        notes.append(f"diagnosed on block means at {trial.rate_hz:.0f} Hz ({trial.time_s.size} samples) of the "
                     f"{rate_in:.0f} Hz recording: a long trial is averaged down; effects faster than "
                     f"{trial.rate_hz / 5:.0f} Hz are not seen")
    moving = np.abs(prep.omega) > np.deg2rad(0.5)
    both_ways = (prep.omega[moving] > 0).mean() if moving.any() else 0.0
    if moving.sum() < 0.05 * prep.t.size:
        notes.append("the angle barely moves: velocity-dependent causes are not testable; record a movement")
        names = [n for n in names if n not in ("coulomb_friction", "viscous_damping", "time_delay")]
    elif not 0.05 < both_ways < 0.95:
        notes.append("the joint moves one way only: friction, damping and a delay are offsets here and cannot be "
                     "seen; record a return movement")
        names = [n for n in names if n not in ("coulomb_friction", "viscous_damping", "time_delay")]
    library = dict(CAUSES)
    search = _Search(prep, folds, min_delta_bic, min_heldout_gain, library)
    for n in LAW_VARIANTS:  # the search's friction and drift are the trial's likeliest laws, their fits already made
        if n in names:
            library[n], search.fits[n] = likeliest_law(prep, n, library, search.fits)
            search.causes[n] = library[n]
    for n in names:
        search.fit((n,))
    fits = {n: search.fits[n] for n in names}
    base = fits["none"]
    base_ho = search.heldout(("none",))
    # a cause that must also beat the flexible baseline (hysteretic: not a function of angle alone, or a series
    # compliance) cannot be shown where that baseline mimics it, and is judged there: a series compliance in a slow
    # trial turns the joint by θ − c·τ(θ), a curve in angle again. On spent trials of the fifteenth and seventeenth
    # families (clean and with a compliance, 48) its direction had R² > 0.999 on the flexible basis in 41, on the
    # parametric one in 23; no compliance was named in any of the sixteen held-out families run before
    absorbed = {n: absorbed_by_baseline(prep, library[n], f, flexible=library[n].hysteretic)
                for n, f in fits.items() if n != "none"}
    for n, r2 in absorbed.items():
        if r2 > max_absorbed_r2:
            notes.append(f"{n} cannot be told from the baseline in this trial (its effect is {100 * r2:.2f} % the "
                         f"baseline's own shape); it needs {UNTESTABLE_HINT.get(n, 'another protocol')}")
    testable = [n for n in names if n != "none" and absorbed.get(n, 0.0) <= max_absorbed_r2]
    single = {n: search.evidence((n,), ("none",)) for n in testable}
    cands = [Candidate("none", base.params, math.sqrt(base.rss / base.n), base_ho, bic(base, effective_n(
        prep.torque - base.prediction)), 0.0, 1.0, False)]
    for n in names:
        if n == "none":
            continue
        f = fits[n]
        ev = single.get(n)
        ho = ev.heldout_rmse if ev else float("nan")
        cands.append(Candidate(n, f.params, math.sqrt(f.rss / f.n), ho, bic(f, ev.n_eff) if ev else float("nan"),
                               ev.delta_bic if ev else float("nan"),
                               ho / base_ho if math.isfinite(ho) and base_ho > 0 else float("nan"),
                               bool(ev and ev.accepted),
                               ("transient: judged in-sample, no held-out blocks;" if CAUSES[n].transient else "")
                               + ("" if ev is None or not math.isfinite(ev.flexible_delta_bic) else
                                  f" ΔBIC {ev.flexible_delta_bic:.1f} against a free curve in angle")
                               + ("" if ev is None or not math.isfinite(ev.flexible_own_delta_bic) else
                                  f" ({ev.flexible_own_delta_bic:.1f} at that fit's own n_eff)")
                               + ("" if ev is None or ev.isolated is None else
                                  f"; as one event at its own time scale z {ev.isolated.z_event:.1f} against a level of "
                                  f"{ev.isolated.z_critical:.1f}, elsewhere at most {ev.isolated.z_elsewhere:.1f}")))
    accepted = [n for n in single if single[n].accepted]
    if accepted:
        # rank at one noise model for all: each cause's own residual gives its own n_eff, and a cause that
        # leaves a second effect's slow structure behind (friction beside a drift) gets the smallest n_eff
        # and the weakest ΔBIC although it fits best. The common n_eff is the best-fitting accepted cause's.
        # On fresh seeds of the independent generator (60000–62009, 10 per pair) AFO friction + drift went
        # from 3 to 10 of 10 (7 had been named damping alone) and all pairs 276 → 284 of 310; singles and
        # clean trials (seeds 50000–51005) named the same
        common_n_eff = effective_n(prep.torque - min((fits[n] for n in accepted), key=lambda f: f.rss / f.n).prediction)
        accepted.sort(key=lambda n: bic(fits[n], common_n_eff))
    chosen: tuple[str, ...] = ()
    if accepted:
        winner = accepted[0]
        chosen = (winner,)
        best: tuple[float, str] | None = None
        for other in testable:
            if other == winner or (other in ARGUMENT_CAUSES and winner in ARGUMENT_CAUSES):
                continue
            ev = search.evidence((winner, other), (winner,))
            if not ev.accepted:
                continue
            still = search.evidence((winner, other), (other,))  # the first stays needed beside the second
            if still.delta_bic < -min_delta_bic and (best is None or ev.delta_bic < best[0]):
                best = (ev.delta_bic, other)
        if best is not None:
            chosen = (winner, best[1])
    # one effect can hide another, or lead the forward step astray: the pairs of the best-fitting causes,
    # each cause tested given the other, replace the forward step's model when the criterion, at the
    # pair's own noise model, prefers them (by min_delta_bic over a single cause or the baseline). Fast
    # ankle sweeps with friction and a drift (seeds 102000–102001): damping alone → both named; fresh
    # pairs (60000–62009) 290 of 310 and 450 clean and 152 single-effect trials (70000–71007) unchanged
    top = sorted(testable, key=lambda n: fits[n].rss / fits[n].n)[:4]
    ref_fit = search.fit(chosen)[1] if chosen else base
    best_pair: tuple[float, tuple[str, str]] | None = None
    for a, b in itertools.combinations(top, 2):
        if (a in ARGUMENT_CAUSES and b in ARGUMENT_CAUSES) or {a, b} == set(chosen):
            continue
        _, pf = search.fit((a, b))
        pair_n_eff = effective_n(prep.torque - pf.prediction)  # the n_eff evidence() judges the pair at
        d = bic(pf, pair_n_eff) - bic(ref_fit, pair_n_eff)
        if d >= (0.0 if len(chosen) == 2 else -min_delta_bic) or (best_pair is not None and d >= best_pair[0]):
            continue  # the criterion alone rules it out: its held-out folds are not needed
        if search.evidence((a, b), (b,)).accepted and search.evidence((a, b), (a,)).accepted:
            best_pair = (d, (a, b))
    if best_pair is not None:
        a, b = best_pair[1]
        chosen = (a, b) if fits[a].rss <= fits[b].rss else (b, a)
    winner = chosen[0] if chosen else "none"
    ambiguous, separate = [], []
    if winner != "none":
        effect_w = fits[winner].prediction - base.prediction
        w_bic = single[winner].delta_bic if winner in single else 0.0
        for c in accepted:
            close = single[c].delta_bic - w_bic <= ambiguity_bic or \
                math.sqrt(fits[c].rss / fits[c].n) <= (1.0 + ambiguity_rmse) * math.sqrt(fits[winner].rss / fits[winner].n)
            if c == winner or not close or c in chosen:
                continue
            effect_c = fits[c].prediction - base.prediction
            ok = np.isfinite(effect_w) & np.isfinite(effect_c)
            if ok.sum() > 10 and np.std(effect_w[ok]) > 0 and np.std(effect_c[ok]) > 0:
                if abs(np.corrcoef(effect_w[ok], effect_c[ok])[0, 1]) > 0.9:
                    ambiguous.append(c)
                    hint = SEPARATE_BY.get(frozenset({winner, c}))
                    if hint:
                        separate.append(hint)
    if "hard_stop" not in chosen and search.stops_not_told_from_smooth:
        unsure = tuple(min(search.stops_not_told_from_smooth, key=len).split("+"))
        # a joint's stop is judged on the flexible baseline, its angle searched there (_Search.stop_is_a_kink)
        stop_fit = search.fit(unsure)[1] if prep.trial.kind not in ("knee", "ankle") else \
            search.flexible(unsure, searched=True)
        hint = AFO_STOP_OR_SPRING_HINT if prep.trial.kind == "afo" else STOP_OR_STEEPER_END_HINT
        if prep.trial.kind in ("knee", "ankle"):
            # the stop was left unsure by either test: a smooth stiffening at its end predicted held-out blocks as
            # well (the parametric test), or a rounded engagement or a toe's onset fitted it clearly better on the free
            # curve in angle (stop_is_a_kink); the opening words are the orthosis's note's, which reports count on
            notes.append(f"the end of the range stiffens beyond the baseline's passive curve from about "
                         f"{stop_fit.params['stop_angle_deg']:.0f}°: a stop, or a passive term steeper than the "
                         "baseline's or taken up over a few degrees (a toe region); this trial cannot tell them apart, so "
                         f"neither is named; to tell them apart: {hint}")
        else:
            curve = "the spring's curve" if prep.trial.kind == "afo" else "a passive term"
            notes.append(f"the end of the range stiffens beyond the baseline's passive curve from about "
                         f"{stop_fit.params['stop_angle_deg']:.0f}°: a stop, or {curve} steeper than the baseline's; "
                         "this trial cannot tell them apart (the stop does not predict held-out blocks clearly better), "
                         f"so neither is named; to tell them apart: {hint}")
        separate.append(hint)
    if "activation_burst" not in chosen and search.bursts_at_unrevisited_angles:
        notes.append(f"an event about {min(search.bursts_at_unrevisited_angles):.0f} s into the trial lies at angles the "
                     "trial reaches only then: a burst, or the passive curve at those angles, which this trial cannot "
                     f"tell apart, so neither is named; to tell them apart: {BURST_OR_UNREVISITED_HINT}")
    drift_swings = search.swings_below_noise.get("sensor_drift", [])
    if "sensor_drift" not in chosen and drift_swings:
        notes.append(f"the torque's zero wanders by about {max(drift_swings):.1f} × the residual noise: "
                     "below the noise, so no drift is named (a gain changing slowly or mains hum aliased to a slow beat "
                     "does this); zero the sensor before the trial, and read small torques with that in mind")
    loop_swings = [*search.swings_below_noise.get("coulomb_friction", []), *search.swings_below_noise.get("viscous_damping", [])]
    if loop_swings and not {"coulomb_friction", "viscous_damping"}.intersection(chosen):
        notes.append(f"loading and unloading differ by about {max(loop_swings):.1f} × the residual noise (a loop): below "
                     "the noise, so no friction or damping is named (play of a few hundredths of a degree in the angle's "
                     "coupling does this, as does a little friction); check the encoder's coupling for play")
    final_cause, final = search.fit(chosen) if chosen else (CAUSES["none"], base)
    n_eff = effective_n(prep.torque - final.prediction)
    if n_eff <= 20:
        notes.append(f"the residual holds only about {n_eff:.0f} independent samples (a short or heavily filtered "
                     "trial, or several effects at once): record a longer trial with more bends before trusting "
                     "a 'none'")
    also: list[dict[str, Any]] = []
    params = final.params
    if len(chosen) == 2:
        second = chosen[1]
        ev2 = search.evidence(chosen, (winner,))
        first_keys = set(fits[winner].params)
        extra = {k: v for k, v in final.params.items() if k not in first_keys}
        params = {k: v for k, v in final.params.items() if k in first_keys}
        also.append({"cause": second, "parameters": extra, "delta_bic_vs_single": ev2.delta_bic,
                     "heldout_ratio_vs_single": (ev2.heldout_rmse / search.heldout((winner,))
                                                 if math.isfinite(ev2.heldout_rmse) else None),
                     "rmse_Nm": math.sqrt(final.rss / final.n)})
    se = parameter_se(prep, final_cause, final, n_eff) if chosen else {}
    for name in chosen:
        key = CAUSES[name].magnitude_key
        if not key or not (key in params or (also and key in also[0]["parameters"])):
            continue
        variants = magnitude_variants(prep, name, math.radians(final.params.get("stop_angle_deg", math.nan)))
        # the magnitude: the variants' weighted mean; its variance: within plus between the variants
        fitted = average_variants(variants, chosen, n_eff, library)
        mean, mean_se = averaged_magnitude(fitted, key)
        likeliest = max(fitted, key=lambda o: o.weight)
        holder = params if key in params else also[0]["parameters"]
        holder.update({k: v for k, v in likeliest.params.items() if k in holder}, **{key: mean})
        se.update({k: v for k, v in likeliest.se.items() if k in holder},
                  **{key: mean_se})
        notes.append(f"{name}: {key} averaged over " + ", ".join(f"{o.label} ({o.weight:.2f})" for o in fitted)
                     + f"; its other parameters from the likeliest ({likeliest.label})")
    named_params = {**params, **(also[0]["parameters"] if also else {})}
    if "friction_Nm" in named_params:
        notes.append(play_alike_text(prep, base, float(named_params["friction_Nm"])))
    if "damping_Nm_s_per_rad" in named_params:
        notes.append(lag_alike_text(prep, base, float(named_params["damping_Nm_s_per_rad"])))
    systematic = systematic_regions(prep, prep.torque - base.prediction, n_eff)
    ho_final = search.heldout(chosen) if chosen and not final_cause.transient else (base_ho if not chosen else float("nan"))
    delta = bic(final, n_eff) - bic(base, n_eff) if chosen else 0.0
    return Diagnosis(trial.kind, winner, params, math.sqrt(base.rss / base.n), math.sqrt(final.rss / final.n), base_ho,
                     ho_final, ho_final / base_ho if chosen and math.isfinite(ho_final) and base_ho > 0 else
                     (1.0 if not chosen else float("nan")), delta, n_eff, cands, ambiguous, separate, notes, fits, prep,
                     also, se, systematic, dict(trial.rows_left_out))


__all__ = ["LOCAL_STOP_T", "MAX_RATE_HZ", "Candidate", "CauseFit", "Diagnosis", "diagnose", "effective_n", "fit_cause",
           "likeliest_law", "magnitude"]
