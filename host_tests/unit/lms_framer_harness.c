/* lms_framer_harness.c - see lms_framer_harness.h. */
#include "lms_framer_harness.h"

#include <string.h>

#include "lms_test_util.h"
#include "unity.h"

void fh_log_clear(fh_log_t *log)
{
    log->n_events = 0u;
    log->pool_len = 0u;
    memset(log->count, 0, sizeof log->count);
}

void fh_init(fh_t *h, lms_direction_t direction, fh_log_t *log, const char *label,
             uint32_t seed)
{
    memset(&h->framer, 0xA5, sizeof h->framer); /* init must not rely on zeroed storage */
    lms_framer_init(&h->framer, direction);
    h->direction = direction;
    h->log = log;
    h->sink = NULL;
    h->sink_ctx = NULL;
    h->label = label;
    h->rng = seed != 0u ? seed : 0x9E3779B9u;
    memset(&h->last, 0, sizeof h->last);
    if (log != NULL) {
        fh_log_clear(log);
    }
    const lms_framer_stats_t *s = lms_framer_stats(&h->framer);
    TEST_ASSERT_NOT_NULL_MESSAGE(s, label);
    TEST_ASSERT_TRUE_MESSAGE(tu_all_zero(s, sizeof *s), label);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, lms_framer_pending(&h->framer), label);
    size_t tlen = 99u;
    TEST_ASSERT_NULL_MESSAGE(lms_framer_telegram(&h->framer, &tlen), label);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, tlen, label);
}

static void record(fh_t *h, lms_framer_event_t ev, const uint8_t *t, size_t len)
{
    if (h->log != NULL) {
        fh_log_t *log = h->log;
        TEST_ASSERT_TRUE_MESSAGE(log->n_events < FH_MAX_EVENTS, "harness event log full");
        fh_event_t *e = &log->events[log->n_events++];
        e->event = ev;
        e->pool_offset = 0u;
        e->len = (uint16_t)len;
        if (ev == LMS_FRAMER_TELEGRAM) {
            TEST_ASSERT_TRUE_MESSAGE(log->pool_len + len <= FH_POOL_SIZE, "harness pool full");
            memcpy(&log->pool[log->pool_len], t, len);
            e->pool_offset = (uint32_t)log->pool_len;
            log->pool_len += len;
        }
        log->count[ev]++;
    }
    if (h->sink != NULL) {
        h->sink(h->sink_ctx, ev, t, len);
    }
}

/* Every check of the contract after one feed/flush call. */
static void check_call(fh_t *h, lms_framer_event_t ev, size_t consumed, size_t len,
                       bool is_flush)
{
    const char *m = h->label;
    const lms_framer_stats_t *sp = lms_framer_stats(&h->framer);
    TEST_ASSERT_NOT_NULL_MESSAGE(sp, m);
    const lms_framer_stats_t s = *sp;
    const lms_framer_stats_t p = h->last;
    const size_t pending = lms_framer_pending(&h->framer);

    /* One of the events, NEED_MORE (0) .. TRUNCATED. Compared unsigned: the
     * same check whatever integer type the compiler gives the enum (a
     * byte with ARM EABI's short enums, where ev >= 0 always holds). */
    TEST_ASSERT_TRUE_MESSAGE((unsigned)ev <= (unsigned)LMS_FRAMER_TRUNCATED, m);
    TEST_ASSERT_TRUE_MESSAGE(consumed <= len, m);
    if (ev == LMS_FRAMER_NEED_MORE) {
        TEST_ASSERT_EQUAL_UINT_MESSAGE(len, consumed, m);
    }
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(p.bytes_in + (uint32_t)consumed, s.bytes_in, m);
    TEST_ASSERT_TRUE_MESSAGE(pending <= LMS_FRAMER_BUF_SIZE, m);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(s.bytes_in, s.telegram_bytes + s.acks + s.naks +
                                                     s.bytes_skipped + (uint32_t)pending,
                                     m);
    TEST_ASSERT_TRUE_MESSAGE(s.bytes_skipped >= p.bytes_skipped, m);

    /* Exactly the counter of the event moves, by one. */
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(p.telegrams + (ev == LMS_FRAMER_TELEGRAM ? 1u : 0u),
                                     s.telegrams, m);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(p.acks + (ev == LMS_FRAMER_ACK ? 1u : 0u), s.acks, m);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(p.naks + (ev == LMS_FRAMER_NAK ? 1u : 0u), s.naks, m);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(p.crc_errors + (ev == LMS_FRAMER_CRC_ERROR ? 1u : 0u),
                                     s.crc_errors, m);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(p.length_errors +
                                         (ev == LMS_FRAMER_LENGTH_ERROR ? 1u : 0u),
                                     s.length_errors, m);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(p.truncated + (ev == LMS_FRAMER_TRUNCATED ? 1u : 0u),
                                     s.truncated, m);
    if (ev == LMS_FRAMER_TELEGRAM) {
        TEST_ASSERT_TRUE_MESSAGE(s.resyncs == p.resyncs || s.resyncs == p.resyncs + 1u, m);
    } else {
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(p.resyncs, s.resyncs, m);
    }
    if (h->direction == LMS_FROM_HOST) {
        TEST_ASSERT_TRUE_MESSAGE(ev != LMS_FRAMER_ACK && ev != LMS_FRAMER_NAK, m);
    }
    if (is_flush) {
        TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, consumed, m); /* flush takes no bytes */
    }

    size_t tlen = 12345u;
    const uint8_t *t = lms_framer_telegram(&h->framer, &tlen);
    if (ev == LMS_FRAMER_TELEGRAM) {
        TEST_ASSERT_NOT_NULL_MESSAGE(t, m);
        TEST_ASSERT_TRUE_MESSAGE(tlen >= LMS_OVERHEAD + 1u && tlen <= LMS_TELEGRAM_MAX, m);
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(p.telegram_bytes + (uint32_t)tlen, s.telegram_bytes,
                                         m);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(LMS_STX, t[0], m);
        if (h->direction == LMS_FROM_SCANNER) {
            TEST_ASSERT_TRUE_MESSAGE((t[1] & LMS_ADDR_REPLY_BIT) != 0u, m);
            TEST_ASSERT_TRUE_MESSAGE(tlen >= LMS_OVERHEAD + 2u, m);
        } else {
            TEST_ASSERT_TRUE_MESSAGE((t[1] & LMS_ADDR_REPLY_BIT) == 0u, m);
        }
        TEST_ASSERT_EQUAL_UINT_MESSAGE(tlen, (size_t)tu_get_le16(&t[2]) + LMS_OVERHEAD, m);
        TEST_ASSERT_TRUE_MESSAGE(tu_crc_ok(t, tlen), m);
        record(h, ev, t, tlen);
    } else {
        TEST_ASSERT_NULL_MESSAGE(t, m);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, tlen, m);
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(p.telegram_bytes, s.telegram_bytes, m);
        if (ev != LMS_FRAMER_NEED_MORE) {
            record(h, ev, NULL, 0u);
        }
    }
    h->last = s;
}

static void feed_chunk(fh_t *h, const uint8_t *bytes, size_t len)
{
    /* Guard against a framer that never returns NEED_MORE. */
    size_t calls_left = 4u * (len + 16u) + 4096u;
    for (;;) {
        size_t consumed = 0xDEADu;
        const lms_framer_event_t ev =
            lms_framer_feed(&h->framer, len > 0u ? bytes : NULL, len, &consumed);
        check_call(h, ev, consumed, len, false);
        bytes += consumed;
        len -= consumed;
        if (ev == LMS_FRAMER_NEED_MORE) {
            return;
        }
        TEST_ASSERT_TRUE_MESSAGE(--calls_left > 0u, "framer never returned NEED_MORE");
    }
}

void fh_feed(fh_t *h, const uint8_t *bytes, size_t len, fh_chunking_t chunking)
{
    size_t off = 0u;
    while (off < len) {
        size_t n = len - off;
        switch (chunking) {
        case FH_CHUNK_WHOLE:
            break;
        case FH_CHUNK_BYTES:
            n = 1u;
            break;
        case FH_CHUNK_RANDOM: {
            const uint32_t r = tu_rand(&h->rng);
            size_t want = (r % 16u == 0u) ? (size_t)(r >> 20) % 2000u : (size_t)(r >> 8) % 65u;
            if (want < n) {
                n = want; /* 0 is allowed: an empty feed */
            }
            break;
        }
        case FH_CHUNK_SMALL: {
            const size_t want = (size_t)tu_rand_range(&h->rng, 1u, 5u);
            if (want < n) {
                n = want;
            }
            break;
        }
        }
        feed_chunk(h, bytes + off, n);
        off += n;
    }
}

void fh_flush(fh_t *h)
{
    size_t calls_left = 2u * LMS_FRAMER_BUF_SIZE + 16u;
    for (;;) {
        const lms_framer_event_t ev = lms_framer_flush(&h->framer);
        check_call(h, ev, 0u, 0u, true);
        if (ev == LMS_FRAMER_NEED_MORE) {
            break;
        }
        TEST_ASSERT_TRUE_MESSAGE(--calls_left > 0u, "flush never returned NEED_MORE");
    }
    TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, lms_framer_pending(&h->framer), h->label);
    /* Once flushed, another flush has nothing to do. */
    TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_FRAMER_NEED_MORE, lms_framer_flush(&h->framer), h->label);
    check_call(h, LMS_FRAMER_NEED_MORE, 0u, 0u, true);
}

void fh_run(fh_t *h, const uint8_t *bytes, size_t len, fh_chunking_t chunking)
{
    fh_feed(h, bytes, len, chunking);
    fh_flush(h);
}

size_t fh_log_find(const fh_log_t *log, const uint8_t *t, size_t len)
{
    size_t n = 0u;
    for (size_t i = 0u; i < log->n_events; i++) {
        const fh_event_t *e = &log->events[i];
        if (e->event == LMS_FRAMER_TELEGRAM && e->len == len &&
            memcmp(&log->pool[e->pool_offset], t, len) == 0) {
            n++;
        }
    }
    return n;
}

void fh_log_assert_equal(const fh_log_t *expected, const fh_log_t *actual, const char *label)
{
    TEST_ASSERT_EQUAL_UINT_MESSAGE(expected->n_events, actual->n_events, label);
    for (size_t i = 0u; i < expected->n_events; i++) {
        const fh_event_t *e = &expected->events[i];
        const fh_event_t *a = &actual->events[i];
        TEST_ASSERT_EQUAL_INT_MESSAGE(e->event, a->event, label);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(e->len, a->len, label);
        if (e->event == LMS_FRAMER_TELEGRAM) {
            TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&expected->pool[e->pool_offset],
                                             &actual->pool[a->pool_offset], e->len, label);
        }
    }
    TEST_ASSERT_EQUAL_UINT_MESSAGE(expected->pool_len, actual->pool_len, label);
}
