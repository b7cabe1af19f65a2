/* sig_pwl_image.c - load piecewise-linear tables from a coefficient image
 * (payload of SIG_SECTION_PWL_TABLE: see sig_pwl.h). */
#include "sig_pwl.h"
#include "sig_image.h"

sig_status sig_pwl_load_image(sig_pwl_q16 *tables, uint8_t max_axes, uint8_t *n_axes,
                              int16_t *storage, uint16_t storage_len,
                              const uint8_t *image, size_t len)
{
    const uint8_t *pay = NULL;
    uint16_t pay_len = 0u, k, stride;
    uint8_t axes, knots, a;
    int16_t t_lo, t_hi;
    uint32_t recip;
    sig_pwl_q16 check;
    sig_status st;
    if (tables == NULL || n_axes == NULL || storage == NULL || image == NULL) return SIG_ERR_ARG;
    st = sig_image_find_section(image, len, SIG_SECTION_PWL_TABLE, &pay, &pay_len);
    if (st != SIG_OK) return st;
    if (pay_len < SIG_PWL_IMAGE_FIXED_LEN) return SIG_ERR_FORMAT;
    axes = pay[0];
    knots = pay[1];
    if (axes < 1u || axes > SIG_PWL_MAX_AXES || knots < SIG_PWL_MIN_KNOTS) return SIG_ERR_FORMAT;
    stride = (uint16_t)(1u + 2u * (uint16_t)knots);
    if ((uint32_t)pay_len != (uint32_t)SIG_PWL_IMAGE_FIXED_LEN + (uint32_t)axes * stride)
        return SIG_ERR_FORMAT;
    if (axes > max_axes || (uint32_t)axes * knots > storage_len) return SIG_ERR_ARG;
    t_lo = sig_image_get_i16(pay + 2);
    t_hi = sig_image_get_i16(pay + 4);
    recip = sig_image_get_u32(pay + 6);
    for (a = 0u; a < axes; ++a) {     /* check everything before writing anything */
        st = sig_pwl_init_q16(&check, storage, knots, t_lo, t_hi, recip,
                              pay[SIG_PWL_IMAGE_FIXED_LEN + (uint16_t)a * stride]);
        if (st != SIG_OK) return SIG_ERR_FORMAT;
    }
    for (a = 0u; a < axes; ++a) {
        const uint8_t *src = pay + SIG_PWL_IMAGE_FIXED_LEN + (uint16_t)a * stride;
        int16_t *dst = storage + (uint16_t)a * knots;
        for (k = 0u; k < knots; ++k) dst[k] = sig_image_get_i16(src + 1u + 2u * k);
        (void)sig_pwl_init_q16(&tables[a], dst, knots, t_lo, t_hi, recip, src[0]);
    }
    *n_axes = axes;
    return SIG_OK;
}
