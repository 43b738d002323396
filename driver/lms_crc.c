/* lms_crc.c - see lms_crc.h. */
#include "lms_crc.h"

#define LMS_CRC_POLY 0x8005u

void lms_crc_init(lms_crc_t *crc)
{
    crc->reg = 0u;
    crc->prev = 0u;
}

void lms_crc_update(lms_crc_t *crc, const uint8_t *data, size_t len)
{
    uint16_t reg = crc->reg;
    uint8_t prev = crc->prev;
    for (size_t i = 0u; i < len; i++) {
        const uint8_t b = data[i];
        const uint16_t feedback = (reg & 0x8000u) ? LMS_CRC_POLY : 0u;
        reg = (uint16_t)((uint16_t)(reg << 1) ^ feedback);
        reg = (uint16_t)(reg ^ (uint16_t)(((unsigned)prev << 8) | b));
        prev = b;
    }
    crc->reg = reg;
    crc->prev = prev;
}

uint16_t lms_crc16(const uint8_t *data, size_t len)
{
    lms_crc_t crc;
    lms_crc_init(&crc);
    lms_crc_update(&crc, data, len);
    return crc.reg;
}
