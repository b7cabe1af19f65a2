/* sig_device_id.h - which device a coefficient image belongs to.
 *
 * A production line calibrates every unit and writes each one its own image;
 * flashing one unit's image into another is the classic mistake.  The image
 * carries a SIG_SECTION_DEVICE_ID section with the unit's id, and the loader,
 * given the id of the device it runs on, refuses an image made for another
 * with SIG_ERR_DEVICE (the image itself is valid; it is just not ours).
 *
 * The id of a serial number (any bytes, at least one):
 *   - a serial of at most SIG_DEVICE_ID_MAX_LEN (16) bytes is its own id
 *     (kind SIG_DEVICE_ID_VERBATIM);
 *   - a longer one becomes 16 bytes (kind SIG_DEVICE_ID_HASHED): the 32-bit
 *     FNV-1a hash of the whole serial, little-endian, then its last 12 bytes
 *     (the running number usually sits at the end, so ids stay readable and
 *     two serials must agree on both parts to collide).
 *
 * Payload of SIG_SECTION_DEVICE_ID:
 *   0  u8  kind (0 verbatim, 1 hashed)   1  u8 n (1..16)   2  n bytes: the id
 *   length = 2 + n.
 */
#ifndef SIG_DEVICE_ID_H
#define SIG_DEVICE_ID_H

#include "sig_types.h"

#define SIG_DEVICE_ID_MAX_LEN   16u
#define SIG_DEVICE_ID_VERBATIM  0u
#define SIG_DEVICE_ID_HASHED    1u
#define SIG_DEVICE_ID_TAIL_LEN  12u
#define SIG_DEVICE_ID_HDR_LEN   2u

typedef struct {
    uint8_t kind;                          /* SIG_DEVICE_ID_VERBATIM or _HASHED */
    uint8_t len;                           /* bytes used in id, 1..16 */
    uint8_t id[SIG_DEVICE_ID_MAX_LEN];
} sig_device_id;

/* The id of `serial[0..len)`.  SIG_ERR_ARG for NULL pointers or len 0;
 * *out untouched on error. */
sig_status sig_device_id_make(sig_device_id *out, const uint8_t *serial, size_t len);

/* Does the image in buf[0..len) belong to `expected`?  SIG_OK when it holds
 * a device-id section equal to `expected`; SIG_ERR_DEVICE when that section
 * names another device, or when the image has no device-id section at all
 * (a firmware that checks ids must not take an image nobody addressed to
 * it); SIG_ERR_FORMAT for a malformed section; the image's own validation
 * status (sig_image_validate) when the image is not valid; SIG_ERR_ARG for
 * NULL pointers. */
sig_status sig_device_id_check_image(const uint8_t *buf, size_t len, const sig_device_id *expected);

#endif /* SIG_DEVICE_ID_H */
