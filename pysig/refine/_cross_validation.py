"""Out-of-sample error of a refine model: cross-validation blocked in time.
The samples are cut into `folds` contiguous blocks (pysig.folds, the same
blocked folds tcomp's model choice uses); each block is predicted by a model
fitted on the others minus a guard band of `gap` samples on each side of it,
so a lag or a drift cannot leak from neighbouring samples into the test
block.  A candidate's nonlinear parameter (time constant, width) is chosen
inside each fold on its training samples only."""
import numpy as np
from scipy import stats

from . import _effect_models as fx
from ..errors import InsufficientDataError
from ..folds import equal_count_blocks, held_out_blocks
from ..lsq import fit_linear_model

# training rows cannot tell two values of one parameter apart: their SSEs
# differ by less than the chi-square(1) 95 % point in residual variances
TIE_CHI2 = float(stats.chi2.ppf(0.95, 1))


def guard_band(data, opts):
    """Samples left out on each side of a held-out block: `opts.gap`, else
    a quarter of a block."""
    return opts.gap if opts.gap is not None else max(1, data.n // (4 * opts.folds))


def fold_rows(n, folds, gap):
    """(train, test) boolean masks of each non-empty contiguous time block."""
    return held_out_blocks(equal_count_blocks(n, folds), folds, gap=gap)


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


UNSEEN_NORM = 1e-2     # a column with under 1e-4 of its energy on the training rows


def unseen_columns(X, rows, names, full=None):
    """Columns the training rows do not determine: their norm there is
    under UNSEEN_NORM of their norm on the whole record (a warm-up of a
    short time constant when its start is held out).  Fitted, such a column
    takes a coefficient of the noise over its tiny training norm and
    extrapolates it into the held-out rows; it is left out instead (its
    coefficient 0: the fold predicts as if the effect were absent).  Table
    knots are not among them: bridge_rows ties those to their neighbours.
    `full`: the column norms on the whole record, when already computed."""
    full = np.linalg.norm(X, axis=0) if full is None else full
    unseen = np.linalg.norm(X[rows], axis=0) < UNSEEN_NORM * full
    return unseen & ~np.array([nm.startswith(fx.TABLE_PREFIX) for nm in names])


def fit_rows(X, y, rows, names, full=None):
    """Least squares of X[rows] on y[rows], table knots bridged (bridge_rows),
    columns the rows do not determine left at 0 (unseen_columns; `full`,
    X's column norms, computed once for all folds)."""
    keep = ~unseen_columns(X, rows, names, full)
    Xt, yt = X[rows][:, keep], y[rows]
    extra = bridge_rows(Xt, [nm for nm, k in zip(names, keep) if k])
    if extra is not None:
        Xt, yt = np.vstack([Xt, extra[0]]), np.concatenate([yt, extra[1]])
    beta = np.zeros(X.shape[1])
    beta[keep], _ = fit_linear_model(Xt, yt, what="refine cv")
    return beta, None


def cv_residual(data, spec, opts, candidate=None):
    """Out-of-sample residual of `spec` (+ `candidate`, a (family, variant),
    (family, variant, grid top) or (family, variant, grid top, full-data
    fit) whose nonlinear parameter is chosen per fold on the training rows
    among Family.fold_grid).
    NaN where the sample is masked out."""
    gap = guard_band(data, opts)
    specs, params, center = [spec], [None], None
    if candidate is not None:
        fam, variant, top, center = (*candidate, None, None)[:4]
        params = fam.fold_grid(data, top, center)
        specs = [spec.with_effect(fx.Effect(fam.name, variant, p)) for p in params]
    designs = [fx.design(data, s) for s in specs]
    norms = [np.linalg.norm(X, axis=0) for X, _ in designs]
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
        fits = []
        for (X, names), full in zip(designs, norms):
            beta, _ = fit_rows(X, data.y, tr, names, full)
            res = data.y[tr] - X[tr] @ beta
            fits.append((float(res @ res), X, beta))
        _, X, beta = fits[fold_choice([f[0] for f in fits], params, center, int(tr.sum()),
                                      designs[0][0].shape[1] + 1)]
        e[te] = data.y[te] - X[te] @ beta
    return e


def fold_choice(sse, params, center, n_train, n_coef):
    """Index of the parameter a fold takes: the least training SSE, unless
    the training rows cannot tell it from others (inside the 95 % profile-
    likelihood interval of one parameter: SSE within TIE_CHI2 residual
    variances of the least); then, among those, the one nearest the
    full-data fit `center` (in log).  A fold that holds out the start of a
    warm-up sees only its tail, whose SSE is nearly flat in the time
    constant: the least SSE is then a coin toss that decides how the
    held-out start is extrapolated.  A tie of one residual variance (what
    one fitted parameter moves by chance) was too narrow for that: the
    tail's noise could put the least SSE two or three variances away from
    the value the whole record resolves, and the start was extrapolated
    from there (held-out warm-ups missed, p 0.023 against 0.0125)."""
    i = int(np.argmin(sse))
    if center is None or params[i] is None:
        return i
    tie = sse[i] + TIE_CHI2 * sse[i] / max(1, n_train - n_coef)
    near = [k for k, v in enumerate(sse) if v <= tie]
    return min(near, key=lambda k: abs(np.log(params[k] / center)))


def fold_mse(data, e, opts):
    """Mean squared out-of-sample error of each blocked fold's test block
    (the folds cv_residual holds out), for the spread of a CV score."""
    gap = guard_band(data, opts)
    out = []
    for _, test in fold_rows(data.n, opts.folds, gap):
        v = e[test & np.isfinite(e)]
        if v.size:
            out.append(float(np.mean(v ** 2)))
    return np.array(out)


def fewest_within_one_se(fold_errors):
    """The one-standard-error rule of CV model choice: the smallest size
    (key of `fold_errors`, {size: each fold's mean squared error}) whose
    mean fold error exceeds the best's by at most one standard error of
    their difference over the folds.  The folds are the same for every size,
    so the difference is paired: its spread is what the CV score cannot
    tell apart (the spread of one size's fold errors is mostly how hard
    each block is, the same for all)."""
    best = min(fold_errors, key=lambda k: fold_errors[k].mean())
    within = []
    for k, errs in fold_errors.items():
        diff = errs - fold_errors[best]
        se = float(np.std(diff, ddof=1) / np.sqrt(diff.size)) if diff.size > 1 else 0.0
        if diff.mean() <= se:
            within.append(k)
    return min(within)


def rms(e):
    e = e[np.isfinite(e)]
    return float(np.sqrt(np.mean(e ** 2))) if e.size else float("nan")
