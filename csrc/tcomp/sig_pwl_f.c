/* sig_pwl_f.c - piecewise-linear table with uniform knots, float form
 * (see sig_pwl.h). */
#include "sig_pwl.h"

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */

sig_status sig_pwl_init_f(sig_pwl_f *p, const sig_real *table, uint8_t n_knots,
                          sig_real t_lo, sig_real t_hi, sig_real inv_step)
{
    sig_real end_pos;
    if (p == NULL || table == NULL) return SIG_ERR_ARG;
    if (n_knots < SIG_PWL_MIN_KNOTS || !sig_real_isfinite(t_lo) || !sig_real_isfinite(t_hi)
        || !sig_real_isfinite(inv_step) || !(t_hi > t_lo) || !(inv_step > SIG_REAL(0.0)))
        return SIG_ERR_ARG;
    end_pos = (t_hi - t_lo) * inv_step;
    if (!sig_real_isfinite(end_pos) || end_pos < (sig_real)(n_knots - 2u)
        || end_pos > (sig_real)(n_knots - 1u) * SIG_REAL(1.0001)) return SIG_ERR_ARG;
    if (!sig_real_all_finite(table, n_knots)) return SIG_ERR_NONFINITE;
    p->table = table;
    p->t_lo = t_lo;
    p->t_hi = t_hi;
    p->inv_step = inv_step;
    p->n_knots = n_knots;
    return SIG_OK;
}

sig_status sig_pwl_eval_f(const sig_pwl_f *p, sig_real t, sig_real *out)
{
    sig_status st;
    sig_real pos, lo, hi, frac, y;
    int32_t seg;
    if (p == NULL || out == NULL || p->table == NULL) return SIG_ERR_ARG;
    if (sig_real_isnan(t)) return SIG_ERR_NONFINITE;
    st = sig_clamp_real(&t, p->t_lo, p->t_hi);
    pos = (t - p->t_lo) * p->inv_step;
    seg = (int32_t)pos;                      /* pos >= 0: truncation is floor */
    if (seg >= (int32_t)(p->n_knots - 1u)) {
        *out = p->table[p->n_knots - 1u];
    } else {
        /* (1-f)*lo + f*hi cannot overflow (hi - lo can); the clamp keeps a
         * last-bit rounding from stepping outside the two knots. */
        lo = p->table[seg];
        hi = p->table[seg + 1];
        frac = pos - (sig_real)seg;
        y = (SIG_REAL(1.0) - frac) * lo + frac * hi;
        if (y < (lo < hi ? lo : hi)) y = lo < hi ? lo : hi;
        if (y > (lo < hi ? hi : lo)) y = lo < hi ? hi : lo;
        *out = y;
    }
    return st;
}
#endif /* SIG_NO_FLOAT */
