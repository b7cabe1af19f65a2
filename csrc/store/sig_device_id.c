/* sig_device_id.c - device ids of serial numbers and the image check
 * (format in sig_device_id.h). */
#include "sig_device_id.h"
#include "sig_image.h"

#define FNV32_OFFSET UINT32_C(2166136261)

/* h * 16777619 (the FNV-1a 32-bit prime, 2^24 + 403) modulo 2^32, written
 * as a shift and a small multiply so no 16-bit-int promotion can bite. */
static uint32_t fnv32_mul(uint32_t h)
{
    return (uint32_t)((h << 24) + h * UINT32_C(403));
}

sig_status sig_device_id_make(sig_device_id *out, const uint8_t *serial, size_t len)
{
    uint32_t h = FNV32_OFFSET;
    size_t i;
    uint8_t k;
    if (out == NULL || serial == NULL || len == 0u) return SIG_ERR_ARG;
    if (len <= (size_t)SIG_DEVICE_ID_MAX_LEN) {
        out->kind = (uint8_t)SIG_DEVICE_ID_VERBATIM;
        out->len = (uint8_t)len;
        for (k = 0u; k < (uint8_t)len; k++) out->id[k] = serial[k];
        return SIG_OK;
    }
    for (i = 0u; i < len; i++) h = fnv32_mul(h ^ (uint32_t)serial[i]);
    out->kind = (uint8_t)SIG_DEVICE_ID_HASHED;
    out->len = (uint8_t)SIG_DEVICE_ID_MAX_LEN;
    for (k = 0u; k < 4u; k++) out->id[k] = (uint8_t)((h >> (8u * k)) & 0xFFu);
    for (k = 0u; k < (uint8_t)SIG_DEVICE_ID_TAIL_LEN; k++)
        out->id[4u + k] = serial[len - (size_t)SIG_DEVICE_ID_TAIL_LEN + (size_t)k];
    return SIG_OK;
}

sig_status sig_device_id_check_image(const uint8_t *buf, size_t len, const sig_device_id *expected)
{
    const uint8_t *p = NULL;
    uint16_t plen = 0u;
    uint8_t k;
    sig_status st;
    if (buf == NULL || expected == NULL) return SIG_ERR_ARG;
    st = sig_image_find_section(buf, len, (uint16_t)SIG_SECTION_DEVICE_ID, &p, &plen);
    if (st == SIG_ERR_EMPTY) return SIG_ERR_DEVICE;
    if (st != SIG_OK) return st;
    if (plen < SIG_DEVICE_ID_HDR_LEN || p[0] > SIG_DEVICE_ID_HASHED || p[1] == 0u ||
        p[1] > SIG_DEVICE_ID_MAX_LEN || plen != (uint16_t)(SIG_DEVICE_ID_HDR_LEN + p[1]))
        return SIG_ERR_FORMAT;
    if (p[0] != expected->kind || p[1] != expected->len) return SIG_ERR_DEVICE;
    for (k = 0u; k < p[1]; k++)
        if (p[SIG_DEVICE_ID_HDR_LEN + k] != expected->id[k]) return SIG_ERR_DEVICE;
    return SIG_OK;
}
