/* fuzz_chain.c - the weighing chain step (sig_chain: limit -> anti-pulse ->
 * Kalman -> stability) with arbitrary parameters and arbitrary samples, in
 * both numeric forms, interleaved with tare, set_offset and reset.
 *
 * Float samples come from raw bits (NaN, inf, subnormals, -0, +-FLT_MAX) or,
 * when the steering bit says so, from int16 codes scaled into the
 * parameters' range; fixed samples are int32 with the rails favoured.
 * Invariants after every call:
 *   - rejected parameters (init) and rejected calls (NULL, NaN offset, a
 *     non-finite sample before the first finite one) return an error and
 *     leave the chain byte for byte as it was;
 *   - float: the Kalman state x, P, the gain and the limit reference Dc are
 *     never NaN, P >= 0 (> 0 while Q > 0 or P0 > 0 has not been consumed),
 *     0 <= K <= 1; the output is never NaN and is exactly the Kalman
 *     estimate minus the offset (no uninitialised value can leak out);
 *   - both: 0 <= window count <= N, head < N, stability run >= 0;
 *   - fixed: held window codes and Dc stay in +-SIG_CODE_MAX, 0 < y <= 1.0
 *     (Q30), the Kalman estimate stays within the hull of x0 and the codes,
 *     and the output is exactly sat32(x - offset): it saturates, never wraps;
 *   - noise measured on the fly (noise_auto, steered): sigma stays within
 *     its floor and ceiling, never NaN, and the thresholds are exactly the
 *     multiples of sigma that sig_chain.h states (A0 >= 1 code when fixed);
 *     hold-off <= window, skip count <= 2 x SIG_CHAIN_NOISE_FROZEN_MAX. */
#include <stdlib.h>

#include "fuzz_input.h"
#include "sig_chain.h"

#define REQUIRE(cond) do { if (!(cond)) abort(); } while (0)

/* A chain init that refuses its parameters must say SIG_ERR_ARG and leave
 * the (poisoned) state byte for byte as it was; the harness then stops. */
#define INIT_OR_STOP(chain, before, init_call) do {                        \
        sig_status init_st;                                                \
        memset(&(chain), 0x77, sizeof (chain));                            \
        (before) = (chain);                                                \
        init_st = (init_call);                                             \
        if (init_st != SIG_OK) {                                           \
            REQUIRE(init_st == SIG_ERR_ARG                                 \
                    && memcmp(&(chain), &(before), sizeof (chain)) == 0);  \
            return;                                                        \
        }                                                                  \
    } while (0)

static int not_nan(sig_real x) { return x == x; }

static void check_noise_f(const sig_chain_f *c)
{
    sig_real s = c->noise.sigma;
    if (!c->noise_auto) return;
    REQUIRE(not_nan(s) && s >= SIG_NOISE_FLOOR_ABS && s <= SIG_NOISE_MAX_F);
    REQUIRE(c->limit.a0 == SIG_REAL(6.0) * (c->noise.count == 0u ? SIG_NOISE_MAX_F : s));
    REQUIRE(c->motion_band == SIG_REAL(1.5) * s);
    REQUIRE(c->st.step == SIG_REAL(0.25) * s && c->zero_band == s);
    REQUIRE(c->zero_rate == SIG_REAL(0.0625) * s);
    REQUIRE(c->gate.holdoff <= c->ap.n && c->gate.frozen <= 2u * SIG_CHAIN_NOISE_FROZEN_MAX);
}

static void check_noise_q(const sig_chain_q *c)
{
    int32_t s = c->noise.sigma;
    if (!c->noise_auto) return;
    REQUIRE(s >= SIG_NOISE_FLOOR_Q7 && s <= SIG_NOISE_MAX_Q7);
    REQUIRE(c->noise.count == 0u ? c->limit.a0 == 2 * SIG_CODE_MAX
            : c->limit.a0 == (((int64_t)s * 6 + 64) >> 7 > 0 ? ((int64_t)s * 6 + 64) >> 7 : 1));
    REQUIRE(c->motion_band == s + s / 2 && c->st.step == s / 4 && c->zero_band == s && c->zero_rate == s / 16);
    REQUIRE(c->gate.holdoff <= c->ap.n && c->gate.frozen <= 2u * SIG_CHAIN_NOISE_FROZEN_MAX);
    REQUIRE(!c->noise.has_prev || (c->noise.prev >= -SIG_CODE_MAX && c->noise.prev <= SIG_CODE_MAX));
}

static void check_f(const sig_chain_f *c)
{
    check_noise_f(c);
    REQUIRE(c->ap.count <= c->ap.n && c->ap.head < c->ap.n);
    REQUIRE(not_nan(c->kf.x) && not_nan(c->kf.p) && not_nan(c->kf.k));
    REQUIRE(c->kf.p >= 0 && c->kf.k >= 0 && c->kf.k <= 1);
    REQUIRE(not_nan(c->limit.dc) && not_nan(c->offset) && not_nan(c->zero) && not_nan(c->out));
}

static void check_q(const sig_chain_q *c, int32_t x0)
{
    unsigned i;
    int64_t hull = (int64_t)SIG_CODE_MAX * 128, ax0 = x0 < 0 ? -(int64_t)x0 : x0;
    if (ax0 > hull) hull = ax0;
    check_noise_q(c);
    REQUIRE(c->ap.count <= c->ap.n && c->ap.head < c->ap.n);
    for (i = 0; i < c->ap.count; i++) REQUIRE(c->ap.buf[i] >= -SIG_CODE_MAX && c->ap.buf[i] <= SIG_CODE_MAX);
    REQUIRE(!c->limit.t.seeded || (c->limit.dc >= -SIG_CODE_MAX && c->limit.dc <= SIG_CODE_MAX));
    REQUIRE(c->kf.y > 0 && c->kf.y <= UINT32_C(1073741824) && c->kf.phase <= 3);
    REQUIRE((int64_t)c->kf.x <= hull + 1 && (int64_t)c->kf.x >= -hull - 1);
}

static void fuzz_float(fuzz_input *in)
{
    sig_chain_params_f p;
    sig_chain_f c, before;
    uint8_t steer = fuzz_u8(in);
    sig_real scale = 1;
    sig_status st;
    int seeded_any = 0, n;

    (void)sig_chain_params_paper_f(&p);
    if (steer & 1u) {
        /* paper parameters with a few switched on, at a fuzzed scale */
        scale = (sig_real)(1u + fuzz_u16(in)) / 64;
        p.a0 *= scale;
        p.window = (uint8_t)(3u + fuzz_u8(in) % 30u);
        p.stable_count = (uint8_t)(1u + fuzz_u8(in) % 4u);
        p.lockout_n = fuzz_u8(in) % 5u;
        p.motion_band = (fuzz_u8(in) & 1u) ? scale / 2 : 0;
        p.zero_band = (fuzz_u8(in) & 1u) ? scale / 100 : 0;
        p.zero_rate = p.zero_band / 10;
        p.seed_first = (fuzz_u8(in) & 1u) != 0;
    } else {
        p.a0 = fuzz_real(in); p.window = fuzz_u8(in);
        p.q = fuzz_real(in); p.r = fuzz_real(in); p.p0 = fuzz_real(in); p.x0 = fuzz_real(in);
        p.seed_first = (fuzz_u8(in) & 1u) != 0;
        p.stable_step = fuzz_real(in); p.stable_count = fuzz_u8(in); p.lockout_n = fuzz_u8(in);
        p.motion_band = fuzz_real(in); p.motion_count = fuzz_u8(in);
        p.zero_band = fuzz_real(in); p.zero_rate = fuzz_real(in);
    }
    p.noise_auto = (steer & 4u) != 0;
    INIT_OR_STOP(c, before, sig_chain_init_f(&c, &p));
    check_f(&c);
    for (n = 0; n < 4096 && fuzz_left(in) > 0; n++) {
        uint8_t op = fuzz_u8(in);
        sig_real x, out = (sig_real)-999;
        bool stable = false;
        if (op >= 0xF0u) {
            switch (op & 3u) {
            case 0: REQUIRE(sig_chain_tare_f(&c) >= 0); break;
            case 1: {
                sig_real off = fuzz_real(in);
                before = c;
                st = sig_chain_set_offset_f(&c, off);
                if (off - off != 0) REQUIRE(st == SIG_ERR_ARG && memcmp(&c, &before, sizeof c) == 0);
                else REQUIRE(st == SIG_OK && c.offset == off);
                break;
            }
            case 2: REQUIRE(sig_chain_reset_f(&c) == SIG_OK); seeded_any = 0; break;
            default:
                before = c;
                REQUIRE(sig_chain_step_f(&c, 0, NULL, &stable) == SIG_ERR_ARG);
                REQUIRE(memcmp(&c, &before, sizeof c) == 0);
            }
            check_f(&c);
            continue;
        }
        x = (steer & 2u) && (op & 1u) ? fuzz_real(in) : (sig_real)fuzz_i16(in) * scale / 256;
        before = c;
        st = sig_chain_step_f(&c, x, &out, &stable);
        if (st < 0) {
            REQUIRE(st == SIG_ERR_NONFINITE && !seeded_any && x - x != 0);
            REQUIRE(memcmp(&c, &before, sizeof c) == 0 && out == (sig_real)-999);
        } else {
            if (x - x == 0) seeded_any = 1;
            REQUIRE(not_nan(out) && out == c.out && out == c.kf.x - c.offset);
            if (x - x != 0) REQUIRE(st & SIG_WARN_REJECTED);
        }
        check_f(&c);
    }
}

static void fuzz_fixed(fuzz_input *in)
{
    sig_chain_params_q p;
    sig_chain_q c, before;
    uint8_t steer = fuzz_u8(in);
    sig_status st;
    int n;

    memset(&p, 0, sizeof p);
    if (steer & 1u) {
        p.a0 = 1 + (int32_t)(fuzz_u16(in)) * 64;
        p.window = (uint8_t)(3u + fuzz_u8(in) % 30u);
        p.q_q30 = fuzz_take_bits(in, 4) % (SIG_KALMAN1_Q_MAX + 1u);
        p.p0_q16 = fuzz_take_bits(in, 4) % (SIG_KALMAN1_P0_MAX + 1u);
        p.x0_q7 = fuzz_i32_edgy(in);
        p.seed_first = (fuzz_u8(in) & 1u) != 0;
        p.stable_step_q7 = fuzz_u16(in);
        p.stable_count = (uint8_t)(1u + fuzz_u8(in) % 4u);
        p.lockout_n = fuzz_u8(in) % 5u;
        p.motion_band_q7 = (int32_t)fuzz_u16(in) * ((fuzz_u8(in) & 1u) ? 256 : 0);
        p.motion_count = (uint8_t)(1u + fuzz_u8(in) % 4u);
        p.zero_band_q7 = (fuzz_u8(in) & 1u) ? (int32_t)fuzz_u16(in) : 0;
        p.zero_rate_q7 = p.zero_band_q7 / 8;
    } else {
        p.a0 = fuzz_i32_edgy(in); p.window = fuzz_u8(in);
        p.q_q30 = fuzz_take_bits(in, 4); p.p0_q16 = fuzz_take_bits(in, 4); p.x0_q7 = fuzz_i32_edgy(in);
        p.seed_first = (fuzz_u8(in) & 1u) != 0;
        p.stable_step_q7 = fuzz_i32_edgy(in); p.stable_count = fuzz_u8(in); p.lockout_n = fuzz_u8(in);
        p.motion_band_q7 = fuzz_i32_edgy(in); p.motion_count = fuzz_u8(in);
        p.zero_band_q7 = fuzz_i32_edgy(in); p.zero_rate_q7 = fuzz_i32_edgy(in);
    }
    p.noise_auto = (steer & 4u) != 0;
    INIT_OR_STOP(c, before, sig_chain_init_q(&c, &p));
    check_q(&c, p.x0_q7);
    for (n = 0; n < 4096 && fuzz_left(in) > 0; n++) {
        uint8_t op = fuzz_u8(in);
        int32_t x, out = -999;
        bool stable = false;
        if (op >= 0xF0u) {
            switch (op & 3u) {
            case 0: REQUIRE(sig_chain_tare_q(&c) >= 0); break;
            case 1: REQUIRE(sig_chain_set_offset_q(&c, fuzz_i32_edgy(in)) == SIG_OK); break;
            case 2: REQUIRE(sig_chain_reset_q(&c) == SIG_OK); break;
            default:
                before = c;
                REQUIRE(sig_chain_step_q(&c, 0, &out, NULL) == SIG_ERR_ARG);
                REQUIRE(memcmp(&c, &before, sizeof c) == 0);
            }
            check_q(&c, p.x0_q7);
            continue;
        }
        x = (op & 1u) ? fuzz_i32_edgy(in) : (int32_t)fuzz_i16(in) * (int32_t)(1 + (steer >> 4));
        st = sig_chain_step_q(&c, x, &out, &stable);
        REQUIRE(st >= 0);
        REQUIRE(((st & SIG_WARN_CLAMPED) != 0) == (x > SIG_CODE_MAX || x < -SIG_CODE_MAX));
        {
            int64_t want = (int64_t)c.kf.x - c.offset;
            want = want > INT32_MAX ? INT32_MAX : want < INT32_MIN ? INT32_MIN : want;
            REQUIRE(out == want && out == c.out);
        }
        check_q(&c, p.x0_q7);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = fuzz_input_make(data, size);
    if (fuzz_u8(&in) & 1u) fuzz_float(&in);
    else fuzz_fixed(&in);
    return 0;
}
