/* sig_tmodel_image.c - load any temperature model from a coefficient image
 * (sig_tmodel.h); separate from the evaluator so firmware with a built-in
 * model links none of the image code. */
#include "sig_tmodel.h"
#include "sig_image.h"

static sig_status load_code_kind(const uint8_t *image, size_t len, uint8_t *kind)
{
    const uint8_t *p = NULL;
    uint16_t plen = 0u;
    sig_status st = sig_image_find_section(image, len, SIG_SECTION_TEMP_CODE, &p, &plen);
    if (st == SIG_ERR_EMPTY) {
        *kind = SIG_TCODE_INT16;
        return SIG_OK;
    }
    if (st != SIG_OK) return st;
    if (plen != SIG_TEMP_CODE_LEN || p[1] != 0u || p[0] > SIG_TCODE_UINT16) return SIG_ERR_FORMAT;
    *kind = p[0];
    return SIG_OK;
}

sig_status sig_tmodel_load_image(sig_tmodel *m, int16_t *storage, uint16_t storage_len,
                                 const uint8_t *image, size_t len)
{
    sig_tmodel tmp;
    const uint8_t *p = NULL;
    uint16_t plen = 0u;
    sig_status st;
    if (m == NULL || image == NULL) return SIG_ERR_ARG;
    st = load_code_kind(image, len, &tmp.code_kind);
    if (st != SIG_OK) return st;
    if (sig_image_find_section(image, len, SIG_SECTION_COMPACT_POLY, &p, &plen) == SIG_OK) {
        st = sig_tcomp16_load_image(&tmp.m.compact, image, len);
        if (st != SIG_OK) return st;
        tmp.family = SIG_TMODEL_COMPACT;
        tmp.n_axes = tmp.m.compact.n_axes;
    } else if (sig_image_find_section(image, len, SIG_SECTION_OFFSET_POLY, &p, &plen) == SIG_OK) {
        st = sig_tcomp_load_image(&tmp.m.poly, image, len);
        if (st != SIG_OK) return st;
        tmp.family = SIG_TMODEL_POLY;
        tmp.n_axes = tmp.m.poly.n_axes;
    } else {
        if (storage == NULL) return SIG_ERR_ARG;
        st = sig_pwl_load_image(tmp.m.table, (uint8_t)SIG_PWL_MAX_AXES, &tmp.n_axes,
                                storage, storage_len, image, len);
        if (st != SIG_OK) return st;
        tmp.family = SIG_TMODEL_TABLE;
    }
    *m = tmp;
    return SIG_OK;
}
