/* sig_tmodel.c - evaluate whichever temperature model was loaded (sig_tmodel.h). */
#include "sig_tmodel.h"

int16_t sig_tmodel_code_to_t(uint8_t code_kind, uint16_t code)
{
    if (code_kind == SIG_TCODE_UINT16) return (int16_t)((int32_t)code - INT32_C(32768));
    if (code > 0x7FFFu) return (int16_t)((int32_t)code - INT32_C(65536));
    return (int16_t)code;
}

/* floor(x / 2^16) for any int32 x: the high word of x + 2^31, unsigned. */
static int32_t floor_div_2p16(int32_t x)
{
    return (int32_t)(((uint32_t)x + UINT32_C(0x80000000)) >> 16) - INT32_C(32768);
}

static sig_status apply_tables(const sig_tmodel *m, int16_t t, const int16_t *in, int16_t *out)
{
    sig_status st = SIG_OK;
    int32_t v, corrected;
    uint8_t a;
    for (a = 0u; a < m->n_axes; a++) {
        st = (sig_status)(st | sig_pwl_eval_q16(&m->m.table[a], t, &v));
        corrected = (int32_t)in[a] - floor_div_2p16(v + INT32_C(32768));
        if (corrected > INT16_MAX || corrected < INT16_MIN) st = (sig_status)(st | SIG_WARN_SATURATED);
        out[a] = sig_sat16(corrected);
    }
    return st;
}

sig_status sig_tmodel_init_table(sig_tmodel *m, uint8_t n_axes, const int16_t *table, uint8_t n_knots,
                                 int16_t t_lo, int16_t t_hi, uint32_t recip, const uint8_t *value_frac,
                                 uint8_t code_kind)
{
    sig_pwl_q16 check;
    uint8_t a;
    if (m == NULL || table == NULL || value_frac == NULL) return SIG_ERR_ARG;
    if (n_axes < 1u || n_axes > SIG_PWL_MAX_AXES || code_kind > SIG_TCODE_UINT16) return SIG_ERR_ARG;
    for (a = 0u; a < n_axes; a++)       /* every axis checked before anything is written */
        if (sig_pwl_init_q16(&check, table, n_knots, t_lo, t_hi, recip, value_frac[a]) != SIG_OK)
            return SIG_ERR_ARG;
    for (a = 0u; a < n_axes; a++)
        (void)sig_pwl_init_q16(&m->m.table[a], table + (uint16_t)a * n_knots, n_knots, t_lo, t_hi,
                               recip, value_frac[a]);
    m->family = SIG_TMODEL_TABLE;
    m->code_kind = code_kind;
    m->n_axes = n_axes;
    return SIG_OK;
}

sig_status sig_tmodel_apply(const sig_tmodel *m, uint16_t code, const int16_t *in, int16_t *out)
{
    int16_t t;
    if (m == NULL || in == NULL || out == NULL) return SIG_ERR_ARG;
    t = sig_tmodel_code_to_t(m->code_kind, code);
    if (m->family == SIG_TMODEL_POLY) return sig_tcomp_apply_q(&m->m.poly, t, in, out);
    if (m->family == SIG_TMODEL_COMPACT) return sig_tcomp16_apply_q(&m->m.compact, t, in, out);
    if (m->family == SIG_TMODEL_TABLE) return apply_tables(m, t, in, out);
    return SIG_ERR_ARG;
}
