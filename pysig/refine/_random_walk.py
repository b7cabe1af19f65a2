"""A slow-in-time effect judged under a random-walk zero.

A hysteresis's branch term is a slow square wave in time, a warm-up a slow
exponential; a zero that wanders as a random walk correlates with either by
chance, and the correlation carries into held-out blocks because the walk
is correlated across all of them (the blocked-CV test cannot see memory as
long as the record).  So before such an effect is claimed it is fitted once
more with the smooth drift replaced by a random-walk level estimated with it
(a local-level state-space model, statsmodels UnobservedComponents, the
rest of the model's columns as regressors): under a random walk the
evidence comes only from the increments, and a walk that happens to step
with the cold and warm spells no longer makes a branch.  When the level's
fitted variance is about zero this is the plain regression, so an effect
under a smooth drift keeps its evidence.

Long records are fitted on the means of consecutive blocks (at least a
reported reading long, at most MAX_BLOCKS of them) within each session,
which also averages the fast coloured noise the local level's white
irregular does not model; the steps at session breaks stay regressors."""
import warnings

import numpy as np
from scipy import stats
from statsmodels.tsa.statespace.structural import UnobservedComponents

SLOW_IN_TIME = ("hysteresis", "warm_up")
MAX_BLOCKS = 2000


def block_size(data, per_report):
    """Samples in a block: a reported reading, or more so that at most
    MAX_BLOCKS blocks are fitted."""
    return max(per_report, int(np.ceil(np.count_nonzero(data.mask) / MAX_BLOCKS)))


def block_rows(data, per_report):
    """Index arrays of the used samples in each block: consecutive used
    samples of one session, block_size of them."""
    used = np.flatnonzero(data.mask)
    size = block_size(data, per_report)
    edges = [0, *data.breaks, data.n]
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        rows = used[(used >= a) & (used < b)]
        out += [rows[i:i + size] for i in range(0, rows.size, size)]
    return [r for r in out if r.size]


def random_walk_check(data, model, names, per_report):
    """Wald test of the columns of the effects `names` in `model` (a fitted
    pysig.refine._effect_models.FittedModel) with its smooth drift and its
    constant replaced by a random-walk level.  Returns {"effect", "p_value",
    "level_sd" (the level's step per block, the reading's unit),
    "irregular_sd", "blocks", "block_s" (a block's length in time)}."""
    keep = [j for j, nm in enumerate(model.names)
            if nm != "const" and not nm.startswith("drift:knot") and not nm.startswith("table:0")]
    tested = [k for k, j in enumerate(keep) if model.names[j].split(":")[0] in names]
    blocks = block_rows(data, per_report)
    y = np.array([data.y[r].mean() for r in blocks])
    X = np.array([model.design[r][:, keep].mean(axis=0) for r in blocks])
    # scaled so the diffuse start and the optimiser see numbers near 1
    y_sd = float(np.std(y)) or 1.0
    x_sd = np.where(np.std(X, axis=0) > 0, np.std(X, axis=0), 1.0)
    yz, Xz = (y - y.mean()) / y_sd, (X - X.mean(axis=0)) / x_sd
    # the regression coefficients in the state (mle_regression=False): the
    # likelihood is maximised over the two variances only, the coefficients
    # and their covariance are the smoother's (GLS given the variances)
    uc = UnobservedComponents(yz, exog=Xz, level="llevel", mle_regression=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = uc.fit(disp=False)
    beta_idx = np.arange(1, 1 + Xz.shape[1])      # state 0 is the level
    b = res.smoothed_state[beta_idx[tested], -1]
    cov = res.smoothed_state_cov[np.ix_(beta_idx[tested], beta_idx[tested], [-1])][:, :, 0]
    wald = float(b @ np.linalg.solve(cov, b))
    variances = dict(zip(uc.param_names, res.params))
    return {"effect": " + ".join(names), "p_value": float(stats.chi2.sf(wald, len(tested))),
            "level_sd": float(np.sqrt(variances["sigma2.level"])) * y_sd,
            "irregular_sd": float(np.sqrt(variances["sigma2.irregular"])) * y_sd,
            "blocks": len(blocks), "block_s": block_size(data, per_report) * data.dt}
