/* test_device_id.c - the device-id check in C: an image made for device A
 * is taken by A and refused by B with SIG_ERR_DEVICE; an image with no id is
 * refused; long serials are hashed and still told apart; a malformed id
 * section is SIG_ERR_FORMAT; a corrupt image keeps its validation status. */
#include <string.h>

#include "check.h"
#include "sig_crc16.h"
#include "sig_device_id.h"
#include "sig_image.h"

static void put16(uint8_t *p, uint32_t v) { p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); }

/* An image holding one section (type, payload); returns its length. */
static size_t build(uint8_t *img, uint16_t type, const uint8_t *payload, uint16_t plen)
{
    size_t total = SIG_IMAGE_HEADER_LEN + SIG_IMAGE_SECTION_HDR_LEN + plen + SIG_IMAGE_CRC_LEN;
    memcpy(img, "psig", 4);
    img[4] = SIG_IMAGE_VERSION;
    img[5] = 0;
    put16(img + 6, (uint32_t)total);
    memset(img + 8, 0, 4);
    put16(img + 12, type);
    put16(img + 14, plen);
    memcpy(img + 16, payload, plen);
    put16(img + total - 2, sig_crc16_ccitt(SIG_CRC16_INIT, img, total - 2));
    return total;
}

/* An image whose device-id section names `serial`. */
static size_t image_for(uint8_t *img, const char *serial)
{
    sig_device_id id;
    uint8_t payload[2 + SIG_DEVICE_ID_MAX_LEN];
    CHECK_EQ_I(sig_device_id_make(&id, (const uint8_t *)serial, strlen(serial)), SIG_OK);
    payload[0] = id.kind;
    payload[1] = id.len;
    memcpy(payload + 2, id.id, id.len);
    return build(img, SIG_SECTION_DEVICE_ID, payload, (uint16_t)(2u + id.len));
}

static sig_status check_on(const uint8_t *img, size_t len, const char *serial)
{
    sig_device_id id;
    CHECK_EQ_I(sig_device_id_make(&id, (const uint8_t *)serial, strlen(serial)), SIG_OK);
    return sig_device_id_check_image(img, len, &id);
}

int main(void)
{
    uint8_t img[64], other[64];
    const char *long_a = "FACTORY-7/LINE-3/2026-11-23/BOARD-000000123456";
    const char *long_b = "FACTORY-7/LINE-3/2026-11-23/BOARD-000000123457";
    const char *long_c = "FACTORY-8/LINE-3/2026-11-23/BOARD-000000123456";   /* same tail as long_a */
    sig_device_id id, untouched;
    size_t n = image_for(img, "SN-A-0001");
    uint8_t bad_payload[4] = {0u, 3u, 'a', 'b'};
    uint8_t zero = 0u;

    CHECK_EQ_I(sig_image_validate(img, n), SIG_OK);
    CHECK_EQ_I(check_on(img, n, "SN-A-0001"), SIG_OK);
    CHECK_EQ_I(check_on(img, n, "SN-B-0002"), SIG_ERR_DEVICE);
    CHECK_EQ_I(check_on(img, n, "SN-A-000"), SIG_ERR_DEVICE);          /* a prefix is another device */

    n = image_for(img, long_a);
    CHECK_EQ_I(check_on(img, n, long_a), SIG_OK);
    CHECK_EQ_I(check_on(img, n, long_b), SIG_ERR_DEVICE);
    CHECK_EQ_I(check_on(img, n, long_c), SIG_ERR_DEVICE);               /* the hash tells them apart */
    CHECK_EQ_I(sig_device_id_make(&id, (const uint8_t *)long_a, strlen(long_a)), SIG_OK);
    CHECK_EQ_I(id.kind, SIG_DEVICE_ID_HASHED);
    CHECK_EQ_I(id.len, SIG_DEVICE_ID_MAX_LEN);
    CHECK(memcmp(id.id + 4, long_a + strlen(long_a) - 12u, 12u) == 0);

    /* FNV-1a 32 of 17 x 'a' is 0x1509BA9C (check value from spec.device_id), little-endian */
    {
        uint8_t seventeen[17];
        memset(seventeen, 'a', sizeof seventeen);
        CHECK_EQ_I(sig_device_id_make(&id, seventeen, sizeof seventeen), SIG_OK);
        CHECK_EQ_I(id.kind, SIG_DEVICE_ID_HASHED);
        CHECK_EQ_I(id.id[0], 0x9C); CHECK_EQ_I(id.id[1], 0xBA); CHECK_EQ_I(id.id[2], 0x09); CHECK_EQ_I(id.id[3], 0x15);
        CHECK_EQ_I(id.id[4], 'a'); CHECK_EQ_I(id.id[15], 'a');
    }

    /* an image nobody addressed: refused */
    n = build(other, SIG_SECTION_OFFSET_POLY, bad_payload, 4u);
    CHECK_EQ_I(check_on(other, n, "SN-A-0001"), SIG_ERR_DEVICE);
    /* a malformed id section: length disagrees with n */
    n = build(other, SIG_SECTION_DEVICE_ID, bad_payload, 4u);
    CHECK_EQ_I(check_on(other, n, "SN-A-0001"), SIG_ERR_FORMAT);
    /* a corrupt image keeps its own status */
    n = image_for(img, "SN-A-0001");
    img[20] ^= 1u;
    CHECK_EQ_I(check_on(img, n, "SN-A-0001"), SIG_ERR_CRC);

    /* bad arguments leave the output untouched */
    memset(&untouched, 0x5A, sizeof untouched);
    id = untouched;
    CHECK_EQ_I(sig_device_id_make(&id, &zero, 0u), SIG_ERR_ARG);
    CHECK(memcmp(&id, &untouched, sizeof id) == 0);
    CHECK_EQ_I(sig_device_id_make(NULL, &zero, 1u), SIG_ERR_ARG);
    CHECK_EQ_I(sig_device_id_check_image(NULL, 10u, &id), SIG_ERR_ARG);
    CHECK_EQ_I(sig_device_id_check_image(img, n, NULL), SIG_ERR_ARG);
    return check_report("test_device_id");
}
