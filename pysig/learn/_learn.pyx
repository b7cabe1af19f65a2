# cython: language_level=3
"""Cython bridge to csrc/learn/sig_learn.c and sig_learn_solve.c: the device
learner, and the device loop that replays a field log through it (apply the
model in use, step the learner, solve every so many samples, load what it
commits)."""
import numpy as np
cimport numpy as cnp
from libc.stdint cimport int16_t, int32_t, uint8_t, uint16_t, uint32_t
from libc.string cimport memcpy

from ..tcomp._axes cimport sig_tmodel, sig_tmodel_apply

cnp.import_array()

cdef extern from "sig_types.h":
    ctypedef int16_t sig_status

cdef extern from "sig_tmodel.h":
    int16_t sig_tmodel_code_to_t(uint8_t code_kind, uint16_t code) nogil
    sig_status sig_tmodel_load_image(sig_tmodel *m, int16_t *storage, uint16_t storage_len,
                                     const uint8_t *image, size_t len) nogil

cdef extern from "sig_image.h":
    sig_status sig_image_sequence(const uint8_t *buf, size_t len, uint32_t *seq)

cdef extern from "sig_learn.h":
    int SIG_LEARN_IMAGE_MAX
    ctypedef struct sig_learn_config:
        uint32_t period
        int16_t t_base
        uint16_t min_count, sigma_floor, k_sigma, h_sigma
        uint8_t bin_shift, n_bins, min_bins, margin_shift, n_axes, code_kind
    ctypedef struct sig_learn:
        sig_learn_config cfg
        uint32_t sum_y[48]
        uint32_t sum_dt[32]
        uint16_t count[32]
        uint8_t acc_bin, acc_n
        int16_t k[3]
        int16_t h[3]
        uint16_t noise[3]
        uint32_t steps
        int16_t model_lo, model_hi
        bint has_model, committed, stale
    ctypedef struct sig_learn_scratch:
        pass
    ctypedef struct sig_learn_report:
        uint32_t sse_new, sse_stored
        uint8_t outcome, covered, validated, n_knots
        int16_t t_lo, t_hi
    sig_status sig_learn_init(sig_learn *s, const sig_learn_config *cfg)
    sig_status sig_learn_use_model(sig_learn *s, const sig_tmodel *m) nogil
    sig_status sig_learn_step(sig_learn *s, int16_t t, const int16_t *raw, const int16_t *resid,
                              bint still) nogil
    sig_status sig_learn_solve(sig_learn *s, const sig_tmodel *model, uint32_t live_seq,
                               uint8_t *image, uint16_t image_cap, uint16_t *image_len,
                               sig_learn_report *report, sig_learn_scratch *work) nogil

CONFIG_FIELDS = ("period", "t_base", "min_count", "sigma_floor", "k_sigma", "h_sigma",
                 "bin_shift", "n_bins", "min_bins", "margin_shift", "n_axes", "code_kind")
OUTCOMES = ("commit", "wait-period", "wait-coverage", "not-better")
STORAGE_ENTRIES = 3 * 255
STATE_BYTES = sizeof(sig_learn)


cdef dict _report(sig_learn_report *r):
    return dict(sse_new=r.sse_new, sse_stored=r.sse_stored, outcome=r.outcome, covered=r.covered,
                validated=r.validated, n_knots=r.n_knots, t_lo=r.t_lo, t_hi=r.t_hi)


cdef class DeviceLearner:
    """sig_learn and the model it watches (a sig_tmodel loaded from an image),
    as the firmware holds them.  cfg: a dict of the sig_learn_config fields."""
    cdef sig_learn s
    cdef sig_tmodel model
    cdef sig_learn_scratch work
    cdef bint has_model
    cdef uint32_t live_seq
    cdef int16_t storage[765]
    cdef public bytes image
    cdef public int status

    def __init__(self, dict cfg):
        cdef sig_learn_config c
        for name in CONFIG_FIELDS:
            if name not in cfg:
                raise KeyError(name)
        c.period, c.t_base, c.min_count = cfg["period"], cfg["t_base"], cfg["min_count"]
        c.sigma_floor, c.k_sigma, c.h_sigma = cfg["sigma_floor"], cfg["k_sigma"], cfg["h_sigma"]
        c.bin_shift, c.n_bins, c.min_bins = cfg["bin_shift"], cfg["n_bins"], cfg["min_bins"]
        c.margin_shift, c.n_axes, c.code_kind = cfg["margin_shift"], cfg["n_axes"], cfg["code_kind"]
        self.status = sig_learn_init(&self.s, &c)
        self.has_model = False
        self.live_seq = 0
        self.image = None


    def use_image(self, data):
        """Load a coefficient image as the model in use (None: none) and tell
        the learner; the C status (the loader's, then sig_learn_use_model's)."""
        cdef const uint8_t[::1] b
        cdef uint32_t seq = 0
        if data is None:
            self.has_model = False
            self.image = None
            return sig_learn_use_model(&self.s, NULL)
        data = bytes(data)
        b = data + b"\0"
        st = sig_tmodel_load_image(&self.model, self.storage, STORAGE_ENTRIES, &b[0], len(data))
        if st != 0:
            return st
        st = sig_learn_use_model(&self.s, &self.model)
        if st != 0:
            self.has_model = False
            return st
        sig_image_sequence(&b[0], len(data), &seq)
        self.has_model, self.live_seq, self.image = True, seq, data
        return 0

    def step(self, int16_t t, raw, resid, bint still):
        """sig_learn_step for one sample (resid None: NULL)."""
        cdef int16_t r[3]
        cdef int16_t e[3]
        cdef int i
        for i, v in enumerate(raw):
            r[i] = v
        if resid is None:
            return sig_learn_step(&self.s, t, r, NULL, still)
        for i, v in enumerate(resid):
            e[i] = v
        return sig_learn_step(&self.s, t, r, e, still)

    def solve(self):
        """(status, image bytes or None, report dict) of sig_learn_solve with
        the model in use; a committed image is NOT loaded (use_image does)."""
        cdef uint8_t buf[160]
        cdef uint16_t n = 0
        cdef sig_learn_report rep
        st = sig_learn_solve(&self.s, &self.model if self.has_model else NULL, self.live_seq,
                             buf, 160, &n, &rep, &self.work)
        if st < 0:
            return st, None, None
        return st, (bytes(buf[:n]) if n else None), _report(&rep)

    @property
    def stale(self):
        return bool(self.s.stale)

    @property
    def model_range(self):
        """(t_lo, t_hi) of the model in use, None when none."""
        return (self.s.model_lo, self.s.model_hi) if self.has_model else None

    @property
    def sequence(self):
        return self.live_seq if self.has_model else 0

    def counts(self):
        """Samples per bin (numpy uint16), the pending ones included."""
        out = np.array([self.s.count[i] for i in range(self.s.cfg.n_bins)], dtype=np.uint16)
        out[self.s.acc_bin] += self.s.acc_n
        return out

    def replay(self, codes, raw, still, uint32_t solve_every):
        """The device loop over a log: per sample apply the model in use
        (sig_tmodel_apply) and step the learner; after every solve_every-th
        step of the learner (its own clock) solve, and load a committed image (as firmware writes it to
        the free slot and boots from it).  codes: uint16 temperature codes
        (n,); raw: int16 (n, n_axes); still: bool (n,).  Returns (comp int16
        (n, n_axes), learner status int16 (n,), model sequence uint32 (n,),
        commits [(index, report, image bytes)], solves [(index, report)])."""
        cdef const uint16_t[::1] c = np.ascontiguousarray(codes, dtype=np.uint16)
        cdef const int16_t[:, ::1] x = np.ascontiguousarray(raw, dtype=np.int16)
        cdef const uint8_t[::1] g = np.ascontiguousarray(still, dtype=np.uint8)
        cdef Py_ssize_t n = c.shape[0], i
        cdef int na = self.s.cfg.n_axes
        if x.shape[0] != n or x.shape[1] != na or g.shape[0] != n or solve_every < 1:
            raise ValueError("codes, raw (n, n_axes) and still must have one row per sample")
        comp_a = np.zeros((n, na), dtype=np.int16)
        stat_a = np.zeros(n, dtype=np.int16)
        seq_a = np.zeros(n, dtype=np.uint32)
        cdef int16_t[:, ::1] y = comp_a
        cdef int16_t[::1] stv = stat_a
        cdef uint32_t[::1] sq = seq_a
        cdef uint8_t buf[160]
        cdef uint16_t img_len = 0
        cdef sig_learn_report rep
        cdef int16_t t
        cdef uint8_t kind = self.s.cfg.code_kind
        commits, solves = [], []
        for i in range(n):
            t = sig_tmodel_code_to_t(kind, c[i])
            if self.has_model:
                sig_tmodel_apply(&self.model, c[i], &x[i, 0], &y[i, 0])
                stv[i] = sig_learn_step(&self.s, t, &x[i, 0], &y[i, 0], g[i] != 0)
            else:
                memcpy(&y[i, 0], &x[i, 0], na * sizeof(int16_t))
                stv[i] = sig_learn_step(&self.s, t, &x[i, 0], NULL, g[i] != 0)
            sq[i] = self.sequence
            if self.s.steps % solve_every:      # the device's clock, so split calls agree
                continue
            img_len = 0
            st = sig_learn_solve(&self.s, &self.model if self.has_model else NULL, self.live_seq,
                                 buf, 160, &img_len, &rep, &self.work)
            solves.append((i, _report(&rep)))
            if st > 0 and img_len:
                data = bytes(buf[:img_len])
                if self.use_image(data) != 0:
                    raise RuntimeError("the learner wrote an image its own loader rejects")
                commits.append((i, _report(&rep), data))
        return comp_a, stat_a, seq_a, commits, solves
