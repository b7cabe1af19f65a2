"""The stopping rule: when a candidate may be added (a one-sided
Diebold-Mariano test on the out-of-sample errors, a relative gain and a
material one), and when a fitted parameter does not mean what its name says
(at the top of its search range, or shorter than the record resolves).

A candidate with the lowest CV RMS is added only if
  * its out-of-sample squared errors beat the current model's in a one-sided
    Diebold-Mariano test (mean loss differential, HAC/Newey-West standard
    error over a window as long as the new residual stays correlated, at
    most n / `hac_blocks` samples; statsmodels OLS) at
    p < alpha / (number of candidate families tried in that step) (Bonferroni;
    a family's variant, such as an order or a start branch, is chosen by CV
    as the offset shape's size is), and
  * the systematic error of a reported reading drops by at least `min_gain`
    (relative) and by at least `material` x that reading's noise."""
import numpy as np
from scipy import stats
import statsmodels.api as sm
from statsmodels.tsa.stattools import acf

from . import _robust as robust

EDGE_LOG_MARGIN = 0.05         # within 5 % of the largest value the record resolves
MIN_TAU_PERIODS = 3.0          # a shorter time constant only smooths noise
SOKAL_C = 5.0                  # a HAC window of 5 integrated autocorrelation times (Sokal)
MIN_WIDTH_NOISE = 3.0          # a narrower play operator only smooths the temperature's noise


def decorrelation_window(e, cap):
    """Samples over which `e` stays correlated: Sokal's automatic window,
    the smallest M with M >= SOKAL_C x the integrated autocorrelation time
    1 + 2 sum_{k<=M} acf(k) (statsmodels acf), at most `cap`."""
    e = e[np.isfinite(e)]
    cap = int(max(1, min(cap, e.size - 1)))
    r = acf(e - e.mean(), nlags=cap, fft=True)
    tau_int = 1.0 + 2.0 * np.cumsum(r[1:])
    fits = np.flatnonzero(np.arange(1, tau_int.size + 1) >= SOKAL_C * tau_int)
    return int(fits[0] + 1) if fits.size else cap


def improvement_p(e_old, e_new, blocks):
    """One-sided Diebold-Mariano p-value that e_new predicts better than
    e_old: the loss differential d = e_old^2 - e_new^2 regressed on a
    constant (statsmodels OLS) with a HAC (Newey-West) standard error, so
    autocorrelated losses do not overstate the evidence.

    The HAC window is how long the new model's out-of-sample residual stays
    correlated (decorrelation_window), at most n / blocks samples.  The
    random part of d is 2 (e_old - e_new) e_new: it is as correlated as
    e_new.  A fixed window of a twentieth of the record, whatever the
    residual, counted the gain's own shape as noise: a gain confined to one
    such window (a warm-up at the start of a record) could never be
    significant, however large; and it was too short for a residual that
    wanders for longer (a random-walk zero), whose chance gains it
    overstated.  Where structure is left unexplained e_new stays correlated
    and the window grows, up to a fifth of the record by default."""
    ok = np.isfinite(e_old) & np.isfinite(e_new)
    d = e_old[ok] ** 2 - e_new[ok] ** 2
    if d.size < 10 or not np.any(d):
        return 1.0
    lags = decorrelation_window(e_new[ok], max(1, d.size // blocks))
    res = sm.OLS(d, np.ones(d.size)).fit(cov_type="HAC", cov_kwds={"maxlags": lags})
    se = float(res.bse[0])
    if not se > 0:
        return 0.0 if d.mean() > 0 else 1.0
    return float(stats.norm.sf(float(res.params[0]) / se))



def judge(e_old, e_new, opts, per_report, n_tried):
    """The stopping rule on two out-of-sample residuals: (accepted, p,
    threshold, systematic before, after, relative gain, removed, noise)."""
    p = improvement_p(e_old, e_new, opts.hac_blocks)
    threshold = opts.alpha / n_tried
    sigma = robust.white_sigma(e_old)
    sys_old = robust.systematic_rms(e_old, per_report, sigma)
    sys_new = robust.systematic_rms(e_new, per_report, robust.white_sigma(e_new))
    gain = 1.0 - sys_new / sys_old if sys_old > 0 else 0.0
    removed = float(np.sqrt(max(0.0, sys_old ** 2 - sys_new ** 2)))
    noise = sigma / np.sqrt(per_report)
    verdict = {"p_value": p, "p_threshold": threshold, "cv_systematic": sys_new,
               "cv_systematic_now": sys_old, "systematic_gain": gain,
               "systematic_removed": removed, "reading_noise": float(noise)}
    return p < threshold and material(verdict, opts), verdict


def material(verdict, opts):
    """The practical half of the rule on a `judge` verdict: the systematic
    error of a reading falls by >= min_gain and by >= material x its noise."""
    return (verdict["systematic_gain"] >= opts.min_gain
            and verdict["systematic_removed"] >= opts.material * verdict["reading_noise"])


STOP_TEST = ("add the candidate with the lowest blocked-CV RMS only if a one-sided Diebold-Mariano "
             "test on the out-of-sample squared-error differential (HAC standard error, window "
             "as long as the new residual stays correlated, at most n/{tb} samples) gives p < {a} / (candidate families tried; a family's variant chosen "
             "by CV), the systematic error of a reading averaged over {r:g} s falls by >= {g:.0%} and by at least {m:g} x that reading's "
             "noise (in quadrature); impulses are left out of fitting and scoring")


def stop_test(opts):
    return STOP_TEST.format(tb=opts.hac_blocks, a=opts.alpha, g=opts.min_gain, r=opts.report_s,
                            m=opts.material)


def at_search_edge(data, family, spec):
    """None, or what is wrong when `family`'s fitted parameter in `spec` sits
    at the largest value the record resolves (family.limit: a time constant
    of the whole record, a hysteresis width of the whole span; the search
    follows a fit past its first range up to there): the term is then a slow
    trend in time or a line in temperature wearing the effect's name (a step
    in time pulls creep's time constant there).  Such a candidate is not
    tried; what is left shows as unexplained."""
    if family.param_name is None:
        return None
    eff = next(e for e in spec.effects if e.name == family.name)
    hi = family.limit(data)
    if np.log(eff.param) < np.log(hi) - EDGE_LOG_MARGIN:
        return None
    return {family.param_name: eff.param, "search_top": float(hi)}


def not_physical(data, family, spec, opts, t_sigma):
    """None, or why `family`'s fitted parameter in `spec` does not mean
    what its name says: a time constant under MIN_TAU_PERIODS sample periods
    only smooths noise (no lag, creep or warm-up is resolved that fast); a
    play-operator width under MIN_WIDTH_NOISE x the temperature reading's
    noise only smooths that noise."""
    if family.param_name is None:
        return None
    eff = next(e for e in spec.effects if e.name == family.name)
    if family.param_name == "tau_s" and eff.param < MIN_TAU_PERIODS * data.dt:
        return {"tau_s": eff.param, "reason": (
            f"time constant {eff.param:.3g} s is under {MIN_TAU_PERIODS:g} sample periods "
            f"({MIN_TAU_PERIODS * data.dt:.3g} s): noise smoothing, not a physical {family.name}")}
    if family.name == "hysteresis" and eff.param < MIN_WIDTH_NOISE * t_sigma:
        return {"width": eff.param, "reason": (
            f"width {eff.param:.3g} is under {MIN_WIDTH_NOISE:g} x the temperature noise "
            f"({t_sigma:.3g}): smoothing of the temperature reading, not a hysteresis")}
    return None
