/* test_lms_framer_length.c - the length rules of lms_framer.h, applied
 * before the data arrive: impossible length fields (general bounds, the
 * exact sizes of the known replies and commands, B0 against its count
 * word) are rejected as soon as the bytes that prove them arrive; possible
 * ones make the candidate wait; the largest telegrams (814 bytes) pass.
 * Every feed/flush call is checked by lms_framer_harness.c.
 */
#include <string.h>

#include "lms_encode.h"
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

static const lms_vector_t *vec(const char *id)
{
    const lms_vector_t *v = lms_vector_find(id);
    TEST_ASSERT_NOT_NULL_MESSAGE(v, id);
    return v;
}

static const lms_framer_stats_t *stats(void)
{
    return lms_framer_stats(&g_h.framer);
}

/* --- length rules before the data ----------------------------------------- */

typedef struct {
    const char *name;
    lms_direction_t dir;
    uint8_t bytes[8];
    size_t len; /* bytes fed; the error must come no later than the last */
} early_case_t;

static const early_case_t k_early[] = {
    {"scanner L 0", LMS_FROM_SCANNER, {0x02, 0x80, 0x00, 0x00}, 4u},
    {"scanner L 1", LMS_FROM_SCANNER, {0x02, 0x80, 0x01, 0x00}, 4u},
    {"scanner L 809", LMS_FROM_SCANNER, {0x02, 0x80, 0x29, 0x03}, 4u},
    {"scanner L FFFF", LMS_FROM_SCANNER, {0x02, 0x81, 0xFF, 0xFF}, 4u},
    {"host L 0", LMS_FROM_HOST, {0x02, 0x00, 0x00, 0x00}, 4u},
    {"host L 809", LMS_FROM_HOST, {0x02, 0x00, 0x29, 0x03}, 4u},
    {"host L 8000", LMS_FROM_HOST, {0x02, 0x05, 0x00, 0x80}, 4u},
    {"A0 L 4", LMS_FROM_SCANNER, {0x02, 0x80, 0x04, 0x00, 0xA0}, 5u},
    {"A0 L 2", LMS_FROM_SCANNER, {0x02, 0x80, 0x02, 0x00, 0xA0}, 5u},
    {"90 L 22", LMS_FROM_SCANNER, {0x02, 0x80, 0x16, 0x00, 0x90}, 5u},
    {"91 L 3", LMS_FROM_SCANNER, {0x02, 0x80, 0x03, 0x00, 0x91}, 5u},
    {"92 L 23", LMS_FROM_SCANNER, {0x02, 0x80, 0x17, 0x00, 0x92}, 5u},
    {"B1 L 152", LMS_FROM_SCANNER, {0x02, 0x80, 0x98, 0x00, 0xB1}, 5u},
    {"BA L 24", LMS_FROM_SCANNER, {0x02, 0x80, 0x18, 0x00, 0xBA}, 5u},
    {"BB L 6", LMS_FROM_SCANNER, {0x02, 0x80, 0x06, 0x00, 0xBB}, 5u},
    {"F4 L 35", LMS_FROM_SCANNER, {0x02, 0x80, 0x23, 0x00, 0xF4}, 5u},
    {"F7 L 36", LMS_FROM_SCANNER, {0x02, 0x80, 0x24, 0x00, 0xF7}, 5u},
    {"B0 N 5 L 15", LMS_FROM_SCANNER, {0x02, 0x80, 0x0F, 0x00, 0xB0, 0x05, 0x40}, 7u},
    {"B0 N 5 L 12", LMS_FROM_SCANNER, {0x02, 0x80, 0x0C, 0x00, 0xB0, 0x05, 0x40}, 7u},
    {"B0 N 5 L 18", LMS_FROM_SCANNER, {0x02, 0x80, 0x12, 0x00, 0xB0, 0x05, 0x40}, 7u},
    {"B0 N 181 L 400", LMS_FROM_SCANNER, {0x02, 0x80, 0x90, 0x01, 0xB0, 0xB5, 0x40}, 7u},
    {"B0 N 361 L 370", LMS_FROM_SCANNER, {0x02, 0x80, 0x72, 0x01, 0xB0, 0x69, 0x41}, 7u},
    {"B0 N 402 L 808", LMS_FROM_SCANNER, {0x02, 0x80, 0x28, 0x03, 0xB0, 0x92, 0x41}, 7u},
    {"B0 N 1023 L 808", LMS_FROM_SCANNER, {0x02, 0x80, 0x28, 0x03, 0xB0, 0xFF, 0x43}, 7u},
    {"B0 L 2", LMS_FROM_SCANNER, {0x02, 0x80, 0x02, 0x00, 0xB0, 0x10, 0x33}, 7u},
    {"host 31 L 2", LMS_FROM_HOST, {0x02, 0x00, 0x02, 0x00, 0x31}, 5u},
    {"host 3B L 2", LMS_FROM_HOST, {0x02, 0x00, 0x02, 0x00, 0x3B}, 5u},
    {"host 77 L 20", LMS_FROM_HOST, {0x02, 0x00, 0x14, 0x00, 0x77}, 5u},
    {"host 74 L 3", LMS_FROM_HOST, {0x02, 0x00, 0x03, 0x00, 0x74}, 5u},
};

/* The impossible length is rejected as soon as the bytes that prove it
 * arrive, without waiting for the rest; the next telegram is then found. */
static void test_lms_framer_rejects_impossible_length_early(void)
{
    for (size_t c = 0u; c < sizeof k_early / sizeof k_early[0]; c++) {
        const early_case_t *k = &k_early[c];
        for (int chunking = 0; chunking < 2; chunking++) {
            fh_init(&g_h, k->dir, &g_log, k->name, 1u);
            fh_feed(&g_h, k->bytes, k->len, chunking == 0 ? FH_CHUNK_WHOLE : FH_CHUNK_BYTES);
            TEST_ASSERT_TRUE_MESSAGE(g_log.n_events >= 1u, k->name);
            TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_FRAMER_LENGTH_ERROR, g_log.events[0].event, k->name);
            TEST_ASSERT_EQUAL_UINT32_MESSAGE(1u, stats()->length_errors, k->name);
            TEST_ASSERT_EQUAL_UINT32_MESSAGE(0u, stats()->truncated, k->name);
            /* Then an intact telegram of the same direction. */
            const lms_vector_t *v = vec(k->dir == LMS_FROM_HOST ? "V13" : "V24");
            fh_run(&g_h, v->bytes, v->len, FH_CHUNK_WHOLE);
            TEST_ASSERT_EQUAL_UINT_MESSAGE(1u, fh_log_find(&g_log, v->bytes, v->len), k->name);
            TEST_ASSERT_EQUAL_UINT32_MESSAGE(1u, stats()->telegrams, k->name);
            TEST_ASSERT_EQUAL_UINT32_MESSAGE(1u, stats()->resyncs, k->name);
            TEST_ASSERT_EQUAL_UINT32_MESSAGE(k->len, stats()->bytes_skipped + stats()->acks +
                                                         stats()->naks,
                                             k->name);
        }
    }
}

/* Lengths that are possible are not rejected early: the candidate waits. */
static void test_lms_framer_accepts_possible_lengths(void)
{
    static const early_case_t ok[] = {
        {"scanner L 2 unknown code", LMS_FROM_SCANNER, {0x02, 0x80, 0x02, 0x00, 0xC4}, 5u},
        {"scanner L 808 unknown code", LMS_FROM_SCANNER, {0x02, 0x80, 0x28, 0x03, 0xC4}, 5u},
        {"host L 1 unknown code", LMS_FROM_HOST, {0x02, 0x00, 0x01, 0x00, 0x6F}, 5u},
        {"host L 808 unknown code", LMS_FROM_HOST, {0x02, 0x7F, 0x28, 0x03, 0x6F}, 5u},
        {"B0 N 5 L 14", LMS_FROM_SCANNER, {0x02, 0x80, 0x0E, 0x00, 0xB0, 0x05, 0x40}, 7u},
        {"B0 N 5 L 16", LMS_FROM_SCANNER, {0x02, 0x80, 0x10, 0x00, 0xB0, 0x05, 0x78}, 7u},
        {"B0 N 401 L 808", LMS_FROM_SCANNER, {0x02, 0x80, 0x28, 0x03, 0xB0, 0x91, 0x41}, 7u},
        {"B0 N 0 L 4", LMS_FROM_SCANNER, {0x02, 0x80, 0x04, 0x00, 0xB0, 0x00, 0x40}, 7u},
        {"F4 L 34", LMS_FROM_SCANNER, {0x02, 0x80, 0x22, 0x00, 0xF4}, 5u},
        {"F4 L 36", LMS_FROM_SCANNER, {0x02, 0x80, 0x24, 0x00, 0xF4}, 5u},
        {"F7 L 35", LMS_FROM_SCANNER, {0x02, 0x80, 0x23, 0x00, 0xF7}, 5u},
        {"F7 L 37", LMS_FROM_SCANNER, {0x02, 0x80, 0x25, 0x00, 0xF7}, 5u},
        {"B1 L 154", LMS_FROM_SCANNER, {0x02, 0x80, 0x9A, 0x00, 0xB1}, 5u},
        {"host 77 L 33", LMS_FROM_HOST, {0x02, 0x00, 0x21, 0x00, 0x77}, 5u},
        {"host 77 L 35", LMS_FROM_HOST, {0x02, 0x00, 0x23, 0x00, 0x77}, 5u},
        {"host 20 L 10", LMS_FROM_HOST, {0x02, 0x00, 0x0A, 0x00, 0x20}, 5u},
    };
    for (size_t c = 0u; c < sizeof ok / sizeof ok[0]; c++) {
        const early_case_t *k = &ok[c];
        fh_init(&g_h, k->dir, &g_log, k->name, 1u);
        fh_feed(&g_h, k->bytes, k->len, FH_CHUNK_BYTES);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, g_log.n_events, k->name);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(k->len, lms_framer_pending(&g_h.framer), k->name);
        fh_flush(&g_h);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_FRAMER_TRUNCATED, g_log.events[0].event, k->name);
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(0u, stats()->length_errors, k->name);
    }
}

/* The largest telegrams: a 401-value B0 with indices (814 bytes, the
 * buffer size) and an 808-byte-L host telegram of an unknown command. */
static void test_lms_framer_largest_telegrams(void)
{
    static lms_scan_t scan;
    static uint8_t t[LMS_TELEGRAM_MAX];
    memset(&scan, 0, sizeof scan);
    scan.count = LMS_SCAN_MAX_VALUES;
    scan.unit = LMS_UNIT_MM;
    scan.has_indices = true;
    scan.status = 0x10u;
    for (size_t i = 0u; i < scan.count; i++) {
        scan.values[i] = (uint16_t)(0x0280u + i); /* 80 02 80 02 ...: candidates inside */
    }
    size_t n = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_encode_scan(t, sizeof t, 0x80u, &scan, &n));
    TEST_ASSERT_EQUAL_UINT(LMS_TELEGRAM_MAX, n);
    for (int chunking = 0; chunking < 4; chunking++) {
        fh_init(&g_h, LMS_FROM_SCANNER, &g_log, "814-byte B0", 3u);
        fh_run(&g_h, t, n, (fh_chunking_t)chunking);
        TEST_ASSERT_EQUAL_UINT(1u, g_log.n_events);
        TEST_ASSERT_EQUAL_UINT(1u, fh_log_find(&g_log, t, n));
    }
    static uint8_t payload[LMS_LENGTH_MAX];
    memset(payload, 0x02, sizeof payload);
    payload[0] = 0x6Fu;
    n = tu_telegram(t, sizeof t, 0x00u, payload, LMS_LENGTH_MAX);
    TEST_ASSERT_EQUAL_UINT(LMS_TELEGRAM_MAX, n);
    fh_init(&g_h, LMS_FROM_HOST, &g_log, "814-byte host telegram", 3u);
    fh_run(&g_h, t, n, FH_CHUNK_RANDOM);
    TEST_ASSERT_EQUAL_UINT(1u, g_log.n_events);
    TEST_ASSERT_EQUAL_UINT(1u, fh_log_find(&g_log, t, n));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lms_framer_rejects_impossible_length_early);
    RUN_TEST(test_lms_framer_accepts_possible_lengths);
    RUN_TEST(test_lms_framer_largest_telegrams);
    return UNITY_END();
}
