/* lms_test_util.c - see lms_test_util.h. */
#include "lms_test_util.h"

#include <string.h>

#include "lms_crc.h"
#include "lms_proto.h"

uint32_t tu_rand(uint32_t *state)
{
    uint32_t x = *state;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    *state = x;
    return x;
}

uint32_t tu_rand_range(uint32_t *state, uint32_t lo, uint32_t hi)
{
    if (lo == 0u && hi == UINT32_MAX) { /* the whole range: span would wrap */
        return tu_rand(state);
    }
    return lo + tu_rand(state) % (hi - lo + 1u);
}

uint8_t tu_rand_byte(uint32_t *state)
{
    return (uint8_t)(tu_rand(state) >> 24);
}

uint16_t tu_get_le16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (p[1] << 8));
}

void tu_put_le16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)(v >> 8);
}

size_t tu_telegram(uint8_t *out, size_t cap, uint8_t address, const uint8_t *payload,
                   size_t payload_len)
{
    const size_t total = payload_len + LMS_OVERHEAD;
    if (total > cap || payload_len > 0xFFFFu) {
        return 0u;
    }
    out[0] = (uint8_t)LMS_STX;
    out[1] = address;
    tu_put_le16(&out[2], (uint16_t)payload_len);
    if (payload_len > 0u) {
        memcpy(&out[LMS_HEADER_SIZE], payload, payload_len);
    }
    tu_fix_crc(out, total);
    return total;
}

void tu_fix_crc(uint8_t *telegram, size_t len)
{
    const uint16_t crc = lms_crc16(telegram, len - LMS_CRC_SIZE);
    tu_put_le16(&telegram[len - LMS_CRC_SIZE], crc);
}

bool tu_crc_ok(const uint8_t *telegram, size_t len)
{
    if (len < LMS_CRC_SIZE) {
        return false;
    }
    return lms_crc16(telegram, len - LMS_CRC_SIZE) == tu_get_le16(&telegram[len - LMS_CRC_SIZE]);
}

bool tu_all_zero(const void *p, size_t n)
{
    const uint8_t *b = (const uint8_t *)p;
    for (size_t i = 0u; i < n; i++) {
        if (b[i] != 0u) {
            return false;
        }
    }
    return true;
}
