"""What the model leaves: structure in the final residual that no
candidate explains, and how much of the base residual each candidate would
explain.

Unexplained structure: statsmodels' Ljung-Box test (acorr_ljungbox) for
autocorrelation, and a one-way ANOVA of the residual across contiguous time
blocks (scipy.stats.f_oneway) for a trend against time.  It counts when
Ljung-Box p < 1e-3 and the structure is material: lag-1 autocorrelation
>= 0.2 or the time blocks carry >= 10 % of the residual variance.  It is
never attributed to a named effect."""
import numpy as np
from scipy import stats
from statsmodels.stats.diagnostic import acorr_ljungbox

from . import _effect_models as fx
from ._options import DEFAULT_TEST_BLOCKS

LB_P = 1e-3
ACF1_MATERIAL = 0.2
TIME_R2_MATERIAL = 0.10


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
