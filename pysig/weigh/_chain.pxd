# C API of the weighing chain (csrc/include/sig_limit.h, sig_antipulse.h,
# sig_kalman1.h, sig_stable.h, sig_chain.h), host build: sig_real is double.
from libc.stdint cimport int8_t, int16_t, int32_t, uint8_t, uint32_t

cdef extern from "sig_types.h":
    ctypedef double sig_real
    ctypedef int16_t sig_status
    ctypedef bint c_bool "bool"

cdef extern from "sig_limit.h":
    # only the fields the wrapper reads; the layout is the header's
    ctypedef struct sig_limit_track:
        uint8_t run
        c_bool seeded
    ctypedef struct sig_limit_f:
        sig_real dc
        sig_limit_track t
    ctypedef struct sig_limit_q:
        int32_t dc
        sig_limit_track t
    sig_status sig_limit_init_f(sig_limit_f *s, sig_real a0, uint8_t lockout_n) nogil
    sig_status sig_limit_reset_f(sig_limit_f *s) nogil
    sig_status sig_limit_step_f(sig_limit_f *s, sig_real x, sig_real *out) nogil
    sig_status sig_limit_init_q(sig_limit_q *s, int32_t a0, uint8_t lockout_n) nogil
    sig_status sig_limit_reset_q(sig_limit_q *s) nogil
    sig_status sig_limit_step_q(sig_limit_q *s, int32_t x, int32_t *out) nogil

cdef extern from "sig_antipulse.h":
    ctypedef struct sig_antipulse_f:
        uint8_t n, count
    ctypedef struct sig_antipulse_q:
        uint8_t n, count
    sig_status sig_antipulse_init_f(sig_antipulse_f *s, uint8_t n) nogil
    sig_status sig_antipulse_reset_f(sig_antipulse_f *s) nogil
    sig_status sig_antipulse_step_f(sig_antipulse_f *s, sig_real x, sig_real *out) nogil
    sig_status sig_antipulse_init_q(sig_antipulse_q *s, uint8_t n) nogil
    sig_status sig_antipulse_reset_q(sig_antipulse_q *s) nogil
    sig_status sig_antipulse_step_q(sig_antipulse_q *s, int32_t x, int32_t *out) nogil

cdef extern from "sig_kalman1.h":
    ctypedef struct sig_kalman1_f:
        sig_real x, p, k, innov
        c_bool seeded
    ctypedef struct sig_kalman1_q:
        int32_t x, innov
        uint32_t p0, y
        uint8_t phase
        c_bool seeded
    sig_status sig_kalman1_init_f(sig_kalman1_f *s, sig_real q, sig_real r, sig_real p0,
                                  sig_real x0, c_bool seed_first) nogil
    sig_status sig_kalman1_reset_f(sig_kalman1_f *s) nogil
    sig_status sig_kalman1_restart_f(sig_kalman1_f *s) nogil
    sig_status sig_kalman1_step_f(sig_kalman1_f *s, sig_real z, sig_real *out) nogil
    sig_status sig_kalman1_init_q(sig_kalman1_q *s, uint32_t q_q30, uint32_t p0_q16,
                                  int32_t x0_q7, c_bool seed_first) nogil
    sig_status sig_kalman1_reset_q(sig_kalman1_q *s) nogil
    sig_status sig_kalman1_restart_q(sig_kalman1_q *s) nogil
    sig_status sig_kalman1_step_q(sig_kalman1_q *s, int32_t z_q7, int32_t *out_q7) nogil

cdef extern from "sig_stable.h":
    ctypedef struct sig_stable_f:
        uint8_t count, run
    ctypedef struct sig_stable_q:
        uint8_t count, run
    sig_status sig_stable_init_f(sig_stable_f *s, sig_real step, uint8_t count) nogil
    sig_status sig_stable_reset_f(sig_stable_f *s) nogil
    sig_status sig_stable_step_f(sig_stable_f *s, sig_real x, c_bool *stable) nogil
    sig_status sig_stable_init_q(sig_stable_q *s, int32_t step_q7, uint8_t count) nogil
    sig_status sig_stable_reset_q(sig_stable_q *s) nogil
    sig_status sig_stable_step_q(sig_stable_q *s, int32_t x_q7, c_bool *stable) nogil

cdef extern from "sig_noise.h":
    ctypedef struct sig_noise_f:
        sig_real sigma
        uint8_t count
    ctypedef struct sig_noise_q:
        int32_t sigma
        uint8_t count
    sig_status sig_noise_reset_f(sig_noise_f *s) nogil
    sig_status sig_noise_step_f(sig_noise_f *s, sig_real x, c_bool update) nogil
    c_bool sig_noise_at_floor_f(const sig_noise_f *s) nogil
    sig_status sig_noise_reset_q(sig_noise_q *s) nogil
    sig_status sig_noise_step_q(sig_noise_q *s, int32_t x, c_bool update) nogil
    c_bool sig_noise_at_floor_q(const sig_noise_q *s) nogil

cdef extern from "sig_chain.h":
    ctypedef struct sig_chain_params_f:
        sig_real a0
        uint8_t window
        sig_real q, r, p0, x0
        c_bool seed_first
        sig_real stable_step
        uint8_t stable_count, lockout_n
        sig_real motion_band
        uint8_t motion_count
        sig_real zero_band, zero_rate
        c_bool noise_auto
    ctypedef struct sig_chain_params_q:
        int32_t a0
        uint8_t window
        uint32_t q_q30, p0_q16
        int32_t x0_q7
        c_bool seed_first
        int32_t stable_step_q7
        uint8_t stable_count, lockout_n
        int32_t motion_band_q7
        uint8_t motion_count
        int32_t zero_band_q7, zero_rate_q7
        c_bool noise_auto
    ctypedef struct sig_chain_f:
        sig_limit_f limit
        sig_antipulse_f ap
        sig_kalman1_f kf
        sig_noise_f noise
        sig_real offset
        c_bool tare_pending, stable, noise_auto
    ctypedef struct sig_chain_q:
        sig_limit_q limit
        sig_antipulse_q ap
        sig_kalman1_q kf
        sig_noise_q noise
        int32_t offset
        c_bool tare_pending, stable, noise_auto
    sig_status sig_chain_params_auto_f(sig_chain_params_f *p) nogil
    sig_status sig_chain_params_auto_q(sig_chain_params_q *p) nogil
    sig_status sig_chain_init_f(sig_chain_f *c, const sig_chain_params_f *p) nogil
    sig_status sig_chain_reset_f(sig_chain_f *c) nogil
    sig_status sig_chain_step_f(sig_chain_f *c, sig_real x, sig_real *out, c_bool *stable) nogil
    sig_status sig_chain_tare_f(sig_chain_f *c) nogil
    sig_status sig_chain_set_offset_f(sig_chain_f *c, sig_real offset) nogil
    sig_status sig_chain_init_q(sig_chain_q *c, const sig_chain_params_q *p) nogil
    sig_status sig_chain_reset_q(sig_chain_q *c) nogil
    sig_status sig_chain_step_q(sig_chain_q *c, int32_t x, int32_t *out_q7, c_bool *stable) nogil
    sig_status sig_chain_tare_q(sig_chain_q *c) nogil
    sig_status sig_chain_set_offset_q(sig_chain_q *c, int32_t offset_q7) nogil

cdef extern from "sig_chain_batch.h":
    sig_status sig_chain_process_f(sig_chain_f *c, const sig_real *x, size_t n, sig_real *out,
                                   uint8_t *stable) nogil
    sig_status sig_chain_process_q(sig_chain_q *c, const int32_t *x, size_t n, int32_t *out_q7,
                                   uint8_t *stable) nogil
