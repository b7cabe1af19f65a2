/* fuzz_device_id.c - the device-id check (sig_device_id) with arbitrary
 * serials and arbitrary device-id sections.
 *
 * Input: u8 serial length s, s bytes of serial (the device the firmware runs
 * on), then the payload of a device-id section; the image around it is well
 * framed (header, one section, CRC), so the check sees any payload.  Both
 * the image and the serial are copied into heap buffers of exactly their
 * length, so a read past the end is an AddressSanitizer report.  Invariants:
 *   - sig_device_id_make accepts every serial of 1+ bytes, its id has 1..16
 *     bytes, and equals the serial when the serial has at most 16;
 *   - the check returns SIG_OK, SIG_ERR_DEVICE or SIG_ERR_FORMAT only;
 *   - SIG_OK exactly when the payload is kind, n, id of the device itself;
 *   - an image built from the device's own id is always accepted, and from
 *     the fuzzed serial with its last byte changed, refused. */
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "sig_crc16.h"
#include "sig_device_id.h"
#include "sig_image.h"

#define REQUIRE(cond) do { if (!(cond)) abort(); } while (0)

static void put16(uint8_t *p, size_t v) { p[0] = (uint8_t)(v & 0xFFu); p[1] = (uint8_t)((v >> 8) & 0xFFu); }

/* A heap image holding one device-id section with `payload`; *len its size. */
static uint8_t *image_with(const uint8_t *payload, size_t plen, size_t *len)
{
    size_t total = SIG_IMAGE_HEADER_LEN + SIG_IMAGE_SECTION_HDR_LEN + plen + SIG_IMAGE_CRC_LEN;
    uint8_t *img = malloc(total);
    REQUIRE(img != NULL);
    memcpy(img, "psig", 4);
    img[4] = SIG_IMAGE_VERSION;
    img[5] = 0;
    put16(img + 6, total);
    memset(img + 8, 0, 4);
    put16(img + 12, SIG_SECTION_DEVICE_ID);
    put16(img + 14, plen);
    if (plen) memcpy(img + 16, payload, plen);
    put16(img + total - 2, sig_crc16_ccitt(SIG_CRC16_INIT, img, total - 2));
    *len = total;
    return img;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = fuzz_input_make(data, size);
    size_t s = fuzz_u8(&in), plen, len;
    uint8_t *serial, *img, own[2 + SIG_DEVICE_ID_MAX_LEN];
    sig_device_id id;
    sig_status st;
    bool same;
    if (s == 0u || fuzz_left(&in) < s) return 0;
    serial = malloc(s);
    REQUIRE(serial != NULL);
    memcpy(serial, data + in.pos, s);
    in.pos += s;
    plen = fuzz_left(&in);
    if (plen > 64u) plen = 64u;

    REQUIRE(sig_device_id_make(&id, serial, s) == SIG_OK);
    REQUIRE(id.len >= 1u && id.len <= SIG_DEVICE_ID_MAX_LEN);
    if (s <= SIG_DEVICE_ID_MAX_LEN) REQUIRE(id.kind == SIG_DEVICE_ID_VERBATIM && id.len == s &&
                                            memcmp(id.id, serial, s) == 0);

    img = image_with(data + in.pos, plen, &len);
    st = sig_device_id_check_image(img, len, &id);
    REQUIRE(st == SIG_OK || st == SIG_ERR_DEVICE || st == SIG_ERR_FORMAT);
    same = plen == 2u + id.len && data[in.pos] == id.kind && data[in.pos + 1] == id.len &&
           memcmp(data + in.pos + 2, id.id, id.len) == 0;
    REQUIRE((st == SIG_OK) == same);
    free(img);

    own[0] = id.kind;
    own[1] = id.len;
    memcpy(own + 2, id.id, id.len);
    img = image_with(own, 2u + id.len, &len);
    REQUIRE(sig_device_id_check_image(img, len, &id) == SIG_OK);
    serial[s - 1] ^= 0x01u;
    REQUIRE(sig_device_id_make(&id, serial, s) == SIG_OK);
    REQUIRE(sig_device_id_check_image(img, len, &id) == SIG_ERR_DEVICE);
    free(img);
    free(serial);
    return 0;
}
