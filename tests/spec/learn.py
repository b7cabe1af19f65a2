"""The on-device learner: the executable spec of csrc/learn/sig_learn.c and
sig_learn_solve.c, one sample at a time, in plain Python integers.

    step     still samples inside the bins (t_base, 2^bin_shift, n_bins) and
             within +-2047 add to the pending sums of their bin (y + 2047),
             which go into count, sum_dt, sum_y of the bin when the bin
             changes, after 16 samples, when the bin reaches 2048 samples
             and at a solve; a bin at 2048 samples is halved (floor).  The residual (model output, or
             raw with no model), clamped to +-511, is summed over blocks of
             8 still samples in the model's range (moving samples are left
             out; an out-of-range still one drops the block and breaks the
             series); per block B:
             noise += min(|B - B_prev|, 2047) - (noise >> 5).  With a
             model and armed thresholds, every block feeds the two-sided
             CUSUM S+ = max(0, S+ + 16 B - 8 k), S- = max(0, S- - 16 B - 8 k)
             (the per-sample CUSUM on 16 r with max(0, .) at block ends
             only); a crossing of h clears the bins and sets stale.
    solve    thresholds from noise (sigma = max(floor, noise*642 >> 12);
             k, h at most 16383);
             period; points (Q4 means) of covered bins; leave-one-bin-out
             SSE of the candidate and of the model in use; commit when
             sse_new <= sse_stored - (sse_stored >> margin_shift) and
             sse_stored > 0: a table over the covered bins and the model's
             range, written as an image (PWL table + temperature code)."""
from . import image, tmodel

COUNT_MAX, Y_MAX, NOISE_MIN_N, ERR_MAX = 2048, 2047, 32, 4095
Y_BIAS, ACC_MAX = 2047, 16     # the sums are of y + 2047; pending samples of one bin at most
BLOCK, CUSUM_X_MAX, CUSUM_MAX = 8, 511, 16383   # noise block length, the CUSUM's residual clamp, k and h limit (Q4)
STALE, SKIPPED, EXTRAPOLATED, COMMITTED = 512, 1024, 2048, 4096
COMMIT, WAIT_PERIOD, WAIT_COVERAGE, NOT_BETTER = 0, 1, 2, 3
SECTION_PWL_TABLE, SECTION_TEMP_CODE = 6, 10


def _clamp(x, lo, hi):
    return max(lo, min(hi, x))


def _rdiv(n, d):
    q = (abs(n) + d // 2) // d
    return -q if n < 0 else q


def _frac(a, b, x):
    n, d = x - a, b - a
    while d >= 0x8000:      # the C divides by a divisor below 2^15
        n, d = n >> 1, d >> 1
    return (n << 12) // d


def _lerp(ya, yb, f):
    return ya + (((yb - ya) * f) >> 12)


def model_range(model):
    """(t_lo, t_hi) of a model from tmodel.load."""
    family, _, data = model
    if family == "table":
        return data[0][1], data[0][2]
    return data["t_lo"], data["t_hi"]


def model_q4(model, t, n_axes):
    """16 * the model's correction at int16 t, per axis."""
    kind = model[1]
    code = (t + 32768) if kind == tmodel.TCODE_UINT16 else t & 0xFFFF
    out, _ = tmodel.apply(model, code, [0] * n_axes)
    return [-16 * y for y in out]


class Learner:
    """sig_learn: cfg is a dict of the sig_learn_config fields."""

    def __init__(self, cfg):
        self.cfg = dict(cfg)
        n = self.cfg["n_axes"]
        self.k, self.h, self.noise, self.prev = [0] * n, [0] * n, [0] * n, [0] * n
        self.steps = self.last_commit = self.noise_n = 0
        self.model, self.model_lo, self.model_hi = None, 0, 0
        self.committed = False
        self._break()
        self.reset()

    def reset(self):
        c = self.cfg
        self.count = [0] * c["n_bins"]
        self.sum_dt = [0] * c["n_bins"]
        self.sum_y = [[0] * c["n_axes"] for _ in range(c["n_bins"])]
        self.pos, self.neg = [0] * c["n_axes"], [0] * c["n_axes"]
        self.acc_y, self.acc_dt, self.acc_n, self.acc_bin, self.acc_room = [0] * c["n_axes"], 0, 0, 0, ACC_MAX
        self.stale = False

    def use_model(self, model):
        """model: tmodel.load's model, or None."""
        self.model = model
        if model is not None:
            self.model_lo, self.model_hi = model_range(model)
        self.pos, self.neg = [0] * self.cfg["n_axes"], [0] * self.cfg["n_axes"]
        self.stale = False
        self._break()

    def flush(self):
        """sig_learn_flush: the pending samples into their bin's sums."""
        b, n = self.acc_bin, self.acc_n
        if n == 0:
            return
        self.sum_dt[b] += self.acc_dt
        self.sum_y[b] = [s + y for s, y in zip(self.sum_y[b], self.acc_y)]
        self.count[b] += n
        self.acc_y, self.acc_dt, self.acc_n = [0] * len(self.acc_y), 0, 0
        if self.count[b] >= COUNT_MAX:
            self.count[b] >>= 1
            self.sum_dt[b] >>= 1
            self.sum_y[b] = [s >> 1 for s in self.sum_y[b]]

    def _learn(self, t, raw):
        c = self.cfg
        d = t - c["t_base"]
        if d < 0 or d >= c["n_bins"] << c["bin_shift"] or any(abs(y) > Y_MAX for y in raw):
            return SKIPPED
        b = d >> c["bin_shift"]
        if self.acc_n == 0 or b != self.acc_bin:
            self.flush()
            self.acc_bin = b
            # the pending samples stop where the bin reaches COUNT_MAX: it is
            # halved at exactly 2048 (even), so the bias 2047 * count stays exact
            self.acc_room = min(ACC_MAX, COUNT_MAX - self.count[b])
        self.acc_dt += d & ((1 << c["bin_shift"]) - 1)
        self.acc_y = [s + y + Y_BIAS for s, y in zip(self.acc_y, raw)]
        self.acc_n += 1
        if self.acc_n >= self.acc_room:
            self.flush()
        return 0

    def _break(self):
        n = self.cfg["n_axes"]
        self.block, self.block_n, self.have_prev = [0] * n, 0, False

    def _watch_block(self):
        """A full block: the noise estimate, then the CUSUM on the block sum
        (16 B - 8 k: the per-sample CUSUM with max(0, .) taken at block ends
        only); True when it crossed."""
        crossed = False
        armed = self.model is not None and self.h[0] != 0
        for a, x in enumerate(self.block):
            if self.have_prev:
                self.noise[a] += min(abs(x - self.prev[a]), Y_MAX) - (self.noise[a] >> 5)
            self.prev[a] = x
            if armed:
                pos = self.pos[a] + 16 * x - BLOCK * self.k[a]
                neg = self.neg[a] - 16 * x - BLOCK * self.k[a]
                self.pos[a], self.neg[a] = max(pos, 0), max(neg, 0)
                crossed |= pos > self.h[a] or neg > self.h[a]
        self.block = [0] * len(self.block)
        if self.have_prev:
            self.noise_n = min(self.noise_n + 1, 65535)
        self.have_prev = True
        return crossed

    def _watch(self, r):
        self.block = [b + _clamp(x, -CUSUM_X_MAX, CUSUM_X_MAX) for b, x in zip(self.block, r)]
        self.block_n += 1
        if self.block_n >= BLOCK:
            self.block_n = 0
            return self._watch_block()
        return False

    def step(self, t, raw, resid, still):
        """Status of sig_learn_step (resid: the model's outputs, or None)."""
        self.steps = (self.steps + 1) & 0xFFFFFFFF
        st, in_range = 0, True
        if self.model is not None and not self.model_lo <= t <= self.model_hi:
            st, in_range = EXTRAPOLATED, False
        if still:
            st |= self._learn(t, raw)
            if not in_range:
                self._break()
            elif not self.stale and self._watch(resid if self.model is not None else raw):
                self.reset()
                self.stale = True
        return st | (STALE if self.stale else 0)

    # ---- solve ----------------------------------------------------------
    def _points(self):
        c = self.cfg
        return [(b, (b << (c["bin_shift"] + 4)) + _rdiv(self.sum_dt[b] * 16, n),
                 [_rdiv((s - Y_BIAS * n) * 16, n) for s in self.sum_y[b]])
                for b, n in enumerate(self.count) if n >= c["min_count"]]

    def _t(self, tq):
        return self.cfg["t_base"] + ((tq + 8) >> 4)

    def _validate(self, pts):
        n, m = self.cfg["n_axes"], len(pts)
        sse_new = sse_old = 0
        for i, (_, t, y) in enumerate(pts):
            j, l = (1, 2) if i == 0 else ((m - 3, m - 2) if i == m - 1 else (i - 1, i + 1))
            (_, ta, ya), (_, tb, yb) = pts[j], pts[l]
            f = -min(((ta - t) << 12) // (tb - ta), 8192) if t < ta else min(_frac(ta, tb, t), 12288)
            ref = model_q4(self.model, self._t(t), n) if self.model else [0] * n
            for a in range(n):
                sse_new += _clamp(y[a] - _lerp(ya[a], yb[a], f), -ERR_MAX, ERR_MAX) ** 2
                sse_old += _clamp(y[a] - ref[a], -ERR_MAX, ERR_MAX) ** 2
        return sse_new, sse_old, m

    def _knot(self, pts, k):
        c, n = self.cfg, self.cfg["n_axes"]
        w = 1 << c["bin_shift"]
        cent = k * w + w // 2
        cq = 16 * cent
        if pts[0][1] <= cq <= pts[-1][1]:
            j = max(i for i in range(len(pts) - 1) if pts[i][1] < cq or i == 0)
            (_, ta, ya), (_, tb, yb) = pts[j], pts[j + 1]
            f = _frac(ta, tb, cq)
            return [_lerp(ya[a], yb[a], f) for a in range(n)]
        end = pts[0] if cq < pts[0][1] else pts[-1]
        if self.model is None:
            return list(end[2])
        at_knot = model_q4(self.model, c["t_base"] + cent, n)
        at_end = model_q4(self.model, self._t(end[1]), n)
        return [end[2][a] + at_knot[a] - at_end[a] for a in range(n)]

    def _image(self, pts, k_lo, k_hi, seq):
        c = self.cfg
        w = 1 << c["bin_shift"]
        knots = [self._knot(pts, k) for k in range(k_lo, k_hi + 1)]
        t_lo = c["t_base"] + k_lo * w + w // 2
        t_hi = t_lo + (len(knots) - 1) * w
        pay = bytes([c["n_axes"], len(knots)]) + _le(t_lo, 2) + _le(t_hi, 2) + _le(1 << (32 - c["bin_shift"]), 4)
        for a in range(c["n_axes"]):
            mx = max(abs(v[a]) for v in knots)
            vf = 4
            while vf > 0 and (mx >> (4 - vf)) >= 32767:
                vf -= 1
            sh = 4 - vf
            pay += bytes([vf]) + b"".join(
                _le(_clamp((v[a] + ((1 << (sh - 1)) if sh else 0)) >> sh, -32768, 32767), 2) for v in knots)
        return image.build([(SECTION_PWL_TABLE, pay), (SECTION_TEMP_CODE, bytes([c["code_kind"], 0]))], seq)

    def _model_bins(self):
        c = self.cfg
        top = c["n_bins"] << c["bin_shift"]
        a, b = self.model_lo - c["t_base"], self.model_hi - c["t_base"]
        if b < 0 or a >= top:
            return None
        return _clamp(a, 0, top - 1) >> c["bin_shift"], _clamp(b, 0, top - 1) >> c["bin_shift"]

    def solve(self, live_seq):
        """(status, image bytes or None, report dict) of sig_learn_solve."""
        c = self.cfg
        if self.noise_n >= NOISE_MIN_N:
            for a in range(c["n_axes"]):
                sigma = max(c["sigma_floor"], (self.noise[a] * 642) >> 12)
                self.k[a] = min((sigma * c["k_sigma"]) >> 4, CUSUM_MAX)
                self.h[a] = min((sigma * c["h_sigma"]) >> 4, CUSUM_MAX)
        self.flush()
        rep = dict(sse_new=0, sse_stored=0, covered=0, validated=0, n_knots=0, t_lo=0, t_hi=0)
        if self.committed and ((self.steps - self.last_commit) & 0xFFFFFFFF) < c["period"]:
            return 0, None, dict(rep, outcome=WAIT_PERIOD)
        pts = self._points()
        rep["covered"] = len(pts)
        if len(pts) < c["min_bins"]:
            return 0, None, dict(rep, outcome=WAIT_COVERAGE)
        rep["sse_new"], rep["sse_stored"], rep["validated"] = self._validate(pts)
        old = rep["sse_stored"]
        if old == 0 or rep["sse_new"] > old - (old >> c["margin_shift"]):
            return 0, None, dict(rep, outcome=NOT_BETTER)
        k_lo, k_hi = pts[0][0], pts[-1][0]
        mb = self._model_bins() if self.model is not None else None
        if mb is not None:
            k_lo, k_hi = min(k_lo, mb[0]), max(k_hi, mb[1])
        img = self._image(pts, k_lo, k_hi, (live_seq + 1) & 0xFFFFFFFF)
        self.committed, self.last_commit = True, self.steps
        w = 1 << c["bin_shift"]
        t_lo = c["t_base"] + k_lo * w + w // 2
        rep.update(outcome=COMMIT, n_knots=k_hi - k_lo + 1, t_lo=t_lo, t_hi=t_lo + (k_hi - k_lo) * w)
        return COMMITTED, img, rep


def _le(v, n):
    return (v & ((1 << (8 * n)) - 1)).to_bytes(n, "little")


class Device:
    """The learner and the model in use, as DeviceLearner holds them."""

    def __init__(self, cfg, start_image=None):
        self.lr, self.model, self.seq = Learner(cfg), None, 0
        if start_image is not None:
            self.use_image(start_image)

    def use_image(self, img):
        _, self.model = tmodel.load(img)
        self.seq = image.sequence(img)
        self.lr.use_model(self.model)


def replay(dev, codes, raw, still, solve_every):
    """The device loop of DeviceLearner.replay on a Device: (comp, status,
    seq, commits, solves) as lists, commits [(index, report, image)]."""
    lr, cfg = dev.lr, dev.lr.cfg
    comp, stat, seqs, commits, solves = [], [], [], [], []
    for i, (code, x, g) in enumerate(zip(codes, raw, still)):
        t = tmodel.code_to_t(cfg["code_kind"], int(code))
        x = [int(v) for v in x]
        y = tmodel.apply(dev.model, int(code), x)[0] if dev.model is not None else list(x)
        comp.append(y)
        stat.append(lr.step(t, x, y if dev.model is not None else None, bool(g)))
        seqs.append(dev.seq if dev.model is not None else 0)
        if lr.steps % solve_every:
            continue
        st, img, rep = lr.solve(dev.seq)
        solves.append((i, rep))
        if img is not None:
            dev.use_image(img)
            commits.append((i, rep, img))
    return comp, stat, seqs, commits, solves
