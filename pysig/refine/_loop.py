"""The refinement loop: fit the base model, look at the residual,
add the candidate effect that most lowers the out-of-sample error, repeat
while the gain is significant, and say when structure is left that no
candidate explains.

Out-of-sample error: cross-validation blocked in time.  The samples are cut
into `folds` contiguous blocks; each block is predicted by a model fitted on
the others minus a guard band of `gap` samples on each side of it, so a lag
or a drift cannot leak from neighbouring samples into the test block.  A
candidate's nonlinear parameter (time constant, width) is chosen inside each
fold on its training samples only.

Stopping rule (the significance test): the candidate with the lowest CV RMS
is added only if
  * its out-of-sample squared errors beat the current model's in a one-sided
    Diebold-Mariano test (mean loss differential, HAC/Newey-West standard
    error over a window of n / `test_blocks` samples; statsmodels OLS) at
    p < alpha / (number of candidates tried in that step) (Bonferroni), and
  * the CV RMS drops by at least `min_gain` (relative; default 2 %).
A candidate whose fitted time constant or width sits at the top of its
search range is not tried (see at_search_edge).

Unexplained structure: on the final residual, statsmodels' Ljung-Box test
(acorr_ljungbox) for autocorrelation, and a one-way ANOVA of the residual
across contiguous time blocks (scipy.stats.f_oneway) for a trend against
time.  `unexplained` is true when Ljung-Box p < 1e-3 and the structure is
material: lag-1 autocorrelation >= 0.2 or the time blocks carry >= 10 % of
the residual variance.  It is never attributed to a named effect."""
from dataclasses import dataclass, field, replace

import numpy as np
from scipy import stats
import statsmodels.api as sm
from statsmodels.stats.diagnostic import acorr_ljungbox

from . import _effect_models as fx
from . import _robust as robust
from ._shape import shape_trials
from ..errors import InsufficientDataError
from ..lsq import fit_linear_model

DEFAULT_FOLDS = 10
DEFAULT_TEST_BLOCKS = 20
DEFAULT_ALPHA = 0.05
DEFAULT_MIN_GAIN = 0.02
MAX_BASE_ORDER = 5
LB_P = 1e-3
ACF1_MATERIAL = 0.2
TIME_R2_MATERIAL = 0.10
EDGE_LOG_MARGIN = 0.05         # within 5 % of the top of a parameter's search range
DEFAULT_REPORT_S = 10.0        # a reported reading averages this long
DEFAULT_MATERIAL = 0.5         # removed systematic error, in units of a reported reading's noise
MIN_TAU_PERIODS = 3.0          # a shorter time constant only smooths noise
MIN_WIDTH_NOISE = 3.0          # a narrower play operator only smooths the temperature's noise


@dataclass
class Options:
    folds: int = DEFAULT_FOLDS
    gap: int = None              # guard band (samples); default n // (4 * folds)
    test_blocks: int = DEFAULT_TEST_BLOCKS
    alpha: float = DEFAULT_ALPHA
    min_gain: float = DEFAULT_MIN_GAIN
    max_steps: int = 6
    families: tuple = tuple(fx.FAMILIES)
    report_s: float = DEFAULT_REPORT_S      # time a reported reading averages over
    material: float = DEFAULT_MATERIAL
    impulse_k: float = robust.HAMPEL_K      # None: no impulse screening
    shape: bool = True                      # try a larger polynomial or a table for the offset


# ---- blocked cross-validation --------------------------------------------------

def fold_rows(n, folds, gap):
    """(train, test) boolean masks of each contiguous time block."""
    edges = np.linspace(0, n, folds + 1).round().astype(int)
    out = []
    idx = np.arange(n)
    for a, b in zip(edges[:-1], edges[1:]):
        test = (idx >= a) & (idx < b)
        train = (idx < a - gap) | (idx >= b + gap)
        out.append((train, test))
    return out


def bridge_rows(X_train, names):
    """Rows tying the table knots the training rows do not determine (a
    held-out block falls between them) to their neighbours by a zero second
    difference, so the table is linear across the gap, as interpolating
    firmware would be (pysig.tcomp._table_fit bridges the same way).  Returns
    (rows, zeros) to stack under the training design, or None."""
    idx = [j for j, nm in enumerate(names) if nm.startswith(fx.TABLE_PREFIX)]
    if len(idx) < 3:
        return None
    weight = X_train[:, idx].sum(axis=0)
    weak = [k for k in range(len(idx)) if weight[k] < 0.5]
    if not weak:
        return None
    rows = np.zeros((len(weak), X_train.shape[1]))
    for r, k in enumerate(weak):
        c = min(max(k, 1), len(idx) - 2)
        rows[r, idx[c - 1]], rows[r, idx[c]], rows[r, idx[c + 1]] = 1.0, -2.0, 1.0
    return rows, np.zeros(len(weak))


def fit_rows(X, y, rows, names):
    """Least squares of X[rows] on y[rows], table knots bridged (bridge_rows)."""
    Xt, yt = X[rows], y[rows]
    extra = bridge_rows(Xt, names)
    if extra is not None:
        Xt, yt = np.vstack([Xt, extra[0]]), np.concatenate([yt, extra[1]])
    return fit_linear_model(Xt, yt, what="refine cv")


def cv_residual(data, spec, opts, candidate=None):
    """Out-of-sample residual of `spec` (+ `candidate`, a (family, variant)
    whose nonlinear parameter is chosen per fold on the training rows).
    NaN where the sample is masked out."""
    gap = opts.gap if opts.gap is not None else max(1, data.n // (4 * opts.folds))
    specs = [spec]
    if candidate is not None:
        fam, variant = candidate
        specs = [spec.with_effect(fx.Effect(fam.name, variant, p)) for p in fam.grid(data)]
    designs = [fx.design(data, s) for s in specs]
    e = np.full(data.n, np.nan)
    for train, test in fold_rows(data.n, opts.folds, gap):
        tr = train & data.mask
        te = test & data.mask
        if not te.any():
            continue
        if tr.sum() < designs[0][0].shape[1] + 1:
            raise InsufficientDataError(
                f"refine: a cross-validation fold keeps {int(tr.sum())} training samples for "
                f"{designs[0][0].shape[1]} parameters; use fewer folds or more data")
        best = None
        for X, names in designs:
            beta, _ = fit_rows(X, data.y, tr, names)
            res = data.y[tr] - X[tr] @ beta
            sse = float(res @ res)
            if best is None or sse < best[0]:
                best = (sse, X, beta)
        _, X, beta = best
        e[te] = data.y[te] - X[te] @ beta
    return e


def rms(e):
    e = e[np.isfinite(e)]
    return float(np.sqrt(np.mean(e ** 2))) if e.size else float("nan")


def block_mse(e, blocks):
    """Mean squared error of each contiguous block (NaNs skipped)."""
    out = []
    for part in np.array_split(e, blocks):
        part = part[np.isfinite(part)]
        out.append(float(np.mean(part ** 2)) if part.size else np.nan)
    return np.asarray(out)


def improvement_p(e_old, e_new, blocks):
    """One-sided Diebold-Mariano p-value that e_new predicts better than
    e_old: the loss differential d = e_old^2 - e_new^2 regressed on a
    constant (statsmodels OLS) with a HAC (Newey-West) standard error whose
    window is one time block (n / blocks samples), so autocorrelated losses
    do not overstate the evidence."""
    ok = np.isfinite(e_old) & np.isfinite(e_new)
    d = e_old[ok] ** 2 - e_new[ok] ** 2
    if d.size < 10 or not np.any(d):
        return 1.0
    lags = int(max(1, d.size // blocks))
    res = sm.OLS(d, np.ones(d.size)).fit(cov_type="HAC", cov_kwds={"maxlags": lags})
    se = float(res.bse[0])
    if not se > 0:
        return 0.0 if d.mean() > 0 else 1.0
    return float(stats.norm.sf(float(res.params[0]) / se))


# ---- base model ------------------------------------------------------------------

def choose_base_order(data, opts, effects=()):
    """Offset order by blocked CV (1..5, bounded by distinct temperatures),
    with `effects` in the model; 0 when there is no temperature.
    Returns (order, {order: cv_rms})."""
    if data.T is None:
        return 0, {}
    distinct = np.unique(data.T[data.mask]).size
    orders = range(1, max(1, min(MAX_BASE_ORDER, distinct - 1)) + 1)
    scores = {}
    for p in orders:
        try:
            scores[p] = rms(cv_residual(data, fx.ModelSpec(p, tuple(effects)), opts))
        except InsufficientDataError:
            break
    if not scores:
        raise InsufficientDataError("refine: too few samples for an offset polynomial of order 1")
    return min(scores, key=scores.get), scores


# ---- residual diagnostics -----------------------------------------------------

def residual_diagnostics(data, resid, blocks=DEFAULT_TEST_BLOCKS):
    """What is left: Ljung-Box, lag-1 autocorrelation, structure against time."""
    e = resid[data.mask]
    n = e.size
    lags = int(max(1, min(20, n // 5)))
    lb = acorr_ljungbox(e - e.mean(), lags=[lags], return_df=True)
    lb_p = float(lb["lb_pvalue"].iloc[0])
    ec = e - e.mean()
    denom = float(ec @ ec)
    acf1 = float(ec[1:] @ ec[:-1] / denom) if denom > 0 and n > 2 else 0.0
    nb = int(max(2, min(blocks, n // 5)))
    parts = [p for p in np.array_split(e, nb) if p.size >= 2]
    if len(parts) >= 2 and denom > 0:
        f_p = float(stats.f_oneway(*parts).pvalue)
        between = sum(p.size * (p.mean() - e.mean()) ** 2 for p in parts)
        time_r2 = float(between / denom)
    else:
        f_p, time_r2 = 1.0, 0.0
    t_used = data.t[data.mask]
    slope = stats.linregress(t_used, e) if n > 2 and np.ptp(t_used) > 0 else None
    structured = lb_p < LB_P and (acf1 >= ACF1_MATERIAL or time_r2 >= TIME_R2_MATERIAL)
    return {
        "ljung_box_lags": lags,
        "ljung_box_p": lb_p,
        "acf_lag1": acf1,
        "time_blocks": len(parts),
        "time_blocks_anova_p": f_p,
        "time_blocks_r2": time_r2,
        "time_slope_per_s": float(slope.slope) if slope is not None else 0.0,
        "time_slope_p": float(slope.pvalue) if slope is not None else 1.0,
        "structured": bool(structured),
    }


def candidate_relations(data, model):
    """How much of the current residual each absent candidate's regressors
    explain in-sample (partial R^2 at its best parameter): the pointer to
    the missing term."""
    out = {}
    resid_ss = float(np.sum(model.residual[data.mask] ** 2))
    for fam in fx.FAMILIES.values():
        if fam.name in model.spec.names() or fam.unavailable(data):
            continue
        best = None
        for v in fam.variants:
            m = fx.fit_param(data, model.spec, fam, v)
            ss = float(np.sum(m.residual[data.mask] ** 2))
            if best is None or ss < best:
                best = ss
        out[fam.name] = 1.0 - best / resid_ss if resid_ss > 0 else 0.0
    return out


def at_search_edge(data, family, spec):
    """None, or what is wrong when `family`'s fitted parameter in `spec` sits
    at the top of its search range (a time constant of a third of the record,
    a hysteresis width of 30 % of the span): the record does not resolve it,
    and the term is then a slow trend in time wearing the effect's name (a
    step in time pulls creep's time constant there).  Such a candidate is
    not tried; what is left shows as unexplained."""
    if family.param_name is None:
        return None
    eff = next(e for e in spec.effects if e.name == family.name)
    hi = family.bounds(data)[1]
    if np.log(eff.param) < np.log(hi) - EDGE_LOG_MARGIN:
        return None
    return {family.param_name: eff.param, "search_top": float(hi)}


def repolish(data, spec, passes=2):
    """Refit every nonlinear parameter in turn with the others held
    (coordinate passes), so an effect fitted before a later one is not stuck
    with the value it took when the model lacked the later one."""
    model = fx.fit(data, spec)
    n_nonlinear = sum(1 for e in spec.effects if fx.FAMILIES[e.name].param_name)
    for _ in range(passes if n_nonlinear > 1 else 1):
        for e in spec.effects:
            fam = fx.FAMILIES[e.name]
            if fam.param_name is None:
                continue
            model = fx.fit_param(data, model.spec.without(e.name), fam, e.variant)
    return model


def reselect(data, model, opts):
    """After an effect is added: choose the offset order again with the
    effects in place (a lag, for one, changes which order fits), then
    re-polish the nonlinear parameters."""
    if data.T is None or model.spec.base_family != "poly":
        return model
    order, _ = choose_base_order(data, opts, model.spec.effects)
    if order == model.spec.base_order:
        return model
    return repolish(data, fx.ModelSpec(order, model.spec.effects))


def plateau_reference(y, t):
    """Reference for a weighing run given without --ref and --temp: the
    level of each held load (pysig.weigh._calibration.find_plateaus, median of the
    plateau).  Samples between plateaus (the load moving) and read glitches
    are masked out of fitting and scoring; the reference steps to the next
    level where the transition starts, so a creep term sees the step.
    Returns (reference, mask, number of plateaus)."""
    from ..weigh._calibration import find_plateaus, glitch_indices
    y = np.asarray(y, dtype=float)
    dt = float(np.median(np.diff(t)))
    plateaus = find_plateaus(y, 1.0 / dt)
    if len(plateaus) < 2:
        raise InsufficientDataError(
            f"refine: without --ref and --temp the reference is the held load levels, "
            f"and {len(plateaus)} plateau(s) were found; need at least 2 (or give --ref)")
    r = np.empty(y.size)
    mask = np.zeros(y.size, dtype=bool)
    start = 0
    for p in plateaus:
        r[start:p.stop] = p.level
        mask[p.start:p.stop] = True
        start = p.stop
    r[start:] = plateaus[-1].level
    mask[glitch_indices(y)] = False
    return r, mask, len(plateaus)


# ---- the loop ----------------------------------------------------------------------

@dataclass
class Step:
    effect: str
    params: dict
    rms_before: float
    rms_after: float
    cv_rms_before: float
    cv_rms_after: float
    p_value: float
    candidates: list = field(default_factory=list)
    cv_systematic_before: float = float("nan")
    cv_systematic_after: float = float("nan")

    def as_dict(self):
        return {"effect": self.effect, "params": self.params,
                "rms_before": self.rms_before, "rms_after": self.rms_after,
                "cv_rms_before": self.cv_rms_before, "cv_rms_after": self.cv_rms_after,
                "cv_systematic_before": self.cv_systematic_before,
                "cv_systematic_after": self.cv_systematic_after,
                "p_value": self.p_value, "candidates": self.candidates}


@dataclass
class Result:
    data: fx.FitData
    base: fx.FittedModel
    final: fx.FittedModel
    base_order_cv: dict
    steps: list
    rejected: list               # the best candidate of the last round, not added
    at_edge: list                # candidates of the last round left out: parameter at the search edge
    base_cv_rms: float
    final_cv_rms: float
    diagnostics_before: dict
    diagnostics_after: dict
    relations_before: dict
    unavailable: dict
    test: str
    used: np.ndarray = None      # samples usable before impulse screening
    impulses: np.ndarray = None  # samples treated as impulses
    not_claimed: list = field(default_factory=list)
    per_report: int = 1          # samples in one reported reading
    report_s: float = DEFAULT_REPORT_S

    @property
    def base_rms(self):
        return self.base.rms(self.data.mask)

    @property
    def final_rms(self):
        return self.final.rms(self.data.mask)

    def figures(self, model):
        """Robust (impulses left out) and plain (impulses in) per-sample RMS,
        the RMS of a reported reading (the residual averaged over report_s)
        and its systematic part."""
        robust_e = np.where(self.data.mask, model.residual, np.nan)
        out = robust.figures(robust_e, self.per_report)
        used = self.used if self.used is not None else self.data.mask
        out["plain_rms"] = float(np.sqrt(np.mean(model.residual[used] ** 2)))
        out["plain_averaged_rms"] = robust.averaged_rms(np.where(used, model.residual, np.nan),
                                                        self.per_report)
        return out

    def report(self):
        d = self.diagnostics_after
        unexplained = {"unexplained": bool(d["structured"])}
        unexplained.update({k: v for k, v in d.items() if k != "structured"})
        if d["structured"]:
            what = []
            if d["acf_lag1"] >= ACF1_MATERIAL:
                what.append(f"residual autocorrelated (lag-1 r = {d['acf_lag1']:.2f}, "
                            f"Ljung-Box p = {d['ljung_box_p']:.2g})")
            if d["time_blocks_r2"] >= TIME_R2_MATERIAL:
                what.append(f"residual varies with time ({100 * d['time_blocks_r2']:.0f} % of its "
                            f"variance between {d['time_blocks']} time blocks, "
                            f"ANOVA p = {d['time_blocks_anova_p']:.2g})")
            unexplained["seen"] = "; ".join(what)
        n_imp = int(self.impulses.sum()) if self.impulses is not None else 0
        return {
            "base_rms": self.base_rms,
            "final_rms": self.final_rms,
            "base_cv_rms": self.base_cv_rms,
            "final_cv_rms": self.final_cv_rms,
            "n_samples": int(self.data.mask.sum()),
            "impulses": {"count": n_imp,
                         "rule": (f"|r - running median of {2 * robust.HAMPEL_HALF_WINDOW + 1}| > "
                                  f"{robust.HAMPEL_K:g} robust sigma on the base residual; "
                                  "left out of fitting and scoring"),
                         "first_indices": [int(i) for i in np.flatnonzero(self.impulses)[:20]]
                         if n_imp else []},
            "report_s": self.report_s,
            "samples_per_report": self.per_report,
            "before": self.figures(self.base),
            "after": self.figures(self.final),
            "base_model": {"offset_order": self.base.spec.base_order,
                           "offset_order_cv_rms": {str(k): v for k, v in self.base_order_cv.items()},
                           "reference": self.data.labels.get("reference", "given")},
            "final_offset": self.final.spec.describe_base() if self.data.T is not None else None,
            "steps": [s.as_dict() for s in self.steps],
            "not_added": self.rejected,
            "not_claimed": self.not_claimed,
            "at_search_edge": self.at_edge,
            "unexplained": unexplained,
            "residual_vs_candidates_before": self.relations_before,
            "unavailable": self.unavailable,
            "stopping_test": self.test,
            "model": model_dict(self.data, self.final),
        }


def model_dict(data, model):
    """The refined model as data: spec, coefficients and the scalings the
    columns were built with (what export needs)."""
    out = {"offset_order": model.spec.base_order,
           "offset_family": model.spec.base_family,
           "effects": [{"effect": e.name, "variant": e.variant, "param": e.param}
                       for e in model.spec.effects],
           "coefficients": model.coefficients(),
           "dt": data.dt}
    if data.T is not None:
        out["t_center"], out["t_scale"] = data.t_center, data.t_scale
    if data.r is not None:
        out["r_center"], out["r_scale"], out["r_abs"] = data.r_center, data.r_scale, data.r_abs
    return out


STOP_TEST = ("add the candidate with the lowest blocked-CV RMS only if a one-sided Diebold-Mariano "
             "test on the out-of-sample squared-error differential (HAC standard error, window "
             "n/{tb} samples) gives p < {a} / (candidates tried), the systematic error of a reading "
             "averaged over {r:g} s falls by >= {g:.0%} and by at least {m:g} x that reading's "
             "noise (in quadrature); impulses are left out of fitting and scoring")


def stop_test(opts):
    return STOP_TEST.format(tb=opts.test_blocks, a=opts.alpha, g=opts.min_gain, r=opts.report_s,
                            m=opts.material)


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


def screen_impulses(data, opts):
    """Fit the base offset with every usable sample, flag impulses on its
    residual (robust.impulse_mask) and return (data without them, used
    mask, impulse mask)."""
    used = data.mask.copy()
    if opts.impulse_k is None:
        return data, used, np.zeros(data.n, dtype=bool)
    order, _ = choose_base_order(data, opts)
    resid = fx.fit(data, fx.ModelSpec(order)).residual
    imp = robust.impulse_mask(resid, used, opts.impulse_k)
    if not imp.any():
        return data, used, imp
    return replace(data, mask=used & ~imp), used, imp


def judge(e_old, e_new, opts, per_report, n_tried):
    """The stopping rule on two out-of-sample residuals: (accepted, p,
    threshold, systematic before, after, relative gain, removed, noise)."""
    p = improvement_p(e_old, e_new, opts.test_blocks)
    threshold = opts.alpha / n_tried
    sigma = robust.white_sigma(e_old)
    sys_old = robust.systematic_rms(e_old, per_report, sigma)
    sys_new = robust.systematic_rms(e_new, per_report, robust.white_sigma(e_new))
    gain = 1.0 - sys_new / sys_old if sys_old > 0 else 0.0
    removed = float(np.sqrt(max(0.0, sys_old ** 2 - sys_new ** 2)))
    noise = sigma / np.sqrt(per_report)
    ok = p < threshold and gain >= opts.min_gain and removed >= opts.material * noise
    return ok, {"p_value": p, "p_threshold": threshold, "cv_systematic": sys_new,
                "cv_systematic_now": sys_old, "systematic_gain": gain,
                "systematic_removed": removed, "reading_noise": float(noise)}


def refine(data, opts=None):
    """Find what the base calibration model leaves out: fit the base model,
    then add, one at a time, the named effect that most lowers the blocked
    cross-validated error, while the gain is significant; say when structure
    is left that no candidate explains.

    Impulses are screened on the base model's residual; when the refined
    model's residual screens differently (structure the base model lacked
    looked like spikes to the running median), the loop runs once more
    with the screening of the refined residual.

    Parameters
    ----------
    data : pysig.refine._effect_models.FitData
        One measured column, its times, temperature and reference (true
        value), and the mask of samples to fit and score.
    opts : Options, optional
        Folds, guard band, significance level, smallest gain, the effect
        families to try (all by default).

    Returns
    -------
    Result
        The base and final models, the steps taken (effect, parameters,
        RMS and CV RMS before and after, p-value), the candidates rejected
        or left at their search edge, residual diagnostics before and after;
        `report()` gives all of it as a JSON-ready dict.

    Raises
    ------
    InsufficientDataError
        Fewer usable samples than 3 per fold.

    Examples
    --------
    >>> from lab.studies.refine_cases import chamber_run, fit_data
    >>> result = refine(fit_data(chamber_run("thermal_lag", seed=3)))   # a 90-s lag, not declared
    >>> [step.effect for step in result.steps], round(result.steps[0].params["tau_s"])
    (['thermal_lag'], 90)
    >>> result.base_rms / result.final_rms > 3, result.report()["unexplained"]["unexplained"]
    (True, False)
    """
    opts = opts or Options()
    if data.mask.sum() < 3 * opts.folds:
        raise InsufficientDataError(
            f"refine: {int(data.mask.sum())} usable samples; need at least {3 * opts.folds}")
    screened, used, impulses = screen_impulses(data, opts)
    result = _loop(screened, used, impulses, opts)
    if opts.impulse_k is None or not result.steps:
        return result
    again = robust.impulse_mask(result.final.residual, used, opts.impulse_k)
    if np.array_equal(again, impulses):
        return result
    return _loop(replace(data, mask=used & ~again), used, again, opts)


def _loop(data, used, impulses, opts):
    per_report = robust.samples_per_report(data.dt, opts.report_s)
    t_sigma = robust.white_sigma(np.where(data.mask, data.T, np.nan)) if data.T is not None else 0.0
    order, order_cv = choose_base_order(data, opts)
    spec = fx.ModelSpec(order)
    model = fx.fit(data, spec)
    base = model
    e_cv = cv_residual(data, spec, opts)
    base_cv = rms(e_cv)
    unavailable = {f: fx.FAMILIES[f].unavailable(data) for f in opts.families
                   if fx.FAMILIES[f].unavailable(data)}
    diag_before = residual_diagnostics(data, model.residual, opts.test_blocks)
    relations = candidate_relations(data, model)
    steps, rejected, at_edge, not_claimed = [], [], [], []
    shaped = False
    for _ in range(opts.max_steps):
        tried, at_edge, not_claimed = [], [], []
        for name in opts.families:
            fam = fx.FAMILIES[name]
            if name in model.spec.names() or fam.unavailable(data):
                continue
            for v in fam.variants:
                trial = fx.fit_param(data, model.spec, fam, v)
                edge = at_search_edge(data, fam, trial.spec)
                if edge is not None:
                    at_edge.append({"effect": name, "variant": v, **edge})
                    continue
                bad = not_physical(data, fam, trial.spec, opts, t_sigma)
                if bad is not None:
                    not_claimed.append({"effect": name, "variant": v, **bad})
                    continue
                if any(fx.FAMILIES[e.name].param_name for e in model.spec.effects):
                    # the earlier effects' parameters move with the newcomer
                    # (a lag fitted alone absorbs part of a hysteresis)
                    trial = repolish(data, trial.spec)
                e_new = cv_residual(data, trial.spec.without(name), opts, (fam, v))
                tried.append((rms(e_new), name, v, e_new, trial))
        if opts.shape and not shaped:
            # the best larger offset (one candidate: the size chosen by CV)
            shapes = [(rms(e), params, e, s) for params, s in shape_trials(data, model)
                      for e in [cv_residual(data, s, opts)]]
            if shapes:
                c, params, e_new, s = min(shapes, key=lambda x: x[0])
                tried.append((c, "offset_shape", params, e_new, fx.fit(data, s)))
        if not tried:
            break
        tried.sort(key=lambda x: x[0])
        summary = [{"effect": n, "variant": v, "cv_rms": c} for c, n, v, _, _ in tried]
        cv_new, name, variant, e_new, trial = tried[0]
        cv_old = rms(e_cv)
        ok, verdict = judge(e_cv, e_new, opts, per_report, len(tried))
        if not ok:
            rejected = [{"effect": name, "variant": variant, "cv_rms": cv_new, "cv_rms_now": cv_old,
                         "cv_gain": 1.0 - cv_new / cv_old if cv_old > 0 else 0.0, **verdict}]
            break
        if name == "offset_shape":
            shaped = True
            new_model = trial
            params = dict(variant)
        else:
            fam = fx.FAMILIES[name]
            new_model = reselect(data, trial, opts)
            eff = next(e for e in new_model.spec.effects if e.name == name)
            params = fam.describe(eff)
            params["coefficients"] = {k: v for k, v in new_model.coefficients().items()
                                      if k.startswith(name + ":")}
        e_cv_new = cv_residual(data, new_model.spec, opts)   # CV of the model actually kept
        if not rms(e_cv_new) < cv_old:
            # the per-fold parameter choice won, the model as kept does not
            rejected = [{"effect": name, "variant": variant, "cv_rms": rms(e_cv_new),
                         "cv_rms_now": cv_old, "cv_gain": 1.0 - rms(e_cv_new) / cv_old,
                         **verdict, "kept_model_cv_worse": True}]
            break
        steps.append(Step(name, params, model.rms(data.mask), new_model.rms(data.mask),
                          cv_old, rms(e_cv_new), verdict["p_value"], summary,
                          verdict["cv_systematic_now"],
                          robust.systematic_rms(e_cv_new, per_report)))
        model, e_cv = new_model, e_cv_new
    return Result(data=data, base=base, final=model, base_order_cv=order_cv, steps=steps,
                  rejected=rejected, at_edge=at_edge, base_cv_rms=base_cv, final_cv_rms=rms(e_cv),
                  diagnostics_before=diag_before,
                  diagnostics_after=residual_diagnostics(data, model.residual, opts.test_blocks),
                  relations_before=relations, unavailable=unavailable, test=stop_test(opts),
                  used=used, impulses=impulses, not_claimed=not_claimed,
                  per_report=per_report, report_s=opts.report_s)
