/* fuzz_image.c - the coefficient-image parser (sig_image) and the tcomp
 * loaders (sig_tcomp_load_image, sig_tcomp16_load_image) with arbitrary bytes.
 *
 * The first input byte picks how the rest becomes an image:
 *   raw         the bytes as they are (almost always rejected early);
 *   fixed-up    header magic/version/total_len and the CRC are patched so
 *               the section walk and the loaders see arbitrary bodies;
 *   structured  a well-framed image with an offset-polynomial section of
 *               fuzzed contents, between sections of fuzzed types (and
 *               optionally a compact section of fuzzed contents).
 * Every image is copied into a heap buffer of exactly its length, so a read
 * past the end is an AddressSanitizer report.  Invariants:
 *   - sig_image_validate's status equals an independent re-implementation
 *     here (own bitwise CRC): an image is accepted only if its CRC matches;
 *   - a found section lies inside [12, total_len - 2);
 *   - sig_tcomp_load_image leaves the model untouched on error, and a loaded
 *     model is in range and can be applied to any temperature and reading;
 *   - sig_tcomp16_load_image likewise, and it accepts only images whose
 *     compact payload sig_tcomp16_init accepts (checked by calling it);
 *   - sig_pwl_load_image (storage in an exactly sized heap buffer, room
 *     fuzzed) writes nothing on error; loaded tables evaluate at any
 *     temperature within the storage;
 *   - sig_tmodel_load_image (any family; storage exactly sized, room fuzzed)
 *     leaves the model untouched on error, takes the family of the first
 *     model section the image holds (compact, offset, table) and a valid
 *     temperature-code section (kind 0/1, reserved 0, length 2) or none;
 *     a loaded model applies at any code with only warning bits;
 *   - for an accepted image: any single bit flip outside the length field,
 *     and any truncation below total_len, is rejected; the A/B loader then
 *     keeps the good slot, and of two good slots picks the newer sequence. */
#include <stdlib.h>

#include "fuzz_input.h"
#include "sig_crc16.h"
#include "sig_image.h"
#include "sig_pwl.h"
#include "sig_tcomp.h"
#include "sig_tcomp16.h"
#include "sig_tmodel.h"

#define REQUIRE(cond) do { if (!(cond)) abort(); } while (0)

static uint16_t ref_crc(const uint8_t *d, size_t n)
{
    uint16_t crc = 0xFFFFu;
    size_t i;
    int b;
    for (i = 0; i < n; i++) {
        crc ^= (uint16_t)(d[i] << 8);
        for (b = 0; b < 8; b++) crc = (crc & 0x8000u) ? (uint16_t)((crc << 1) ^ 0x1021u) : (uint16_t)(crc << 1);
    }
    return crc;
}

static unsigned rd16(const uint8_t *p) { return (unsigned)p[0] | ((unsigned)p[1] << 8); }

static void wr16(uint8_t *p, unsigned v) { p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); }

static sig_status ref_validate(const uint8_t *b, size_t len)
{
    size_t total, end, pos;
    if (len < 14) return SIG_ERR_FORMAT;
    if (memcmp(b, "psig", 4) != 0 || b[4] != 1 || b[5] != 0) return SIG_ERR_FORMAT;
    total = rd16(b + 6);
    if (total < 14 || total > len) return SIG_ERR_FORMAT;
    end = total - 2;
    if (ref_crc(b, end) != rd16(b + end)) return SIG_ERR_CRC;
    for (pos = 12; pos < end;) {
        if (end - pos < 4 || rd16(b + pos) == 0) return SIG_ERR_FORMAT;
        pos += 4 + rd16(b + pos + 2);
        if (pos > end) return SIG_ERR_FORMAT;
    }
    return SIG_OK;
}

/* Finish an image in place: header fields, total_len = len, CRC at the end. */
static void seal(uint8_t *b, size_t len, uint32_t seq)
{
    memcpy(b, "psig", 4);
    b[4] = 1;
    b[5] = 0;
    wr16(b + 6, (unsigned)len);
    b[8] = (uint8_t)seq; b[9] = (uint8_t)(seq >> 8); b[10] = (uint8_t)(seq >> 16); b[11] = (uint8_t)(seq >> 24);
    wr16(b + len - 2, ref_crc(b, len - 2));
}

static uint8_t *copy_exact(const uint8_t *src, size_t len)
{
    uint8_t *p = malloc(len ? len : 1u);
    if (len) memcpy(p, src, len);
    return p;
}

static void check_model(const sig_tcomp_q *m, fuzz_input *in)
{
    int16_t r[3], out[3];
    int k;
    REQUIRE(m->n_axes >= 1 && m->n_axes <= 3 && m->order >= 1 && m->order <= 8);
    REQUIRE(m->t_lo < m->t_hi && m->t_center >= m->t_lo && m->t_center <= m->t_hi);
    REQUIRE(m->u_mul > 0 && m->u_shift <= 30);
    for (k = 0; k < 3; k++) REQUIRE(m->q[k] <= 30);
    for (k = 0; k < 4; k++) {
        int16_t t = k == 0 ? INT16_MIN : k == 1 ? INT16_MAX : fuzz_i16(in);
        sig_status st;
        r[0] = fuzz_i16(in); r[1] = INT16_MIN; r[2] = INT16_MAX;
        st = sig_tcomp_apply_q(m, t, r, out);
        REQUIRE(st >= 0 && (st & ~(SIG_WARN_CLAMPED | SIG_WARN_SATURATED)) == 0);
        REQUIRE(((st & SIG_WARN_CLAMPED) != 0) == (t < m->t_lo || t > m->t_hi));
    }
}

/* The compact loader: untouched on error; on success the same struct as
 * sig_tcomp16_init on the payload's fields, applicable at any temperature. */
static void check_tcomp16_loader(const uint8_t *buf, size_t len, sig_status image_status, fuzz_input *in)
{
    sig_tcomp16_q m, before, direct;
    const uint8_t *p;
    uint16_t plen;
    int16_t top[3], r[3], out[3];
    int32_t add[15];
    unsigned a, k, pos;
    sig_status st;
    memset(&m, 0xA5, sizeof m);
    before = m;
    st = sig_tcomp16_load_image(&m, buf, len);
    if (st != SIG_OK) {
        REQUIRE(st == SIG_ERR_FORMAT || st == SIG_ERR_CRC || st == SIG_ERR_EMPTY);
        if (image_status != SIG_OK) REQUIRE(st == image_status);
        REQUIRE(memcmp(&m, &before, sizeof m) == 0);
        return;
    }
    REQUIRE(image_status == SIG_OK);
    REQUIRE(sig_image_find_section(buf, len, SIG_SECTION_COMPACT_POLY, &p, &plen) == SIG_OK);
    REQUIRE(p[0] >= 1 && p[0] <= 3 && p[1] >= 1 && p[1] <= 5 && p[3] == 0);
    REQUIRE(plen == 8u + p[0] * (2u + 4u * p[1]));
    for (a = 0, pos = 8; a < p[0]; a++) {
        top[a] = (int16_t)(uint16_t)rd16(p + pos);
        pos += 2;
        for (k = 0; k < p[1]; k++, pos += 4)
            add[a * p[1] + k] = (int32_t)((uint32_t)rd16(p + pos) | ((uint32_t)rd16(p + pos + 2) << 16));
    }
    memset(&direct, 0xA5, sizeof direct);
    REQUIRE(sig_tcomp16_init(&direct, p[0], p[1], top, add, (int16_t)(uint16_t)rd16(p + 4),
                             (int16_t)(uint16_t)rd16(p + 6), p[2]) == SIG_OK);
    REQUIRE(memcmp(&m, &direct, sizeof m) == 0);
    for (k = 0; k < 4; k++) {
        int16_t t = k == 0 ? INT16_MIN : k == 1 ? INT16_MAX : fuzz_i16(in);
        r[0] = fuzz_i16(in); r[1] = INT16_MIN; r[2] = INT16_MAX;
        st = sig_tcomp16_apply_q(&m, t, r, out);
        REQUIRE(st >= 0 && (st & ~(SIG_WARN_CLAMPED | SIG_WARN_SATURATED)) == 0);
        REQUIRE(((st & SIG_WARN_CLAMPED) != 0) == (t < m.t_lo || t > m.t_hi));
    }
}

static void check_pwl_loader(const uint8_t *buf, size_t len, sig_status image_status, fuzz_input *in)
{
    uint8_t max_axes = (uint8_t)(fuzz_u8(in) % 5u), n_axes = 0xEE, a;
    uint16_t room = (uint16_t)(fuzz_u8(in) & 1u ? 3u * 255u : fuzz_u16(in) % 800u);
    int16_t *storage = malloc(room ? room * sizeof *storage : 1u), *storage_before;
    sig_pwl_q16 tables[4], tables_before[4];
    sig_status st;
    memset(storage, 0x4D, room ? room * sizeof *storage : 1u);
    storage_before = malloc(room ? room * sizeof *storage : 1u);
    memcpy(storage_before, storage, room ? room * sizeof *storage : 1u);
    memset(tables, 0x3E, sizeof tables);
    memcpy(tables_before, tables, sizeof tables);
    st = sig_pwl_load_image(tables, max_axes, &n_axes, storage, room, buf, len);
    if (st != SIG_OK) {
        REQUIRE(st == SIG_ERR_FORMAT || st == SIG_ERR_CRC || st == SIG_ERR_EMPTY || st == SIG_ERR_ARG);
        if (image_status != SIG_OK) REQUIRE(st == image_status);
        REQUIRE(n_axes == 0xEE && memcmp(tables, tables_before, sizeof tables) == 0);
        REQUIRE(memcmp(storage, storage_before, room ? room * sizeof *storage : 1u) == 0);
    } else {
        REQUIRE(image_status == SIG_OK && n_axes >= 1 && n_axes <= max_axes && n_axes <= 3);
        REQUIRE(memcmp(&tables[n_axes], &tables_before[n_axes], sizeof tables[0] * (4u - n_axes)) == 0);
        for (a = 0; a < n_axes; a++) {
            int16_t ts[4] = {INT16_MIN, INT16_MAX, tables[a].t_lo, tables[a].t_hi};
            int k;
            REQUIRE(tables[a].table >= storage && tables[a].table + tables[a].n_knots <= storage + room);
            for (k = 0; k < 6; k++) {
                int32_t out;
                int16_t t = k < 4 ? ts[k] : fuzz_i16(in);
                st = sig_pwl_eval_q16(&tables[a], t, &out);
                REQUIRE(st == ((t < tables[a].t_lo || t > tables[a].t_hi) ? SIG_WARN_CLAMPED : SIG_OK));
            }
        }
    }
    free(storage);
    free(storage_before);
}

static void check_tmodel_loader(const uint8_t *buf, size_t len, sig_status image_status, fuzz_input *in)
{
    uint16_t room = (uint16_t)(fuzz_u8(in) & 1u ? 3u * 255u : fuzz_u16(in) % 800u);
    int16_t *storage = malloc(room ? room * sizeof *storage : 1u), r[3], out[3];
    sig_tmodel m, before;
    const uint8_t *p;
    uint16_t plen;
    sig_status st;
    int k;
    memset(&m, 0x5A, sizeof m);
    before = m;
    st = sig_tmodel_load_image(&m, storage, room, buf, len);
    if (st != SIG_OK) {
        REQUIRE(st == SIG_ERR_FORMAT || st == SIG_ERR_CRC || st == SIG_ERR_EMPTY || st == SIG_ERR_ARG);
        if (image_status != SIG_OK) REQUIRE(st == image_status);
        REQUIRE(memcmp(&m, &before, sizeof m) == 0);
        free(storage);
        return;
    }
    REQUIRE(image_status == SIG_OK && m.n_axes >= 1 && m.n_axes <= 3 && m.code_kind <= SIG_TCODE_UINT16);
    if (sig_image_find_section(buf, len, SIG_SECTION_TEMP_CODE, &p, &plen) == SIG_OK)
        REQUIRE(plen == 2u && p[1] == 0u && p[0] == m.code_kind);
    else REQUIRE(m.code_kind == SIG_TCODE_INT16);
    if (sig_image_find_section(buf, len, SIG_SECTION_COMPACT_POLY, &p, &plen) == SIG_OK)
        REQUIRE(m.family == SIG_TMODEL_COMPACT);
    else if (sig_image_find_section(buf, len, SIG_SECTION_OFFSET_POLY, &p, &plen) == SIG_OK)
        REQUIRE(m.family == SIG_TMODEL_POLY);
    else REQUIRE(m.family == SIG_TMODEL_TABLE);
    for (k = 0; k < 5; k++) {
        uint16_t code = k == 0 ? 0u : k == 1 ? 0xFFFFu : k == 2 ? 0x8000u : fuzz_u16(in);
        r[0] = fuzz_i16(in); r[1] = INT16_MIN; r[2] = INT16_MAX;
        st = sig_tmodel_apply(&m, code, r, out);
        REQUIRE(st >= 0 && (st & ~(SIG_WARN_CLAMPED | SIG_WARN_SATURATED)) == 0);
    }
    free(storage);
}

static void check_image(const uint8_t *img, size_t len, int sealed, fuzz_input *in)
{
    uint8_t *buf = copy_exact(img, len);
    sig_status st = sig_image_validate(buf, len), st2;
    sig_tcomp_q m, before;
    const uint8_t *payload;
    uint16_t plen;
    uint32_t seq;
    uint8_t which;
    unsigned type;

    REQUIRE(st == ref_validate(buf, len));
    if (sealed) REQUIRE(st == SIG_OK || st == SIG_ERR_FORMAT);   /* the CRC we wrote matches */

    for (type = 1; type <= SIG_SECTION_TEMP_CODE; type++) {
        payload = NULL;
        plen = 0;
        st2 = sig_image_find_section(buf, len, (uint16_t)type, &payload, &plen);
        if (st != SIG_OK) REQUIRE(st2 == st && payload == NULL);
        else if (st2 == SIG_OK) {
            size_t end = rd16(buf + 6) - 2u;
            REQUIRE(payload >= buf + 16 && payload + plen <= buf + end);
            REQUIRE(rd16(payload - 4) == type && rd16(payload - 2) == plen);
        } else REQUIRE(st2 == SIG_ERR_EMPTY);
    }

    memset(&m, 0xC3, sizeof m);
    before = m;
    st2 = sig_tcomp_load_image(&m, buf, len);
    if (st2 == SIG_OK) {
        REQUIRE(st == SIG_OK);
        check_model(&m, in);
    } else {
        REQUIRE(st2 == SIG_ERR_FORMAT || st2 == SIG_ERR_CRC || st2 == SIG_ERR_EMPTY);
        REQUIRE(st != SIG_OK || st2 != SIG_ERR_CRC);
        REQUIRE(memcmp(&m, &before, sizeof m) == 0);
    }

    check_tcomp16_loader(buf, len, st, in);
    check_pwl_loader(buf, len, st, in);
    check_tmodel_loader(buf, len, st, in);

    if (st == SIG_OK) {
        size_t total = rd16(buf + 6), bit = fuzz_u16(in) % (total * 8u), cut = fuzz_u16(in) % total;
        uint8_t *flipped = copy_exact(buf, len), *cutbuf = copy_exact(buf, cut);
        REQUIRE(sig_image_sequence(buf, len, &seq) == SIG_OK);
        if (bit / 8u == 6 || bit / 8u == 7) bit += 16;      /* a flipped length may frame a new image */
        if (bit / 8u < total) {
            flipped[bit / 8u] ^= (uint8_t)(1u << (bit % 8u));
            REQUIRE(sig_image_validate(flipped, len) != SIG_OK);
            REQUIRE(sig_image_select_slot(buf, len, flipped, len, &which) == SIG_OK && which == SIG_IMAGE_SLOT_A);
            REQUIRE(sig_image_select_slot(flipped, len, buf, len, &which) == SIG_OK && which == SIG_IMAGE_SLOT_B);
        }
        REQUIRE(sig_image_validate(cutbuf, cut) != SIG_OK);
        REQUIRE(sig_image_select_slot(cutbuf, cut, buf, len, &which) == SIG_OK && which == SIG_IMAGE_SLOT_B);
        REQUIRE(sig_image_select_slot(NULL, 0, NULL, 0, &which) == SIG_ERR_EMPTY);
        if (total == len) {
            /* the same image re-sealed with a sequence number d ahead */
            uint32_t d = (uint32_t)fuzz_take_bits(in, 4), diff;
            memcpy(flipped, buf, len);
            seal(flipped, len, seq + d);
            diff = d;
            REQUIRE(sig_image_select_slot(buf, len, flipped, len, &which) == SIG_OK);
            REQUIRE(which == ((diff != 0 && diff < 0x80000000u) ? SIG_IMAGE_SLOT_B : SIG_IMAGE_SLOT_A));
        }
        free(flipped);
        free(cutbuf);
    }
    free(buf);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = fuzz_input_make(data, size);
    uint8_t mode = fuzz_u8(&in) % 3u;
    const uint8_t *body = data + in.pos;
    size_t n = size - in.pos;

    if (mode == 0) {
        check_image(body, n, 0, &in);
    } else if (mode == 1) {
        uint8_t *img;
        size_t len = n < 14 ? 14 : n > 4096 ? 4096 : n;
        img = calloc(len, 1);
        memcpy(img, body, n < len ? n : len);
        seal(img, len, rd16(img + 8) | ((uint32_t)rd16(img + 10) << 16));
        in.pos = in.size;                        /* the body is spent */
        check_image(img, len, 1, &in);
        free(img);
    } else {
        uint8_t img[4096], g;
        size_t pos = 12, off_pos;
        uint8_t n_axes = fuzz_u8(&in), order = fuzz_u8(&in), extra = fuzz_u8(&in);
        unsigned a, k, plen, axes = 1u + n_axes % 3u, ord = 1u + order % 8u;
        if (extra & 0x80u) { axes = n_axes; ord = order; }    /* out-of-range counts too */
        plen = 14u + (axes > 3 || ord > 8 ? 0u : axes * (1u + 4u * (ord + 1u)));
        if (extra & 1u) {                                     /* an unknown section first */
            wr16(img + pos, 0x8000u | fuzz_u16(&in)); wr16(img + pos + 2, 3);
            img[pos + 4] = img[pos + 5] = img[pos + 6] = 0xEE;
            pos += 7;
        }
        off_pos = pos;
        wr16(img + pos, SIG_SECTION_OFFSET_POLY);
        wr16(img + pos + 2, plen);
        img[pos + 4] = (uint8_t)axes;
        img[pos + 5] = (uint8_t)ord;
        img[pos + 6] = fuzz_u8(&in) % 32u;                       /* u_shift */
        img[pos + 7] = (extra & 2u) ? fuzz_u8(&in) : 0u;         /* reserved */
        for (k = 8; k < 18; k++) img[pos + k] = fuzz_u8(&in);    /* t_lo t_hi t_center t0 u_mul */
        pos += 18;
        for (a = 0; plen > 14u && a < axes; a++) {
            img[pos++] = fuzz_u8(&in) % 32u;
            for (k = 0; k <= ord; k++) {
                int32_t c = fuzz_i32_edgy(&in);
                wr16(img + pos, (unsigned)(uint32_t)c & 0xFFFFu);
                wr16(img + pos + 2, (unsigned)((uint32_t)c >> 16));
                pos += 4;
            }
        }
        if (extra & 4u) { wr16(img + pos, SIG_SECTION_PWL_TABLE); wr16(img + pos + 2, 0); pos += 4; }
        if (extra & 32u) {
            /* a compact section: counts in range unless bit 6, t_lo < t_hi
             * unless bit 1 of its flags, small coefficients (of 16 bits)
             * half the time so that sig_tcomp16_init accepts some */
            uint8_t f = fuzz_u8(&in);
            unsigned c_axes = 1u + fuzz_u8(&in) % 3u, c_ord = 1u + fuzz_u8(&in) % 5u, plen3;
            int16_t lo = fuzz_i16(&in), hi = fuzz_i16(&in);
            if (extra & 64u) { c_axes = fuzz_u8(&in) % 5u; c_ord = fuzz_u8(&in) % 7u; }
            if (!(f & 2u) && lo > hi) { int16_t x = lo; lo = hi; hi = x; }
            plen3 = 8u + c_axes * (2u + 4u * c_ord);
            if (f & 4u) plen3 = (plen3 + fuzz_u8(&in) % 5u) - 2u;      /* a wrong length */
            wr16(img + pos, SIG_SECTION_COMPACT_POLY);
            wr16(img + pos + 2, plen3);
            pos += 4;
            for (k = 0; k < plen3; k++) img[pos + k] = fuzz_u8(&in);
            if (plen3 >= 8u) {
                img[pos] = (uint8_t)c_axes;
                img[pos + 1] = (uint8_t)c_ord;
                img[pos + 2] = fuzz_u8(&in) % 17u;                        /* w_shift */
                if (f & 32u && lo < hi) {                                  /* the largest valid one */
                    unsigned span = (unsigned)((int32_t)hi - lo), j = 0;
                    while (j < 15u && (span << (j + 1u)) <= 0xFFFFu) j++;
                    img[pos + 2] = (uint8_t)j;
                }
                img[pos + 3] = (f & 8u) ? fuzz_u8(&in) : 0u;              /* reserved */
                wr16(img + pos + 4, (unsigned)(uint16_t)lo);
                wr16(img + pos + 6, (unsigned)(uint16_t)hi);
                if ((f & 16u) && plen3 == 8u + c_axes * (2u + 4u * c_ord)) {
                    unsigned q = pos + 8u;                                 /* small coefficients */
                    for (a = 0; a < c_axes; a++) {
                        wr16(img + q, (unsigned)(uint16_t)(int16_t)(int8_t)fuzz_u8(&in));
                        q += 2u;
                        for (k = 0; k < c_ord; k++, q += 4u) {
                            uint32_t c = (uint32_t)(int32_t)fuzz_i16(&in);
                            wr16(img + q, c & 0xFFFFu);
                            wr16(img + q + 2u, c >> 16);
                        }
                    }
                }
            }
            pos += plen3;
        }
        if (extra & 8u) {
            /* a table section: axes, knots, range, recip (derived unless bit 4), entries */
            unsigned t_axes = 1u + fuzz_u8(&in) % 3u, knots = 2u + fuzz_u8(&in) % 40u, plen2;
            int16_t lo = fuzz_i16(&in), hi = fuzz_i16(&in);
            uint32_t recip = (uint32_t)fuzz_take_bits(&in, 4);
            if (lo > hi) { int16_t x = lo; lo = hi; hi = x; }
            if (lo == hi) hi = (int16_t)(lo == INT16_MAX ? lo : lo + 1), lo = (int16_t)(hi - 1);
            if (!(extra & 16u)) {
                int64_t r = ((int64_t)(knots - 1u) << 32) / ((int32_t)hi - lo);
                recip = r > (int64_t)UINT32_MAX ? UINT32_MAX : (uint32_t)r;
            }
            plen2 = 10u + t_axes * (1u + 2u * knots);
            wr16(img + pos, SIG_SECTION_PWL_TABLE);
            wr16(img + pos + 2, plen2);
            img[pos + 4] = (uint8_t)t_axes;
            img[pos + 5] = (uint8_t)knots;
            wr16(img + pos + 6, (unsigned)(uint16_t)lo);
            wr16(img + pos + 8, (unsigned)(uint16_t)hi);
            wr16(img + pos + 10, recip & 0xFFFFu);
            wr16(img + pos + 12, recip >> 16);
            pos += 14;
            for (a = 0; a < t_axes; a++) {
                img[pos++] = fuzz_u8(&in) % 17u;
                for (k = 0; k < knots; k++) { wr16(img + pos, fuzz_u16(&in)); pos += 2; }
            }
        }
        g = fuzz_u8(&in);
        if (g & 1u) wr16(img + off_pos, 0x8001u);     /* the offset section hidden: table or compact family */
        if (g & 2u) {                                  /* a temperature-code section, sometimes malformed */
            unsigned clen = (g & 0x40u) ? 3u : 2u;
            wr16(img + pos, SIG_SECTION_TEMP_CODE);
            wr16(img + pos + 2, clen);
            img[pos + 4] = (uint8_t)((g >> 2) % 3u);
            img[pos + 5] = (g & 0x80u) ? fuzz_u8(&in) : 0u;
            img[pos + 6] = 0u;
            pos += 4u + clen;
        }
        pos += 2;
        seal(img, pos, (uint32_t)fuzz_take_bits(&in, 4));
        check_image(img, pos, 1, &in);
    }
    return 0;
}
