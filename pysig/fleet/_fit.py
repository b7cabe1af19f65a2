"""Batched temperature-compensation fits for a whole fleet of devices: the
per-device fit of pysig.tcomp._poly_fit (polynomial f(T) on the device's centred,
scaled temperature; delta = f(T) - f(T0); order by leave-one-temperature-out
cross-validation; int32 coefficients in an automatic Q format), done for
every device at once in numpy instead of a Python loop per device.

How it is batched.  Rows carry a device index.  Per device the temperature
scaling (pysig.tcomp._quant.choose_scaling, vectorised) gives u in [-1, 1];
the readings are centred on the device's mean.  The normal equations of
every device, and of every device with one temperature group left out (the
cross-validation folds), come from np.bincount sums of u^k and u^k y; one
stacked np.linalg.solve per polynomial order solves all of them, and one
step of iterative refinement on the residuals brings the result to what the
SVD solver of pysig.lsq gives (tests: batched == pysig.tcomp._poly_fit.fit_tcomp).

A device that cannot be fitted (too few temperatures, T0 outside its range,
a non-finite or saturated reading, a drift too steep for the fixed-point
form) is not an error for the fleet: it gets ``ok = False`` and a reason,
and the others go on."""
from dataclasses import dataclass

import numpy as np

from ..tcomp import _poly_fit as single
from ..tcomp import _quant as quant
from .._rails import INT16_RAILS, at_rail
from ..tcomp._poly_model import TcompModel

CV_TOLERANCE = 0.05        # as pysig.tcomp._poly_fit.select_order


@dataclass
class FleetFit:
    """Per-device results, arrays indexed by device (D devices, A axes).

    coef[d, a, :order[d] + 1] is the delta polynomial (ascending powers of
    u), f_t0 the reading at T0, coef_q / q its fixed-point form; cv_rms the
    held-out RMS at the chosen order (NaN where cross-validation needs more
    temperatures than the device has), rms the in-sample residual RMS, drift
    the mean slope of delta over the calibrated range (reading units / °C).
    """
    devices: np.ndarray
    axes: list
    t0: float
    ok: np.ndarray
    reason: np.ndarray
    order: np.ndarray
    n_temps: np.ndarray
    samples: np.ndarray
    t_lo: np.ndarray
    t_hi: np.ndarray
    t_center: np.ndarray
    u_mul: np.ndarray
    u_shift: np.ndarray
    coef: np.ndarray
    f_t0: np.ndarray
    q: np.ndarray
    coef_q: np.ndarray
    bound: np.ndarray
    rms: np.ndarray
    cv_rms: np.ndarray
    drift: np.ndarray

    def model(self, d, temp_column="temp"):
        """The TcompModel of device d (as pysig.tcomp._poly_fit would build it)."""
        if not self.ok[d]:
            raise ValueError(f"device {self.devices[d]!r} was not fitted: {self.reason[d]}")
        n = int(self.order[d])
        scaling = quant.TemperatureScaling(int(self.t_lo[d]), int(self.t_hi[d]), int(self.t_center[d]),
                                           int(self.u_mul[d]), int(self.u_shift[d]))
        per_axis = {a: {"rms": float(self.rms[d, i]), "q": int(self.q[d, i]),
                        "error_bound_lsb": float(self.bound[d, i]),
                        "cv_rms": None if np.isnan(self.cv_rms[d, i]) else float(self.cv_rms[d, i])}
                    for i, a in enumerate(self.axes)}
        report = {"device": str(self.devices[d]), "fleet_fit": True, "per_axis": per_axis,
                  "samples": int(self.samples[d]), "temperatures": int(self.n_temps[d])}
        return TcompModel(axes=list(self.axes), order=n, t0=float(self.t0), scaling=scaling,
                          coef=[self.coef[d, i, :n + 1].copy() for i in range(len(self.axes))],
                          f_t0=[float(v) for v in self.f_t0[d]], q=[int(v) for v in self.q[d]],
                          coef_q=[tuple(int(v) for v in self.coef_q[d, i, :n + 1])
                                  for i in range(len(self.axes))],
                          error_bound_lsb=[float(v) for v in self.bound[d]],
                          temp_column=temp_column, report=report)


# ---- temperature groups, per device ---------------------------------------------
def device_groups(dev, temp, n_dev, gap=single.GAP_C, max_span=single.MAX_SPAN_C,
                  min_share=single.MIN_SHARE):
    """Per row the device's temperature-group label (-1: a piece too small
    to count), and per device the number of groups: the rule of
    pysig.tcomp._poly_fit.temperature_groups, vectorised; devices with a cluster
    wider than `max_span` (a ramp, cut into pieces) take the per-device code."""
    order = np.lexsort((temp, dev))
    sd, st = dev[order], temp[order]
    new = np.ones(sd.size, dtype=bool)
    new[1:] = (sd[1:] != sd[:-1]) | (np.diff(st) > gap)
    cluster = np.cumsum(new) - 1
    starts = np.flatnonzero(new)
    lo, hi = st[starts], st[np.r_[starts[1:], sd.size] - 1]
    cdev = sd[starts]
    count = np.diff(np.r_[starts, sd.size])
    wide = np.ceil((hi - lo) / max_span - 1e-9) > 1
    biggest = np.zeros(n_dev, dtype=np.int64)
    np.maximum.at(biggest, cdev, count)
    keep = count >= min_share * biggest[cdev]
    rank = np.cumsum(keep) - 1                                 # rank among kept clusters, fleet-wide
    dev_start = np.flatnonzero(np.r_[True, cdev[1:] != cdev[:-1]])
    first_rank = np.zeros(n_dev, dtype=np.int64)
    first_rank[cdev[dev_start]] = np.r_[0, np.cumsum(keep)][dev_start]   # kept clusters of earlier devices
    label_sorted = np.where(keep[cluster], rank[cluster] - first_rank[sd], -1)
    labels = np.empty_like(label_sorted)
    labels[order] = label_sorted
    n_groups = np.bincount(cdev[keep], minlength=n_dev)
    for d in np.unique(cdev[wide]):                        # ramps: a Python call per such device
        rows = np.sort(order[np.searchsorted(sd, d, "left"):np.searchsorted(sd, d, "right")])
        g = single.temperature_groups(temp[rows], gap, max_span, min_share)
        labels[rows] = g.labels
        n_groups[d] = g.count
    return labels, n_groups


# ---- fixed point, vectorised --------------------------------------------------
def choose_scaling(t_lo, t_hi):
    """pysig.tcomp._quant.choose_scaling over arrays (needs t_lo < t_hi)."""
    t_lo, t_hi = np.asarray(t_lo, np.int64), np.asarray(t_hi, np.int64)
    t_center = (t_lo + t_hi) // 2
    half = np.maximum(t_hi - t_center, t_center - t_lo)
    shift = np.zeros_like(t_lo)
    u_mul = np.zeros_like(t_lo)
    found = np.zeros(t_lo.shape, dtype=bool)
    for s in range(30, -1, -1):
        m = (np.int64(quant.INT16_MAX) << s) // half
        take = ~found & (m <= quant.INT16_MAX)
        shift[take], u_mul[take] = s, m[take]
        found |= take
    return t_center, u_mul, shift


def quantize(coef, order):
    """pysig.tcomp._quant.quantize_axis over arrays: coef (..., n+1), zero
    above each row's `order` (broadcast); returns (q, ints, bound, fits).
    Starts each row at the largest q the coefficient sum allows and steps
    down only where the rounded sum does not fit (one or two steps)."""
    shape = coef.shape
    coef = coef.reshape(-1, shape[-1])
    orders = np.broadcast_to(np.asarray(order), shape[:-1]).astype(np.int64).ravel()
    total = np.abs(coef).sum(-1)
    with np.errstate(divide="ignore"):
        upper = np.floor(np.log2((quant.INT32_MAX + (orders + 1) / 2.0) / total))
    q = np.clip(np.nan_to_num(upper, nan=-1, posinf=quant.MAX_Q, neginf=-1), -1, quant.MAX_Q).astype(np.int64)
    pending = q >= 0
    ints = np.zeros(coef.shape, dtype=np.int64)
    while np.any(pending):
        qp = q[pending]
        vals = np.rint(coef[pending] * np.ldexp(1.0, qp)[:, None])
        half = np.where(qp > 0, np.ldexp(1.0, np.maximum(qp - 1, 0)), 0.0)
        fits = np.abs(vals).sum(-1) + orders[pending] + half <= quant.INT32_MAX
        where = np.flatnonzero(pending)
        ints[where[fits]] = vals[fits].astype(np.int64)
        q[where[~fits]] -= 1
        pending[where[fits]] = False
        pending &= q >= 0
    ok = q >= 0
    qq = np.where(ok, q, 0)
    weights = np.arange(coef.shape[-1])
    bound = ((orders + 1) * 0.5 + orders) / np.ldexp(1.0, qq) + (weights * np.abs(coef)).sum(-1) / 65536.0
    return q.reshape(shape[:-1]), ints.reshape(shape), bound.reshape(shape[:-1]), ok.reshape(shape[:-1])


def _solve_spd(G, rhs):
    """Solve G x = rhs for a stack of small symmetric positive definite
    systems: G[i][j] and rhs[i] are m-long arrays (rhs[i] of shape (A, m)).
    Cholesky vectorised over the stack, k steps of numpy on contiguous
    m-long arrays (LAPACK's per-matrix call costs more for k <= 9).
    Returns x as a list of k arrays of shape (A, m)."""
    k = len(G)
    L = [[None] * k for _ in range(k)]
    for j in range(k):
        d = G[j][j] - sum(L[j][p] * L[j][p] for p in range(j)) if j else G[j][j]
        L[j][j] = np.sqrt(d)
        for i in range(j + 1, k):
            acc = G[i][j] - sum(L[i][p] * L[j][p] for p in range(j)) if j else G[i][j]
            L[i][j] = acc / L[j][j]
    z = []
    for i in range(k):
        acc = rhs[i] - sum(L[i][j] * z[j] for j in range(i)) if i else rhs[i]
        z.append(acc / L[i][i])
    x = [None] * k
    for i in range(k - 1, -1, -1):
        acc = z[i] - sum(L[j][i] * x[j] for j in range(i + 1, k)) if i < k - 1 else z[i]
        x[i] = acc / L[i][i]
    return x


# ---- the batched least squares ----------------------------------------------------
def _power_sums(index, n_bins, u, y, kmax):
    """S[b, k] = sum u^k, B[b, a, k] = sum u^k y_a over rows of bin b."""
    S = np.empty((n_bins, 2 * kmax + 1))
    B = np.empty((n_bins, y.shape[1], kmax + 1))
    p = np.ones_like(u)
    for k in range(2 * kmax + 1):
        S[:, k] = np.bincount(index, p, minlength=n_bins)
        if k <= kmax:
            for a in range(y.shape[1]):
                B[:, a, k] = np.bincount(index, p * y[:, a], minlength=n_bins)
        p = p * u
    return S, B


def _solve(S, B, n, valid):
    """Stacked normal equations of order n for m systems: S (m, >=2n+1)
    power sums, B (m, A, >=n+1) moment sums; systems where `valid` is False
    get the identity (their result is not used).  Returns (x (m, n+1, A),
    the Gram entries for a later refinement step)."""
    St = np.ascontiguousarray(S[:, :2 * n + 1].T)
    G = [[np.where(valid, St[i + j], float(i == j)) for j in range(n + 1)] for i in range(n + 1)]
    Bt = np.ascontiguousarray(np.transpose(B[:, :, :n + 1], (2, 1, 0)))     # (n+1, A, m)
    return _stack(_solve_spd(G, list(Bt))), G


def _stack(x):
    """List of k arrays (A, m) -> array (m, k, A)."""
    return np.transpose(np.stack(x), (2, 0, 1))


def _eval(u, c):
    """Rows' polynomial values: u (N,), c (N, n+1, A) ascending -> (N, A)."""
    out = c[:, -1, :].copy()
    for k in range(c.shape[1] - 2, -1, -1):
        out = out * u[:, None] + c[:, k, :]
    return out


def _poly_sums(index, n_bins, u, r, n):
    """sum u^k r_a per bin, as (n_bins, n+1, A)."""
    out = np.empty((n_bins, n + 1, r.shape[1]))
    p = np.ones_like(u)
    for k in range(n + 1):
        for a in range(r.shape[1]):
            out[:, k, a] = np.bincount(index, p * r[:, a], minlength=n_bins)
        p = p * u
    return out


def fit_fleet(dev, temp, values, devices, axes, model="auto", t0=25.0, max_order=single.MAX_FIT_ORDER):
    """Fit every device of a long-format log at once.

    Parameters
    ----------
    dev : ndarray of int
        Per row the device index, 0 .. len(devices) - 1.
    temp : ndarray of float
        Per row the temperature, °C.
    values : ndarray, shape (rows, axes)
        Readings (int16 sensor codes, as pysig.tcomp._poly_fit expects).
    devices : sequence
        Device names (serials), indexed by `dev`.
    axes : list of str
        Column names of `values`.
    model : "auto" or int
        Polynomial order 1..8, or "auto" (leave-one-temperature-out CV,
        the rule of pysig.tcomp._poly_fit.select_order).
    t0 : float
        Reference temperature, °C (delta(T0) = 0); must lie inside every
        device's calibrated range (devices where it does not are not fitted).

    Returns
    -------
    FleetFit
        Per device: ``ok``, ``reason`` (why a device was not fitted),
        ``order``, the delta polynomial ``coef`` and its fixed-point form,
        ``cv_rms``, ``rms``, ``drift``.

    Examples
    --------
    Two devices, four chamber temperatures, one axis; the second device
    drifts twice as fast:

    >>> import numpy as np
    >>> temps = np.array([0.0, 25.0, 50.0, 70.0])
    >>> dev = np.repeat([0, 1], 4 * 10)
    >>> temp = np.tile(np.repeat(temps, 10), 2)
    >>> x = np.where(dev == 0, 1.0, 2.0) * 0.02 * (temp - 25.0) ** 2
    >>> r = fit_fleet(dev, temp, x[:, None], ["A1", "B2"], ["x"], model=2)
    >>> r.ok.tolist(), r.order.tolist()
    ([True, True], [2, 2])
    >>> np.round(r.drift[:, 0] / r.drift[0, 0], 6).tolist()
    [1.0, 2.0]
    """
    dev = np.asarray(dev, dtype=np.int64)
    temp = np.asarray(temp, dtype=float)
    y = np.asarray(values, dtype=float).reshape(dev.size, -1)
    D, A = len(devices), y.shape[1]
    refused = np.zeros(D, dtype=bool)
    reasons = {}
    samples = np.bincount(dev, minlength=D)

    def refuse(mask, text):
        fresh = np.flatnonzero(mask & ~refused)
        if fresh.size:
            texts = text(fresh) if callable(text) else [text] * fresh.size
            reasons.update(zip(fresh.tolist(), texts))
            refused[fresh] = True

    refuse(samples == 0, "no samples")
    bad_row = ~np.isfinite(temp) | ~np.all(np.isfinite(y), axis=1)
    refuse(np.bincount(dev[bad_row], minlength=D) > 0, "non-finite temperature or reading")
    sat_row = np.any(at_rail(y, INT16_RAILS), axis=1)
    refuse(np.bincount(dev[sat_row], minlength=D) > 0,
           "a reading at the int16 rail (saturated: its true value is unknown)")
    # rows of refused devices take no part in the sums (their values may be NaN)
    live = ~refused[dev]
    t_c = np.where(live, np.rint(np.where(live, temp, 0) * quant.T_PER_DEGC), 0)
    refuse(np.bincount(dev[live & (np.abs(t_c) > 32767)], minlength=D) > 0,
           "temperature outside the int16 range in 0.01 °C")
    live = ~refused[dev]
    big = np.iinfo(np.int64).max
    t_lo = np.full(D, big, dtype=np.int64)
    t_hi = np.full(D, -big, dtype=np.int64)
    np.minimum.at(t_lo, dev[live], t_c[live].astype(np.int64))
    np.maximum.at(t_hi, dev[live], t_c[live].astype(np.int64))
    labels, n_groups = device_groups(dev, np.where(live, temp, 0.0), D)
    n_groups = np.where(refused, 0, n_groups)
    refuse(t_hi <= t_lo, "constant temperature: a temperature model needs at least 2 distinct temperatures")
    if model == "auto":
        refuse(n_groups < 3, lambda ds: [f"{n_groups[d]} temperatures: choosing the order by "
                                         f"cross-validation needs at least 3" for d in ds])
    else:
        need = int(model) + 1
        refuse(n_groups < need, lambda ds: [f"{n_groups[d]} temperatures: order {model} needs at "
                                            f"least {need}" for d in ds])
    ok = ~refused
    lo_c, hi_c = np.where(ok, t_lo, 0), np.where(ok, t_hi, 1)
    t_center, u_mul, u_shift = choose_scaling(lo_c, hi_c)
    refuse(ok & ((t0 * quant.T_PER_DEGC < lo_c) | (t0 * quant.T_PER_DEGC > hi_c)),
           lambda ds: [f"T0 = {t0} °C is outside the calibrated range {lo_c[d] / 100:.2f}.."
                       f"{hi_c[d] / 100:.2f} °C" for d in ds])
    ok = ~refused
    center_c = t_center / quant.T_PER_DEGC
    scale_c = (2.0 ** (u_shift + 15)) / np.maximum(u_mul, 1) / quant.T_PER_DEGC

    # rows of fittable devices only
    rows = ok[dev]
    d_r, t_r, y_r, g_r = dev[rows], temp[rows], y[rows], labels[rows]
    u = (t_r - center_c[d_r]) / scale_c[d_r]
    ybar = np.zeros((D, A))
    for a in range(A):
        ybar[:, a] = np.bincount(d_r, y_r[:, a], minlength=D) / np.maximum(samples, 1)
    yc = y_r - ybar[d_r]
    G_max = int(n_groups.max()) if D else 0
    n_bins = D * (G_max + 1)
    b_r = d_r * (G_max + 1) + (g_r + 1)                  # bin 0 of a device: rows in no group
    top = int(min(max_order, max(int(n_groups.max()) - 2, 1))) if D else 1
    orders = list(range(1, top + 1)) if model == "auto" else [int(model)]
    kmax = max(orders)
    S_g, B_g = _power_sums(b_r, n_bins, u, yc, kmax)
    S_g = S_g.reshape(D, G_max + 1, -1)
    B_g = B_g.reshape(D, G_max + 1, A, -1)
    S_d, B_d = S_g.sum(1), B_g.sum(1)

    cv_var = np.full((D, len(orders)), np.inf)
    cv_rms_all = np.full((D, len(orders), A), np.nan)
    kept = g_r >= 0
    n_kept = np.bincount(d_r[kept], minlength=D)
    for j, n in enumerate(orders):
        can = ok & (n_groups - 1 >= n + 1)
        if not np.any(can):
            continue
        # leave group g out: the device's sums minus the group's
        S_cv = (S_d[:, None, :] - S_g[:, 1:, :]).reshape(D * G_max, -1)
        B_cv = (B_d[:, None] - B_g[:, 1:]).reshape(D * G_max, A, -1)
        valid = (can[:, None] & (np.arange(G_max)[None, :] < n_groups[:, None])).ravel()
        c_cv, _ = _solve(S_cv, B_cv, n, valid)
        sel = kept & can[d_r]
        idx = d_r[sel] * G_max + g_r[sel]
        r = yc[sel] - _eval(u[sel], c_cv[idx])
        dd = d_r[sel]
        m = np.maximum(n_kept, 1)[:, None]
        s1 = np.stack([np.bincount(dd, r[:, a], minlength=D) for a in range(A)], 1)
        s2 = np.stack([np.bincount(dd, r[:, a] ** 2, minlength=D) for a in range(A)], 1)
        var = s2 / m - (s1 / m) ** 2
        cv_var[can, j] = var[can].mean(1)
        cv_rms_all[can, j] = np.sqrt(s2 / m)[can]

    if model == "auto":
        best = cv_var.min(1)
        within = cv_var <= best[:, None] * (1 + CV_TOLERANCE)
        order = np.where(ok, np.asarray(orders)[np.argmax(within, axis=1)], 0)
        cv_rms = cv_rms_all[np.arange(D), np.argmax(within, axis=1)]
    else:
        order = np.where(ok, int(model), 0)
        cv_rms = cv_rms_all[:, 0]

    coef = np.zeros((D, A, kmax + 1))
    rms = np.full((D, A), np.nan)
    for n in sorted(set(order[ok].tolist())):
        sel_d = ok & (order == n)
        c, G = _solve(S_d, B_d, n, sel_d)
        rsel = sel_d[d_r]
        rr = yc[rsel] - _eval(u[rsel], c[d_r[rsel]])
        rhs = np.transpose(_poly_sums(d_r[rsel], D, u[rsel], rr, n), (1, 2, 0))
        dc = _stack(_solve_spd(G, list(rhs)))                # one refinement step
        c = c + dc
        rr = yc[rsel] - _eval(u[rsel], c[d_r[rsel]])
        ss = np.stack([np.bincount(d_r[rsel], rr[:, a] ** 2, minlength=D) for a in range(A)], 1)
        rms[sel_d] = np.sqrt(ss / np.maximum(samples, 1)[:, None])[sel_d]
        coef[sel_d, :, :n + 1] = np.transpose(c, (0, 2, 1))[sel_d]
    coef[:, :, 0] += ybar
    u0 = (t0 - center_c) / scale_c
    f_t0 = np.zeros((D, A))
    for k in range(coef.shape[2] - 1, -1, -1):
        f_t0 = f_t0 * u0[:, None] + coef[:, :, k]
    coef[:, :, 0] -= f_t0
    coef = coef[:, :, :kmax + 1]
    q, coef_q, bound, fits = quantize(coef, order[:, None])
    too_steep = ok & (~np.all(fits, 1) | np.any(bound > quant.MAX_ERROR_LSB, 1))
    refuse(too_steep, lambda ds: [f"the fixed-point correction could be off by up to "
                                  f"{bound[d].max():.2f} LSB (> {quant.MAX_ERROR_LSB}): the drift "
                                  f"is too steep for a Q15 temperature" for d in ds])
    ok = ~refused
    # mean slope of delta over the calibrated range: (delta(t_hi) - delta(t_lo)) / span
    u_lo = (t_lo / quant.T_PER_DEGC - center_c) / scale_c
    u_hi = (t_hi / quant.T_PER_DEGC - center_c) / scale_c
    pv = [np.zeros((D, A)), np.zeros((D, A))]
    for k in range(coef.shape[2] - 1, -1, -1):
        pv = [pv[0] * u_lo[:, None] + coef[:, :, k], pv[1] * u_hi[:, None] + coef[:, :, k]]
    span = np.maximum((t_hi - t_lo) / quant.T_PER_DEGC, 1e-9)
    drift = np.where(ok[:, None], (pv[1] - pv[0]) / span[:, None], np.nan)
    keep_if = ok[:, None]
    reason = np.full(D, "", dtype=object)
    for d, text in reasons.items():
        reason[d] = text
    return FleetFit(devices=np.asarray(devices, dtype=object), axes=list(axes), t0=float(t0), ok=ok,
                    reason=reason, order=np.where(ok, order, 0), n_temps=n_groups, samples=samples,
                    t_lo=np.where(ok, t_lo, 0), t_hi=np.where(ok, t_hi, 0), t_center=t_center,
                    u_mul=u_mul, u_shift=u_shift, coef=np.where(keep_if[..., None], coef, 0.0),
                    f_t0=np.where(keep_if, f_t0, np.nan), q=q, coef_q=coef_q, bound=bound,
                    rms=np.where(keep_if, rms, np.nan), cv_rms=np.where(keep_if, cv_rms, np.nan),
                    drift=drift)
