/* sig_image.c - coefficient image validation, section lookup and A/B slot
 * selection (format in sig_image.h). */
#include "sig_image.h"
#include "sig_crc16.h"

uint16_t sig_image_get_u16(const uint8_t *p)
{
    return (uint16_t)((uint16_t)p[0] | (uint16_t)((uint16_t)p[1] << 8));
}

int16_t sig_image_get_i16(const uint8_t *p)
{
    uint16_t v = sig_image_get_u16(p);
    /* two's complement without implementation-defined conversion */
    return v >= 0x8000u ? (int16_t)(-(int32_t)(0x10000L - (int32_t)v)) : (int16_t)v;
}

uint32_t sig_image_get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

int32_t sig_image_get_i32(const uint8_t *p)
{
    uint32_t v = sig_image_get_u32(p);
    if (v < UINT32_C(0x80000000)) return (int32_t)v;
    /* v - 2^32 = -(2^32 - v) = -((~v) + 1), computed without overflow */
    return -(int32_t)(~v) - 1;
}

sig_status sig_image_validate(const uint8_t *buf, size_t len)
{
    uint16_t total, end, pos, plen, type;
    if (buf == NULL) return SIG_ERR_ARG;
    if (len < SIG_IMAGE_MIN_LEN) return SIG_ERR_FORMAT;
    if (buf[0] != SIG_IMAGE_MAGIC0 || buf[1] != SIG_IMAGE_MAGIC1 ||
        buf[2] != SIG_IMAGE_MAGIC2 || buf[3] != SIG_IMAGE_MAGIC3)
        return SIG_ERR_FORMAT;
    if (buf[4] != SIG_IMAGE_VERSION || buf[5] != 0u) return SIG_ERR_FORMAT;
    total = sig_image_get_u16(buf + 6);
    if (total < SIG_IMAGE_MIN_LEN || (size_t)total > len) return SIG_ERR_FORMAT;
    end = (uint16_t)(total - SIG_IMAGE_CRC_LEN);
    if (sig_crc16_ccitt(SIG_CRC16_INIT, buf, end) != sig_image_get_u16(buf + end))
        return SIG_ERR_CRC;
    pos = SIG_IMAGE_HEADER_LEN;
    while (pos < end) {
        if ((uint16_t)(end - pos) < SIG_IMAGE_SECTION_HDR_LEN) return SIG_ERR_FORMAT;
        type = sig_image_get_u16(buf + pos);
        plen = sig_image_get_u16(buf + pos + 2u);
        if (type == SIG_SECTION_INVALID) return SIG_ERR_FORMAT;
        pos = (uint16_t)(pos + SIG_IMAGE_SECTION_HDR_LEN);
        if (plen > (uint16_t)(end - pos)) return SIG_ERR_FORMAT;
        pos = (uint16_t)(pos + plen);
    }
    return SIG_OK;
}

sig_status sig_image_sequence(const uint8_t *buf, size_t len, uint32_t *seq)
{
    sig_status st;
    if (seq == NULL) return SIG_ERR_ARG;
    st = sig_image_validate(buf, len);
    if (st != SIG_OK) return st;
    *seq = sig_image_get_u32(buf + 8);
    return SIG_OK;
}

sig_status sig_image_find_section(const uint8_t *buf, size_t len, uint16_t type,
                                  const uint8_t **payload, uint16_t *payload_len)
{
    sig_status st;
    uint16_t end, pos, plen;
    if (payload == NULL || payload_len == NULL || type == SIG_SECTION_INVALID) return SIG_ERR_ARG;
    st = sig_image_validate(buf, len);
    if (st != SIG_OK) return st;
    end = (uint16_t)(sig_image_get_u16(buf + 6) - SIG_IMAGE_CRC_LEN);
    pos = SIG_IMAGE_HEADER_LEN;
    while (pos < end) {            /* validated: every section lies inside */
        plen = sig_image_get_u16(buf + pos + 2u);
        if (sig_image_get_u16(buf + pos) == type) {
            *payload = buf + pos + SIG_IMAGE_SECTION_HDR_LEN;
            *payload_len = plen;
            return SIG_OK;
        }
        pos = (uint16_t)(pos + SIG_IMAGE_SECTION_HDR_LEN + plen);
    }
    return SIG_ERR_EMPTY;
}

sig_status sig_image_select_slot(const uint8_t *slot_a, size_t len_a,
                                 const uint8_t *slot_b, size_t len_b, uint8_t *which)
{
    uint32_t seq_a = 0, seq_b = 0, diff;
    bool ok_a, ok_b;
    if (which == NULL) return SIG_ERR_ARG;
    ok_a = slot_a != NULL && sig_image_sequence(slot_a, len_a, &seq_a) == SIG_OK;
    ok_b = slot_b != NULL && sig_image_sequence(slot_b, len_b, &seq_b) == SIG_OK;
    if (!ok_a && !ok_b) return SIG_ERR_EMPTY;
    if (ok_a && ok_b) {
        diff = seq_b - seq_a;
        *which = (diff != 0u && diff < UINT32_C(0x80000000)) ? SIG_IMAGE_SLOT_B : SIG_IMAGE_SLOT_A;
    } else {
        *which = ok_a ? SIG_IMAGE_SLOT_A : SIG_IMAGE_SLOT_B;
    }
    return SIG_OK;
}
