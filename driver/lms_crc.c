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
    /* 32-bit working copies: the shift may carry into bit 16, which the
     * mask drops; cheaper on 32-bit cores than 16-bit arithmetic. */
    uint32_t reg = crc->reg;
    uint32_t prev = crc->prev;
    for (size_t i = 0u; i < len; i++) {
        const uint32_t b = data[i];
        const uint32_t feedback = (reg & 0x8000u) ? LMS_CRC_POLY : 0u;
        reg = (((reg << 1) ^ feedback) ^ ((prev << 8) | b)) & 0xFFFFu;
        prev = b;
    }
    crc->reg = (uint16_t)reg;
    crc->prev = (uint8_t)prev;
}

uint16_t lms_crc16(const uint8_t *data, size_t len)
{
    lms_crc_t crc;
    lms_crc_init(&crc);
    lms_crc_update(&crc, data, len);
    return crc.reg;
}
