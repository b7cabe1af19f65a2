"""Choosing a drift model's size (polynomial order, table knot count) by
blocked cross-validation over temperature, and what the magnetometer paper's
four-temperature calibration would have chosen.

Blocked CV: the temperature range is cut into `n_blocks` contiguous blocks
of equal width.  Each interior block in turn is held out, the model is fitted
on everything else and evaluated on the block.  Holding out whole blocks
(several °C) makes the score measure interpolation between calibration
temperatures, not memorising the neighbouring bin (on a dense curve plain
leave-one-out would reward the biggest table).  The two end blocks always
stay in the training set, so no fold extrapolates: the firmware clamps
outside its calibrated range, and extrapolation error is a different
question (a polynomial's is unbounded).

Four-temperature calibration (the magnetometer paper: 0, 25, 50, 70 °C): when the
data covers the targets, the nearest distinct data temperature to each;
otherwise ("spread") the targets are mapped affinely onto the data's range,
keeping the magnetometer paper's relative spacing, and the nearest distinct points taken."""
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputFileError, InsufficientDataError, NonFiniteError, RangeError
from ..io import read_csv
from ..lsq import fit_poly
from ._table_fit import fit_pwl

PAPER_TEMPS = (0.0, 25.0, 50.0, 70.0)
PAPER_ORDER = 2
DEFAULT_BLOCKS = 8


# ---- input curve -------------------------------------------------------------

@dataclass(frozen=True)
class Curve:
    """A drift curve: strictly increasing temperatures, one row per
    temperature, one column per axis."""
    temp: np.ndarray                 # (n,)
    values: np.ndarray               # (n, axes)
    names: tuple                     # axis names
    notes: tuple = field(default=()) # what tidying did (averaged repeats)

    def axis(self, name):
        return self.values[:, self.names.index(name)]


def tidy_curve(temp, values, names, where="curve"):
    """Average runs of a repeated temperature (saying so) and insist that
    what remains is strictly increasing.

    `values` is (n,) or (n, axes).  Repeated temperatures must be adjacent
    (a sorted log): a temperature lower than the one before it raises
    InputFileError naming the row (data rows counted from 1 after the
    header, i.e. the file's row minus one), as does a non-finite cell
    (NonFiniteError).  Each averaged run is reported in `notes` and by a
    UserWarning."""
    temp = np.asarray(temp, dtype=float).ravel()
    values = np.asarray(values, dtype=float)
    if values.ndim == 1:
        values = values[:, None]
    names = tuple(names)
    if values.shape != (temp.size, len(names)):
        raise ValueError(f"{where}: {temp.size} temperatures, values of shape {values.shape}, "
                         f"{len(names)} names")
    if temp.size == 0:
        raise InsufficientDataError(f"{where}: no rows")
    for col, arr in [("temperature", temp)] + [(n, values[:, j]) for j, n in enumerate(names)]:
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            raise NonFiniteError(f"{where}: data row {int(bad[0]) + 1}, column '{col}': "
                                 f"non-finite value {float(arr[bad[0]])!r}")
    step = np.diff(temp)
    down = np.flatnonzero(step < 0)
    if down.size:
        i = int(down[0])
        raise InputFileError(
            f"{where}: data row {i + 2}: temperature {float(temp[i + 1])!r} after {float(temp[i])!r}; the "
            f"temperature column must be increasing (repeats are averaged)")
    starts = np.concatenate([[0], np.flatnonzero(step > 0) + 1])
    counts = np.diff(np.concatenate([starts, [temp.size]]))
    notes = tuple(f"{where}: averaged {c} rows at {temp[s]:g} °C (data rows {s + 1}-{s + c})"
                  for s, c in zip(starts, counts) if c > 1)
    for note in notes:
        warnings.warn(note, UserWarning, stacklevel=2)
    sums = np.add.reduceat(values, starts, axis=0)
    return Curve(temp=temp[starts].copy(), values=sums / counts[:, None], names=names, notes=notes)


def bin_by_temperature(temp, values, names, width, where="recording"):
    """A drift curve from a time series: samples averaged into temperature
    bins of `width` °C (as PX4's calibration script and the MatrixPilot
    table do; otherwise slowly-crossed temperatures get more weight).  Each
    bin's temperature is the mean temperature of its samples."""
    temp = np.asarray(temp, dtype=float).ravel()
    values = np.asarray(values, dtype=float)
    if values.ndim == 1:
        values = values[:, None]
    if not (np.isfinite(width) and width > 0):
        raise RangeError(f"{where}: bin width must be > 0 °C, got {width!r}")
    for col, arr in [("temperature", temp)] + [(n, values[:, j]) for j, n in enumerate(names)]:
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            raise NonFiniteError(f"{where}: sample {int(bad[0])}, column '{col}': non-finite value")
    if temp.size == 0:
        raise InsufficientDataError(f"{where}: no samples")
    key = np.floor(temp / width).astype(np.int64)
    bins, inverse, counts = np.unique(key, return_inverse=True, return_counts=True)
    t_mean = np.bincount(inverse, weights=temp) / counts
    v_mean = np.column_stack([np.bincount(inverse, weights=values[:, j]) / counts
                              for j in range(values.shape[1])])
    note = (f"{where}: {temp.size} samples averaged into {bins.size} temperature bins of "
            f"{width:g} °C ({counts.min()}..{counts.max()} samples per bin)")
    return Curve(temp=t_mean, values=v_mean, names=tuple(names), notes=(note,))


def load_curve(path, temp_column, value_columns):
    """Read a drift curve from CSV (pysig.io) and tidy it; errors name the file."""
    cols = read_csv(path, [temp_column, *value_columns])
    return tidy_curve(cols[temp_column], np.column_stack([cols[c] for c in value_columns]),
                      value_columns, where=str(path))


# ---- model families ------------------------------------------------------------

def poly_fitter(order):
    """fit(temp, y) -> callable model, a least-squares polynomial (pysig.lsq)."""
    def fit(temp, y):
        return fit_poly(temp, y, order, what=f"polynomial order {order}")
    return fit


def pwl_fitter(n_knots, bridge=True):
    """fit(temp, y) -> callable table of n_knots uniform knots over the data
    range; `bridge` lets a held-out block fall between knots (the table is
    then linear across it, as interpolating firmware would be)."""
    def fit(temp, y):
        return fit_pwl(temp, y, n_knots, bridge=bridge, what=f"table of {n_knots} knots")
    return fit


FAMILIES = {"poly": poly_fitter, "pwl": pwl_fitter}


def check_size(family, size, n_distinct):
    """Named errors for a size the data cannot support."""
    if family == "poly":
        if not isinstance(size, (int, np.integer)) or size < 0:
            raise RangeError(f"polynomial order must be a non-negative integer, got {size!r}")
        if size + 1 > n_distinct:
            raise InsufficientDataError(
                f"polynomial order {size} needs {size + 1} distinct temperatures, "
                f"the data has {n_distinct}")
    elif family == "pwl":
        if not isinstance(size, (int, np.integer)) or size < 2:
            raise RangeError(f"a table needs at least 2 knots, got {size!r}")
        if size > n_distinct:
            raise InsufficientDataError(
                f"a table of {size} knots needs {size} distinct temperatures, the data has {n_distinct}")
    else:
        raise RangeError(f"unknown model family {family!r} (known: {', '.join(FAMILIES)})")


# ---- blocked cross-validation --------------------------------------------------

def blocked_folds(temp, n_blocks=DEFAULT_BLOCKS):
    """Index arrays of the held-out interior blocks: equal-width contiguous
    temperature blocks, the first and last never held out; empty blocks are
    skipped."""
    temp = np.asarray(temp, dtype=float)
    if not isinstance(n_blocks, (int, np.integer)) or n_blocks < 3:
        raise RangeError(f"blocked CV needs at least 3 blocks (two ends kept), got {n_blocks!r}")
    lo, hi = float(temp.min()), float(temp.max())
    if not hi > lo:
        raise InsufficientDataError("blocked CV: all temperatures are equal")
    block = np.minimum(((temp - lo) / (hi - lo) * n_blocks).astype(int), n_blocks - 1)
    folds = [np.flatnonzero(block == b) for b in range(1, n_blocks - 1)]
    folds = [f for f in folds if f.size]
    if not folds:
        raise InsufficientDataError("blocked CV: no data in the interior blocks")
    return folds


def cross_validate(fitter, temp, y, n_blocks=DEFAULT_BLOCKS):
    """RMS of the held-out residuals over all interior blocks (each point is
    held out once), and the per-fold RMS."""
    temp = np.asarray(temp, dtype=float)
    y = np.asarray(y, dtype=float)
    resid = []
    per_fold = []
    for test in blocked_folds(temp, n_blocks):
        train = np.ones(temp.size, bool)
        train[test] = False
        model = fitter(temp[train], y[train])
        r = y[test] - model(temp[test])
        resid.append(r)
        per_fold.append(float(np.sqrt(np.mean(r ** 2))))
    allr = np.concatenate(resid)
    return float(np.sqrt(np.mean(allr ** 2))), per_fold


@dataclass(frozen=True)
class SizeScore:
    family: str
    size: int
    cv_rms: float
    fit_rms: float
    fold_rms: tuple


def score_sizes(family, sizes, temp, y, n_blocks=DEFAULT_BLOCKS):
    """Blocked-CV and in-sample RMS for each size of one family."""
    n_distinct = np.unique(temp).size
    out = []
    for size in sizes:
        check_size(family, size, n_distinct)
        fitter = FAMILIES[family](size)
        cv, folds = cross_validate(fitter, temp, y, n_blocks)
        full = fitter(temp, y)
        fit_rms = float(np.sqrt(np.mean((y - full(temp)) ** 2)))
        out.append(SizeScore(family, int(size), cv, fit_rms, tuple(folds)))
    return out


CHOICE_TOLERANCE = 0.05


def choose(scores, tolerance=CHOICE_TOLERANCE):
    """The smallest size whose blocked-CV RMS is within `tolerance` (relative)
    of the best one: a bigger model must earn its cost by more than noise
    (the same rule as pysig.tcomp._poly_fit.select_order)."""
    best = min(s.cv_rms for s in scores)
    return min((s for s in scores if s.cv_rms <= best * (1.0 + tolerance)), key=lambda s: s.size)


# ---- the magnetometer paper's four-temperature calibration ----------------------------------

@dataclass(frozen=True)
class PaperPoints:
    index: np.ndarray        # indices into the curve, in target order
    targets: tuple           # the temperatures aimed at (after mapping)
    mode: str                # "nearest" or "spread"


def paper_points(temp, targets=PAPER_TEMPS):
    """Nearest distinct data temperatures to the magnetometer paper's calibration
    temperatures ("nearest" when the data covers them, else "spread": the
    targets mapped onto the data's range first)."""
    temp = np.asarray(temp, dtype=float)
    targets = np.asarray(targets, dtype=float)
    distinct = np.unique(temp)
    if distinct.size < targets.size:
        raise InsufficientDataError(
            f"four-point calibration needs {targets.size} distinct temperatures, "
            f"the data has {distinct.size}")
    lo, hi = float(temp.min()), float(temp.max())
    tol = 0.5
    if targets.min() >= lo - tol and targets.max() <= hi + tol:
        mode, aims = "nearest", targets
    else:
        mode = "spread"
        aims = lo + (targets - targets.min()) / (targets.max() - targets.min()) * (hi - lo)
    chosen = []
    for aim in aims:
        order = np.argsort(np.abs(temp - aim), kind="stable")
        pick = next(int(i) for i in order if not any(temp[i] == temp[j] for j in chosen))
        chosen.append(pick)
    return PaperPoints(index=np.array(chosen), targets=tuple(float(a) for a in aims), mode=mode)


@dataclass(frozen=True)
class FourPointResult:
    order: int
    points_rms: float        # residual at the calibration points (what the magnetometer paper saw)
    loo_rms: float           # leave-one-out over the calibration points (NaN: not possible)
    dense_rms: float         # residual over the whole curve (what it costs)


def four_point_study(temp, y, orders=(1, 2, 3), targets=PAPER_TEMPS):
    """Fit each order on the magnetometer paper's four points; error at the points, their
    leave-one-out error (the only cross-validation four points allow: orders
    up to 2) and the error on the dense curve."""
    pts = paper_points(temp, targets)
    tp, yp = np.asarray(temp)[pts.index], np.asarray(y)[pts.index]
    results = []
    for order in orders:
        check_size("poly", order, np.unique(tp).size)
        model = fit_poly(tp, yp, order, what=f"four-point order {order}")
        if order + 1 <= tp.size - 1:
            loo = [yp[i] - fit_poly(np.delete(tp, i), np.delete(yp, i), order,
                                    what=f"four-point order {order}")(tp[i])
                   for i in range(tp.size)]
            loo_rms = float(np.sqrt(np.mean(np.square(loo))))
        else:
            loo_rms = float("nan")
        results.append(FourPointResult(
            order=int(order),
            points_rms=float(np.sqrt(np.mean((yp - model(tp)) ** 2))),
            loo_rms=loo_rms,
            dense_rms=float(np.sqrt(np.mean((np.asarray(y) - model(temp)) ** 2)))))
    return pts, results


def four_point_choice(results, tolerance=CHOICE_TOLERANCE):
    """The order a four-temperature calibration would choose by its own
    leave-one-out error (same rule as `choose`)."""
    scored = [r for r in results if np.isfinite(r.loo_rms)]
    if not scored:
        raise InsufficientDataError("four-point study: no order allows leave-one-out")
    best = min(r.loo_rms for r in scored)
    return min((r for r in scored if r.loo_rms <= best * (1.0 + tolerance)), key=lambda r: r.order)
