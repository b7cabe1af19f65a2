"""The base model refine starts from and returns to: the offset order
chosen by blocked CV, re-chosen once effects are in, the nonlinear
parameters re-polished together, and the impulse screening on the base
residual."""
from dataclasses import replace

import numpy as np

from . import _effect_models as fx
from . import _robust as robust
from ._cross_validation import cv_residual, fewest_within_one_se, fold_mse, rms
from ..errors import InsufficientDataError

MAX_BASE_ORDER = 5


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


def repolish(data, spec, passes=2):
    """Refit every nonlinear parameter in turn with the others held
    (coordinate passes), so an effect fitted before a later one is not stuck
    with the value it took when the model lacked the later one.  A family
    with several start variants (a hysteresis's branch before the first
    sample) takes the one that fits best with the others in: the branch
    chosen before a drift was in bends to imitate part of the drift.  The
    variants have the same number of coefficients, so the least squared
    error chooses among them."""
    model = fx.fit(data, spec)
    n_nonlinear = sum(1 for e in spec.effects if fx.FAMILIES[e.name].param_name)
    for _ in range(passes if n_nonlinear > 1 else 1):
        for e in spec.effects:
            fam = fx.FAMILIES[e.name]
            if fam.param_name is None:
                continue
            rest = model.spec.without(e.name)
            model = min((fx.fit_param(data, rest, fam, v) for v in fam.variants),
                        key=lambda m: float(np.sum(m.residual[data.mask] ** 2)))
    return model


def base_spec(data, opts):
    """(ModelSpec, {order: cv_rms}) of the base model: the starting model
    `opts.base` when given, else the offset order chosen by blocked CV."""
    if opts.base is not None:
        family, size = opts.base
        return fx.ModelSpec(int(size), (), family), {}
    order, order_cv = choose_base_order(data, opts)
    return fx.ModelSpec(order), order_cv


def reselect(data, model, opts, polish=True):
    """After an effect is added: choose the offset order again with the
    effects in place (a lag, for one, changes which order fits), then
    re-polish the nonlinear parameters (`polish`; else refit the linear
    coefficients only)."""
    if data.T is None or model.spec.base_family != "poly" or opts.base is not None:
        return model            # a starting model given by the user keeps its size
    order, _ = choose_base_order(data, opts, model.spec.effects)
    if order == model.spec.base_order:
        return model
    spec = fx.ModelSpec(order, model.spec.effects)
    return repolish(data, spec) if polish else fx.fit(data, spec)


def rechoose_drift(data, model, opts):
    """After an effect is added: choose the drift's knots again by blocked CV
    with the effect in (the other parameters held), then re-polish.  Knots
    chosen before a hysteresis was in were too few (the unexplained branches
    made a more flexible drift look worse out of sample); a drift with too
    few knots leaves its settling for a warm-up to take.  The knots are the
    fewest within one standard error of the best (fewest_within_one_se): a
    nuisance drift is the simplest one the record supports, since a more
    flexible one takes part of any slow physical effect it can imitate."""
    drift = next((e for e in model.spec.effects if e.name == "drift"), None)
    if drift is None:
        return model
    rest = model.spec.without("drift")
    knots = fewest_within_one_se(
        {k: fold_mse(data, cv_residual(data, rest.with_effect(fx.Effect("drift", k)), opts), opts)
         for k in fx.FAMILIES["drift"].variants})
    if knots == drift.variant:
        return model
    return repolish(data, rest.with_effect(fx.Effect("drift", knots)))


def screen_impulses(data, opts):
    """Fit the base offset with every usable sample, flag impulses on its
    residual (robust.impulse_mask) and return (data without them, used
    mask, impulse mask)."""
    used = data.mask.copy()
    if opts.impulse_k is None:
        return data, used, np.zeros(data.n, dtype=bool)
    resid = fx.fit(data, base_spec(data, opts)[0]).residual
    imp = robust.impulse_mask(resid, used, opts.impulse_k)
    if not imp.any():
        return data, used, imp
    return replace(data, mask=used & ~imp), used, imp
