/* sig_chain_mcs51.c - the fixed weighing chain for the 8051; see
 * sig_chain_mcs51.h.  Plain C99 (the host build and the bit-exactness tests
 * compile the very same file); under sdcc the state sits in direct and
 * indirect RAM and the 16x16 products are MUL AB sequences. */
#include "sig_chain_mcs51.h"
#ifdef SIG_CHAIN_MCS51_AUTO
#include "sig_chain_stages.h"    /* csrc/weigh: the portable chain's shared decisions */
#endif

SIG_MCS51_IDATA sig_chain_mcs51_state sig_chain_mcs51;
SIG_MCS51_XDATA sig_chain_mcs51_config sig_chain_mcs51_cfg;
SIG_MCS51_XDATA int16_t sig_chain_mcs51_window[SIG_ANTIPULSE_MAX];

#define S sig_chain_mcs51
#define CFG sig_chain_mcs51_cfg
#define WIN sig_chain_mcs51_window
#define DEV_MAX 16383            /* |deviation| bound of the window: differences fit int16 */
#define Q30_HALF UINT32_C(0x20000000)

/* ---- 16x16 -> 32 unsigned product ------------------------------------------ */
/* Operands and result in fixed direct-RAM cells, so the 8051 form is four
 * MUL AB with no argument passing (sdcc would widen (uint32_t)a * b into its
 * 32x32 __mullong). */
static SIG_MCS51_DATA uint16_t mul_a, mul_b;
static SIG_MCS51_DATA uint32_t mul_r;

#ifdef __SDCC
/* A and B only: sdcc takes a naked function to leave R0-R7 alone, and with
 * --stack-auto keeps values in them across the call.  The two cross
 * products (low x high, high x low) are added at byte 1 of the result by
 * one assembler macro. */
static void mul16(void) __naked
{
    __asm
    .macro mul16_add_cross a_byte, b_byte
    mov a,a_byte
    mov b,b_byte
    mul ab
    add a,(_mul_r + 1)
    mov (_mul_r + 1),a
    mov a,b
    addc a,(_mul_r + 2)
    mov (_mul_r + 2),a
    clr a
    addc a,(_mul_r + 3)
    mov (_mul_r + 3),a
    .endm
    mov a,_mul_a
    mov b,_mul_b
    mul ab
    mov _mul_r,a
    mov (_mul_r + 1),b
    mov a,(_mul_a + 1)
    mov b,(_mul_b + 1)
    mul ab
    mov (_mul_r + 2),a
    mov (_mul_r + 3),b
    mul16_add_cross _mul_a, (_mul_b+1)
    /* cppcheck-suppress constStatement ; assembler macro operands, not a C comma expression */
    mul16_add_cross (_mul_a+1), _mul_b
    ret
    __endasm;
}
#else
static void mul16(void)
{
    mul_r = (uint32_t)mul_a * mul_b;
}
#endif

/* ---- helpers of the general (slow) branches --------------------------------- */
static uint32_t mag32(int32_t v)
{
    return v < 0 ? (uint32_t)0 - (uint32_t)v : (uint32_t)v;
}

/* floor((s + floor(d/2)) / d), d = 1..30, any |s| < 2^30 (the portable
 * anti-pulse rounding), by shift and subtract */
static int32_t div_round_any(int32_t s, uint8_t d)
{
    int32_t t = s + (int32_t)(d >> 1);
    uint32_t u = t >= 0 ? (uint32_t)t : (uint32_t)(-t) + (uint32_t)d - 1u;
    uint32_t q = 0u, r = 0u;
    uint8_t i;
    for (i = 0u; i < 32u; i++) {
        r = (r << 1) | (u >> 31);
        u <<= 1;
        q <<= 1;
        if (r >= d) { r -= d; q |= 1u; }
    }
    return t >= 0 ? (int32_t)q : -(int32_t)q;
}

/* sign(a) * floor((|a| K + 2^29) / 2^30) for any a (the portable gain
 * product), from four 16x16 products */
static int32_t gain_any(int32_t a)
{
    uint32_t ua = mag32(a), ll, lh, hl, hh, mid, lo, r;
    mul_a = (uint16_t)ua; mul_b = (uint16_t)S.k; mul16(); ll = mul_r;
    mul_b = (uint16_t)(S.k >> 16); mul16(); lh = mul_r;
    mul_a = (uint16_t)(ua >> 16); mul16(); hh = mul_r;
    mul_b = (uint16_t)S.k; mul16(); hl = mul_r;
    mid = lh + hl;
    if (mid < lh) hh += UINT32_C(0x10000);
    lo = ll + (mid << 16);
    if (lo < ll) hh++;
    hh += mid >> 16;
    lo += Q30_HALF;
    if (lo < Q30_HALF) hh++;
    r = (hh << 2) | (lo >> 30);
    if (a >= 0) return (int32_t)r;
    return r >= UINT32_C(0x80000000) ? INT32_MIN : -(int32_t)r;
}

/* saturating int32 arithmetic of the portable chain (sig_types.h), for the
 * branches where the operands' signs differ (the common case is one
 * subtraction: a ^ b >= 0 means no overflow) */
static int32_t sat_sub(int32_t a, int32_t b)
{
    if (b < 0 && a > INT32_MAX + b) return INT32_MAX;
    if (b > 0 && a < INT32_MIN + b) return INT32_MIN;
    return a - b;
}

static int32_t sat_add(int32_t a, int32_t b)
{
    if (b > 0 && a > INT32_MAX - b) return INT32_MAX;
    if (b < 0 && a < INT32_MIN - b) return INT32_MIN;
    return a + b;
}

#define SUB_SAT(a, b) (((a) ^ (b)) >= 0 ? (a) - (b) : sat_sub((a), (b)))
#define ABS_SAT(v) ((v) >= 0 ? (v) : (v) == INT32_MIN ? INT32_MAX : -(v))

static int32_t codes_to_q7(int32_t m)
{
    return m >= 0 ? (int32_t)((uint32_t)m << 7) : -(int32_t)((uint32_t)-m << 7);
}

/* |v| < 2^30 */
static bool fits30(int32_t v)
{
    return v > -INT32_C(0x40000000) && v < INT32_C(0x40000000);
}

/* The fast path's range: x - offset and m7 - x cannot overflow, and every
 * value the fast step makes stays inside (x between x and m7, the offset
 * moving towards x): |x|, |offset| < 2^30, |base7| < 2^30 - 2^22 (a
 * deviation in Q24.7 is below 2^21). */
static void update_small(void)
{
    S.small = fits30(S.x) && fits30(S.offset) && S.base7 > -INT32_C(0x3FC00000)
        && S.base7 < INT32_C(0x3FC00000);
}

static void window_reset(void)
{
    S.count = 0u;
    S.head = 0u;
    S.sum = 0;
    S.mx = S.mn = 0;
}

/* Move the base to base + s: every held deviation, the extremes and Dc shift
 * by -s.  false (nothing changed) if a value would leave +-DEV_MAX. */
static bool rebase(int32_t s) SIG_MCS51_REENTRANT
{
    uint8_t i;
    int32_t v;
    for (i = 0u; i < S.count; i++) {
        v = (int32_t)WIN[i] - s;
        if (v > DEV_MAX || v < -DEV_MAX) return false;
    }
    v = (int32_t)S.dc - s;
    if (v > DEV_MAX || v < -DEV_MAX) return false;
    for (i = 0u; i < S.count; i++) WIN[i] = (int16_t)(WIN[i] - s);
    S.dc = (int16_t)v;
    S.mx = (int16_t)(S.mx - s);
    S.mn = (int16_t)(S.mn - s);
    S.sum -= s * (int32_t)S.count;
    S.base += s;
    S.base7 = codes_to_q7(S.base);
    return true;
}

/* ---- the anti-pulse window on deviations ------------------------------------ */
/* y: deviation to add; returns the trimmed mean's deviation (round half up) */
static int16_t window_step(int16_t y)
{
    int16_t old, v, mx, mn;
    int32_t t;
    uint8_t i, d;
    uint8_t full = S.count == S.n;     /* uint8_t, not bool: sdcc keeps bool locals in the bit area that would split the direct RAM */
    old = WIN[S.head];
    WIN[S.head] = y;
    if (++S.head >= S.n) S.head = 0u;
    if (!full) S.count++;
    if (S.count == 1u) {
        S.mx = S.mn = y;
    } else if (full && (old == S.mx || old == S.mn)) {
        mx = mn = WIN[0];
        for (i = 1u; i < S.count; i++) {
            v = WIN[i];
            if (v > mx) mx = v;
            if (v < mn) mn = v;
        }
        S.mx = mx;
        S.mn = mn;
    } else {
        if (y > S.mx) S.mx = y;
        if (y < S.mn) S.mn = y;
    }
    S.sum += full ? (int32_t)y - old : (int32_t)y;
    if (S.count >= 3u) {
        t = S.sum - S.mx - S.mn;
        d = (uint8_t)(S.count - 2u);
    } else {
        t = S.sum;
        d = S.count;
    }
    if (d == 1u) return (int16_t)t;
    if (full) {
        /* floor(u / d) by the init reciprocal while u is in its exact range */
        t += (int32_t)(d >> 1);
        if (t >= 0 && t <= (int32_t)S.u_lim) {
            mul_a = (uint16_t)t; mul_b = S.recip; mul16();
            return (int16_t)(mul_r >> S.recip_shift);
        }
        if (t < 0 && -t + (int32_t)d - 1 <= (int32_t)S.u_lim) {
            mul_a = (uint16_t)(-t + (int32_t)d - 1); mul_b = S.recip; mul16();
            return (int16_t)-(int16_t)(mul_r >> S.recip_shift);
        }
        t -= (int32_t)(d >> 1);
    }
    return (int16_t)div_round_any(t, d);
}

/* ---- init ------------------------------------------------------------------- */
/* the checks of sig_chain_init_q (sig_chain.c), plus the port's own range;
 * noise_auto only in a SIG_CHAIN_MCS51_AUTO build (sig_chain_mcs51.h) */
static bool params_ok(const sig_chain_params_q *p)
{
#ifndef SIG_CHAIN_MCS51_AUTO
    if (p->noise_auto) return false;
#endif
    return p->a0 > 0 && p->a0 <= SIG_CHAIN_MCS51_A0_MAX
        && p->window >= 3u && p->window <= SIG_ANTIPULSE_MAX
        && p->q_q30 <= SIG_KALMAN1_Q_MAX && p->p0_q16 <= SIG_KALMAN1_P0_MAX
        && p->stable_step_q7 >= 0 && p->stable_count >= 1u
        && p->motion_band_q7 >= 0 && p->motion_count >= 1u
        && p->zero_band_q7 >= 0 && p->zero_rate_q7 >= 0
        /* the portable chain's start rule (sig_chain.h) */
        && (p->seed_first || (!p->noise_auto && p->p0_q16 >= (uint32_t)SIG_Q16_ONE));
}

#ifdef SIG_CHAIN_MCS51_AUTO
static sig_status tare_auto(void);
static sig_status step_auto(int32_t x);
#endif

sig_status sig_chain_mcs51_init(const sig_chain_params_q *p,
                                const SIG_MCS51_CODE uint32_t *gains, uint16_t n_gains) SIG_MCS51_REENTRANT
{
    uint32_t e, lim, best = 0u;
    uint8_t k, d;
    if (p == NULL || !params_ok(p) || gains == NULL || n_gains == 0u) return SIG_ERR_ARG;
#ifdef SIG_CHAIN_MCS51_AUTO
    if (p->noise_auto && sig_chain_init_q(&sig_chain_mcs51_auto, p) != SIG_OK) return SIG_ERR_ARG;
#endif
    S.noise_auto = p->noise_auto;
    CFG.gains = gains;
    S.a0 = (int16_t)p->a0;
    S.n = p->window;
    S.stable_step = p->stable_step_q7;
    S.stable_step16 = p->stable_step_q7 > INT16_MAX ? INT16_MAX : (int16_t)p->stable_step_q7;
    S.motion_band16 = p->motion_band_q7 > INT16_MAX ? INT16_MAX : (int16_t)p->motion_band_q7;
    S.stable_count = p->stable_count;
    CFG.lockout_n = p->lockout_n;
    S.motion_band = p->motion_band_q7;
    S.motion_count = p->motion_count;
    S.zero_band = p->zero_band_q7;
    CFG.zero_rate = p->zero_rate_q7;
    CFG.seed_first = p->seed_first;
    CFG.gain_n = n_gains;
    /* floor(u * M / 2^k) == floor(u / d) for u <= lim when M = ceil(2^k / d)
     * and (lim + 1) * e <= 2^k, e = M d - 2^k (then u e / (d 2^k) < 1/d);
     * the largest lim over the k whose M fits 16 bits */
    d = (uint8_t)(p->window - 2u);
    S.half = (uint8_t)(d >> 1);
    S.recip = 0u;
    S.recip_shift = 16u;
    S.u_lim = 0u;
    for (k = 16u; k < 31u; k++) {
        uint32_t pk = UINT32_C(1) << k;
        uint32_t m = (pk + d - 1u) / d;
        if (m > UINT32_C(0xFFFF)) break;
        e = m * d - pk;
        lim = e == 0u ? UINT32_C(0xFFFF) : pk / e - 1u;
        if (lim > UINT32_C(0xFFFF)) lim = UINT32_C(0xFFFF);
        if (lim > best) {
            best = lim;
            S.recip = (uint16_t)m;
            S.recip_shift = k;
            S.u_lim = (uint16_t)lim;
        }
    }
    CFG.x0 = p->x0_q7;
    return sig_chain_mcs51_reset();
}

sig_status sig_chain_mcs51_reset(void)
{
    window_reset();
    S.base = 0;
    S.base7 = 0;
    S.dc = 0;
    S.seeded = false;
    S.lock_run = 0u;
    S.lock_side = 0;
    S.x = CFG.x0;
    S.kf_seeded = false;
    S.gain_i = 0u;
    S.k = 0u;
    S.has_prev = false;
    S.stable_run = 0u;
    S.offset = 0;
    S.out = 0;
    S.motion_run = 0u;
    S.tare_pending = false;
    S.stable = false;
    S.has_out = false;
    update_small();
    S.hot = false;
#ifdef SIG_CHAIN_MCS51_AUTO
    if (S.noise_auto) (void)sig_chain_reset_q(&sig_chain_mcs51_auto);
#endif
    return SIG_OK;
}

sig_status sig_chain_mcs51_tare(void)
{
#ifdef SIG_CHAIN_MCS51_AUTO
    if (S.noise_auto && !S.hot) return tare_auto();
#endif
    if (S.has_out && S.stable) {
        S.offset = S.x;
#ifdef SIG_CHAIN_MCS51_AUTO
        sig_chain_mcs51_auto.zero = S.x;    /* the set zero (hot: the portable struct keeps it) */
#endif
        S.out = 0;
        S.tare_pending = false;
        update_small();
        return SIG_CHAIN_TARED;
    }
    S.tare_pending = true;
    return SIG_OK;
}

/* ---- the step ---------------------------------------------------------------- */
/* The limit stage on x (codes, clamped): the deviation to feed the window
 * in *y, the limit's status.  SIG_ERR_ARG when x is accepted but cannot be
 * held as a deviation (nothing changed). */
static sig_status limit_step(int32_t x, int16_t *y)
{
    int32_t xd = x - S.base, dd;
    int8_t side;
    if (!S.seeded) {                      /* first sample: seeds Dc and the base */
        S.seeded = true;
        S.lock_run = 0u;
        S.lock_side = 0;
        window_reset();
        S.base = x;
        S.base7 = codes_to_q7(x);
        S.dc = 0;
        *y = 0;
        return SIG_OK;
    }
    if (xd >= -DEV_MAX && xd <= DEV_MAX) {
        dd = (int32_t)(int16_t)((int16_t)xd - S.dc);        /* both within +-DEV_MAX */
    } else {
        dd = x - (S.base + (int32_t)S.dc);   /* |codes| <= 2^24: no overflow */
    }
    if (dd > S.a0 || dd < -S.a0) {
        side = dd > 0 ? (int8_t)1 : (int8_t)-1;
        if (side == S.lock_side) {
            if (S.lock_run < 255u) S.lock_run++;
        } else {
            S.lock_side = side;
            S.lock_run = 1u;
        }
        if (CFG.lockout_n != 0u && S.lock_run >= CFG.lockout_n) {
            S.lock_run = 0u;
            S.lock_side = 0;
            window_reset();               /* the chain empties the window on a re-seed */
            S.base = x;
            S.base7 = codes_to_q7(x);
            S.dc = 0;
            *y = 0;
            return SIG_LIMIT_RESEEDED;
        }
        *y = S.dc;
        return SIG_WARN_REJECTED;
    }
    if (xd < -DEV_MAX || xd > DEV_MAX) {
        /* accepted but beyond the deviation range: move the base to Dc */
        if (!rebase(S.dc)) return SIG_ERR_ARG;
        xd = x - S.base;
    }
    S.lock_run = 0u;
    S.lock_side = 0;
    *y = (int16_t)xd;
    return SIG_OK;
}


/* ---- the steady state --------------------------------------------------------- */
/* Any step: the portable chain's stages in order, on the deviation window. */
static sig_status step_general(int32_t x)
{
    sig_status ret = SIG_OK, st;
    int32_t m7, innov, inc, dz;
    int16_t y, m;
    uint16_t a;
    uint8_t stab, small;
    if (x > SIG_CODE_MAX) { x = SIG_CODE_MAX; ret = SIG_WARN_CLAMPED; }
    else if (x < -SIG_CODE_MAX) { x = -SIG_CODE_MAX; ret = SIG_WARN_CLAMPED; }
    st = limit_step(x, &y);
    if (st < 0) return st;                 /* cannot be held: nothing changed */
    ret = (sig_status)(ret | st);
    if ((st & SIG_LIMIT_RESEEDED) != 0) {
        if (S.motion_band > 0) S.gain_i = 0u;          /* Kalman restart */
        S.motion_run = 0u;
    }
    m = window_step(y);
    m7 = codes_to_q7(S.base + m);
    innov = SUB_SAT(m7, S.x);
    if (S.motion_band > 0 && S.kf_seeded) {
        if (ABS_SAT(innov) > S.motion_band) {
            if (S.motion_run < 255u) S.motion_run++;
        } else {
            S.motion_run = 0u;
        }
        if (S.motion_run >= S.motion_count) {
            window_reset();
            S.base = S.base + y;
            S.base7 = codes_to_q7(S.base);
            S.dc = 0;
            m = window_step(0);
            m7 = codes_to_q7(S.base + m);
            innov = SUB_SAT(m7, S.x);
            S.gain_i = 0u;
            S.motion_run = 0u;
            ret = (sig_status)(ret | SIG_CHAIN_MOTION);
        }
    }
    S.dc = m;                              /* the limit's reference: the trimmed mean */
    /* Kalman */
    if (!S.kf_seeded) {
        S.kf_seeded = true;
        if (CFG.seed_first) {
            S.x = m7;
            innov = 0;
        }
    }
    if (S.gain_i < CFG.gain_n) S.k = CFG.gains[S.gain_i++];   /* then the steady gain holds */
    small = innov > -32768 && innov < 32768;
    if (small) {
        /* |innov| < 2^15, K <= 2^30: |innov| K = hi * 2^16 + lo with two
         * 16x16 products, rounded half up at 2^30 */
        a = (uint16_t)(innov < 0 ? -innov : innov);
        mul_a = a; mul_b = (uint16_t)S.k; mul16();
        dz = (int32_t)((mul_r + Q30_HALF) >> 16);     /* < 2^16 + 2^13 */
        mul_b = (uint16_t)(S.k >> 16); mul16();
        inc = (int32_t)((mul_r + (uint32_t)dz) >> 14);
        if (innov < 0) inc = -inc;
        S.x += inc;                        /* between x and m7: no overflow */
    } else {
        inc = 0;
        dz = S.x;
        S.x = sat_add(S.x, gain_any(innov));
        inc = SUB_SAT(S.x, dz);
    }
    /* stability: |x - previous x| <= step */
    if (S.has_prev && ABS_SAT(inc) <= S.stable_step) {
        if (S.stable_run < 255u) S.stable_run++;
    } else {
        S.stable_run = 0u;
    }
    S.has_prev = true;
    stab = S.stable_run >= S.stable_count;
    if (stab) {
        if (S.tare_pending) {
            S.offset = S.x;
            S.tare_pending = false;
            ret = (sig_status)(ret | SIG_CHAIN_TARED);
        } else if (S.zero_band > 0) {
            dz = SUB_SAT(S.x, S.offset);
            if (ABS_SAT(dz) <= S.zero_band) {
                if (dz > CFG.zero_rate) dz = CFG.zero_rate;
                if (dz < -CFG.zero_rate) dz = -CFG.zero_rate;
                S.offset = sat_add(S.offset, dz);
            }
        }
    }
    S.out = SUB_SAT(S.x, S.offset);
    S.stable = stab;
    S.has_out = true;
    update_small();
    return ret;
}

/* The steady state's limit, window and trimmed mean, shared by the fixed
 * step and the default chain's (sig_chain_mcs51_step, step_auto): on x
 * (codes), in the caller's locals t, y, dd, old, mx, mn, i, v, m, m7, innov,
 * a (|innovation|); `general` is the caller's step for any other case,
 * taken before anything has changed.  A macro: the 8051 pays for a call
 * and its arguments more than for the text. */
#define STEADY_MEAN(x, general) do {                                                        \
        if ((x) > SIG_CODE_MAX || (x) < -SIG_CODE_MAX) return general(x);   /* clamped */    \
        t = (x) - S.base;                                                                   \
        if (t < -DEV_MAX || t > DEV_MAX) return general(x);                                 \
        y = (int16_t)t;                                                                     \
        dd = (int16_t)(y - S.dc);                                                           \
        if (dd > S.a0 || dd < -S.a0) return general(x);                                     \
        old = WIN[S.head];                                                                  \
        mx = S.mx;                                                                          \
        mn = S.mn;                                                                          \
        if (old == mx || old == mn) {                                                       \
            /* an extreme leaves the window: the extremes of the window with y in          \
             * old's slot (the portable stage rescans the same values) */                  \
            mx = mn = y;                                                                    \
            for (i = 0u; i < S.n; i++) {                                                    \
                if (i == S.head) continue;                                                  \
                v = WIN[i];                                                                 \
                if (v > mx) mx = v;                                                         \
                if (v < mn) mn = v;                                                         \
            }                                                                               \
        } else {                                                                            \
            if (y > mx) mx = y;                                                             \
            if (y < mn) mn = y;                                                             \
        }                                                                                   \
        t = S.sum + (y - old);                /* int16 difference: both within +-DEV_MAX */ \
        t = t - mx - mn + S.half;                                                           \
        if (t >= 0) {                                                                       \
            if (t > (int32_t)S.u_lim) return general(x);                                    \
            mul_a = (uint16_t)t;                                                            \
            mul_b = S.recip; mul16();                                                       \
            m = (int16_t)((uint16_t)(mul_r >> 16) >> (uint8_t)(S.recip_shift - 16u));      \
        } else {                                                                            \
            t = -t + (int32_t)(S.n - 3u);     /* floor(t / d) = -floor((-t + d - 1) / d) */ \
            if (t > (int32_t)S.u_lim) return general(x);                                    \
            mul_a = (uint16_t)t;                                                            \
            mul_b = S.recip; mul16();                                                       \
            m = (int16_t)-(int16_t)((uint16_t)(mul_r >> 16) >> (uint8_t)(S.recip_shift - 16u)); \
        }                                                                                   \
        m7 = S.base7 + (int32_t)m * 128;     /* sdcc: shifts, no 32x32 product */           \
        innov = m7 - S.x;                     /* |m7|, |x| < 2^30 (S.small): exact */       \
        if (innov <= -32768 || innov >= 32768) return general(x);                           \
        a = (uint16_t)(innov < 0 ? -innov : innov);                                         \
    } while (0)

/* Then, once the step is sure: the limit (accepted: run cleared), the
 * window, the motion run, Dc; the Kalman update x += K innov with the gain
 * of this step from the table (|innov| K / 2^30 rounded half up, two 16x16
 * products; locals u, inc). */
#define STEADY_COMMIT() do {                                                                \
        S.lock_run = 0u;                                                                    \
        S.lock_side = 0;                                                                    \
        WIN[S.head] = y;                                                                    \
        if (++S.head >= S.n) S.head = 0u;                                                   \
        S.mx = mx;                                                                          \
        S.mn = mn;                                                                          \
        S.sum += y - old;                                                                   \
        S.motion_run = motion_run;                                                          \
        S.dc = m;                                                                           \
        if (S.gain_i < CFG.gain_n) S.k = CFG.gains[S.gain_i++];                             \
        mul_a = a;                                                                          \
        mul_b = (uint16_t)S.k; mul16();                                                     \
        u = (uint16_t)((mul_r + Q30_HALF) >> 16);                                           \
        mul_b = (uint16_t)(S.k >> 16); mul16();                                             \
        inc = (int16_t)((mul_r + u) >> 14);    /* <= |innov| < 2^15 */                      \
        if (innov < 0) inc = (int16_t)-inc;                                                 \
        S.x += inc;                           /* between x and m7: |x| stays < 2^30 */      \
    } while (0)

/* One sample.  The common case runs here, in int16 where the values
 * allow: window full, the sample accepted and within the deviation range
 * (an evicted extreme costs a rescan of the window), the trimmed sum within
 * the reciprocal's range,
 * |innovation| < 2^15, no motion restart.  When any of these fails, before
 * anything has changed, the general step runs instead. */
sig_status sig_chain_mcs51_step(int32_t x)
{
    int32_t t, m7, innov, dz;
    int16_t y, old, mx, mn, m, inc, dd, v;
    uint16_t a, u;
    uint8_t motion_run = 0u, stab, i;
#ifdef SIG_CHAIN_MCS51_AUTO
    if (S.noise_auto) return step_auto(x);
#endif
    if (S.count != S.n || !S.kf_seeded || !S.small) return step_general(x);
    STEADY_MEAN(x, step_general);
    if (S.motion_band > 0) {
        if ((int16_t)a > S.motion_band16) {
            motion_run = (uint8_t)(S.motion_run + 1u);
            if (motion_run >= S.motion_count) return step_general(x);
        }
    }
    STEADY_COMMIT();
    /* stability */
    if ((inc < 0 ? -inc : inc) <= S.stable_step16) {
        if (S.stable_run < 255u) S.stable_run++;
    } else {
        S.stable_run = 0u;
    }
    stab = S.stable_run >= S.stable_count;
    S.stable = stab;
    /* output: x - offset, exact while |x|, |offset| < 2^30: out + inc */
    t = S.out + inc;
    if (stab) {
        if (S.tare_pending) {
            S.offset = S.x;
            S.tare_pending = false;
            S.out = 0;
            return SIG_CHAIN_TARED;
        }
        if (S.zero_band > 0 && (t < 0 ? -t : t) <= S.zero_band) {
            /* offset moves towards x (stays within 2^30), out by the same */
            dz = t > CFG.zero_rate ? CFG.zero_rate : t < -CFG.zero_rate ? -CFG.zero_rate : t;
            S.offset += dz;
            t -= dz;
        }
    }
    S.out = t;
    return SIG_OK;
}

#ifdef SIG_CHAIN_MCS51_AUTO
/* ---- the default chain (noise_auto; sig_chain_mcs51.h) ----------------------- */
SIG_MCS51_XDATA sig_chain_q sig_chain_mcs51_auto;
#define A sig_chain_mcs51_auto

static int16_t clamp16(int32_t v)
{
    return v > INT16_MAX ? INT16_MAX : (int16_t)v;      /* v >= 0 */
}

/* the int16 copies of the thresholds the steady state tests */
static void mirror_thresholds(void)
{
    S.a0 = clamp16(A.limit.a0);
    S.motion_band16 = clamp16(A.motion_band);
    S.stable_step16 = clamp16(A.st.step);
}

/* The hot fields into the portable struct (the window is full while hot).
 * The Kalman's phase and y after gain_i steps since a restart are those of
 * the run that made the gain table (sig_chain_mcs51_gains): phase 1 after
 * one step, 2 until the table's last entry, then 3. */
static void hot_to_portable(void)
{
    uint8_t i;
    int32_t sum = 0, v;
    A.limit.dc = S.base + S.dc;
    A.limit.t.run = S.lock_run;
    A.limit.t.side = S.lock_side;
    A.limit.t.seeded = S.seeded;
    for (i = 0u; i < S.n; i++) {
        v = S.base + WIN[i];
        A.ap.buf[i] = v;
        sum += v;
    }
    A.ap.sum = sum;
    A.ap.mx = S.base + S.mx;
    A.ap.mn = S.base + S.mn;
    A.ap.count = S.count;
    A.ap.head = S.head;
    A.kf.x = S.x;
    A.kf.seeded = S.kf_seeded;
    A.kf.phase = S.gain_i == 0u ? 0u : S.gain_i == 1u ? 1u : S.gain_i >= CFG.gain_n ? 3u : 2u;
    A.kf.y = UINT32_C(1073741824) - (S.gain_i == 0u ? 0u : CFG.gains[S.gain_i - 1u]);   /* Q30 */
    A.st.prev = S.x;
    A.st.run = S.stable_run;
    A.st.has_prev = S.has_prev;
    A.offset = S.offset;
    A.out = S.out;
    A.motion_run = S.motion_run;
    A.tare_pending = S.tare_pending;
    A.stable = S.stable;
    A.has_out = S.has_out;
    S.hot = false;
}

/* Back into the hot fields when the next step may be the steady state:
 * window full, settled, no ramp, and the window held as int16 deviations
 * around Dc (its trimmed mean); otherwise the portable struct keeps the
 * chain. */
static void portable_to_hot(void) SIG_MCS51_REENTRANT
{
    uint8_t i;
    int32_t base = A.limit.dc, v, sum = 0;
    if (A.ap.count != A.ap.n || !A.settled || A.ramp || !A.kf.seeded || S.gain_i == 0u
        || A.st.prev != A.kf.x)
        return;
    for (i = 0u; i < A.ap.n; i++) {
        v = A.ap.buf[i] - base;
        if (v > DEV_MAX || v < -DEV_MAX) return;
    }
    for (i = 0u; i < A.ap.n; i++) {
        v = A.ap.buf[i] - base;
        WIN[i] = (int16_t)v;
        sum += v;
    }
    S.base = base;
    S.base7 = codes_to_q7(base);
    S.dc = 0;
    S.sum = sum;
    S.mx = (int16_t)(A.ap.mx - base);
    S.mn = (int16_t)(A.ap.mn - base);
    S.count = A.ap.count;
    S.head = A.ap.head;
    S.seeded = A.limit.t.seeded;
    S.lock_run = A.limit.t.run;
    S.lock_side = A.limit.t.side;
    S.x = A.kf.x;
    S.kf_seeded = true;
    S.k = CFG.gains[S.gain_i - 1u];
    S.stable_run = A.st.run;
    S.has_prev = A.st.has_prev;
    S.offset = A.offset;
    S.motion_run = A.motion_run;
    S.tare_pending = A.tare_pending;
    mirror_thresholds();
    update_small();
    S.hot = true;
}

/* Any step but the steady state: the portable chain itself. */
static sig_status step_portable(int32_t x)
{
    sig_status ret;
    int32_t out;
    bool stab;
    if (S.hot) hot_to_portable();
    ret = sig_chain_step_q(&A, x, &out, &stab);
    /* steps since the Kalman's last restart (phase 1: this step restarted it) */
    if (A.kf.phase == 1u) S.gain_i = 1u;
    else if (A.kf.phase == 3u || S.gain_i >= CFG.gain_n) S.gain_i = CFG.gain_n;
    else S.gain_i++;
    S.out = out;
    S.stable = stab;
    S.has_out = true;
    portable_to_hot();
    return ret;
}

static sig_status tare_auto(void)
{
    sig_status st = sig_chain_tare_q(&A);
    S.offset = A.offset;
    S.out = A.out;
    S.tare_pending = A.tare_pending;
    return st;
}

/* The steady state of sig_chain_step_q on the hot fields: the limit accepts
 * the sample (no ramp under way: the follower passes), the window and the
 * Kalman as in the fixed steady state, the motion run below its count, no
 * settling re-seed (the window is full and the last step was settled).
 * Anything else, before anything has changed, runs the portable step. */
static sig_status step_auto(int32_t x)
{
    int32_t t, m7, innov, xk;
    int16_t y, old, mx, mn, m, inc, dd, v;
    uint16_t a, u;
    uint8_t motion_run, i;
    bool stab, update;
    sig_status ret = SIG_OK;
    if (!S.hot || !S.small || !A.settled) return step_portable(x);
    STEADY_MEAN(x, step_portable);
    motion_run = S.motion_run;            /* a restart is the portable step's */
    if (sig_chain_motion((int16_t)a > S.motion_band16, &motion_run, S.motion_count))
        return step_portable(x);
    STEADY_COMMIT();
    A.prev_x = x;                         /* the ramp follower's last sample */
    xk = S.x;
    /* the stability detector, its verdict backed by the samples */
    S.stable_run = SIG_RUN_NEXT(S.stable_run, (inc < 0 ? -inc : inc) <= S.stable_step16);
    stab = S.stable_run >= S.stable_count;
    A.settled = stab;
    if (sig_chain_drift_due(false, false, &A.drift_age, S.n, &A.drifting, &A.hold_block)) {
        A.drifting = sig_chain_drift_verdict(sig_abs32_sat(sig_sat_sub32(xk, A.anchor)) > A.noise.sigma,
                                             &A.hold_block);
        A.anchor = xk;
    }
    /* the trend test runs on every sample (the window is full here) */
    A.trending = sig_chain_trend_q(false, sig_sat_sub32(S.base7 + (int32_t)y * 128, xk), A.noise.sigma,
                                   &A.trend_mean);
    if (stab)
        stab = sig_chain_backed(ret, S.count, S.n, motion_run, A.drifting, A.trending,
                                sig_abs32_sat(S.base7 + (int32_t)y * 128 - xk) <= A.near_band
                                && sig_abs32_sat(m7 - xk) <= A.noise.sigma);
    if (stab) {
        A.level = xk;
        A.has_level = true;
    }
    if (stab && sig_chain_offset_q(xk, &S.offset, &A.zero, &S.tare_pending, A.zero_band, A.zero_rate))
        ret = (sig_status)(ret | SIG_CHAIN_TARED);
    S.out = xk - S.offset;                /* |x|, |offset| < 2^30 */
    S.stable = stab;
    /* the noise estimate, its gate and the thresholds */
    SIG_CHAIN_NOISE_GATE(A.gate, ret, S.n, S.motion_run, A.noise.count, update);
    (void)sig_noise_step_q(&A.noise, x, update);
    SIG_CHAIN_THRESHOLDS_Q(A.noise.sigma, A.noise.count == 0u, A.limit.a0, A.motion_band,
                           A.st.step, A.zero_band, A.zero_rate, A.near_band);
    mirror_thresholds();
    return A.noise.sigma <= SIG_NOISE_FLOOR_Q7 ? (sig_status)(ret | SIG_CHAIN_NOISE_FLOOR) : ret;
}
#endif /* SIG_CHAIN_MCS51_AUTO */
