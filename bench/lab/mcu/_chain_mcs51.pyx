# cython: language_level=3, boundscheck=False, wraparound=False
"""The 8051 form of the fixed weighing chain (csrc/port/mcs51/
sig_chain_mcs51.c, with the default chain: SIG_CHAIN_MCS51_AUTO), compiled for the host: the bit-exactness tests run it
against the portable chain (pysig.weigh.Chain(fixed=True)) on the same
samples.  The C keeps one chain at a fixed address, so this module holds one
chain at a time (ChainMcs51.__init__ takes it over)."""
import numpy as np
cimport numpy as cnp
from libc.stdint cimport int32_t, uint32_t, uint8_t, int16_t, uint16_t

from pysig.errors import RangeError

cnp.import_array()

cdef extern from "sig_chain.h":
    ctypedef int16_t sig_status
    ctypedef struct sig_chain_params_q:
        int32_t a0
        uint8_t window
        uint32_t q_q30
        uint32_t p0_q16
        int32_t x0_q7
        bint seed_first
        int32_t stable_step_q7
        uint8_t stable_count
        uint8_t lockout_n
        int32_t motion_band_q7
        uint8_t motion_count
        int32_t zero_band_q7
        int32_t zero_rate_q7
        bint noise_auto

cdef extern from "sig_chain_mcs51_gains.c":
    pass

cdef extern from "sig_chain_mcs51.c":
    ctypedef struct sig_chain_mcs51_state:
        int32_t out
        bint stable
        bint hot
    sig_chain_mcs51_state sig_chain_mcs51
    sig_status sig_chain_mcs51_gains(uint32_t q_q30, uint32_t p0_q16, uint32_t *table,
                                     uint16_t max, uint16_t *n)
    sig_status sig_chain_mcs51_init(const sig_chain_params_q *p, const uint32_t *gains,
                                    uint16_t n_gains)
    sig_status sig_chain_mcs51_step(int32_t x)

GAINS_MAX = 65535


def gain_table(q_q30, p0_q16, max_len=GAINS_MAX):
    """The Kalman gain sequence (Q30, uint32) from a restart to its steady
    value, computed by the portable sig_kalman1 (sig_chain_mcs51_gains)."""
    cdef cnp.ndarray[cnp.uint32_t] t = np.zeros(max_len, np.uint32)
    cdef uint16_t n = 0
    if sig_chain_mcs51_gains(q_q30, p0_q16, &t[0], max_len, &n) < 0:
        raise RangeError(f"Kalman q={q_q30} p0={p0_q16}: gain does not settle within "
                         f"{max_len} steps")
    return t[:n].copy()


cdef class ChainMcs51:
    """One 8051-form chain from sig_chain_params_q fields (the dict of
    pysig.weigh._presets.chain_fixed_params)."""
    cdef sig_chain_params_q p
    cdef readonly cnp.ndarray gains
    cdef public object hot

    def __init__(self, fixed):
        self.p.a0 = fixed["a0"]; self.p.window = fixed["window"]
        self.p.q_q30 = fixed["q_q30"]; self.p.p0_q16 = fixed["p0_q16"]
        self.p.x0_q7 = fixed["x0_q7"]; self.p.seed_first = fixed["seed_first"]
        self.p.stable_step_q7 = fixed["stable_step_q7"]; self.p.stable_count = fixed["stable_count"]
        self.p.lockout_n = fixed["lockout_n"]; self.p.motion_band_q7 = fixed["motion_band_q7"]
        self.p.motion_count = fixed["motion_count"]; self.p.zero_band_q7 = fixed["zero_band_q7"]
        self.p.zero_rate_q7 = fixed["zero_rate_q7"]; self.p.noise_auto = fixed.get("noise_auto", False)
        self.gains = gain_table(self.p.q_q30, self.p.p0_q16)
        self.reset()

    def reset(self):
        """Re-initialise the (single) C chain with this object's parameters."""
        cdef cnp.ndarray[cnp.uint32_t] g = self.gains
        if sig_chain_mcs51_init(&self.p, &g[0], <uint16_t>g.shape[0]) < 0:
            raise RangeError("parameters outside the 8051 chain's range "
                             "(sig_chain_mcs51_init rejected them)")

    def process(self, x):
        """int32 codes -> (out_q7 int32, stable bool, status int16) per sample.
        self.hot: per sample, whether the default chain's state was in the
        port's own fields after it (the next step may take its steady-state
        path; always False for fixed thresholds)."""
        cdef cnp.ndarray[cnp.int32_t] xs = np.ascontiguousarray(x, dtype=np.int32)
        cdef Py_ssize_t i, n = xs.shape[0]
        out = np.empty(n, np.int32)
        stable = np.empty(n, bool)
        status = np.empty(n, np.int16)
        hot = np.empty(n, bool)
        cdef sig_status st
        for i in range(n):
            st = sig_chain_mcs51_step(xs[i])
            out[i] = sig_chain_mcs51.out
            stable[i] = sig_chain_mcs51.stable
            status[i] = st
            hot[i] = sig_chain_mcs51.hot
        self.hot = hot
        return out, stable, status
