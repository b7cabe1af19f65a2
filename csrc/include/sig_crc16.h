/* sig_crc16.h - CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection,
 * no final xor; check value of "123456789" is 0x29B1), bitwise so it needs
 * no table in the MCU's flash.  Used by the coefficient image (sig_image.h). */
#ifndef SIG_CRC16_H
#define SIG_CRC16_H

#include "sig_types.h"

#define SIG_CRC16_INIT ((uint16_t)0xFFFFu)

/* Continue a CRC over len bytes: start with SIG_CRC16_INIT; feeding a buffer
 * in pieces gives the same result as feeding it whole.  data may be NULL only
 * when len == 0. */
uint16_t sig_crc16_ccitt(uint16_t crc, const uint8_t *data, size_t len);

#endif /* SIG_CRC16_H */
