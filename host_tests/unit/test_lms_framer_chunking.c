/* test_lms_framer_chunking.c - chunking invariance of lms_framer
 * (lms_framer.h): a long mixed stream (reply vectors, B0 telegrams of many
 * sizes, ACK/NAK bytes, garbage, bogus headers, truncated and bit-flipped
 * telegrams) fed whole, byte by byte and in seeded random chunk sizes
 * gives the same events, the same telegram bytes and the same statistics.
 * Every feed/flush call is checked by lms_framer_harness.c (including the
 * stats invariant after every call).
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
static fh_log_t g_log2;
static uint8_t g_stream[64u * 1024u];

static const lms_framer_stats_t *stats(void)
{
    return lms_framer_stats(&g_h.framer);
}

/* --- chunking invariance ------------------------------------------------- */

/* A long scanner stream: all reply vectors, ACK/NAK bytes, B0 telegrams of
 * many sizes built with lms_encode_scan, garbage (with 02 and 02 8x
 * pairs), bogus headers, truncated and bit-flipped telegrams. */
static size_t build_mixed_stream(uint8_t *s, size_t cap, uint32_t seed, lms_direction_t dir)
{
    static lms_scan_t scan;
    static uint8_t t[LMS_TELEGRAM_MAX];
    static const uint16_t counts[] = {0u, 1u, 5u, 101u, 181u, 201u, 361u, 401u};
    uint32_t rng = seed;
    size_t n = 0u;
    while (n + 2u * LMS_TELEGRAM_MAX + 64u < cap) {
        const uint32_t pick = tu_rand_range(&rng, 0u, 99u);
        size_t tl = 0u;
        if (pick < 35u) { /* a vector of this direction */
            const lms_vector_t *v;
            do {
                v = &lms_vectors[tu_rand_range(&rng, 0u, LMS_VECTOR_COUNT - 1u)];
            } while (v->direction != dir);
            memcpy(t, v->bytes, v->len);
            tl = v->len;
        } else if (pick < 60u) { /* a B0 (scanner) or a random host command */
            if (dir == LMS_FROM_SCANNER) {
                memset(&scan, 0, sizeof scan);
                scan.count = counts[tu_rand_range(&rng, 0u, 7u)];
                scan.unit = (tu_rand(&rng) & 1u) ? LMS_UNIT_MM : LMS_UNIT_CM;
                scan.has_indices = (tu_rand(&rng) & 3u) == 0u;
                scan.status = 0x10u;
                for (size_t i = 0u; i < scan.count; i++) {
                    scan.values[i] = (uint16_t)tu_rand(&rng);
                }
                TEST_ASSERT_EQUAL_INT(LMS_OK, lms_encode_scan(t, sizeof t, 0x80u, &scan, &tl));
            } else {
                uint8_t payload[40];
                const size_t pl = tu_rand_range(&rng, 1u, 40u);
                for (size_t i = 0u; i < pl; i++) {
                    payload[i] = tu_rand_byte(&rng);
                }
                payload[0] = 0x6Fu; /* not a command of lms_encode.h: any L */
                tl = tu_telegram(t, sizeof t, (uint8_t)tu_rand_range(&rng, 0u, 0x7Fu), payload,
                                 pl);
            }
        } else if (pick < 70u) { /* ACK / NAK bytes */
            t[0] = (tu_rand(&rng) & 1u) ? LMS_ACK : LMS_NAK;
            tl = 1u;
        } else if (pick < 85u) { /* garbage, rich in 02 and 8x */
            tl = tu_rand_range(&rng, 1u, 40u);
            for (size_t i = 0u; i < tl; i++) {
                const uint32_t r = tu_rand_range(&rng, 0u, 5u);
                t[i] = r == 0u ? 0x02u : r == 1u ? (uint8_t)(0x80u | tu_rand_byte(&rng)) :
                                         tu_rand_byte(&rng);
            }
        } else { /* a vector, damaged: truncated or one bit flipped */
            const lms_vector_t *v;
            do {
                v = &lms_vectors[tu_rand_range(&rng, 0u, LMS_VECTOR_COUNT - 1u)];
            } while (v->direction != dir);
            memcpy(t, v->bytes, v->len);
            tl = v->len;
            if (tu_rand(&rng) & 1u) {
                tl = tu_rand_range(&rng, 1u, (uint32_t)v->len - 1u);
            } else {
                const size_t at = tu_rand_range(&rng, 0u, (uint32_t)v->len - 1u);
                t[at] = (uint8_t)(t[at] ^ (1u << tu_rand_range(&rng, 0u, 7u)));
            }
        }
        memcpy(s + n, t, tl);
        n += tl;
    }
    return n;
}

static void check_chunking_invariance(lms_direction_t dir, uint32_t stream_seed)
{
    const size_t n = build_mixed_stream(g_stream, sizeof g_stream, stream_seed, dir);
    fh_init(&g_h, dir, &g_log, "whole", 1u);
    fh_run(&g_h, g_stream, n, FH_CHUNK_WHOLE);
    const lms_framer_stats_t ref = *stats();
    TEST_ASSERT_TRUE(ref.telegrams > 50u);
    TEST_ASSERT_TRUE(ref.crc_errors + ref.length_errors > 0u);
    TEST_ASSERT_TRUE(ref.truncated > 0u || ref.crc_errors > 0u);
    TEST_ASSERT_EQUAL_UINT32(n, ref.bytes_in);
    static const struct {
        fh_chunking_t chunking;
        uint32_t seed;
        const char *name;
    } runs[] = {
        {FH_CHUNK_BYTES, 1u, "byte by byte"},   {FH_CHUNK_RANDOM, 1u, "random seed 1"},
        {FH_CHUNK_RANDOM, 0xDEADBEEFu, "random seed 2"}, {FH_CHUNK_RANDOM, 12345u, "random seed 3"},
        {FH_CHUNK_SMALL, 77u, "small seed 77"},  {FH_CHUNK_SMALL, 4242u, "small seed 4242"},
    };
    for (size_t r = 0u; r < sizeof runs / sizeof runs[0]; r++) {
        fh_init(&g_h, dir, &g_log2, runs[r].name, runs[r].seed);
        fh_run(&g_h, g_stream, n, runs[r].chunking);
        fh_log_assert_equal(&g_log, &g_log2, runs[r].name);
        TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&ref, stats(), sizeof ref, runs[r].name);
    }
}

static void test_lms_framer_chunking_invariance_scanner(void)
{
    check_chunking_invariance(LMS_FROM_SCANNER, 0x5EED0001u);
    check_chunking_invariance(LMS_FROM_SCANNER, 0x5EED0002u);
}

static void test_lms_framer_chunking_invariance_host(void)
{
    check_chunking_invariance(LMS_FROM_HOST, 0x5EED0003u);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lms_framer_chunking_invariance_scanner);
    RUN_TEST(test_lms_framer_chunking_invariance_host);
    return UNITY_END();
}
