/* sig_tmodel.h - one entry point for whatever temperature-compensation model
 * a coefficient image holds: an int32 offset polynomial (sig_tcomp.h), a
 * compact polynomial (sig_tcomp16.h) or a piecewise-linear table per axis
 * (sig_pwl.h).  The image names the family by the section it carries; an
 * optional SIG_SECTION_TEMP_CODE section says how to read the temperature.
 *
 * Temperature code.  The firmware passes the 16 bits its temperature source
 * delivers, as a uint16_t `code`:
 *   SIG_TCODE_INT16   the bits are a two's-complement int16 (the 0.01 °C
 *                     unit of pysig, or a signed sensor register such as the
 *                     MPU-6000 TEMP_OUT); t = the int16 value;
 *   SIG_TCODE_UINT16  the bits are an unsigned code 0..65535 (a uint16
 *                     sensor register); t = code - 32768, so the order of
 *                     the codes is kept over the whole uint16 range.
 * Every model's t_lo, t_hi and knots are in that int16 t.  No image section
 * means SIG_TCODE_INT16.
 *
 * Correction.  out = sat16(in - corr), corr the model's delta rounded to an
 * int16 count: polynomials as sig_tcomp_apply_q / sig_tcomp16_apply_q; a
 * table's Q16.16 value v as corr = floor((v + 2^15) / 2^16) (round half up;
 * |v| <= 32767 * 2^16 so v + 2^15 fits int32).  Outside [t_lo, t_hi] the
 * model is evaluated at the nearer end and SIG_WARN_CLAMPED is returned;
 * SIG_WARN_SATURATED when an output hit an int16 rail.
 *
 * Payload of SIG_SECTION_TEMP_CODE (sig_image.h):
 *   0  u8 code kind (SIG_TCODE_INT16 or SIG_TCODE_UINT16)   1  u8 reserved (0)
 *   length 2.
 *
 * Payload of SIG_SECTION_UNITS (sig_image.h): the units the model was fitted
 * in, so a tool applies the image to a log without being told them again and
 * firmware can report physical values; the evaluator needs none of it.
 * Numbers are decimals m x 10^e (i32 mantissa, i8 exponent -38..38):
 *   0  i32 value scale mantissa (> 0)   4  i8 exponent: the int16 reading is
 *          round(value x scale), value in the log's unit (tesla, g, ...)
 *   5  u8  flags: bit 0 SIG_UNITS_RAW_CODES the temperature is the sensor's
 *          raw code (else 0.01 °C); bit 1 SIG_UNITS_CELSIUS a conversion
 *          °C = code x temp_scale + temp_offset follows; other bits 0
 *   6  i32 temp_scale mantissa   10 i8 exponent   (°C per code)
 *   11 i32 temp_offset mantissa  15 i8 exponent   (°C at code 0; both 0 without bit 1)
 *   length 16.  No section: the units are not recorded (an older image). */
#ifndef SIG_TMODEL_H
#define SIG_TMODEL_H

#include "sig_types.h"
#include "sig_tcomp.h"
#include "sig_tcomp16.h"
#include "sig_pwl.h"

#define SIG_TMODEL_POLY    1u   /* SIG_SECTION_OFFSET_POLY */
#define SIG_TMODEL_COMPACT 2u   /* SIG_SECTION_COMPACT_POLY */
#define SIG_TMODEL_TABLE   3u   /* SIG_SECTION_PWL_TABLE */

#define SIG_TCODE_INT16  0u
#define SIG_TCODE_UINT16 1u
#define SIG_TEMP_CODE_LEN 2u
#define SIG_UNITS_LEN     16u
#define SIG_UNITS_RAW_CODES ((uint8_t)1u)
#define SIG_UNITS_CELSIUS   ((uint8_t)2u)

/* A decimal number mantissa x 10^exp10. */
typedef struct {
    int32_t mantissa;
    int8_t exp10;
} sig_decimal;

/* SIG_SECTION_UNITS, decoded (see above). */
typedef struct {
    sig_decimal value_scale;
    sig_decimal temp_scale;
    sig_decimal temp_offset;
    uint8_t flags;      /* SIG_UNITS_* */
} sig_tmodel_units;

typedef struct {
    union {
        sig_tcomp_q poly;
        sig_tcomp16_q compact;
        sig_pwl_q16 table[SIG_PWL_MAX_AXES];   /* entries in the caller's storage */
    } m;
    uint8_t family;     /* SIG_TMODEL_* */
    uint8_t code_kind;  /* SIG_TCODE_* */
    uint8_t n_axes;     /* 1..3 */
} sig_tmodel;

/* The int16 temperature t of a 16-bit code read as `code_kind` (see above). */
int16_t sig_tmodel_code_to_t(uint8_t code_kind, uint16_t code);

/* Load the model of a coefficient image.  The first of these sections found
 * decides the family: SIG_SECTION_COMPACT_POLY, SIG_SECTION_OFFSET_POLY,
 * SIG_SECTION_PWL_TABLE (a table's entries are copied into `storage`, room for
 * `storage_len` int16 entries: n_axes * n_knots are needed; polynomials need
 * none, storage may then be NULL).  SIG_OK; the image's validation status
 * (SIG_ERR_FORMAT, SIG_ERR_CRC); SIG_ERR_EMPTY when it holds no model
 * section; SIG_ERR_FORMAT for a malformed model or temperature-code section;
 * SIG_ERR_ARG for NULL pointers or too little storage.  *m untouched on any
 * error (storage may have been written only on SIG_OK). */
sig_status sig_tmodel_load_image(sig_tmodel *m, int16_t *storage, uint16_t storage_len,
                                 const uint8_t *image, size_t len);

/* The SIG_SECTION_UNITS section of a coefficient image into *u.  SIG_OK;
 * SIG_ERR_EMPTY when the image has none; the image's validation status;
 * SIG_ERR_FORMAT for a wrong length, unknown flag bits, a value scale <= 0,
 * an exponent outside -38..38 or a conversion without SIG_UNITS_RAW_CODES;
 * SIG_ERR_ARG for NULL pointers.  *u untouched on any error. */
sig_status sig_tmodel_load_units(sig_tmodel_units *u, const uint8_t *image, size_t len);

/* A table model from const arrays (what `pysig export --format c` writes for
 * a table): n_axes tables of n_knots entries back to back in `table`, one
 * value_frac per axis, shared t_lo, t_hi, recip (sig_pwl.h), and the code
 * kind.  SIG_ERR_ARG (*m untouched) for NULL pointers, n_axes outside 1..3,
 * a code kind other than SIG_TCODE_INT16/UINT16, or parameters
 * sig_pwl_init_q16 rejects.  The entries stay in the caller's array. */
sig_status sig_tmodel_init_table(sig_tmodel *m, uint8_t n_axes, const int16_t *table, uint8_t n_knots,
                                 int16_t t_lo, int16_t t_hi, uint32_t recip, const uint8_t *value_frac,
                                 uint8_t code_kind);

/* THE firmware entry point: compensate the n_axes int16 readings in[] taken
 * at the temperature `code` into out[] (may be the same array).  Status as
 * above; SIG_ERR_ARG (out untouched) for NULL pointers or an unknown family. */
sig_status sig_tmodel_apply(const sig_tmodel *m, uint16_t code, const int16_t *in, int16_t *out);

#endif /* SIG_TMODEL_H */
