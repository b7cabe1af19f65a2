"""Least-squares polynomial fitting shared by every calibration in pysig:
temperature compensation (offset f(T), gain drift), weighing (counts -> kg)
and the refinement loop.  One copy of the solver, used by all.

The fit runs on a centred and scaled abscissa u = (x - center) / scale, which
keeps the Vandermonde matrix well conditioned, and solves it with numpy's
SVD-based least squares.  `fit_normal_equations` is the textbook form
(C^T C a = C^T y) of the magnetometer paper, kept to show how much worse it
conditions."""

__all__ = ["PolyFit", "fit_poly", "fit_linear_model", "fit_normal_equations", "center_scale", "finite_pairs"]
from dataclasses import dataclass

import numpy as np

from .errors import InsufficientDataError, NonFiniteError


@dataclass(frozen=True)
class PolyFit:
    """y ~ sum_k coef[k] * u**k with u = (x - center) / scale."""
    coef: np.ndarray          # ascending powers of u
    center: float
    scale: float
    rms: float                # in-sample residual RMS
    cond: float               # condition number of the scaled design matrix

    @property
    def order(self):
        return len(self.coef) - 1

    def __call__(self, x):
        u = (np.asarray(x, dtype=float) - self.center) / self.scale
        return np.polynomial.polynomial.polyval(u, self.coef)

    def raw_coefficients(self):
        """Coefficients in ascending powers of x itself (un-scaled); worse
        conditioned, for users who want the magnetometer paper's form."""
        p = np.polynomial.Polynomial(self.coef, domain=[self.center - self.scale, self.center + self.scale],
                                     window=[-1, 1])
        return p.convert().coef


def finite_pairs(x, y, what, names=("x", "y")):
    """x and y as flat float arrays of one length with no NaN or inf; a
    ValueError or NonFiniteError naming `what`, the series and the index."""
    x = np.asarray(x, dtype=float).ravel()
    y = np.asarray(y, dtype=float).ravel()
    if x.shape != y.shape:
        raise ValueError(f"{what}: {names[0]} and {names[1]} differ in length ({x.size} vs {y.size})")
    for name, arr in zip(names, (x, y)):
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            raise NonFiniteError(f"{what}: non-finite {name} at index {int(bad[0])}")
    return x, y


def _check(x, y, order, what):
    x, y = finite_pairs(x, y, what)
    if not (isinstance(order, (int, np.integer)) and order >= 0):
        raise ValueError(f"{what}: order must be a non-negative integer, got {order!r}")
    distinct = np.unique(x).size
    if distinct < order + 1:
        raise InsufficientDataError(
            f"{what}: order {order} needs at least {order + 1} distinct x values, "
            f"the data has {distinct}")
    return x, y


def center_scale(x):
    """Centre at the middle of the range, scale to half the span (u in [-1, 1])."""
    lo, hi = float(np.min(x)), float(np.max(x))
    scale = (hi - lo) / 2.0
    return (hi + lo) / 2.0, (scale if scale > 0 else 1.0)


def fit_poly(x, y, order, center=None, scale=None, weights=None, what="fit"):
    """Least-squares polynomial of `order` (SVD solver, centred/scaled x).

    Parameters
    ----------
    x, y : array_like
        Abscissa and data, of one length, finite.
    order : int
        Polynomial order (>= 0).
    center, scale : float, optional
        u = (x - center) / scale; by default the middle and half-span of x.
    weights : array_like, optional
        Per-sample weights.
    what : str, optional
        Names the data in error messages.

    Returns
    -------
    PolyFit
        Coefficients in ascending powers of u, center, scale, residual RMS
        and the condition number; calling it evaluates the polynomial.

    Raises
    ------
    NonFiniteError
        NaN or inf in x or y (the index named).
    InsufficientDataError
        Fewer distinct x values than order + 1.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.array([0.0, 25.0, 50.0, 70.0])
    >>> fit = fit_poly(x, 3.0 + 0.5 * x - 0.01 * x ** 2, 2)
    >>> np.round(fit.raw_coefficients(), 6), round(float(fit(40.0)), 6)
    (array([ 3.  ,  0.5 , -0.01]), 7.0)
    >>> fit_poly([1.0, 1.0, 1.0], [1.0, 2.0, 3.0], 1)
    Traceback (most recent call last):
        ...
    pysig.errors.InsufficientDataError: fit: order 1 needs at least 2 distinct x values, the data has 1
    """
    x, y = _check(x, y, order, what)
    c0, s0 = center_scale(x)
    center = c0 if center is None else float(center)
    scale = s0 if scale is None else float(scale)
    u = (x - center) / scale
    design = np.vander(u, order + 1, increasing=True)
    if weights is not None:
        w = np.sqrt(np.asarray(weights, dtype=float))
        coef = np.linalg.lstsq(design * w[:, None], y * w, rcond=None)[0]
    else:
        coef = np.linalg.lstsq(design, y, rcond=None)[0]
    resid = y - design @ coef
    return PolyFit(coef=coef, center=center, scale=scale,
                   rms=float(np.sqrt(np.mean(resid ** 2))), cond=float(np.linalg.cond(design)))


def fit_normal_equations(x, y, order, what="fit"):
    """The magnetometer paper's form: solve (C^T C) a = C^T y on the raw (unscaled) x.
    Returns (coef ascending in x, condition number of C^T C)."""
    x, y = _check(x, y, order, what)
    design = np.vander(x, order + 1, increasing=True)
    gram = design.T @ design
    return np.linalg.solve(gram, design.T @ y), float(np.linalg.cond(gram))


def fit_linear_model(design, y, what="fit"):
    """General linear least squares y ~ design @ beta (the refinement loop's
    candidate effects are columns of `design`).  Returns (beta, residual)."""
    design = np.asarray(design, dtype=float)
    y = np.asarray(y, dtype=float)
    if not np.all(np.isfinite(design)) or not np.all(np.isfinite(y)):
        raise NonFiniteError(f"{what}: non-finite value in the regressors or the target")
    if design.shape[0] < design.shape[1]:
        raise InsufficientDataError(
            f"{what}: {design.shape[1]} parameters need at least as many samples, got {design.shape[0]}")
    beta = np.linalg.lstsq(design, y, rcond=None)[0]
    return beta, y - design @ beta
