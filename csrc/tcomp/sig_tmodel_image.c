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
    /* Each family's loader writes its part of m->m only on success, so no
     * copy of the model is needed (the 8051's stack holds ~200 bytes). */
    const uint8_t *p = NULL;
    uint16_t plen = 0u;
    uint8_t kind = 0u, family, n_axes = 0u;   /* set by load_code_kind; gcc-avr 5 cannot see it */
    sig_status st;
    if (m == NULL || image == NULL) return SIG_ERR_ARG;
    st = load_code_kind(image, len, &kind);
    if (st != SIG_OK) return st;
    if (sig_image_find_section(image, len, SIG_SECTION_COMPACT_POLY, &p, &plen) == SIG_OK) {
        st = sig_tcomp16_load_image(&m->m.compact, image, len);
        family = SIG_TMODEL_COMPACT;
        if (st == SIG_OK) n_axes = m->m.compact.n_axes;
    } else if (sig_image_find_section(image, len, SIG_SECTION_OFFSET_POLY, &p, &plen) == SIG_OK) {
        st = sig_tcomp_load_image(&m->m.poly, image, len);
        family = SIG_TMODEL_POLY;
        if (st == SIG_OK) n_axes = m->m.poly.n_axes;
    } else {
        if (storage == NULL) return SIG_ERR_ARG;
        st = sig_pwl_load_image(m->m.table, (uint8_t)SIG_PWL_MAX_AXES, &n_axes,
                                storage, storage_len, image, len);
        family = SIG_TMODEL_TABLE;
    }
    if (st != SIG_OK) return st;
    m->family = family;
    m->code_kind = kind;
    m->n_axes = n_axes;
    return SIG_OK;
}
