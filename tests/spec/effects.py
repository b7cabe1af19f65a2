"""On-device refinement effects: the executable spec of csrc/refine/sig_effects.c,
one sample at a time, in plain Python integers (read next to sig_effects.h).

    mul_q16(a, b)   = sat32(floor(a * b / 2^16))          (sig_mul_q16_sat)
    round_shift(v,n)= floor((sat32(v + 2^(n-1))) / 2^n)   (n = 0: v)
    lag             xs = sat32(x * 2^frac); first: z = xs;
                    else d = sat32(xs - z); z = sat32(z + mul_q16(d, alpha_q16));
                    out = round_shift(z, frac)
    hysteresis      p = t - start*width (first) or p moved to within width of t; b = t - p;
                    contribution = mul_q16(b * 2^16, k_q16)
    creep           lag step; d = sat32(z - xs); v = mul_q16(d, k_q16);
                    c = round_shift(v, frac); corrected = sat32(x - c)
    gain            G = horner_q15(coef, u); out = mul_q16(x, G)
    nonlinearity    u = clamp(floor(mul_q16(sat32(x - center), k_q16) / 2^shift), +-32767);
                    out = sat32(x + horner_q15(coef, u))
    cross-axis      acc = sum sat32 mul_q16(o_j, k_j); out = sat32(x - acc)
Status: SIG_WARN_SATURATED (2) when a saturating result equals an int32 rail,
SIG_WARN_CLAMPED (1) when the nonlinearity's u was clamped; OR-ed with the
Horner status.  Float forms mirror the same recurrences."""
from spec.tcomp import horner_f, horner_q15

SIG_OK = 0
SIG_WARN_CLAMPED = 1
SIG_WARN_SATURATED = 2
INT16_MAX = (1 << 15) - 1
INT32_MIN, INT32_MAX = -(1 << 31), (1 << 31) - 1
Q16_ONE = 1 << 16


def sat32(x):
    return max(INT32_MIN, min(INT32_MAX, x))


def rail(st, v):
    return st | SIG_WARN_SATURATED if v in (INT32_MIN, INT32_MAX) else st


def mul_q16(a, b):
    return sat32((a * b) >> 16)


def round_shift(v, n):
    if n == 0:
        return v
    return sat32(v + (1 << (n - 1))) >> n


class LagQ:
    """sig_lag_q: first-order IIR, state in Q(frac) of the input unit."""

    def __init__(self, alpha_q16, frac):
        if not (1 <= alpha_q16 <= Q16_ONE and 0 <= frac <= 16):
            raise ValueError("lag: alpha_q16 in 1..65536, frac in 0..16")
        self.alpha_q16, self.frac = alpha_q16, frac
        self.reset()

    def reset(self):
        self.z, self.primed = 0, False

    def step(self, x):
        st = SIG_OK
        xs = sat32(x << self.frac)
        st = rail(st, xs)
        if not self.primed:
            z = xs
        else:
            d = sat32(xs - self.z)
            st = rail(st, d)
            z = sat32(self.z + mul_q16(d, self.alpha_q16))
            st = rail(st, z)
        self.z, self.primed = z, True
        return round_shift(z, self.frac), st


class HystQ:
    """sig_hyst_q: play operator on 0.01 °C temperatures."""

    def __init__(self, width, k_q16, start=0):
        if width < 1 or start not in (-1, 0, 1):
            raise ValueError("hysteresis: width >= 1, start in -1, 0, 1")
        self.width, self.k_q16, self.start = width, k_q16, start
        self.reset()

    def reset(self):
        self.p, self.primed = 0, False

    def step(self, t):
        if not self.primed:
            p = t - self.start * self.width
        else:
            p = self.p
            if t - p > self.width:
                p = t - self.width
            elif p - t > self.width:
                p = t + self.width
        b = t - p
        c = mul_q16(b * Q16_ONE, self.k_q16)
        self.p, self.primed = p, True
        return b, c, rail(SIG_OK, c)


class CreepQ:
    """sig_creep_q: contribution k * (lag(x) - x), corrected = x - contribution."""

    def __init__(self, alpha_q16, frac, k_q16):
        self.lag = LagQ(alpha_q16, frac)
        self.k_q16 = k_q16

    def reset(self):
        self.lag.reset()

    def step(self, x):
        _, st = self.lag.step(x)
        xs = sat32(x << self.lag.frac)
        d = sat32(self.lag.z - xs)
        st = rail(st, d)
        v = mul_q16(d, self.k_q16)
        st = rail(st, v)
        c = round_shift(v, self.lag.frac)
        y = sat32(x - c)
        return c, y, rail(st, y)


def gain_apply_q(coef, u, x):
    g, st = horner_q15(list(coef), u)
    y = mul_q16(x, g)
    return y, rail(st, y)


def nonlin_apply_q(coef, center, k_q16, shift, x):
    st = SIG_OK
    d = sat32(x - center)
    st = rail(st, d)
    v = mul_q16(d, k_q16)
    st = rail(st, v)
    v >>= shift
    if v > INT16_MAX:
        u, st = INT16_MAX, st | SIG_WARN_CLAMPED
    elif v < -INT16_MAX:
        u, st = -INT16_MAX, st | SIG_WARN_CLAMPED
    else:
        u = v
    p, hs = horner_q15(list(coef), u)
    y = sat32(x + p)
    return y, rail(st | hs, y)


def cross_apply_q(k_q16, x, others):
    st, acc = SIG_OK, 0
    for k, o in zip(k_q16, others):
        v = mul_q16(o, k)
        st = rail(st, v)
        acc = sat32(acc + v)
        st = rail(st, acc)
    y = sat32(x - acc)
    return y, rail(st, y)


# ---- float forms ----------------------------------------------------------------

class LagF:
    def __init__(self, alpha):
        self.alpha = alpha
        self.reset()

    def reset(self):
        self.z, self.primed = 0.0, False

    def step(self, x):
        self.z = x if not self.primed else (1.0 - self.alpha) * self.z + self.alpha * x
        self.primed = True
        return self.z


class HystF:
    def __init__(self, width, k, start=0):
        self.width, self.k, self.start = width, k, start
        self.reset()

    def reset(self):
        self.p, self.primed = 0.0, False

    def step(self, t):
        p = t - self.start * self.width if not self.primed else self.p
        if self.primed:
            if t - p > self.width:
                p = t - self.width
            elif p - t > self.width:
                p = t + self.width
        self.p, self.primed = p, True
        return t - p, (t - p) * self.k


def creep_step_f(lag, k, x):
    z = lag.step(x)
    c = k * z - k * x
    return c, x - c


def gain_apply_f(coef, u, x):
    return x * horner_f(list(coef), u)


def nonlin_apply_f(coef, center, inv_scale, x):
    u = min(1.0, max(-1.0, (x - center) * inv_scale))
    return x + horner_f(list(coef), u)


def cross_apply_f(k, x, others):
    return x - sum(a * b for a, b in zip(k, others))


# ---- the refined temperature model of one axis (sig_refined_step_q) -----------------

class RefinedQ:
    """offset: dict of sig_tcomp_q fields for one axis (coef list, q, t_lo,
    t_hi, t_center, u_mul, u_shift); lag: alpha_q16 or None; hyst: (width,
    k_q16, start) or None; gain: Q16 coefficient list or None."""

    def __init__(self, offset, lag=None, hyst=None, gain=None):
        from spec.tcomp import delta_q
        self._delta_q = delta_q
        self.model = {"coef": [list(offset["coef"])], "q": [offset["q"]], "t_lo": offset["t_lo"],
                      "t_hi": offset["t_hi"], "t_center": offset["t_center"],
                      "u_mul": offset["u_mul"], "u_shift": offset["u_shift"]}
        self.lag = LagQ(lag, 16) if lag is not None else None
        self.hyst = HystQ(*hyst) if hyst is not None else None
        self.gain = list(gain) if gain is not None else None

    def reset(self):
        for part in (self.lag, self.hyst):
            if part is not None:
                part.reset()

    def step(self, t, y):
        from spec.tcomp import scale_q, sat16
        st = SIG_OK
        tl = t
        if self.lag is not None:
            v, s = self.lag.step(t)
            st |= s
            tl = sat16(v)
        delta, s = self._delta_q(self.model, 0, tl)
        st |= s
        q = self.model["q"][0]
        d16 = round_shift(delta, q - 16) if q >= 16 else sat32(delta << (16 - q))
        st = rail(st, d16)
        acc = sat32(y * Q16_ONE - d16)
        st = rail(st, acc)
        if self.hyst is not None:
            _, c, s = self.hyst.step(tl)
            st |= s
            acc = sat32(acc - c)
            st = rail(st, acc)
        if self.gain is not None:
            m = self.model
            u, _ = scale_q(tl, m["t_lo"], m["t_hi"], m["t_center"], m["u_mul"], m["u_shift"])
            acc, s = gain_apply_q(self.gain, u, acc)
            st |= s
        return acc, st
