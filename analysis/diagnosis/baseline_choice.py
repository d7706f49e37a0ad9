"""The baseline's passive curve chosen per trial: a steeper end adopted where the data ask for it.

The baseline is a fixed family (an orthosis's spring a quadratic in angle; a joint's passive moment a cubic with
exponentials of fixed rates at its ends: :func:`causes.baseline_columns`). A passive curve stiffening faster than that
family at an end (an orthosis's band or strap stiffening exponentially, a joint whose end is steeper than the published
terms) leaves a residual many times the noise: every other cause is then judged against the misfit, not the noise, and
none is named. The remedy is the one the causes get: a model extension judged by the same criterion. One more
exponential at either end, its rate the best of :data:`causes.SMOOTH_END_RATES_PER_RAD` (the smooth rival a stop is
judged against), joins the baseline when it lowers the criterion by more than the search's ``min_delta_bic`` (its
rate counted as a parameter) and predicts held-out blocks better by the search's ``min_heldout_gain``. At most two,
the better-fitting first, at either end (a second rate at the same end too). A stop is then judged against this
baseline, still by its own tests (a stop is a kink; the adopted end is smooth).

A smooth end is adopted only where it fits better than a kink at the best angle would (a hinge stop: the same count of
parameters): without that, the development generator's hinge stops at 21° on a linear spring (the AADS test's) were
taken into an adopted end and refused (18 of 20 of its random AFO effects right, a test's floor is 19). And a stop at an
end the baseline adopted is not named (engine._Search.at_adopted_end; it is said, as a stop the smooth rival matches):
the data there already preferred a smooth stiffening, and a kink beside it is that curve steeper still, which one bend
cannot tell from the spring's (on the spent thirty-second family's Hart-Smith bands, exponential in the squared
invariant, stops beside an adopted end were named in 11 of 67 AFO trials hiding none).

Only an orthosis's spring: its baseline is a bare quadratic. A joint's already carries exponentials at the published
passive terms' rates at both ends, and its stop tests judge a steeper end as the stop's rival (engine._Search.smooth_rival);
tried on the joints too, a clean knee of the spent thirty-second family (seed 100) adopted a 7.5 /rad low end and then
named a stop at 42° (a passive end's onset)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .causes import CAUSES, SMOOTH_END_RATES_PER_RAD, Prepared
from .evidence import bic, effective_n, heldout_residuals
from .fitting import CauseFit, fit_cause


@dataclass(frozen=True)
class AdoptedEnd:
    """An exponential adopted into the baseline: its end (``"low"``/``"high"``), its rate (1/rad), the criterion's
    change (ΔBIC, its rate counted) and the held-out gain (n_eff · ln of the held-out MSE ratio) it was adopted at."""

    end: str
    rate_per_rad: float
    delta_bic: float
    heldout_gain: float


def _heldout_mse(prep: Prepared, folds: int) -> float:
    resid = heldout_residuals(prep, CAUSES["none"], folds)
    resid = resid[np.isfinite(resid)]
    return float(np.mean(resid**2)) if resid.size else math.inf


def adopt_steeper_ends(prep: Prepared, folds: int, min_delta_bic: float, min_heldout_gain: float
                       ) -> tuple[Prepared, list[AdoptedEnd]]:
    """``prep`` with the steeper ends its data ask for (an orthosis's only), and what was adopted."""
    if prep.trial.kind != "afo":
        return prep, []
    adopted: list[AdoptedEnd] = []
    current: CauseFit = fit_cause(prep, CAUSES["none"])
    current_ho = _heldout_mse(prep, folds)
    for _ in range(2):
        taken = {(a.end, a.rate_per_rad) for a in adopted}
        trials: list[tuple[float, str, float, Prepared, CauseFit]] = []
        for end in ("low", "high"):
            for rate in SMOOTH_END_RATES_PER_RAD:
                if (end, float(rate)) in taken:
                    continue
                p = prep.with_end_term(end, float(rate))
                f = fit_cause(p, CAUSES["none"])
                trials.append((f.rss, end, float(rate), p, f))
        if not trials:
            break
        _, end, rate, p, f = min(trials, key=lambda row: row[0])
        # a smooth end only where it fits better than a kink would (a stop: the same count of parameters, an angle and a
        # stiffness against a rate and an amplitude); where the kink fits better, the stop's own tests decide
        if fit_cause(prep, CAUSES["hard_stop"]).rss <= f.rss:
            break
        n_eff = effective_n(p.torque - f.prediction)
        delta = bic(f, n_eff) + math.log(n_eff) - bic(current, n_eff)  # the searched rate counted as a parameter
        ho = _heldout_mse(p, folds)
        gain = n_eff * math.log(current_ho / ho) if ho > 0 and math.isfinite(current_ho) else -math.inf
        if not (delta < -min_delta_bic and gain > min_heldout_gain):
            break
        adopted.append(AdoptedEnd(end, rate, delta, gain))
        prep, current, current_ho = p, f, ho
    return prep, adopted


__all__ = ["AdoptedEnd", "adopt_steeper_ends"]
