/* lms_framer.c - see lms_framer.h.
 *
 * The buffer holds the bytes from head to tail. Bytes head .. head +
 * examined - 1 have been examined as the current candidate; the rest were
 * buffered but not examined yet (they come back after a candidate is
 * rejected, because everything after its STX is searched again). New input
 * is appended only when every buffered byte has been examined, so the
 * buffered bytes always fit: an incomplete candidate is shorter than
 * LMS_TELEGRAM_MAX.
 */
#include "lms_framer.h"

#include <stdbool.h>
#include <string.h>

#include "lms_crc.h"

_Static_assert(LMS_FRAMER_BUF_SIZE <= 0xFFFFu, "indices are 16 bits");

/* Offsets inside a candidate. */
#define OFF_ADDRESS 1u
#define OFF_LENGTH_HI 3u
#define OFF_CODE 4u
#define OFF_COUNT_HI 6u

#define B0_COUNT_MASK 0x03FFu

void lms_framer_init(lms_framer_t *f, lms_direction_t direction)
{
    memset(f, 0, sizeof *f);
    f->direction = (uint8_t)direction;
}

static bool from_scanner(const lms_framer_t *f)
{
    return f->direction == (uint8_t)LMS_FROM_SCANNER;
}

static uint16_t candidate_length_field(const lms_framer_t *f)
{
    const uint8_t *c = &f->buf[f->head];
    return (uint16_t)(c[2] | (c[3] << 8));
}

/* Is L possible for this code? Exact sizes for the replies and commands
 * this project knows; otherwise only the general bounds (already checked). */
static bool length_fits_code(bool scanner, uint8_t code, uint16_t len)
{
    if (scanner) {
        switch (code) {
        case LMS_REPLY_POWER_ON:
        case LMS_REPLY_TYPE:
            return len == 2u + LMS_TYPE_TEXT_SIZE;
        case LMS_REPLY_RESET_ACK:
        case LMS_REPLY_NOT_ACK:
            return len == 2u;
        case LMS_REPLY_MODE:
            return len == 3u;
        case LMS_REPLY_STATUS:
            return len == 2u + LMS_STATUS_DATA_SIZE;
        case LMS_REPLY_VARIANT:
            return len == 7u;
        case LMS_REPLY_CONFIG:
            return len == 2u + LMS_CONFIG_SIZE_OLD || len == 2u + LMS_CONFIG_SIZE_NEW;
        case LMS_REPLY_CONFIG_WRITE:
            return len == 3u + LMS_CONFIG_SIZE_OLD || len == 3u + LMS_CONFIG_SIZE_NEW;
        case LMS_REPLY_VALUES:
            /* Refined by the count word; here: code, count word, status. */
            return len >= 4u && (len % 2u) == 0u;
        default:
            return true;
        }
    }
    switch (code) {
    case LMS_CMD_RESET:
    case LMS_CMD_STATUS:
    case LMS_CMD_ERRORS:
    case LMS_CMD_TYPE:
    case LMS_CMD_CONFIG_READ:
        return len == 1u;
    case LMS_CMD_MODE:
    case LMS_CMD_REQUEST_VALUES:
        return len >= 2u;
    case LMS_CMD_VARIANT:
        return len == 5u;
    case LMS_CMD_CONFIG_WRITE:
        return len == 1u + LMS_CONFIG_SIZE_OLD || len == 1u + LMS_CONFIG_SIZE_NEW;
    default:
        return true;
    }
}

/* B0: L must be 2N + 4, or 2N + 6 with real-time indices. */
static bool count_fits_length(uint16_t count_word, uint16_t len)
{
    const uint16_t n = (uint16_t)(count_word & B0_COUNT_MASK);
    if (n > LMS_SCAN_MAX_VALUES) {
        return false;
    }
    return len == 2u * n + 4u || len == 2u * n + 6u;
}

/* Drops the first buffered byte, counting it as skipped. */
static void skip_first_byte(lms_framer_t *f)
{
    f->head++;
    f->examined = 0u;
    f->expect = 0u;
    f->stats.bytes_skipped++;
    f->skipped_since_sync = 1u;
}

/* A candidate failed: only its STX goes; the rest is searched again. */
static lms_framer_event_t reject(lms_framer_t *f, lms_framer_event_t why)
{
    if (why == LMS_FRAMER_CRC_ERROR) {
        f->stats.crc_errors++;
    } else if (why == LMS_FRAMER_LENGTH_ERROR) {
        f->stats.length_errors++;
    } else {
        f->stats.truncated++;
    }
    skip_first_byte(f);
    return why;
}

static lms_framer_event_t accept(lms_framer_t *f)
{
    f->stats.telegrams++;
    f->stats.telegram_bytes += f->expect;
    if (f->skipped_since_sync != 0u) {
        f->stats.resyncs++;
        f->skipped_since_sync = 0u;
    }
    f->release = f->expect;
    f->examined = 0u;
    f->expect = 0u;
    return LMS_FRAMER_TELEGRAM;
}

/* The candidate is complete: accept it or reject it on its CRC. */
static lms_framer_event_t check_crc(lms_framer_t *f)
{
    const uint8_t *c = &f->buf[f->head];
    const uint16_t body = (uint16_t)(f->expect - LMS_CRC_SIZE);
    const uint16_t sent = (uint16_t)(c[body] | (c[body + 1u] << 8));
    if (lms_crc16(c, body) != sent) {
        return reject(f, LMS_FRAMER_CRC_ERROR);
    }
    return accept(f);
}

/* Examines the next unexamined buffered byte; returns an event or NEED_MORE
 * (meaning: nothing to report, go on). */
static lms_framer_event_t examine(lms_framer_t *f)
{
    const uint16_t i = f->examined;
    const uint8_t b = f->buf[f->head + i];

    if (i == 0u) { /* hunting */
        if (b == LMS_STX) {
            f->examined = 1u;
            return LMS_FRAMER_NEED_MORE;
        }
        if (from_scanner(f) && (b == LMS_ACK || b == LMS_NAK)) {
            f->head++;
            if (b == LMS_ACK) {
                f->stats.acks++;
                return LMS_FRAMER_ACK;
            }
            f->stats.naks++;
            return LMS_FRAMER_NAK;
        }
        skip_first_byte(f);
        return LMS_FRAMER_NEED_MORE;
    }

    f->examined = (uint16_t)(i + 1u);
    if (i == OFF_ADDRESS) {
        const bool is_reply_address = (b & LMS_ADDR_REPLY_BIT) != 0u;
        if (is_reply_address != from_scanner(f)) {
            /* Not a start after all: an ordinary 02 byte. */
            skip_first_byte(f);
        }
        return LMS_FRAMER_NEED_MORE;
    }
    if (i == OFF_LENGTH_HI) {
        const uint16_t len = candidate_length_field(f);
        const uint16_t min_len = from_scanner(f) ? 2u : 1u;
        if (len < min_len || len > LMS_LENGTH_MAX) {
            return reject(f, LMS_FRAMER_LENGTH_ERROR);
        }
        f->expect = (uint16_t)(len + LMS_OVERHEAD);
        return LMS_FRAMER_NEED_MORE;
    }
    if (i == OFF_CODE && !length_fits_code(from_scanner(f), b, candidate_length_field(f))) {
        return reject(f, LMS_FRAMER_LENGTH_ERROR);
    }
    if (i == OFF_COUNT_HI && from_scanner(f) && f->buf[f->head + OFF_CODE] == LMS_REPLY_VALUES) {
        const uint16_t count_word = (uint16_t)(f->buf[f->head + 5u] | (b << 8));
        if (!count_fits_length(count_word, candidate_length_field(f))) {
            return reject(f, LMS_FRAMER_LENGTH_ERROR);
        }
    }
    if (f->examined == f->expect) {
        return check_crc(f);
    }
    return LMS_FRAMER_NEED_MORE;
}

/* Forgets the telegram reported last, and rewinds an empty buffer. */
static void release_reported(lms_framer_t *f)
{
    f->head = (uint16_t)(f->head + f->release);
    f->release = 0u;
    if (f->head == f->tail) {
        f->head = 0u;
        f->tail = 0u;
    }
}

/* Moves the buffered bytes (all of them the incomplete candidate, shorter
 * than the buffer) to the front. */
static void compact(lms_framer_t *f)
{
    const uint16_t kept = (uint16_t)(f->tail - f->head);
    memmove(f->buf, &f->buf[f->head], kept);
    f->head = 0u;
    f->tail = kept;
}

static void append(lms_framer_t *f, uint8_t b)
{
    if (f->tail == LMS_FRAMER_BUF_SIZE) {
        compact(f);
    }
    f->buf[f->tail] = b;
    f->tail++;
    f->stats.bytes_in++;
}

/* Fast path once the header has passed every check: the rest of the
 * candidate (data, status, CRC) needs no per-byte decision, so it is copied
 * from the input in one go. Returns the number of bytes taken. */
static size_t append_body(lms_framer_t *f, const uint8_t *bytes, size_t len)
{
    size_t n = (size_t)(f->expect - f->examined);
    if (n > len) {
        n = len;
    }
    if ((size_t)f->head + f->expect > LMS_FRAMER_BUF_SIZE) {
        compact(f); /* then head + expect <= LMS_TELEGRAM_MAX fits */
    }
    memcpy(&f->buf[f->tail], bytes, n);
    f->tail = (uint16_t)(f->tail + n);
    f->examined = (uint16_t)(f->examined + n);
    f->stats.bytes_in += (uint32_t)n;
    return n;
}

/* True when the candidate's header checks are all done (the last one looks
 * at the B0 count word) and only its body is missing. */
static bool header_checked(const lms_framer_t *f)
{
    return f->expect != 0u && f->examined > OFF_COUNT_HI;
}

/* Examines buffered bytes and appends input until there is an event to
 * report or nothing left to do. Bounded: every pass examines one buffered
 * byte, appends one input byte, or returns; and a buffered byte is examined
 * again only after an earlier byte was dropped. */
static lms_framer_event_t run(lms_framer_t *f, const uint8_t *bytes, size_t len, size_t *consumed,
                              bool flushing)
{
    size_t used = 0u;
    lms_framer_event_t ev = LMS_FRAMER_NEED_MORE;
    if (bytes == NULL) {
        len = 0u;
    }
    release_reported(f);
    while (ev == LMS_FRAMER_NEED_MORE) {
        if (f->examined < (uint16_t)(f->tail - f->head)) {
            ev = examine(f);
            if (f->head == f->tail) {
                f->head = 0u;
                f->tail = 0u;
            }
        } else if (used < len && header_checked(f)) {
            used += append_body(f, &bytes[used], len - used);
            if (f->examined == f->expect) {
                ev = check_crc(f);
            }
        } else if (used < len) {
            append(f, bytes[used]);
            used++;
        } else if (flushing && f->tail != f->head) {
            ev = reject(f, LMS_FRAMER_TRUNCATED);
        } else {
            break;
        }
    }
    if (consumed != NULL) {
        *consumed = used;
    }
    return ev;
}

lms_framer_event_t lms_framer_feed(lms_framer_t *f, const uint8_t *bytes, size_t len,
                                   size_t *consumed)
{
    if (f == NULL) {
        if (consumed != NULL) {
            *consumed = 0u;
        }
        return LMS_FRAMER_NEED_MORE;
    }
    return run(f, bytes, len, consumed, false);
}

lms_framer_event_t lms_framer_flush(lms_framer_t *f)
{
    if (f == NULL) {
        return LMS_FRAMER_NEED_MORE;
    }
    return run(f, NULL, 0u, NULL, true);
}

const uint8_t *lms_framer_telegram(const lms_framer_t *f, size_t *len)
{
    if (f == NULL || f->release == 0u) {
        if (len != NULL) {
            *len = 0u;
        }
        return NULL;
    }
    if (len != NULL) {
        *len = f->release;
    }
    return &f->buf[f->head];
}

size_t lms_framer_pending(const lms_framer_t *f)
{
    return (size_t)(f->tail - f->head - f->release);
}

const lms_framer_stats_t *lms_framer_stats(const lms_framer_t *f)
{
    return &f->stats;
}
