/* test_image.c - the coefficient image in C: the CRC-16/CCITT-FALSE check
 * value, a power cut after every byte of a slot write (the loader keeps the
 * old calibration until the new one is complete, then takes it), every
 * single-bit flip of a valid image rejected, sequence wrap-around, and the
 * tcomp loader leaving its model untouched on a rejected image. */
#include <string.h>

#include "check.h"
#include "sig_crc16.h"
#include "sig_image.h"
#include "sig_tcomp.h"

#define ORDER 2u
#define PAYLOAD_LEN (SIG_OFFSET_POLY_FIXED_LEN + 1u + 4u * (ORDER + 1u))
#define IMAGE_LEN (SIG_IMAGE_HEADER_LEN + SIG_IMAGE_SECTION_HDR_LEN + PAYLOAD_LEN + SIG_IMAGE_CRC_LEN)

static void put16(uint8_t *p, uint32_t v) { p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); }
static void put32(uint8_t *p, uint32_t v) { put16(p, v & 0xFFFFu); put16(p + 2, v >> 16); }

/* A one-axis order-2 offset model image with the given sequence and c0. */
static void build(uint8_t *img, uint32_t seq, int32_t c0)
{
    uint8_t *s = img + SIG_IMAGE_HEADER_LEN, *p = s + SIG_IMAGE_SECTION_HDR_LEN;
    memcpy(img, "psig", 4);
    img[4] = SIG_IMAGE_VERSION;
    img[5] = 0;
    put16(img + 6, IMAGE_LEN);
    put32(img + 8, seq);
    put16(s, SIG_SECTION_OFFSET_POLY);
    put16(s + 2, PAYLOAD_LEN);
    p[0] = 1; p[1] = ORDER; p[2] = 14; p[3] = 0;
    put16(p + 4, (uint32_t)(uint16_t)-4000);   /* t_lo  -40.00 °C */
    put16(p + 6, 8500);                         /* t_hi   85.00 °C */
    put16(p + 8, 2250);                         /* center 22.50 °C */
    put16(p + 10, 2500);                        /* t0     25.00 °C */
    put16(p + 12, 3670);                        /* u_mul: |u| <= 32767 over the range */
    p[14] = 16;                                 /* q */
    put32(p + 15, (uint32_t)c0);
    put32(p + 19, (uint32_t)(int32_t)-(1 << 20));
    put32(p + 23, 12345u);
    put16(img + IMAGE_LEN - 2, sig_crc16_ccitt(SIG_CRC16_INIT, img, IMAGE_LEN - 2));
}

int main(void)
{
    static const uint8_t check[9] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
    uint8_t old_img[IMAGE_LEN], new_img[IMAGE_LEN], slot_b[IMAGE_LEN], flipped[IMAGE_LEN];
    sig_tcomp_q m, before;
    uint8_t which = 9;
    size_t i, bit;
    uint32_t seq;

    CHECK_EQ_I(sig_crc16_ccitt(SIG_CRC16_INIT, check, 9), 0x29B1);
    CHECK_EQ_I(sig_crc16_ccitt(sig_crc16_ccitt(SIG_CRC16_INIT, check, 4), check + 4, 5), 0x29B1);

    build(old_img, 41, 1000);
    build(new_img, 42, 2000);
    CHECK_EQ_I(sig_image_validate(old_img, IMAGE_LEN), SIG_OK);
    CHECK_EQ_I(sig_tcomp_load_image(&m, new_img, IMAGE_LEN), SIG_OK);
    CHECK_EQ_I(m.coef[0][0], 2000);

    /* slot B held an older, erased-to-0xFF region; write the new image byte
     * by byte and cut the power after each byte */
    memset(slot_b, 0xFF, sizeof slot_b);
    for (i = 0; i <= IMAGE_LEN; i++) {
        if (i > 0) slot_b[i - 1] = new_img[i - 1];
        CHECK_EQ_I(sig_image_select_slot(old_img, IMAGE_LEN, slot_b, IMAGE_LEN, &which), SIG_OK);
        CHECK_EQ_I(which, i == IMAGE_LEN ? SIG_IMAGE_SLOT_B : SIG_IMAGE_SLOT_A);
    }

    /* every single-bit flip is rejected; the loader keeps its model */
    memset(&m, 0x5C, sizeof m);
    before = m;
    for (bit = 0; bit < IMAGE_LEN * 8u; bit++) {
        memcpy(flipped, new_img, IMAGE_LEN);
        flipped[bit / 8u] ^= (uint8_t)(1u << (bit % 8u));
        CHECK(sig_image_validate(flipped, IMAGE_LEN) != SIG_OK);
        CHECK(sig_tcomp_load_image(&m, flipped, IMAGE_LEN) < 0);
        CHECK_EQ_I(sig_image_select_slot(old_img, IMAGE_LEN, flipped, IMAGE_LEN, &which), SIG_OK);
        CHECK_EQ_I(which, SIG_IMAGE_SLOT_A);
    }
    CHECK(memcmp(&m, &before, sizeof m) == 0);

    /* a truncated slot is rejected at every length */
    for (i = 0; i < IMAGE_LEN; i++) CHECK(sig_image_validate(new_img, i) != SIG_OK);

    /* serial-number arithmetic: 0 is newer than 0xFFFFFFFF */
    build(old_img, UINT32_C(0xFFFFFFFF), 1);
    build(new_img, 0, 2);
    CHECK_EQ_I(sig_image_select_slot(old_img, IMAGE_LEN, new_img, IMAGE_LEN, &which), SIG_OK);
    CHECK_EQ_I(which, SIG_IMAGE_SLOT_B);
    CHECK_EQ_I(sig_image_sequence(new_img, IMAGE_LEN, &seq), SIG_OK);
    CHECK_EQ_I(seq, 0);
    CHECK_EQ_I(sig_image_select_slot(NULL, 0, NULL, 0, &which), SIG_ERR_EMPTY);
    return check_report("test_image");
}
