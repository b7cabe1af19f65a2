"""Offset shape candidates of the refinement loop: when the residual against
temperature has structure a low-order polynomial cannot follow (a gyro
offset that rises and falls), a larger polynomial or a piecewise-linear
table (pysig.tcomp.pwl's hat basis, what firmware evaluates by lookup) may
remove it.  Each is a replacement of the base offset, scored by the same
blocked CV and the same rules as an effect."""
import numpy as np

from ..tcomp.pwl import hat_basis

MAX_POLY_ORDER = 8
TABLE_KNOTS = (6, 8, 12, 16, 24, 32, 48)
MIN_SAMPLES_PER_KNOT = 3       # distinct temperatures per knot, so a knot is determined


def knots_supported(data, n_knots):
    """True when every knot of an n-knot table over the data's range carries
    at least one sample's weight and there are MIN_SAMPLES_PER_KNOT distinct
    temperatures per knot."""
    T = data.T[data.mask]
    if np.unique(T).size < MIN_SAMPLES_PER_KNOT * n_knots:
        return False
    weight = hat_basis(data.u_T(T), np.linspace(-1.0, 1.0, n_knots)).sum(axis=0)
    return bool(np.all(weight >= 1.0))


def shape_trials(data, spec):
    """Larger base offsets than `spec`'s: [(params, spec)], params naming
    the family and size.  None without temperature."""
    if data.T is None:
        return []
    distinct = np.unique(data.T[data.mask]).size
    out = []
    if spec.base_family == "poly":
        for order in range(spec.base_order + 1, min(MAX_POLY_ORDER, distinct - 1) + 1):
            out.append(({"family": "poly", "order": order}, spec.with_base("poly", order)))
    current = spec.base_order if spec.base_family == "table" else 0
    for k in TABLE_KNOTS:
        if k > current and knots_supported(data, k):
            out.append(({"family": "table", "knots": k}, spec.with_base("table", k)))
    return out


def describe(params):
    """'table, 24 knots' / 'polynomial, order 7'."""
    if params["family"] == "table":
        return f"table, {params['knots']} knots"
    return f"polynomial, order {params['order']}"
