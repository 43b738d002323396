/* lms_crc.h - the LMS 2xx telegram checksum ("CRC SICK").
 *
 * Not a textbook bit-serial CRC: the 16-bit register shifts once per byte
 * (XOR 0x8005 when bit 15 falls out) and then mixes in the word
 * (previous byte << 8 | current byte). Register and previous byte start at
 * 0; no reflection, no final XOR; sent low byte first. Check value: the
 * ASCII bytes "123456789" give 0xA656. Pure functions, reentrant.
 */
#ifndef LMS_CRC_H
#define LMS_CRC_H

#include <stddef.h>
#include <stdint.h>

/* Running state, for checking a telegram as its bytes arrive. */
typedef struct {
    uint16_t reg;
    uint8_t prev;
} lms_crc_t;

/* Starts a new checksum (register 0, previous byte 0). */
void lms_crc_init(lms_crc_t *crc);

/* Adds len bytes (len may be 0; data may then be NULL). */
void lms_crc_update(lms_crc_t *crc, const uint8_t *data, size_t len);

/* Checksum of len bytes in one call; 0 for len == 0. */
uint16_t lms_crc16(const uint8_t *data, size_t len);

#endif /* LMS_CRC_H */
