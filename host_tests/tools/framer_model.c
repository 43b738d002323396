/* framer_model.c - see framer_model.h. */
#include "framer_model.h"

#include <string.h>

#include "lms_proto.h"

uint16_t framer_model_crc(const uint8_t *bytes, size_t len)
{
    unsigned reg = 0u;
    unsigned prev = 0u;
    for (size_t i = 0u; i < len; i++) {
        const unsigned carry = reg & 0x8000u;
        reg = (reg << 1) & 0xFFFFu;
        if (carry != 0u) {
            reg ^= 0x8005u;
        }
        reg ^= (prev << 8) | bytes[i];
        prev = bytes[i];
    }
    return (uint16_t)reg;
}

/* Exact L values of the fixed-size replies; 0 entries are unused. */
typedef struct {
    uint8_t code;
    uint16_t sizes[2];
} fixed_reply_t;

static const fixed_reply_t fixed_replies[] = {
    {LMS_REPLY_POWER_ON, {1u + LMS_TYPE_TEXT_SIZE + 1u, 0u}},
    {LMS_REPLY_RESET_ACK, {2u, 0u}},
    {LMS_REPLY_NOT_ACK, {2u, 0u}},
    {LMS_REPLY_MODE, {3u, 0u}},
    {LMS_REPLY_STATUS, {1u + LMS_STATUS_DATA_SIZE + 1u, 0u}},
    {LMS_REPLY_TYPE, {1u + LMS_TYPE_TEXT_SIZE + 1u, 0u}},
    {LMS_REPLY_VARIANT, {7u, 0u}},
    {LMS_REPLY_CONFIG, {1u + LMS_CONFIG_SIZE_OLD + 1u, 1u + LMS_CONFIG_SIZE_NEW + 1u}},
    {LMS_REPLY_CONFIG_WRITE, {2u + LMS_CONFIG_SIZE_OLD + 1u, 2u + LMS_CONFIG_SIZE_NEW + 1u}},
};

/* 1: code has fixed sizes and L is one of them; 0: fixed and L is not;
 * -1: not a fixed-size code. */
static int fixed_size_matches(uint8_t code, unsigned length)
{
    for (size_t i = 0u; i < sizeof fixed_replies / sizeof fixed_replies[0]; i++) {
        if (fixed_replies[i].code == code) {
            return (length == fixed_replies[i].sizes[0] ||
                    (fixed_replies[i].sizes[1] != 0u && length == fixed_replies[i].sizes[1]))
                       ? 1
                       : 0;
        }
    }
    return -1;
}

framer_model_verdict_t framer_model_judge(const uint8_t *c, size_t avail, size_t *size)
{
    *size = 0u;
    if (avail < 4u) {
        return FRAMER_MODEL_TRUNCATED;
    }
    const unsigned length = (unsigned)c[2] | ((unsigned)c[3] << 8);
    if (length < 2u || length > LMS_LENGTH_MAX) {
        return FRAMER_MODEL_LENGTH_ERROR;
    }
    if (avail < 5u) {
        return FRAMER_MODEL_TRUNCATED;
    }
    const uint8_t code = c[4];
    if (fixed_size_matches(code, length) == 0) {
        return FRAMER_MODEL_LENGTH_ERROR;
    }
    if (code == LMS_REPLY_VALUES) {
        if (avail < 7u) {
            return FRAMER_MODEL_TRUNCATED;
        }
        const unsigned count = ((unsigned)c[5] | ((unsigned)c[6] << 8)) & 0x3FFu;
        if (count > LMS_SCAN_MAX_VALUES ||
            (length != 2u * count + 4u && length != 2u * count + 6u)) {
            return FRAMER_MODEL_LENGTH_ERROR;
        }
    }
    const size_t total = (size_t)length + LMS_OVERHEAD;
    if (avail < total) {
        return FRAMER_MODEL_TRUNCATED;
    }
    const uint16_t crc = framer_model_crc(c, total - LMS_CRC_SIZE);
    const uint16_t sent = (uint16_t)((unsigned)c[total - 2u] | ((unsigned)c[total - 1u] << 8));
    if (crc != sent) {
        return FRAMER_MODEL_CRC_ERROR;
    }
    *size = total;
    return FRAMER_MODEL_TELEGRAM;
}

void framer_model_run(const uint8_t *bytes, size_t len, framer_model_counts_t *counts,
                      framer_model_event_fn on_event, void *ctx)
{
    memset(counts, 0, sizeof *counts);
    counts->bytes_in = (uint32_t)len;
    bool skipped_since_telegram = false;
    size_t pos = 0u;
    while (pos < len) {
        const uint8_t b = bytes[pos];
        if (b == LMS_ACK || b == LMS_NAK) {
            if (b == LMS_ACK) {
                counts->acks++;
            } else {
                counts->naks++;
            }
            pos++;
            continue;
        }
        bool skip = true;
        if (b == LMS_STX && pos + 1u == len) {
            counts->ends_with_lone_stx = true;
        } else if (b == LMS_STX && (bytes[pos + 1u] & LMS_ADDR_REPLY_BIT) != 0u) {
            size_t size = 0u;
            const framer_model_verdict_t verdict =
                framer_model_judge(bytes + pos, len - pos, &size);
            if (on_event != NULL) {
                on_event(ctx, verdict, pos, size);
            }
            switch (verdict) {
            case FRAMER_MODEL_TELEGRAM:
                counts->telegrams++;
                counts->telegram_bytes += (uint32_t)size;
                if (skipped_since_telegram) {
                    counts->resyncs++;
                    skipped_since_telegram = false;
                }
                pos += size;
                skip = false;
                break;
            case FRAMER_MODEL_LENGTH_ERROR:
                counts->length_errors++;
                break;
            case FRAMER_MODEL_CRC_ERROR:
                counts->crc_errors++;
                break;
            case FRAMER_MODEL_TRUNCATED:
                counts->truncated++;
                break;
            }
        }
        if (skip) {
            counts->bytes_skipped++;
            skipped_since_telegram = true;
            pos++;
        }
    }
}
