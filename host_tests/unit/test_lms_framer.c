/* test_lms_framer.c - lms_framer (lms_framer.h): every vector found once
 * in its own direction and never in the other, ACK/NAK, flush, the length
 * found by the rescan, resync counting, lms_framer_telegram after
 * non-telegram events. Every feed/flush call is checked against the
 * header's contract by lms_framer_harness.c. Length rules:
 * test_lms_framer_length.c; chunking invariance:
 * test_lms_framer_chunking.c; fault injection and the long faulty stream:
 * test_lms_framer_faults.c.
 */
#include <string.h>

#include "lms_framer.h"
#include "lms_framer_harness.h"
#include "lms_test_util.h"
#include "lms_vectors.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

static fh_t g_h;
static fh_log_t g_log;
static uint8_t g_stream[64u * 1024u];

static const lms_vector_t *vec(const char *id)
{
    const lms_vector_t *v = lms_vector_find(id);
    TEST_ASSERT_NOT_NULL_MESSAGE(v, id);
    return v;
}

static size_t append(uint8_t *dst, size_t at, size_t cap, const uint8_t *src, size_t n)
{
    TEST_ASSERT_TRUE_MESSAGE(at + n <= cap, "test stream buffer too small");
    memcpy(dst + at, src, n);
    return at + n;
}

static const lms_framer_stats_t *stats(void)
{
    return lms_framer_stats(&g_h.framer);
}

/* --- vectors ------------------------------------------------------------- */

/* Each vector alone, in its own direction, whole and byte by byte: exactly
 * one telegram, reported by the call that delivers its last byte. */
static void test_lms_framer_reports_every_vector_once(void)
{
    for (size_t i = 0u; i < LMS_VECTOR_COUNT; i++) {
        const lms_vector_t *v = &lms_vectors[i];
        for (int mode = 0; mode < 2; mode++) {
            fh_init(&g_h, v->direction, &g_log, v->id, 1u);
            if (mode == 0) {
                fh_feed(&g_h, v->bytes, v->len, FH_CHUNK_WHOLE);
            } else {
                /* All but the last byte: nothing yet, all of it pending. */
                fh_feed(&g_h, v->bytes, v->len - 1u, FH_CHUNK_BYTES);
                TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, g_log.n_events, v->id);
                TEST_ASSERT_EQUAL_UINT_MESSAGE(v->len - 1u, lms_framer_pending(&g_h.framer), v->id);
                fh_feed(&g_h, v->bytes + v->len - 1u, 1u, FH_CHUNK_WHOLE);
            }
            TEST_ASSERT_EQUAL_UINT_MESSAGE(1u, g_log.n_events, v->id);
            TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_FRAMER_TELEGRAM, g_log.events[0].event, v->id);
            TEST_ASSERT_EQUAL_UINT_MESSAGE(1u, fh_log_find(&g_log, v->bytes, v->len), v->id);
            TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, lms_framer_pending(&g_h.framer), v->id);
            fh_flush(&g_h);
            TEST_ASSERT_EQUAL_UINT_MESSAGE(1u, g_log.n_events, v->id);
            const lms_framer_stats_t *s = stats();
            TEST_ASSERT_EQUAL_UINT32_MESSAGE(v->len, s->bytes_in, v->id);
            TEST_ASSERT_EQUAL_UINT32_MESSAGE(1u, s->telegrams, v->id);
            TEST_ASSERT_EQUAL_UINT32_MESSAGE(v->len, s->telegram_bytes, v->id);
            TEST_ASSERT_EQUAL_UINT32_MESSAGE(0u, s->bytes_skipped, v->id);
            TEST_ASSERT_EQUAL_UINT32_MESSAGE(0u, s->resyncs, v->id);
            TEST_ASSERT_EQUAL_UINT32_MESSAGE(0u, s->crc_errors + s->length_errors + s->truncated,
                                             v->id);
        }
    }
}

/* A vector in the other direction is never a telegram (address byte). */
static void test_lms_framer_ignores_the_other_direction(void)
{
    for (size_t i = 0u; i < LMS_VECTOR_COUNT; i++) {
        const lms_vector_t *v = &lms_vectors[i];
        const lms_direction_t other =
            v->direction == LMS_FROM_HOST ? LMS_FROM_SCANNER : LMS_FROM_HOST;
        fh_init(&g_h, other, &g_log, v->id, 1u);
        fh_run(&g_h, v->bytes, v->len, FH_CHUNK_BYTES);
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(0u, stats()->telegrams, v->id);
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(v->len, stats()->bytes_skipped + stats()->acks +
                                                     stats()->naks,
                                         v->id);
    }
}

/* All vectors of one direction back to back, with the scanner's ACK in
 * front of each reply: every one reported, in order, no resync. */
static void test_lms_framer_back_to_back_vectors(void)
{
    for (int d = 0; d < 2; d++) {
        const lms_direction_t dir = d == 0 ? LMS_FROM_SCANNER : LMS_FROM_HOST;
        size_t n = 0u;
        size_t count = 0u;
        for (size_t i = 0u; i < LMS_VECTOR_COUNT; i++) {
            if (lms_vectors[i].direction != dir) {
                continue;
            }
            if (dir == LMS_FROM_SCANNER) {
                const uint8_t ack = LMS_ACK;
                n = append(g_stream, n, sizeof g_stream, &ack, 1u);
            }
            n = append(g_stream, n, sizeof g_stream, lms_vectors[i].bytes, lms_vectors[i].len);
            count++;
        }
        for (int chunking = 0; chunking < 4; chunking++) {
            fh_init(&g_h, dir, &g_log, "back to back", 7u);
            fh_run(&g_h, g_stream, n, (fh_chunking_t)chunking);
            TEST_ASSERT_EQUAL_UINT32(count, stats()->telegrams);
            TEST_ASSERT_EQUAL_UINT32(0u, stats()->resyncs);
            TEST_ASSERT_EQUAL_UINT32(0u, stats()->bytes_skipped);
            TEST_ASSERT_EQUAL_UINT32(dir == LMS_FROM_SCANNER ? count : 0u, stats()->acks);
            size_t ev = 0u;
            for (size_t i = 0u; i < LMS_VECTOR_COUNT; i++) {
                const lms_vector_t *v = &lms_vectors[i];
                if (v->direction != dir) {
                    continue;
                }
                if (dir == LMS_FROM_SCANNER) {
                    TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_FRAMER_ACK, g_log.events[ev].event, v->id);
                    ev++;
                }
                const fh_event_t *e = &g_log.events[ev++];
                TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_FRAMER_TELEGRAM, e->event, v->id);
                TEST_ASSERT_EQUAL_UINT_MESSAGE(v->len, e->len, v->id);
                TEST_ASSERT_EQUAL_MEMORY_MESSAGE(v->bytes, &g_log.pool[e->pool_offset], v->len,
                                                 v->id);
            }
            TEST_ASSERT_EQUAL_UINT(ev, g_log.n_events);
        }
    }
}

/* --- ACK / NAK ----------------------------------------------------------- */

static void test_lms_framer_ack_nak_scanner_direction(void)
{
    const uint8_t bytes[] = {LMS_ACK, LMS_NAK, LMS_ACK};
    fh_init(&g_h, LMS_FROM_SCANNER, &g_log, "ack nak", 1u);
    size_t consumed = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_ACK, lms_framer_feed(&g_h.framer, bytes, 3u, &consumed));
    TEST_ASSERT_EQUAL_UINT(1u, consumed);
    size_t len = 7u;
    TEST_ASSERT_NULL(lms_framer_telegram(&g_h.framer, &len));
    TEST_ASSERT_EQUAL_UINT(0u, len);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_NAK, lms_framer_feed(&g_h.framer, bytes + 1, 2u, &consumed));
    TEST_ASSERT_EQUAL_UINT(1u, consumed);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_ACK, lms_framer_feed(&g_h.framer, bytes + 2, 1u, &consumed));
    TEST_ASSERT_EQUAL_UINT(1u, consumed);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_NEED_MORE, lms_framer_feed(&g_h.framer, NULL, 0u, &consumed));
    TEST_ASSERT_EQUAL_UINT(0u, consumed);
    const lms_framer_stats_t *s = stats();
    TEST_ASSERT_EQUAL_UINT32(3u, s->bytes_in);
    TEST_ASSERT_EQUAL_UINT32(2u, s->acks);
    TEST_ASSERT_EQUAL_UINT32(1u, s->naks);
    TEST_ASSERT_EQUAL_UINT32(0u, s->bytes_skipped);
    TEST_ASSERT_EQUAL_UINT(0u, lms_framer_pending(&g_h.framer));

    /* ACK then the reply: no resync, nothing skipped. */
    const lms_vector_t *v21 = vec("V21");
    uint8_t buf[32];
    buf[0] = LMS_ACK;
    memcpy(&buf[1], v21->bytes, v21->len);
    fh_init(&g_h, LMS_FROM_SCANNER, &g_log, "ack + V21", 1u);
    fh_run(&g_h, buf, v21->len + 1u, FH_CHUNK_WHOLE);
    TEST_ASSERT_EQUAL_UINT(2u, g_log.n_events);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_ACK, g_log.events[0].event);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, g_log.events[1].event);
    TEST_ASSERT_EQUAL_UINT32(0u, stats()->resyncs);
    TEST_ASSERT_EQUAL_UINT32(0u, stats()->bytes_skipped);
}

/* In the host direction 06 and 15 are ordinary (skipped) bytes. */
static void test_lms_framer_ack_nak_are_plain_bytes_from_host(void)
{
    const lms_vector_t *v08 = vec("V08");
    uint8_t buf[32];
    buf[0] = LMS_ACK;
    buf[1] = LMS_NAK;
    memcpy(&buf[2], v08->bytes, v08->len);
    fh_init(&g_h, LMS_FROM_HOST, &g_log, "06 15 + V08 from host", 1u);
    fh_run(&g_h, buf, v08->len + 2u, FH_CHUNK_BYTES);
    TEST_ASSERT_EQUAL_UINT(1u, g_log.n_events);
    TEST_ASSERT_EQUAL_UINT(1u, fh_log_find(&g_log, v08->bytes, v08->len));
    TEST_ASSERT_EQUAL_UINT32(0u, stats()->acks);
    TEST_ASSERT_EQUAL_UINT32(0u, stats()->naks);
    TEST_ASSERT_EQUAL_UINT32(2u, stats()->bytes_skipped);
    TEST_ASSERT_EQUAL_UINT32(1u, stats()->resyncs);
}

/* --- lms_framer_telegram after other events ------------------------------ */

static void test_lms_framer_telegram_null_unless_last_event_was_one(void)
{
    const lms_vector_t *v26 = vec("V26");
    lms_framer_t *f = &g_h.framer;
    size_t len = 5u;
    lms_framer_init(f, LMS_FROM_SCANNER);
    TEST_ASSERT_NULL(lms_framer_telegram(f, &len));
    TEST_ASSERT_EQUAL_UINT(0u, len);
    size_t consumed = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, lms_framer_feed(f, v26->bytes, v26->len, &consumed));
    TEST_ASSERT_EQUAL_UINT(v26->len, consumed);
    const uint8_t *t = lms_framer_telegram(f, &len);
    TEST_ASSERT_NOT_NULL(t);
    TEST_ASSERT_EQUAL_UINT(v26->len, len);
    TEST_ASSERT_EQUAL_HEX8_ARRAY(v26->bytes, t, v26->len);
    /* Asking twice is fine. */
    TEST_ASSERT_NOT_NULL(lms_framer_telegram(f, &len));
    /* The next call (NEED_MORE) invalidates it. */
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_NEED_MORE, lms_framer_feed(f, NULL, 0u, &consumed));
    len = 5u;
    TEST_ASSERT_NULL(lms_framer_telegram(f, &len));
    TEST_ASSERT_EQUAL_UINT(0u, len);
    /* After an ACK. */
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, lms_framer_feed(f, v26->bytes, v26->len, &consumed));
    const uint8_t ack = LMS_ACK;
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_ACK, lms_framer_feed(f, &ack, 1u, &consumed));
    len = 5u;
    TEST_ASSERT_NULL(lms_framer_telegram(f, &len));
    TEST_ASSERT_EQUAL_UINT(0u, len);
    /* After a length error. */
    const uint8_t bad_len[4] = {0x02u, 0x80u, 0xFFu, 0xFFu};
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, lms_framer_feed(f, v26->bytes, v26->len, &consumed));
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_LENGTH_ERROR, lms_framer_feed(f, bad_len, 4u, &consumed));
    len = 5u;
    TEST_ASSERT_NULL(lms_framer_telegram(f, &len));
    TEST_ASSERT_EQUAL_UINT(0u, len);
    /* After a flush. */
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, lms_framer_feed(f, v26->bytes, v26->len, &consumed));
    (void)lms_framer_flush(f);
    len = 5u;
    TEST_ASSERT_NULL(lms_framer_telegram(f, &len));
    TEST_ASSERT_EQUAL_UINT(0u, len);
    /* After init. */
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, lms_framer_feed(f, v26->bytes, v26->len, &consumed));
    lms_framer_init(f, LMS_FROM_SCANNER);
    len = 5u;
    TEST_ASSERT_NULL(lms_framer_telegram(f, &len));
    TEST_ASSERT_EQUAL_UINT(0u, len);
    TEST_ASSERT_TRUE(tu_all_zero(lms_framer_stats(f), sizeof(lms_framer_stats_t)));
}

/* --- flush --------------------------------------------------------------- */

static void test_lms_framer_flush_abandons_incomplete_candidate(void)
{
    const lms_vector_t *v35 = vec("V35");
    lms_framer_t *f = &g_h.framer;
    lms_framer_init(f, LMS_FROM_SCANNER);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_NEED_MORE, lms_framer_flush(f)); /* empty */
    size_t consumed = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_NEED_MORE, lms_framer_feed(f, v35->bytes, 100u, &consumed));
    TEST_ASSERT_EQUAL_UINT(100u, consumed);
    TEST_ASSERT_EQUAL_UINT(100u, lms_framer_pending(f));
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TRUNCATED, lms_framer_flush(f));
    TEST_ASSERT_EQUAL_UINT32(1u, lms_framer_stats(f)->truncated);
    /* The rescanned bytes of V35's start hold no other candidate, but a
     * few 06 bytes (value 1030 = 06 04) that may come out as lone ACKs. */
    lms_framer_event_t ev;
    unsigned guard = 0u;
    while ((ev = lms_framer_flush(f)) != LMS_FRAMER_NEED_MORE) {
        TEST_ASSERT_EQUAL_INT(LMS_FRAMER_ACK, ev);
        TEST_ASSERT_TRUE(++guard < 100u);
    }
    TEST_ASSERT_EQUAL_UINT(0u, lms_framer_pending(f));
    const lms_framer_stats_t *s = lms_framer_stats(f);
    TEST_ASSERT_EQUAL_UINT32(100u, s->bytes_in);
    TEST_ASSERT_EQUAL_UINT32(100u, s->bytes_skipped + s->acks);
    TEST_ASSERT_EQUAL_UINT32(0u, s->telegrams);
    TEST_ASSERT_EQUAL_UINT32(1u, s->truncated);
    /* The framer works normally afterwards. */
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, lms_framer_feed(f, v35->bytes, v35->len, &consumed));
    TEST_ASSERT_EQUAL_UINT32(1u, lms_framer_stats(f)->resyncs);

    /* STX + address (+ length) are incomplete candidates too; a lone STX
     * must at least be kept (its address may follow) and dropped by flush. */
    for (size_t n = 1u; n <= 4u; n++) {
        fh_init(&g_h, LMS_FROM_SCANNER, &g_log, "header only", 1u);
        fh_feed(&g_h, v35->bytes, n, FH_CHUNK_WHOLE);
        TEST_ASSERT_EQUAL_UINT(n, lms_framer_pending(&g_h.framer));
        fh_flush(&g_h);
        if (n == 1u) {
            TEST_ASSERT_TRUE(g_log.n_events <= 1u);
        } else {
            TEST_ASSERT_EQUAL_UINT(1u, g_log.n_events);
        }
        if (g_log.n_events == 1u) {
            TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TRUNCATED, g_log.events[0].event);
        }
        TEST_ASSERT_EQUAL_UINT32(n, stats()->bytes_skipped);
    }
}

/* Flush with two nested incomplete candidates: both abandoned in turn. */
static void test_lms_framer_flush_nested_candidates(void)
{
    /* 02 80 64 00 | 02 80 64 00 11: two candidates with L = 100, the
     * second starting inside the first. */
    const uint8_t bytes[9] = {0x02u, 0x80u, 0x64u, 0x00u, 0x02u, 0x80u, 0x64u, 0x00u, 0x11u};
    fh_init(&g_h, LMS_FROM_SCANNER, &g_log, "nested", 1u);
    fh_run(&g_h, bytes, sizeof bytes, FH_CHUNK_WHOLE);
    TEST_ASSERT_EQUAL_UINT(2u, g_log.n_events);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TRUNCATED, g_log.events[0].event);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TRUNCATED, g_log.events[1].event);
    TEST_ASSERT_EQUAL_UINT32(9u, stats()->bytes_skipped);
}

/* --- hidden telegrams: the rescan ---------------------------------------- */

/* A bogus header whose L is impossible, right before a real telegram. */
static void test_lms_framer_finds_telegram_after_bogus_header(void)
{
    const lms_vector_t *v21 = vec("V21");
    uint8_t buf[64];
    const uint8_t bogus[4] = {0x02u, 0x80u, 0x40u, 0x03u}; /* L = 832 */
    size_t n = append(buf, 0u, sizeof buf, bogus, 4u);
    n = append(buf, n, sizeof buf, v21->bytes, v21->len);
    fh_init(&g_h, LMS_FROM_SCANNER, &g_log, "bogus 02 80 40 03", 1u);
    fh_feed(&g_h, buf, n, FH_CHUNK_WHOLE);
    /* Found without a flush. */
    TEST_ASSERT_EQUAL_UINT(2u, g_log.n_events);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_LENGTH_ERROR, g_log.events[0].event);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, g_log.events[1].event);
    TEST_ASSERT_EQUAL_UINT(1u, fh_log_find(&g_log, v21->bytes, v21->len));
    fh_flush(&g_h);
    TEST_ASSERT_EQUAL_UINT32(1u, stats()->resyncs);
}

/* A bogus header with a possible L that never completes: the real telegram
 * inside it comes out when flush abandons the candidate. */
static void test_lms_framer_finds_telegram_inside_incomplete_candidate(void)
{
    const lms_vector_t *v21 = vec("V21");
    uint8_t buf[64];
    const uint8_t bogus[4] = {0x02u, 0x80u, 0x64u, 0x00u}; /* L = 100, code = 02 */
    for (int chunking = 0; chunking < 4; chunking++) {
        size_t n = append(buf, 0u, sizeof buf, bogus, 4u);
        n = append(buf, n, sizeof buf, v21->bytes, v21->len);
        fh_init(&g_h, LMS_FROM_SCANNER, &g_log, "bogus 02 80 64 00", 5u);
        fh_feed(&g_h, buf, n, (fh_chunking_t)chunking);
        TEST_ASSERT_EQUAL_UINT(0u, g_log.n_events);
        TEST_ASSERT_EQUAL_UINT(n, lms_framer_pending(&g_h.framer));
        fh_flush(&g_h);
        TEST_ASSERT_EQUAL_UINT(2u, g_log.n_events);
        TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TRUNCATED, g_log.events[0].event);
        TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, g_log.events[1].event);
        TEST_ASSERT_EQUAL_UINT(1u, fh_log_find(&g_log, v21->bytes, v21->len));
        TEST_ASSERT_EQUAL_UINT32(4u, stats()->bytes_skipped);
    }
}

/* A bogus candidate that completes over a real telegram and part of the
 * next one: CRC error, then both real telegrams. */
static void test_lms_framer_finds_telegrams_inside_crc_failed_candidate(void)
{
    const lms_vector_t *v21 = vec("V21");
    const lms_vector_t *v26 = vec("V26");
    const lms_vector_t *v35 = vec("V35");
    uint8_t buf[512];
    const uint8_t bogus[4] = {0x02u, 0x80u, 0x0Au, 0x00u}; /* L = 10: 16 bytes */
    for (int chunking = 0; chunking < 4; chunking++) {
        size_t n = append(buf, 0u, sizeof buf, bogus, 4u);
        n = append(buf, n, sizeof buf, v21->bytes, v21->len);
        n = append(buf, n, sizeof buf, v26->bytes, v26->len);
        n = append(buf, n, sizeof buf, v35->bytes, v35->len);
        fh_init(&g_h, LMS_FROM_SCANNER, &g_log, "bogus 02 80 0A 00", 9u);
        fh_run(&g_h, buf, n, (fh_chunking_t)chunking);
        TEST_ASSERT_EQUAL_UINT(4u, g_log.n_events);
        TEST_ASSERT_EQUAL_INT(LMS_FRAMER_CRC_ERROR, g_log.events[0].event);
        TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, g_log.events[1].event);
        TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, g_log.events[2].event);
        TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, g_log.events[3].event);
        TEST_ASSERT_EQUAL_MEMORY(v21->bytes, &g_log.pool[g_log.events[1].pool_offset], v21->len);
        TEST_ASSERT_EQUAL_MEMORY(v26->bytes, &g_log.pool[g_log.events[2].pool_offset], v26->len);
        TEST_ASSERT_EQUAL_MEMORY(v35->bytes, &g_log.pool[g_log.events[3].pool_offset], v35->len);
        TEST_ASSERT_EQUAL_UINT32(1u, stats()->crc_errors);
        TEST_ASSERT_EQUAL_UINT32(4u, stats()->bytes_skipped);
        TEST_ASSERT_EQUAL_UINT32(1u, stats()->resyncs);
    }
}

/* A real telegram whose last byte is wrong, immediately followed by a
 * good one that starts inside nothing: CRC error then the good one. */
static void test_lms_framer_crc_error_then_good_telegram(void)
{
    const lms_vector_t *v24 = vec("V24");
    const lms_vector_t *v22 = vec("V22");
    uint8_t buf[64];
    size_t n = append(buf, 0u, sizeof buf, v24->bytes, v24->len);
    buf[n - 1u] ^= 0x01u;
    n = append(buf, n, sizeof buf, v22->bytes, v22->len);
    fh_init(&g_h, LMS_FROM_SCANNER, &g_log, "bad CRC then V22", 1u);
    fh_feed(&g_h, buf, n, FH_CHUNK_BYTES);
    TEST_ASSERT_EQUAL_UINT(2u, g_log.n_events);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_CRC_ERROR, g_log.events[0].event);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, g_log.events[1].event);
    TEST_ASSERT_EQUAL_UINT(1u, fh_log_find(&g_log, v22->bytes, v22->len));
    TEST_ASSERT_EQUAL_UINT32(v24->len, stats()->bytes_skipped);
    TEST_ASSERT_EQUAL_UINT32(1u, stats()->resyncs);
}

/* --- resyncs ------------------------------------------------------------- */

static void test_lms_framer_resync_counting(void)
{
    const lms_vector_t *a = vec("V21");
    const lms_vector_t *b = vec("V35");
    const uint8_t junk[5] = {0x11u, 0x22u, 0x02u, 0x33u, 0x44u};
    size_t n = 0u;
    /* junk T T junk junk T T T junk(end) */
    n = append(g_stream, n, sizeof g_stream, junk, 5u);
    n = append(g_stream, n, sizeof g_stream, a->bytes, a->len);
    n = append(g_stream, n, sizeof g_stream, b->bytes, b->len);
    n = append(g_stream, n, sizeof g_stream, junk, 5u);
    n = append(g_stream, n, sizeof g_stream, junk, 2u);
    n = append(g_stream, n, sizeof g_stream, a->bytes, a->len);
    n = append(g_stream, n, sizeof g_stream, b->bytes, b->len);
    n = append(g_stream, n, sizeof g_stream, a->bytes, a->len);
    n = append(g_stream, n, sizeof g_stream, junk, 3u);
    for (int chunking = 0; chunking < 4; chunking++) {
        fh_init(&g_h, LMS_FROM_SCANNER, &g_log, "resyncs", 11u);
        fh_run(&g_h, g_stream, n, (fh_chunking_t)chunking);
        TEST_ASSERT_EQUAL_UINT32(5u, stats()->telegrams);
        TEST_ASSERT_EQUAL_UINT32(2u, stats()->resyncs);
        TEST_ASSERT_EQUAL_UINT32(15u, stats()->bytes_skipped);
    }
    /* A clean start: no resync at all. */
    n = 0u;
    for (int k = 0; k < 10; k++) {
        n = append(g_stream, n, sizeof g_stream, b->bytes, b->len);
    }
    fh_init(&g_h, LMS_FROM_SCANNER, &g_log, "clean", 1u);
    fh_run(&g_h, g_stream, n, FH_CHUNK_RANDOM);
    TEST_ASSERT_EQUAL_UINT32(10u, stats()->telegrams);
    TEST_ASSERT_EQUAL_UINT32(0u, stats()->resyncs);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lms_framer_reports_every_vector_once);
    RUN_TEST(test_lms_framer_ignores_the_other_direction);
    RUN_TEST(test_lms_framer_back_to_back_vectors);
    RUN_TEST(test_lms_framer_ack_nak_scanner_direction);
    RUN_TEST(test_lms_framer_ack_nak_are_plain_bytes_from_host);
    RUN_TEST(test_lms_framer_telegram_null_unless_last_event_was_one);
    RUN_TEST(test_lms_framer_flush_abandons_incomplete_candidate);
    RUN_TEST(test_lms_framer_flush_nested_candidates);
    RUN_TEST(test_lms_framer_finds_telegram_after_bogus_header);
    RUN_TEST(test_lms_framer_finds_telegram_inside_incomplete_candidate);
    RUN_TEST(test_lms_framer_finds_telegrams_inside_crc_failed_candidate);
    RUN_TEST(test_lms_framer_crc_error_then_good_telegram);
    RUN_TEST(test_lms_framer_resync_counting);
    return UNITY_END();
}
