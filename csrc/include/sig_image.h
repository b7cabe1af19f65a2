/* sig_image.h - the coefficient image kept in non-volatile memory, and its
 * two-slot (A/B) storage.
 *
 * Layout (all multi-byte fields little-endian, read byte by byte, so the
 * image is the same on every host and MCU; no alignment is assumed):
 *
 *   offset size  field
 *   0      4     magic "psig" (0x70 0x73 0x69 0x67)
 *   4      1     format version, SIG_IMAGE_VERSION (1)
 *   5      1     flags, 0 in version 1
 *   6      2     total_len: bytes of the whole image, header to CRC inclusive
 *   8      4     sequence number (uint32; the A/B loader keeps the newer)
 *   12     ...   sections, back to back, each:
 *                  2  type id (SIG_SECTION_*; 0 is invalid)
 *                  2  payload length n
 *                  n  payload (format owned by the module of that type)
 *   total_len-2  2  CRC-16/CCITT-FALSE (sig_crc16.h) of bytes [0, total_len-2)
 *
 * The sections must tile [12, total_len-2) exactly.  A reader looks up the
 * section(s) it understands with sig_image_find_section and ignores the rest,
 * so new section types never break an old loader, and no module has to edit
 * sig_image.c to add one: reserve its id below and document its payload at
 * the module that parses it.
 *
 * Two-slot storage: the firmware keeps two regions (slots A and B).  To store
 * a new calibration it writes the image, with sequence = current + 1, into
 * the slot the loader did NOT select, never over the live one.  At boot
 * sig_image_select_slot returns the valid slot with the newer sequence
 * (serial-number arithmetic, so the counter may wrap).  A power cut while
 * writing leaves that slot invalid (length, structure or CRC), so the loader
 * still returns the old calibration, and says which slot it used.
 */
#ifndef SIG_IMAGE_H
#define SIG_IMAGE_H

#include "sig_types.h"

#define SIG_IMAGE_MAGIC0 ((uint8_t)0x70u)   /* 'p' */
#define SIG_IMAGE_MAGIC1 ((uint8_t)0x73u)   /* 's' */
#define SIG_IMAGE_MAGIC2 ((uint8_t)0x69u)   /* 'i' */
#define SIG_IMAGE_MAGIC3 ((uint8_t)0x67u)   /* 'g' */
#define SIG_IMAGE_VERSION        1u
#define SIG_IMAGE_HEADER_LEN     12u
#define SIG_IMAGE_SECTION_HDR_LEN 4u
#define SIG_IMAGE_CRC_LEN        2u
#define SIG_IMAGE_MIN_LEN        (SIG_IMAGE_HEADER_LEN + SIG_IMAGE_CRC_LEN)
#define SIG_IMAGE_MAX_LEN        65535u

/* Section type ids.  Each payload is documented where it is parsed. */
#define SIG_SECTION_INVALID       0u  /* never valid */
#define SIG_SECTION_OFFSET_POLY   1u  /* offset polynomial delta(T) per axis: sig_tcomp.h / sig_tcomp_load_image */
#define SIG_SECTION_GAIN_POLY     2u  /* gain (sensitivity) drift polynomial (refinement) */
#define SIG_SECTION_THERMAL_LAG   3u  /* first-order thermal-lag IIR on the temperature (refinement) */
#define SIG_SECTION_HYSTERESIS    4u  /* heating/cooling hysteresis state and offsets (refinement) */
#define SIG_SECTION_CREEP         5u  /* creep compensation (refinement) */
#define SIG_SECTION_PWL_TABLE     6u  /* piecewise-linear lookup table, uniform knots (sig_pwl.h) */
#define SIG_SECTION_LINEAR_SCALE  7u  /* linear scale calibration, counts -> kg */
#define SIG_SECTION_COMPACT_POLY  8u  /* compact offset polynomial: sig_tcomp16.h / sig_tcomp16_load_image */
#define SIG_SECTION_DEVICE_ID     9u  /* the serial of the device the image was made for: sig_device_id.h */
#define SIG_SECTION_TEMP_CODE    10u  /* how to read the temperature code: sig_tmodel.h */
#define SIG_SECTION_EXPERIMENTAL  0x8000u /* 0x8000..0xFFFF: experimental, never assigned */

/* Payload of SIG_SECTION_OFFSET_POLY (written by pysig/store/_image.py):
 *   0  u8  n_axes (1..3)      1  u8 order (1..8)   2  u8 u_shift (0..15)   3  u8 reserved (0)
 *   4  i16 t_lo   6  i16 t_hi   8  i16 t_center   10 i16 t0   12 i16 u_mul
 *   14 per axis: u8 q, then (order + 1) x i32 coefficients, ascending powers of u
 *   length = 14 + n_axes * (1 + 4 * (order + 1)); meaning in sig_tcomp.h. */
#define SIG_OFFSET_POLY_FIXED_LEN 14u

/* Payload of SIG_SECTION_COMPACT_POLY (written by pysig/store/_image.py from a
 * pysig.tcomp._quant.CompactModel):
 *   0  u8  n_axes (1..3)      1  u8 order (1..5)   2  u8 w_shift (0..15)   3  u8 reserved (0)
 *   4  i16 t_lo   6  i16 t_hi
 *   8  per axis: i16 top, then order x i32 add, evaluation order add_(order-1) .. add_0
 *   length = 8 + n_axes * (2 + 4 * order); the arguments of sig_tcomp16_init,
 *   meaning in sig_tcomp16.h. */
#define SIG_COMPACT_POLY_FIXED_LEN 8u

#define SIG_IMAGE_SLOT_A ((uint8_t)0u)
#define SIG_IMAGE_SLOT_B ((uint8_t)1u)

/* Little-endian field readers (p must hold 2 or 4 readable bytes). */
uint16_t sig_image_get_u16(const uint8_t *p);
int16_t  sig_image_get_i16(const uint8_t *p);
uint32_t sig_image_get_u32(const uint8_t *p);
int32_t  sig_image_get_i32(const uint8_t *p);

/* Check an image held in buf[0..len) (len may exceed total_len: a slot is
 * usually larger than the image in it).  SIG_OK; SIG_ERR_ARG for a NULL buf;
 * SIG_ERR_FORMAT for a bad magic, version, flags, total_len (< 14 or > len)
 * or sections that do not tile the body exactly (or type 0); SIG_ERR_CRC for
 * a checksum mismatch. */
sig_status sig_image_validate(const uint8_t *buf, size_t len);

/* Sequence number of a valid image (validates first; status as above). */
sig_status sig_image_sequence(const uint8_t *buf, size_t len, uint32_t *seq);

/* First section of `type` in a valid image: *payload points into buf,
 * *payload_len its length.  SIG_ERR_EMPTY when the image has no such section;
 * the validation errors otherwise; SIG_ERR_ARG for NULL pointers or type 0.
 * Outputs untouched on error. */
sig_status sig_image_find_section(const uint8_t *buf, size_t len, uint16_t type,
                                  const uint8_t **payload, uint16_t *payload_len);

/* Choose the slot to load: the valid one, or of two valid ones the newer by
 * sequence number (serial arithmetic: b is newer when (uint32)(seq_b - seq_a)
 * is in 1 .. 2^31 - 1; equal or ambiguous -> A).  *which = SIG_IMAGE_SLOT_A or
 * SIG_IMAGE_SLOT_B.  SIG_ERR_EMPTY (and *which untouched) when neither slot
 * holds a valid image; SIG_ERR_ARG for a NULL which.  A slot pointer may be
 * NULL (slot absent). */
sig_status sig_image_select_slot(const uint8_t *slot_a, size_t len_a,
                                 const uint8_t *slot_b, size_t len_b, uint8_t *which);

#endif /* SIG_IMAGE_H */
