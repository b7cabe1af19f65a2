/* sig_tcomp16_image.c - the compact model (sig_tcomp16.h) from a coefficient
 * image (sig_image.h, section SIG_SECTION_COMPACT_POLY).  Apart from
 * sig_tcomp16.c so firmware that does not read images links none of this. */
#include "sig_tcomp16.h"
#include "sig_image.h"

sig_status sig_tcomp16_load_image(sig_tcomp16_q *m, const uint8_t *image, size_t len)
{
    const uint8_t *p;
    uint16_t plen, pos;
    uint8_t n_axes, order, a, k;
    int16_t top[SIG_TCOMP16_MAX_AXES];
    int32_t add[SIG_TCOMP16_MAX_AXES * SIG_TCOMP16_MAX_ORDER];
    sig_status st;
    if (m == NULL) return SIG_ERR_ARG;
    st = sig_image_find_section(image, len, SIG_SECTION_COMPACT_POLY, &p, &plen);
    if (st != SIG_OK) return st;
    if (plen < SIG_COMPACT_POLY_FIXED_LEN) return SIG_ERR_FORMAT;
    n_axes = p[0];
    order = p[1];
    if (n_axes < 1u || n_axes > SIG_TCOMP16_MAX_AXES || order < SIG_TCOMP16_MIN_ORDER ||
        order > SIG_TCOMP16_MAX_ORDER || p[3] != 0u)
        return SIG_ERR_FORMAT;
    if (plen != (uint16_t)(SIG_COMPACT_POLY_FIXED_LEN +
                           (uint16_t)n_axes * (uint16_t)(2u + 4u * (uint16_t)order)))
        return SIG_ERR_FORMAT;
    pos = SIG_COMPACT_POLY_FIXED_LEN;
    for (a = 0; a < n_axes; a++) {
        top[a] = sig_image_get_i16(p + pos);
        pos = (uint16_t)(pos + 2u);
        for (k = 0; k < order; k++) {
            add[(uint16_t)a * order + k] = sig_image_get_i32(p + pos);
            pos = (uint16_t)(pos + 4u);
        }
    }
    /* init checks ranges and the no-overflow bound, and writes *m only on success */
    st = sig_tcomp16_init(m, n_axes, order, top, add,
                          sig_image_get_i16(p + 4), sig_image_get_i16(p + 6), p[2]);
    return st == SIG_ERR_ARG ? SIG_ERR_FORMAT : st;
}
