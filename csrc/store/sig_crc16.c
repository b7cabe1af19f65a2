/* sig_crc16.c - CRC-16/CCITT-FALSE (see sig_crc16.h), a byte at a time
 * without a table: the eight bit steps of the polynomial 0x1021 folded into
 * shifts of the byte's top nibble (x ^= x >> 4), a third of the work of the
 * bitwise loop on 8- and 16-bit MCUs, the same CRC. */
#include "sig_crc16.h"

uint16_t sig_crc16_ccitt(uint16_t crc, const uint8_t *data, size_t len)
{
    size_t i;
    uint8_t x;
    for (i = 0; i < len; i++) {
        x = (uint8_t)((uint8_t)(crc >> 8) ^ data[i]);
        x = (uint8_t)(x ^ (uint8_t)(x >> 4));
        crc = (uint16_t)((uint16_t)(crc << 8) ^ (uint16_t)((uint16_t)x << 12) ^
                         (uint16_t)((uint16_t)x << 5) ^ (uint16_t)x);
    }
    return crc;
}
