"""Candidate effects of the refinement loop: each a named family
with its own parameters, turned into regressor columns of one linear model.

The measurement model refine fits, in the sensor's own unit (LSB, counts):

    y = b0 + g*r + sum_k a_k u(T')^k                      base (the magnetometer paper's)
          + sum_j d_j r u(T')^j                           gain_drift
          + h * (T' - play_w(T')) / w                     hysteresis
          + c * (lag_tau(r) - r) / |r|max                 creep
          + sum_k n_k u_r^k  (k >= 2)                     nonlinearity
          + sum_i x_i u_other_i                           cross_axis
          + sum_j q_j s_j(t)                              drift (a nuisance)
    T' = lag_tau(T)  when thermal_lag is in the model, T otherwise

u(T) is T centred and scaled to [-1, 1] (pysig.lsq.center_scale), r the
reference (true value), u_r the reference centred and scaled.  Every
coefficient is linear and is fitted by pysig.lsq.fit_linear_model; the three
nonlinear parameters (lag and creep time constants, hysteresis width) are
found by a 1-D search (a log grid, then scipy.optimize.minimize_scalar on
the full data).

Search ranges come from the record: a time constant from half a sample
period to a third of the record, a hysteresis width from 0.1 % to half the
temperature span.  A fit at the top of that range is followed further, up to
what the record can still resolve (a time constant of the whole record, a
width of the whole span: beyond it the term is a line in time or in
temperature that the base model already has); only there is it at the edge.

The drift is a slow function of time (a cubic spline through a few knots
spanning the record) fitted with the temperature model, so the physical
effects are judged on top of it; it is a nuisance, not a property of the
device, and is left out of the device correction.

Time stamps need not be uniform.  A lag is filtered over the real time
between samples (FitData.runs), so a gap relaxes it as far as that much
time does instead of being filtered through as one sample.  A gap longer
than BREAK_PERIODS sample periods and BREAK_FRACTION of the record parts
two sessions (FitData.breaks): the drift runs over the logged time (each
gap shortened to one sample period) and takes a step at each break, since
nothing ties the zero of one session to the last of the one before.

The on-device forms of the state (lag IIR, play operator) are in
csrc/include/sig_effects.h and csrc/refine/ (sig_lag.c, sig_hyst.c);
tests/spec/effects.py is their fixed-point spec.  The float forms
here are what the fit uses."""
from dataclasses import dataclass, field

import numpy as np
from scipy import interpolate, optimize, signal, stats

from ..errors import InsufficientDataError
from ..lsq import center_scale, fit_linear_model
from ..tcomp._table_fit import hat_basis

GRID_POINTS = 20
LOCAL_FACTOR = 2.0         # a fold's grid is finer within this factor of the full-data fit
LOCAL_POINTS = 11          # (steps of 2**(2/10), 15 %: the 20-point grid steps ~80 %)
EXTEND_FACTOR = 2.0        # a fit at the top of its range: look this much further, step by step
EXTEND_POINTS = 6
MONOTONE_RHO = 0.9       # drift unavailable: time and temperature rank alike
IRREGULAR_FACTOR = 1.5   # an interval this much over the median is filtered on its own
BREAK_PERIODS = 10.0     # a gap of more sample periods than this, and of more than
BREAK_FRACTION = 0.01    # this fraction of the record, parts two sessions

from . import _effects


# ---- state primitives (float) ---------------------------------------------

def lag_alpha(tau, dt):
    """Per-sample gain of the exact first-order lag discretisation."""
    return 1.0 - np.exp(-dt / tau)


def first_order_lag(x, alpha):
    """z[0] = x[0]; z[k] = z[k-1] + alpha * (x[k] - z[k-1])  (the device's IIR)."""
    x = np.asarray(x, dtype=float)
    z, _ = signal.lfilter([alpha], [1.0, -(1.0 - alpha)], x, zi=[(1.0 - alpha) * x[0]])
    return z


def lag_on_times(x, tau, data):
    """first_order_lag of `x` over the real time between samples: each run
    of regular intervals (data.runs) at its mean interval, each longer
    interval (a dropped sample, a gap) relaxing the state by its own
    length, z <- z + (1 - exp(-interval / tau)) (x - z).  Uniform times
    give first_order_lag at the median interval, as the device's IIR."""
    if len(data.runs) == 1:
        return first_order_lag(x, lag_alpha(tau, data.dt))
    x = np.asarray(x, dtype=float)
    z = np.empty(x.size)
    for a, b, step in data.runs:
        alpha = lag_alpha(tau, step)
        start = x[a] if a == 0 else z[a - 1] + lag_alpha(tau, data.t[a] - data.t[a - 1]) * (x[a] - z[a - 1])
        z[a] = start
        if b - a > 1:
            z[a + 1:b], _ = signal.lfilter([alpha], [1.0, -(1.0 - alpha)], x[a + 1:b],
                                           zi=[(1.0 - alpha) * start])
    return z


def play_operator(x, width, start=0):
    """Backlash (play) operator: p follows x only when x moves more than
    `width` away from it; x - p lies in [-width, width] and is +width while
    heating, -width while cooling: the hysteresis branch state.  `start`
    (+1 heating, -1 cooling, 0 neither) is the branch before the first
    sample: p[0] = x[0] - start * width.

    One implementation: the firmware's float form (sig_hyst_step_f in
    csrc/refine/sig_hyst.c) through Cython; its spec is
    spec.effects.HystF."""
    branch, _, _ = _effects.hyst_f(x, float(width), 0.0, int(start))
    return np.asarray(x, dtype=float) - branch


# ---- the data a model is fitted to ------------------------------------------

@dataclass
class FitData:
    """One measured column and what it is fitted against.  `mask` marks the
    samples used for fitting and scoring (False: glitch or transition)."""
    y: np.ndarray
    t: np.ndarray
    T: np.ndarray = None          # temperature, None for weighing
    r: np.ndarray = None          # reference (true value); None: constant field
    others: dict = field(default_factory=dict)   # other axes' references (cross_axis)
    mask: np.ndarray = None
    labels: dict = field(default_factory=dict)   # units/names for reports
    ref_from_y: bool = False      # reference built from y itself (plateau levels)
    segments: tuple = (0,)        # first sample of each power-on (files joined end to end)

    def __post_init__(self):
        self.y = np.asarray(self.y, dtype=float)
        n = self.y.size
        self.t = np.asarray(self.t, dtype=float)
        if self.mask is None:
            self.mask = np.ones(n, dtype=bool)
        self.mask = np.asarray(self.mask, dtype=bool)
        dt = np.diff(self.t)
        self.dt = float(np.median(dt)) if dt.size else 1.0
        self._time_structure(dt)
        if self.T is not None:
            self.T = np.asarray(self.T, dtype=float)
            self.t_center, self.t_scale = center_scale(self.T)
        if self.r is not None:
            self.r = np.asarray(self.r, dtype=float)
            self.r_center, self.r_scale = center_scale(self.r)
            self.r_abs = float(np.max(np.abs(self.r))) or 1.0
        self.others = {k: np.asarray(v, dtype=float) for k, v in self.others.items()}
        self.segments = tuple(sorted({0, *(int(i) for i in self.segments if 0 <= int(i) < n)}))

    def _time_structure(self, dt):
        """`runs`: (first, end, mean interval) of each run of samples joined
        by intervals under IRREGULAR_FACTOR x the median; `breaks`: the first
        sample of each session after the first (a gap over BREAK_PERIODS
        sample periods and BREAK_FRACTION of the record); `t_logged`: the
        time with each break shortened to one sample period; `span_t` its
        span, the time the record resolves."""
        irregular = np.flatnonzero(dt > IRREGULAR_FACTOR * self.dt) + 1
        edges = [0, *irregular.tolist(), self.y.size]
        self.runs = tuple((a, b, float(np.mean(dt[a:b - 1])) if b - a > 1 else self.dt)
                          for a, b in zip(edges[:-1], edges[1:]) if b > a)
        span = float(self.t[-1] - self.t[0]) if dt.size else 0.0
        self.breaks = tuple(int(k) + 1 for k in np.flatnonzero(
            (dt > BREAK_PERIODS * self.dt) & (dt > BREAK_FRACTION * span)))
        self.t_logged = self.t
        if self.breaks:
            shortened = dt.copy()
            shortened[[k - 1 for k in self.breaks]] = self.dt
            self.t_logged = self.t[0] + np.concatenate([[0.0], np.cumsum(shortened)])
        self.span_t = float(self.t_logged[-1] - self.t_logged[0]) if dt.size else 1.0

    @property
    def n(self):
        return self.y.size

    @property
    def has_ref(self):
        """A reference that varies (a constant one carries no gain information)."""
        return self.r is not None and np.unique(self.r[self.mask]).size >= 2

    def u_T(self, T):
        return (T - self.t_center) / self.t_scale

    def u_r(self):
        return (self.r - self.r_center) / self.r_scale


# ---- effect families ----------------------------------------------------------

@dataclass(frozen=True)
class Effect:
    """One fitted term of the model: family name, variant (an order, or 0),
    and the value of its nonlinear parameter (None for linear families)."""
    name: str
    variant: int = 0
    param: float = None


class Family:
    name = ""
    param_name = None      # name of the nonlinear parameter, if any
    param_unit = ""
    variants = (0,)
    nuisance = False       # a nuisance term: judged like an effect, never a property of the device
    time_only = False      # a function of time alone, as the drift is

    def unavailable(self, data):
        """None when the family applies to `data`, else the reason it does not."""
        return None

    def grid(self, data, top=None):
        """Values of the nonlinear parameter to try: log-spaced over bounds
        (up to `top` when the search was extended past them)."""
        b = self.bounds(data)
        if b is None:
            return [None]
        return list(np.geomspace(b[0], max(b[1], top or b[1]), GRID_POINTS))

    def fold_grid(self, data, top=None, center=None):
        """The values a cross-validation fold chooses among: `grid`, and a
        finer log grid within LOCAL_FACTOR of the full-data fit `center`,
        clipped to the searched range.  The parameter moves its columns
        smoothly (a time constant) or moves which samples switch branch (a
        play operator's width), so a fold's out-of-sample prediction is only
        as good as the grid step near its value: a warm-up extrapolated into
        a held-out start; a hysteresis 20 % off its width on the plain grid
        predicted a held-out block worse than none under a drift (CV RMS
        1.12 against 1.01 at the fitted width).  The choice is still made on
        each fold's training rows (_cross_validation.fold_choice)."""
        grid = self.grid(data, top)
        if center is None or grid == [None]:
            return grid
        lo, hi = grid[0], grid[-1]
        local = np.geomspace(center / LOCAL_FACTOR, center * LOCAL_FACTOR, LOCAL_POINTS)
        return sorted(set(grid) | {float(v) for v in local if lo <= v <= hi})

    def bounds(self, data):
        """(low, top) of the first search, from the record."""
        return None

    def limit(self, data):
        """The largest value the record can resolve: the search is extended
        up to it when a fit sits at the top of `bounds`."""
        b = self.bounds(data)
        return None if b is None else b[1]

    def columns(self, data, T_used, effect):
        """Regressor columns (n, k) and their names."""
        raise NotImplementedError

    variant_name = "variant"

    def describe(self, effect):
        d = {self.variant_name: effect.variant} if len(self.variants) > 1 else {}
        if self.param_name:
            d[self.param_name] = effect.param
        return d


class TimeConstantFamily(Family):
    """A family whose parameter is a time constant: from half a sample to a
    third of the recording, extended up to the whole recording."""
    param_name = "tau_s"

    def bounds(self, data):
        return data.dt * 0.5, max(data.dt * 2.0, data.span_t / 3.0)

    def limit(self, data):
        return max(data.dt * 2.0, data.span_t)


class GainDrift(Family):
    """Sensitivity depends on temperature: r * u(T')^j, j = 1..order."""
    name = "gain_drift"
    variants = (1, 2)
    variant_name = "order"

    def unavailable(self, data):
        if data.T is None:
            return "no temperature"
        if not data.has_ref:
            return "the reference is constant (gain cannot be told from offset)"
        return None

    def columns(self, data, T_used, effect):
        u = data.u_T(T_used)
        r = data.r / data.r_abs
        cols = [r * p for p in powers(u, effect.variant)]
        return np.column_stack(cols), [f"r*u^{j}" for j in range(1, effect.variant + 1)]


class ThermalLag(TimeConstantFamily):
    """The sensor's temperature lags the measured one: every temperature
    term uses T' = first_order_lag(T, tau) instead of T (no columns)."""
    name = "thermal_lag"

    def unavailable(self, data):
        return None if data.T is not None else "no temperature"

    def columns(self, data, T_used, effect):
        return np.empty((data.n, 0)), []

    def transform(self, data, T, effect):
        return lag_on_times(T, effect.param, data)


class Hysteresis(Family):
    """Heating and cooling branches differ: h * (T' - play_w(T')) / w."""
    name = "hysteresis"
    param_name = "width"
    variants = (0, 1, -1)      # the branch before the first sample: neither, heating, cooling
    variant_name = "start_branch"

    def unavailable(self, data):
        if data.T is None:
            return "no temperature"
        # both branches must be visited: the temperature (smoothed by a play
        # operator of 5 % of the span) must rise and fall by >= 10 % of the span
        span = float(np.ptp(data.T))
        if span <= 0:
            return "constant temperature"
        moves = np.diff(play_operator(data.T, 0.05 * span))
        if moves[moves > 0].sum() < 0.1 * span or -moves[moves < 0].sum() < 0.1 * span:
            return "the temperature only rises or only falls (one branch)"
        # a record that turns once (heat, then cool) puts one branch before
        # the turn and the other after it: a step in time, not a hysteresis
        sign = np.sign(moves[moves != 0])
        if np.count_nonzero(np.diff(sign)) < 2:
            return "the temperature turns only once (a branch cannot be told from a step in time)"
        return None

    def bounds(self, data):
        span = float(np.ptp(data.T)) or 1.0
        return span * 1e-3, span * 0.5

    def limit(self, data):
        return float(np.ptp(data.T)) or 1.0

    def columns(self, data, T_used, effect):
        w = effect.param
        return ((T_used - play_operator(T_used, w, effect.variant)) / w)[:, None], ["branch"]


class Creep(TimeConstantFamily):
    """Output drifts after a load change, proportional to the step:
    c * (lag_tau(r) - r) / |r|max (an exponential approach of time constant tau)."""
    name = "creep"

    def unavailable(self, data):
        return None if data.has_ref else "no varying reference (no load changes)"

    def columns(self, data, T_used, effect):
        z = lag_on_times(data.r, effect.param, data)
        return ((z - data.r) / data.r_abs)[:, None], ["lag(r)-r"]


class WarmUp(TimeConstantFamily):
    """A transient in time since power-on, at any temperature: one
    w_s * exp(-(t - t_s) / tau) column per power-on segment s (files joined
    end to end are separate power-ons), zero before the segment starts.

    Told apart from the drift by its time scale: a warm-up settles (two time
    constants, 86 %) within the first interval of the most flexible drift,
    so its knee is one the drift's smooth cubic pieces cannot follow.  A
    slower settling is a drift: the drift follows it (an exponential of a
    fifth of the record keeps 1.6 % of its spread off a 5-knot drift, one of
    an eighth 6 %, one of a twelfth 14 %), and the two cannot be told apart.
    So the search stops there and is not followed further."""
    name = "warm_up"
    SETTLED_TIME_CONSTANTS = 2.0
    time_only = True

    def bounds(self, data):
        knots = max(Drift.variants)
        top = data.span_t / ((knots - 1) * self.SETTLED_TIME_CONSTANTS)
        return data.dt * 0.5, max(data.dt * 2.0, top)

    def limit(self, data):
        return self.bounds(data)[1]

    def columns(self, data, T_used, effect):
        starts = list(data.segments) + [data.n]
        cols = np.zeros((data.n, len(data.segments)))
        for j, (a, b) in enumerate(zip(starts[:-1], starts[1:])):
            cols[a:b, j] = np.exp(-(data.t[a:b] - data.t[a]) / effect.param)
        return cols, [f"exp(-t/tau)@{a}" for a in data.segments]


class Nonlinearity(Family):
    """Higher order in the measured quantity: u_r^k, k = 2..order."""
    name = "nonlinearity"
    variants = (2, 3)
    variant_name = "order"

    def unavailable(self, data):
        if not data.has_ref:
            return "no varying reference"
        if data.ref_from_y:
            return "the reference is the reading's own plateau levels (no independent truth)"
        if np.unique(data.r[data.mask]).size < 4:
            return "fewer than 4 distinct reference values"
        return None

    def columns(self, data, T_used, effect):
        u = data.u_r()
        ks = range(2, effect.variant + 1)
        up = powers(u, max(ks))
        return np.column_stack([up[k - 1] for k in ks]), [f"u_r^{k}" for k in ks]


class CrossAxis(Family):
    """Other axes leak into this one: sum_i x_i * (other_i centred, scaled)."""
    name = "cross_axis"

    def unavailable(self, data):
        return None if data.others else "no other axes given"

    def columns(self, data, T_used, effect):
        cols, names = [], []
        for name, v in sorted(data.others.items()):
            c, s = center_scale(v)
            cols.append((v - c) / s)
            names.append(name)
        return np.column_stack(cols), names


class Drift(Family):
    """A slow drift in time under the physics (an instrument settling after
    it is set up, a zero that does not come back): a cubic spline in time
    through its values at `knots` uniform knots spanning the record
    (not-a-knot ends; 2 knots: a straight line, 3: a parabola).  Smooth,
    because a physical drift is: a piecewise-linear drift's corners leave
    the curvature of a settling for a wide hysteresis or a short warm-up to
    take (false claims on records with a drift alone).
    A few knots only, so it is slower than any effect it could hide (a
    warm-up or a lag of a fraction of the record).  Over the logged time,
    with a step at each break between sessions (FitData.breaks): a zero
    that wandered while nothing was logged is a step, which a smooth
    spline cannot follow and a hysteresis or a warm-up would take.  A nuisance: reported as
    its own line, never exported to the device."""
    name = "drift"
    variants = (2, 3, 4, 5)
    variant_name = "knots"
    nuisance = True

    def unavailable(self, data):
        if not data.span_t > 0:
            return "the record has no length in time"
        if data.T is not None:
            # a temperature that only rises (or only falls) with time, such as
            # rows sorted by temperature: a function of time is one of temperature
            rho = stats.spearmanr(data.t[data.mask], data.T[data.mask])[0]
            if abs(rho) >= MONOTONE_RHO:
                return (f"the temperature moves with time (Spearman rho {rho:.2f}): a drift in time "
                        "cannot be told from the offset in temperature")
        return None

    def columns(self, data, T_used, effect):
        t = data.t_logged
        knots = np.linspace(t[0], t[-1], effect.variant)
        # column j: the spline through 1 at knot j and 0 at the others; they
        # sum to one, so the first is the constant the base already has
        basis = interpolate.CubicSpline(knots, np.eye(effect.variant), bc_type="not-a-knot")(t)
        steps = [(np.arange(data.n) >= b).astype(float) for b in data.breaks]
        return (np.column_stack([basis[:, 1:], *steps]),
                [f"knot{j}" for j in range(1, effect.variant)] + [f"session@{b}" for b in data.breaks])


FAMILIES = {f.name: f for f in (GainDrift(), ThermalLag(), Hysteresis(), Creep(),
                                Nonlinearity(), CrossAxis(), WarmUp(), Drift())}
PHYSICAL = tuple(name for name, f in FAMILIES.items() if not f.nuisance)


def drift_curve(data, model):
    """The fitted drift in time (the reading's unit, zero at the start), or None."""
    cols = [j for j, nm in enumerate(model.names) if nm.startswith("drift:")]
    if not cols:
        return None
    curve = model.design[:, cols] @ model.beta[cols]
    return curve - curve[0]


# ---- the model: base + effects ------------------------------------------------

@dataclass
class ModelSpec:
    """Base offset in temperature and the effects.  `base_family` "poly":
    a polynomial of order `base_order` in u(T') (0: no temperature term);
    "table": a piecewise-linear table of `base_order` uniform knots over the
    calibrated range, flat outside it (pysig.tcomp._table_fit's hat basis, what
    the firmware's table lookup evaluates)."""
    base_order: int
    effects: tuple = ()
    base_family: str = "poly"

    def with_effect(self, effect):
        return ModelSpec(self.base_order, tuple(self.effects) + (effect,), self.base_family)

    def with_base(self, family, size):
        return ModelSpec(int(size), tuple(self.effects), family)

    def without(self, name):
        return ModelSpec(self.base_order, tuple(e for e in self.effects if e.name != name),
                         self.base_family)

    def describe_base(self):
        if self.base_family == "table":
            return f"table, {self.base_order} knots"
        return f"polynomial, order {self.base_order}"

    def names(self):
        return [e.name for e in self.effects]


def temperature_used(data, spec):
    """T' of the model: the measured temperature, lagged if thermal_lag is in."""
    T = data.T
    for e in spec.effects:
        fam = FAMILIES[e.name]
        if hasattr(fam, "transform"):
            T = fam.transform(data, T, e)
    return T


TABLE_PREFIX = "table:"


def powers(u, k_max):
    """[u, u^2, ..., u^k_max] by repeated products: a float power of an
    array (u ** 3) costs ten times a product, and the loop builds many
    designs."""
    out = [u]
    for _ in range(1, k_max):
        out.append(out[-1] * u)
    return out[:k_max]


def design(data, spec):
    """Design matrix (n, p) and column names of `spec` on `data`."""
    table = spec.base_family == "table" and data.T is not None
    cols, names = ([], []) if table else ([np.ones(data.n)], ["const"])
    T_used = temperature_used(data, spec) if data.T is not None else None
    if table:                 # the hats sum to one: they carry the constant
        hats = hat_basis(data.u_T(T_used), np.linspace(-1.0, 1.0, spec.base_order))
        cols.extend(hats.T)
        names.extend(f"{TABLE_PREFIX}{j}" for j in range(spec.base_order))
    if data.has_ref:
        cols.append(data.r / data.r_abs)
        names.append("r")
    if T_used is not None and not table:
        cols.extend(powers(data.u_T(T_used), spec.base_order))
        names.extend(f"u^{k}" for k in range(1, spec.base_order + 1))
    for e in spec.effects:
        c, nm = FAMILIES[e.name].columns(data, T_used, e)
        for j in range(c.shape[1]):
            cols.append(c[:, j])
            names.append(f"{e.name}:{nm[j]}")
    return np.column_stack(cols), names


@dataclass
class FittedModel:
    spec: ModelSpec
    beta: np.ndarray
    names: list
    prediction: np.ndarray
    residual: np.ndarray      # y - prediction (all samples; score only on mask)
    design: np.ndarray = None

    def rms(self, mask):
        return float(np.sqrt(np.mean(self.residual[mask] ** 2)))

    def coefficients(self):
        return {n: float(b) for n, b in zip(self.names, self.beta)}


def fit(data, spec, rows=None):
    """Least-squares fit of `spec` on the rows `rows` (default: data.mask)."""
    rows = data.mask if rows is None else rows
    X, names = design(data, spec)
    if rows.sum() < X.shape[1]:
        raise InsufficientDataError(
            f"refine: {X.shape[1]} parameters need at least as many samples, got {int(rows.sum())}")
    beta, _ = fit_linear_model(X[rows], data.y[rows], what="refine")
    pred = X @ beta
    return FittedModel(spec, beta, names, pred, data.y - pred, X)


def grid_top(family, data, param):
    """Top of the grid a fold searches for `family`'s parameter, given the
    full-data fit `param`: the first range's top, or past it (up to what
    the record resolves) when the fit was followed there."""
    b = family.bounds(data)
    if b is None or param is None or param < 0.9 * b[1]:
        return None
    return min(family.limit(data), param * EXTEND_FACTOR)


def fit_param(data, spec, family, variant):
    """Best nonlinear parameter of `family` added to `spec`, on all masked
    samples: the grid minimum (the grid extended past the top of the first
    range, up to family.limit, while the minimum sits at its top), polished
    by a bounded scalar search in log space.  Returns the fitted model with
    the new effect."""
    grid = family.grid(data)
    if grid == [None]:
        return fit(data, spec.with_effect(Effect(family.name, variant, None)))

    def sse(logp):
        m = fit(data, spec.with_effect(Effect(family.name, variant, float(np.exp(logp)))))
        return float(np.sum(m.residual[data.mask] ** 2))

    logs = list(np.log(grid))
    vals = [sse(v) for v in logs]
    limit = np.log(family.limit(data))
    while int(np.argmin(vals)) == len(vals) - 1 and logs[-1] < limit - 1e-9:
        top = min(limit, logs[-1] + np.log(EXTEND_FACTOR))
        more = list(np.linspace(logs[-1], top, EXTEND_POINTS + 1)[1:])
        logs += more
        vals += [sse(v) for v in more]
    logs = np.asarray(logs)
    i = int(np.argmin(vals))
    lo, hi = logs[max(i - 1, 0)], logs[min(i + 1, len(logs) - 1)]
    best = logs[i]
    if hi > lo:
        res = optimize.minimize_scalar(sse, bounds=(lo, hi), method="bounded",
                                       options={"xatol": 0.01})
        if res.success and res.fun < vals[i]:
            best = float(res.x)
    return fit(data, spec.with_effect(Effect(family.name, variant, float(np.exp(best)))))
