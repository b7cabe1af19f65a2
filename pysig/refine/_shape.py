"""Offset shape candidates of the refinement loop: when the residual against
temperature has structure a low-order polynomial cannot follow (a gyro
offset that rises and falls), a larger polynomial or a piecewise-linear
table (pysig.tcomp._table_fit's hat basis, what firmware evaluates by lookup) may
remove it.

The size of each family is chosen as the compensation fit chooses it
(pysig.tcomp._cross_validation: blocked CV over temperature, the smallest size
within 5 % of the best) on the offset part of the current model (its
residual plus its offset term), averaged into at most 200 temperature bins.  The loop then scores the two candidates,
as replacements of the base offset, by its own time-blocked CV and
applies the same rules as to an effect."""
import warnings

import numpy as np

from ..errors import InsufficientDataError, RangeError
from ..tcomp._cross_validation import bin_by_temperature, choose, score_sizes
from ..tcomp._table_fit import hat_basis

MAX_POLY_ORDER = 8
TABLE_KNOTS = (6, 8, 12, 16, 24, 32, 48)
MIN_SAMPLES_PER_KNOT = 3       # distinct temperatures per knot, so a knot is determined
SIZE_BINS = 200                # the size is chosen on at most this many temperature bins


def knots_supported(data, n_knots):
    """True when every knot of an n-knot table over the data's range carries
    at least one sample's weight and there are MIN_SAMPLES_PER_KNOT distinct
    temperatures per knot."""
    T = data.T[data.mask]
    if np.unique(T).size < MIN_SAMPLES_PER_KNOT * n_knots:
        return False
    weight = hat_basis(data.u_T(T), np.linspace(-1.0, 1.0, n_knots)).sum(axis=0)
    return bool(np.all(weight >= 1.0))


def offset_part(model):
    """The current model's offset in temperature plus its residual: what a
    new offset shape has to follow."""
    cols = [j for j, nm in enumerate(model.names)
            if nm == "const" or nm.startswith("u^") or nm.startswith("table:")]
    return model.residual + model.design[:, cols] @ model.beta[cols]


def _chosen(family, sizes, T, y):
    if not sizes:
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return choose(score_sizes(family, sizes, T, y)).size
    except (InsufficientDataError, RangeError):
        return None


def shape_trials(data, model):
    """Larger base offsets than `model`'s: [(params, spec)], params naming
    the family and size (at most one polynomial and one table).  Empty
    without temperature."""
    spec = model.spec
    if data.T is None or np.unique(data.T[data.mask]).size < 4:
        return []
    T, y = data.T[data.mask], offset_part(model)[data.mask]
    distinct = np.unique(T).size
    if distinct > SIZE_BINS:    # a curve, as the compensation fit sees a time series
        curve = bin_by_temperature(T, y, ("offset",), float(np.ptp(T)) / SIZE_BINS)
        T, y = curve.temp, curve.values[:, 0]
    out = []
    if spec.base_family == "poly":
        orders = list(range(spec.base_order + 1, min(MAX_POLY_ORDER, distinct - 1) + 1))
        order = _chosen("poly", orders, T, y)
        if order is not None:
            out.append(({"family": "poly", "order": order}, spec.with_base("poly", order)))
    current = spec.base_order if spec.base_family == "table" else 0
    knots = _chosen("pwl", [k for k in TABLE_KNOTS if k > current and knots_supported(data, k)], T, y)
    if knots is not None:
        out.append(({"family": "table", "knots": knots}, spec.with_base("table", knots)))
    return out


def describe(params):
    """'table, 24 knots' / 'polynomial, order 7'."""
    if params["family"] == "table":
        return f"table, {params['knots']} knots"
    return f"polynomial, order {params['order']}"
