/* sig_chain_batch.c - the chain over a buffer of samples; see sig_chain_batch.h. */
#include "sig_chain_batch.h"
#include "sig_chain_stages.h"
#include "sig_noise_stages.h"

/* Host and 32-bit firmware only.  Under sdcc --stack-auto the fast path's
 * frame (about 259 bytes) outgrows the 8051's internal RAM and its frame
 * offsets wrap (warning 158): silently wrong code.  An 8051 firmware steps
 * the chain one sample at a time (sig_chain_step_*). */
#ifdef __SDCC
#error "sig_chain_batch.c is not for the 8051: call sig_chain_step_f/_q per sample"
#else       /* (sdcc goes on after #error: nothing more for it to compile) */

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
/* Largest |sample| the batch fast path takes: a sum of SIG_ANTIPULSE_MAX + 2
 * such values cannot overflow, so the window sum and trimmed mean need no
 * finiteness checks (DBL_MAX ~ 1.8e308, FLT_MAX ~ 3.4e38). */
#ifdef SIG_REAL_DOUBLE
#define FAST_MAX SIG_REAL(1e300)
#else
#define FAST_MAX SIG_REAL(1e36)
#endif

/* How many of the Kalman gains after a restart the batch path keeps (on its
 * stack: 8 bytes each as double, 4 as float); beyond them it computes each
 * gain again until P reaches its fixed point.  A firmware short of stack
 * may set it lower (0 keeps none). */
#ifndef SIG_CHAIN_BATCH_GAINS
#define SIG_CHAIN_BATCH_GAINS 256u
#endif
#define GAINS_UNKNOWN UINT16_C(0xFFFF)     /* above any index of gains[] */
#if SIG_CHAIN_BATCH_GAINS > 0
#define GAINS_ROOM(fill) ((fill) < SIG_CHAIN_BATCH_GAINS)
#else
#define GAINS_ROOM(fill) false             /* (a test against 0 warns: always false) */
#endif

/* gcc's basic-block vectoriser (on at -O2 since gcc 12) packs pairs of the
 * loop's scalars (the window's extremes, the thresholds, ...) into
 * vectors and pays for it in shuffles: about a tenth more instructions per
 * sample, measured.  The loop is scalar by nature (each sample depends on
 * the last). */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("no-tree-slp-vectorize")
#endif

/* The stages written once for the general path and noise_auto's steady
 * state (process_f), on its locals. */
/* anti-pulse, a full window: one sample in, one out; the extremes again
 * when one leaves */
#define WINDOW_FULL_PUSH() do { \
        old = c->ap.buf[head]; \
        c->ap.buf[head] = y; \
        head++; \
        if (head >= held) head = 0u; \
        if (old >= mx || old <= mn) {          /* == (old lies within): a test without NaN's case */ \
            if (old >= mx) mx = window_max(c->ap.buf, held); \
            else mx = y > mx ? y : mx; \
            if (old <= mn) mn = window_min(c->ap.buf, held); \
            else mn = y < mn ? y : mn; \
            if (mx == SIG_REAL(0.0) || mn == SIG_REAL(0.0)) {   /* +0 or -0: storage order decides */ \
                mx = mn = c->ap.buf[0]; \
                for (j = 1u; j < held; j++) { \
                    v = c->ap.buf[j]; \
                    mx = v > mx ? v : mx; \
                    mn = v < mn ? v : mn; \
                } \
            } \
        } else { \
            mx = y > mx ? y : mx; \
            mn = y < mn ? y : mn; \
        } \
        sum = (sum - old) + y; \
    } while (0)
/* re-sum in storage order when the position wraps */
#define WINDOW_RESUM() do { \
        if (head == 0u) { \
            sum = c->ap.buf[0]; \
            for (j = 1u; j < held; j++) sum += c->ap.buf[j]; \
        } \
    } while (0)
/* Kalman: the gain update only until P reaches its fixed point.  P's
 * course from P0 is the same after every restart: the gains along it, up to
 * the update that reaches the fixed point (not kept: computed again, once
 * per restart), are kept in gains[] as they are first computed and read back
 * after the next restart (kn: the updates since P0 while P is known to be on
 * that course, else GAINS_UNKNOWN), instead of a division on the chain from
 * one sample's P to the next.  E_FINITE (a constant): the innovation is
 * known to be finite (the steady loop: within the motion band). */
#define KALMAN_UPDATE(E_FINITE) do { \
        if (!conv) { \
            if (nauto && kn < gfill) {         /* (the other form restarts only on the step path) */ \
                kk = gains[kn]; \
                pn = kr * kk; \
                kn++; \
            } else { \
                pm = kp + kq; \
                den = pm + kr; \
                kk = sig_real_isfinite(den) ? pm / den : SIG_REAL(1.0) / (SIG_REAL(1.0) + kr / pm); \
                pn = kr * kk; \
                conv = pn == kp; \
                if (nauto && kn == gfill && GAINS_ROOM(gfill) && !conv) { \
                    gains[gfill++] = kk; \
                    kn++; \
                } else { \
                    kn = GAINS_UNKNOWN; \
                } \
            } \
            kp = pn; \
        } \
        e = m - kx; \
        if (E_FINITE || sig_real_isfinite(e)) kx = kx + kk * e; \
        else kx = (SIG_REAL(1.0) - kk) * kx + kk * m; \
        xk = kx; \
    } while (0)
/* stability, (noise_auto) drift blocks, the trend and the backing of
 * `stable`, tare and zero tracking, the outputs, (noise_auto) the noise
 * estimate.  STEADY (a constant): noise_auto's steady loop, where the
 * sample was accepted (finite, SIG_OK), the window is full, no motion run
 * is under way and the noise gate is open (its state stays so: every
 * sample updates the estimate); said outright, the tests for the other
 * cases fold away. */
#define OUTPUT_STAGES(STEADY) do { \
        if (mag(xk - prev) <= TH(STEADY, step, SIG_CHAIN_STEP_F(nz.sigma))) { \
            if (srun < 255u) srun++; \
        } else { \
            srun = 0u; \
        } \
        prev = xk; \
        s = srun >= stable_count;             /* the detector's verdict (`settled`) */ \
        if (nauto) { \
            if (sig_chain_drift_due(held < wn, \
                                    held < wn && has_level \
                                    && mag(xk - level) > nz.sigma * SIG_REAL(1024.0), \
                                    &dage, wn, &drifting, &c->hold_block)) { \
                if (held == wn) drifting = sig_chain_drift_verdict(mag(xk - anchor) > nz.sigma, &c->hold_block); \
                anchor = xk; \
            } \
            trending = sig_chain_trend_f(held < wn, y - xk, nz.sigma, &tmean); \
            if (s) \
                s = sig_chain_backed(STEADY ? SIG_OK : st, STEADY ? wn : held, wn, STEADY ? 0u : mrun, \
                                     drifting, trending, \
                                     (int)(mag(y - xk) <= TH(STEADY, nearb, SIG_CHAIN_NEAR_F(nz.sigma))) \
                                     & (int)(mag(m - xk) <= nz.sigma));   /* no branch (sig_chain_backed) */ \
        } \
        if (nauto) {          /* no branch on `s` either: the last stable output kept by a select */ \
            level = s ? xk : level; \
            has_level = has_level || s; \
            (void)sig_chain_offset_f(s, xk, &offset, &zero, &tare_pending, \
                                     TH(STEADY, zband, SIG_CHAIN_ZBAND_F(nz.sigma)), \
                                     TH(STEADY, zrate, SIG_CHAIN_ZRATE_F(nz.sigma))); \
        } else if (s) {       /* fixed thresholds: `s` seldom flips, a branch costs less */ \
            level = xk; \
            has_level = true; \
            (void)sig_chain_offset_f(true, xk, &offset, &offset, &tare_pending, zband, zrate); \
        } \
        out[i] = xk - offset; \
        stable[i] = (uint8_t)s; \
        stab = s; \
        if (nauto) { \
            if (STEADY || (st == SIG_OK && gate.holdoff == 0u && !gate.rejected_prev && mrun == 0u)) { \
                if (gate.frozen > 0u) gate.frozen--;   /* the gate's steady state, tested at once */ \
                update = true; \
            } else { \
                SIG_CHAIN_NOISE_GATE(gate, st, wn, mrun, nz.count, update); \
            } \
            if (STEADY) sig_noise_next_finite_f(&nz, xi, update); \
            else (void)sig_noise_next_f(&nz, xi, update); \
        } \
    } while (0)

/* The extremes of a full window (n >= 3 finite values) after the one that
 * left was an extreme: the largest (smallest) value in four runs of
 * independent comparisons, not one chain through all n; the extreme that
 * did not leave is kept and compared with the new sample.  The rescan of
 * the step path (sig_antipulse.c) gives both anew, in storage order; the
 * values are the same in any order, and so are their bits unless the
 * value is zero (+0 == -0): then WINDOW_FULL_PUSH scans in storage
 * order. */
static inline sig_real window_max(const sig_real *b, uint8_t n)
{
    sig_real a0 = b[0], a1 = b[1], a2 = b[2], a3 = b[n - 1u];   /* the last may be b[2] again */
    uint8_t j;
    for (j = 3u; j + 4u <= n; j = (uint8_t)(j + 4u)) {
        a0 = b[j] > a0 ? b[j] : a0;
        a1 = b[j + 1u] > a1 ? b[j + 1u] : a1;
        a2 = b[j + 2u] > a2 ? b[j + 2u] : a2;
        a3 = b[j + 3u] > a3 ? b[j + 3u] : a3;
    }
    for (; j + 1u < n; j++) a0 = b[j] > a0 ? b[j] : a0;
    a0 = a1 > a0 ? a1 : a0;
    a2 = a3 > a2 ? a3 : a2;
    return a2 > a0 ? a2 : a0;
}

static inline sig_real window_min(const sig_real *b, uint8_t n)
{
    sig_real a0 = b[0], a1 = b[1], a2 = b[2], a3 = b[n - 1u];
    uint8_t j;
    for (j = 3u; j + 4u <= n; j = (uint8_t)(j + 4u)) {
        a0 = b[j] < a0 ? b[j] : a0;
        a1 = b[j + 1u] < a1 ? b[j + 1u] : a1;
        a2 = b[j + 2u] < a2 ? b[j + 2u] : a2;
        a3 = b[j + 3u] < a3 ? b[j + 3u] : a3;
    }
    for (; j + 1u < n; j++) a0 = b[j] < a0 ? b[j] : a0;
    a0 = a1 < a0 ? a1 : a0;
    a2 = a3 < a2 ? a3 : a2;
    return a2 < a0 ? a2 : a0;
}

/* A threshold in a stage written for both loops: noise_auto's steady loop
 * (STEADY) derives it from sigma where it is used, so that the thresholds
 * are not live across that loop (fewer values than registers: no spills);
 * the general path reads its local (THRESHOLDS). */
#define TH(STEADY, local, from_sigma) ((STEADY) ? (from_sigma) : (local))

/* |v| as a max, no branch on the sign (v - w and w - v are one magnitude
 * exactly: |v - w| <= b is v - w <= b && w - v <= b); NaN for NaN */
static inline sig_real mag(sig_real v)
{
    sig_real nv = -v;
    return v > nv ? v : nv;
}

/* The loop is written once and compiled twice, with and without noise_auto,
 * each copy with the stage set known (gcc/clang: inlined into both calls). */
#ifdef __GNUC__
#define BATCH_BODY inline __attribute__((always_inline))
#else
#define BATCH_BODY inline
#endif

/* The hot state of the batch loop lives in locals (registers) instead of the
 * stage structs; these write it back before, and reload it after, anything
 * that works on the structs.  `fast` says the chain is in the state the fast
 * path is written for: every stage seeded, window values within FAST_MAX.
 * With noise_auto the ramp test's last finite sample (prev_x) is, between
 * samples, the noise estimator's previous sample (both take every finite
 * sample): not held twice, written back from the estimator (within a sample,
 * before the estimator has seen it, nothing reads it). */
#define HOT_LOAD_F() do { \
        dc = c->limit.dc; lrun = c->limit.t.run; lside = c->limit.t.side; \
        sum = c->ap.sum; mx = c->ap.mx; mn = c->ap.mn; head = c->ap.head; held = c->ap.count; \
        kx = c->kf.x; kp = c->kf.p; kk = c->kf.k; conv = c->kf.converged; \
        prev = c->st.prev; srun = c->st.run; mrun = c->motion_run; offset = c->offset; \
        a0 = c->limit.a0; band = c->motion_band; step = c->st.step; zband = c->zero_band; \
        zrate = c->zero_rate; nearb = c->near_band; \
        nz.prev = c->noise.prev; nz.sigma = c->noise.sigma; nz.res = c->noise.res; \
        nz.count = c->noise.count; nz.has_prev = c->noise.has_prev; \
        gate.rejected_prev = c->gate.rejected_prev; gate.holdoff = c->gate.holdoff; gate.frozen = c->gate.frozen; \
        stab = c->stable; \
        anchor = c->anchor; dage = c->drift_age; drifting = c->drifting; \
        tmean = c->trend_mean; \
        zero = c->zero; tare_pending = c->tare_pending; \
        kn = GAINS_UNKNOWN;                   /* P's place on its course from P0 */ \
        has_level = c->has_level; level = has_level ? c->level : SIG_REAL(0.0);   /* set once stable */ \
        fast = c->limit.t.seeded && held != 0u && c->kf.seeded && c->st.has_prev && !c->ramp \
               && mx <= FAST_MAX && mn >= -FAST_MAX; \
    } while (0)
#define HOT_STORE_F() do { \
        c->limit.dc = dc; c->limit.t.run = lrun; c->limit.t.side = lside; \
        c->ap.sum = sum; c->ap.mx = mx; c->ap.mn = mn; c->ap.head = head; c->ap.count = held; \
        c->kf.x = kx; c->kf.p = kp; c->kf.k = kk; c->kf.converged = conv; \
        c->st.prev = prev; c->st.run = srun; c->motion_run = mrun; c->offset = offset; \
        c->limit.a0 = a0; c->motion_band = band; c->st.step = step; c->zero_band = zband; \
        c->zero_rate = zrate; c->near_band = nearb; \
        if (nauto) c->prev_x = nz.prev; \
        c->noise.prev = nz.prev; c->noise.sigma = nz.sigma; c->noise.res = nz.res; \
        c->noise.count = nz.count; c->noise.has_prev = nz.has_prev; \
        c->gate.rejected_prev = gate.rejected_prev; c->gate.holdoff = gate.holdoff; c->gate.frozen = gate.frozen; \
        c->stable = stab; c->settled = srun >= stable_count; \
        c->anchor = anchor; c->drift_age = dage; c->drifting = drifting; \
        c->trend_mean = tmean; \
        c->zero = zero; c->tare_pending = tare_pending; \
        c->has_level = has_level; \
        if (has_level) c->level = level; \
    } while (0)

/* The batch form of sig_chain_step_f: x[0..n) -> out, stable (0/1).
 * With noise_auto its steady state has a loop of its own (below).
 * In the steady state (every stage seeded, |sample| and the window within
 * FAST_MAX, no lock-out re-seed on this sample) a sample takes the fast path:
 * the operations of the stage step functions for that case, in the same
 * order, on the state held in locals; any other sample, and the last one,
 * goes through sig_chain_step_f.  With noise_auto the fast path also does
 * what the step path adds outside a ramp: the Kalman filter started again
 * on the window's trimmed mean while the window fills or the detector has
 * not settled, the drift blocks, the backing of `stable`, the noise gate
 * and estimator and the thresholds from the new sigma (in the locals,
 * written back with the rest of the hot state); a ramp, and a rejection
 * that may start one (a second on one side, or a first after a sample more
 * than A0/2 out on that side), go to the step path.  Results
 * are those of n calls of sig_chain_step_f, bit for bit (tests/test_chain.py,
 * tests/test_chain_batch_auto.py, tests/test_chain_c.py); the status
 * returned is the last sample's (a non-finite sample before the first
 * finite one gives NaN, not stable). */
static BATCH_BODY sig_status process_f(sig_chain_f *c, const sig_real *x, size_t n, sig_real *out,
                                        uint8_t *stable, const bool nauto)
{
    size_t i;
    sig_status st;
    bool s, conv, fast, accept, stab, drifting, trending, seed_first, update;
    sig_real dc, sum, mx, mn, kx, kp, kk, prev, offset;      /* hot state */
    sig_real anchor, tmean, zero, level;                     /* noise_auto: hot state too, */
    bool tare_pending, has_level;
    sig_noise_f nz;                 /* with the estimator and its gate (copied field by field: */
    sig_chain_gate gate;            /* a whole-struct copy costs a store-forwarding stall) */
    uint8_t head, held, lrun, srun, mrun, dage;
    int8_t lside, side;
    sig_real xi, y, d, m, m1, old, e, xk, v, pm, den, pn;
    uint8_t j, nrun;
    sig_real gains[SIG_CHAIN_BATCH_GAINS > 0u ? SIG_CHAIN_BATCH_GAINS : 1u];   /* KALMAN_UPDATE */
    uint16_t kn, gfill = 0u;
    /* parameters, in locals: the stores to the window and to out[] could
     * otherwise alias them and force a reload every sample (with noise_auto
     * the thresholds follow sigma: THRESHOLDS) */
    sig_real a0, inv, band, kq, kr, kx0, kp0, step, zband, zrate, nearb;
    uint8_t wn, lockout_n, motion_count, stable_count;
    /* noise_auto: the thresholds from the current sigma, at the top of each
     * sample (and before the state is written back) */
#define THRESHOLDS() do { \
        if (nauto) sig_chain_thresholds_f(nz.sigma, nz.count == 0u, &a0, &band, &step, &zband, &zrate, &nearb); \
    } while (0)
    inv = c->ap.inv; kq = c->kf.q; kr = c->kf.r; kx0 = c->kf.x0; kp0 = c->kf.p0;
    seed_first = c->kf.seed_first;
    wn = c->ap.n; lockout_n = c->limit.t.lockout_n; motion_count = c->motion_count;
    stable_count = c->st.count;
    HOT_LOAD_F();
    for (i = 0u; i + 1u < n; i++) {
        THRESHOLDS();
        if (nauto && fast && held == wn && mrun == 0u && srun >= stable_count && gate.holdoff == 0u
            && !gate.rejected_prev && nz.count == 255u && lrun == 0u && lside == 0) {
            /* noise_auto's steady state (a full, settled window, no motion
             * run, the noise gate open, the estimator warmed up): the same
             * stages without the tests for what cannot happen here, on fewer
             * live values.  It hands a sample the limit would not take to
             * the general path (`limit`), goes on there from a motion test
             * that trips (`motion`), and ends after a sample that leaves
             * this state. */
            held = wn;
            for (;;) {
                nz.count = 255u;               /* as they are (saturated, seen a sample): now the compiler knows */
                nz.has_prev = true;
                xi = x[i];
                if (!(mag(xi - dc) <= SIG_CHAIN_A0_F(nz.sigma, false) && mag(xi) <= FAST_MAX)) {
                    THRESHOLDS();
                    goto limit;
                }
                y = xi;                        /* accepted: the limit's run stays 0 */
                st = SIG_OK;
                WINDOW_FULL_PUSH();
                WINDOW_RESUM();
                m = (sum - mx - mn) * inv;
                if (!(mag(m - kx) <= SIG_CHAIN_BAND_F(nz.sigma))) {   /* NaN too: e finite below */
                    THRESHOLDS();
                    goto motion;
                }
                dc = m;
                KALMAN_UPDATE(true);
                OUTPUT_STAGES(true);
                if (i + 2u >= n || srun < stable_count) break;   /* THRESHOLDS at the loop's top */
                i++;
            }
            continue;
        }
limit:
        xi = x[i];
        d = xi - dc;
        accept = mag(d) <= a0;                 /* false for NaN */
        /* limit filter: accept, reject (not counted if non-finite), or the
         * lock-out re-seed, which goes to step_f with everything else */
        st = SIG_WARN_REJECTED;
        if (fast && accept && mag(xi) <= FAST_MAX) {
            y = xi;
            lrun = 0u;
            lside = 0;
            st = SIG_OK;
        } else if (fast && !sig_real_isfinite(xi)) {
            y = dc;
        } else {
            side = d > SIG_REAL(0.0) ? (int8_t)1 : (int8_t)-1;
            nrun = side != lside ? 1u : (lrun < 255u ? (uint8_t)(lrun + 1u) : lrun);
            if (!fast || accept || (lockout_n != 0u && nrun >= lockout_n)
                || (nauto && (nrun >= 2u                 /* a ramp may start (sig_chain.c) */
                              || (side > 0 ? nz.prev - dc : dc - nz.prev) > a0 * SIG_REAL(0.5)))) {   /* nz.prev: prev_x */
                HOT_STORE_F();
                if (sig_chain_step_f(c, xi, &out[i], &s) < 0) {
                    out[i] = xi - xi;          /* NaN: non-finite before the first finite sample */
                    s = false;
                }
                stable[i] = (uint8_t)s;
                HOT_LOAD_F();
                continue;
            }
            lside = side;
            lrun = nrun;
            y = dc;
        }
        /* anti-pulse: extremes (rescan when one leaves a full window), sum, mean */
        if (held == wn) {
            WINDOW_FULL_PUSH();
        } else {                               /* filling: held >= 1 before this sample */
            c->ap.buf[head] = y;
            head++;
            if (head >= wn) head = 0u;
            held++;
            mx = y > mx ? y : mx;
            mn = y < mn ? y : mn;
            sum = sum + y;
        }
        WINDOW_RESUM();
        if (held == wn) m = (sum - mx - mn) * inv;
        else if (held == 2u) m = sum * SIG_REAL(0.5);
        else m = (sum - mx - mn) / (sig_real)(held - 2u);
motion:
        /* motion-aware settling (noise_auto: the estimate starts again) */
        if (band > SIG_REAL(0.0) && sig_chain_motion(mag(m - kx) > band, &mrun, motion_count)) {
            HOT_STORE_F();
            (void)sig_antipulse_reset_f(&c->ap);
            (void)sig_antipulse_step_f(&c->ap, y, &m1);
            if (nauto) (void)sig_kalman1_reset_f(&c->kf);
            else (void)sig_kalman1_restart_f(&c->kf);
            HOT_LOAD_F();
            m = m1;
            st = (sig_status)(st | SIG_CHAIN_MOTION);
        }
        dc = m;
        if (nauto && (held < wn || srun < stable_count)) {   /* not settled */
            /* settling: the window's trimmed mean is the estimate (a Kalman
             * reset, then its seeding step) */
            kx = nauto || seed_first ? m : kx0;    /* noise_auto needs seed_first (sig_chain.h) */
            kp = kp0;
            kn = 0u;
            conv = false;
            c->kf.seeded = true;
        }
        KALMAN_UPDATE(false);
        OUTPUT_STAGES(false);
    }
    /* the last sample on the step path: the state completed, its status returned */
    THRESHOLDS();
    HOT_STORE_F();
    st = sig_chain_step_f(c, x[n - 1u], &out[n - 1u], &s);
    if (st < 0) {
        out[n - 1u] = x[n - 1u] - x[n - 1u];
        s = false;
    }
    stable[n - 1u] = (uint8_t)s;
    return st;
}

/* one loop per form of the chain, each with its stage set known to the
 * compiler (the tests of noise_auto folded away) */
#define PROCESS_FORMS() \
    return c->noise_auto ? process_f(c, x, n, out, stable, true) : process_f(c, x, n, out, stable, false)

static sig_status process_forms(sig_chain_f *c, const sig_real *x, size_t n, sig_real *out, uint8_t *stable)
{
    PROCESS_FORMS();
}

/* x86-64 (gcc, clang): the same loops compiled once more for AVX, chosen
 * at run time.  AVX's three-operand encoding of the same scalar operations
 * saves the register copies SSE2's two-operand form needs before most of
 * them (about a sixth of the loop's instructions; measured: about a tenth
 * more samples per second).  Only "avx": without FMA nothing can be
 * contracted, the results are the same bit for bit. */
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(SIG_CHAIN_BATCH_NO_AVX)
#define BATCH_AVX 1
__attribute__((target("avx")))
static sig_status process_forms_avx(sig_chain_f *c, const sig_real *x, size_t n, sig_real *out, uint8_t *stable)
{
    PROCESS_FORMS();
}
#endif

sig_status sig_chain_process_f(sig_chain_f *c, const sig_real *x, size_t n, sig_real *out, uint8_t *stable)
{
    if (!c || (n != 0u && (!x || !out || !stable))) return SIG_ERR_ARG;
    if (n == 0u) return SIG_OK;
#ifdef BATCH_AVX
    if (__builtin_cpu_supports("avx")) return process_forms_avx(c, x, n, out, stable);
#endif
    return process_forms(c, x, n, out, stable);
}
#undef PROCESS_FORMS
#undef BATCH_AVX
#undef THRESHOLDS
#undef GAINS_UNKNOWN
#undef GAINS_ROOM
#undef TH
#undef WINDOW_FULL_PUSH
#undef WINDOW_RESUM
#undef KALMAN_UPDATE
#undef OUTPUT_STAGES
#undef HOT_LOAD_F
#undef HOT_STORE_F
#endif /* SIG_NO_FLOAT */

sig_status sig_chain_process_q(sig_chain_q *c, const int32_t *x, size_t n, int32_t *out_q7, uint8_t *stable)
{
    size_t i;
    sig_status st = SIG_OK;
    bool s;
    if (!c || (n != 0u && (!x || !out_q7 || !stable))) return SIG_ERR_ARG;
    for (i = 0u; i < n; i++) {
        st = sig_chain_step_q(c, x[i], &out_q7[i], &s);
        stable[i] = (uint8_t)s;
    }
    return st;
}

#endif /* __SDCC */
