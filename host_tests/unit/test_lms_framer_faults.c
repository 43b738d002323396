/* test_lms_framer_faults.c - fault injection into lms_framer
 * (lms_framer.h): a damaged telegram followed by an intact one, at every
 * byte offset and every bit (truncation, single-bit flips, corrupted
 * length fields, garbage in front), and a long synthetic B0 stream with
 * seeded faults between and inside the telegrams, where every intact
 * telegram must come out, in order, and nothing else. Every feed/flush
 * call is checked against the header's contract by lms_framer_harness.c
 * (which also checks that every reported telegram has a good CRC).
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
static uint8_t g_buf[4u * LMS_TELEGRAM_MAX];

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

static fh_chunking_t rotate(size_t k)
{
    static const fh_chunking_t order[4] = {FH_CHUNK_WHOLE, FH_CHUNK_SMALL, FH_CHUNK_RANDOM,
                                           FH_CHUNK_BYTES};
    return order[k % 4u];
}

/* Feeds damaged[0..dlen) then the intact telegram, flushes, and checks
 * that the intact one, and only it, was reported, and that every damaged
 * byte was skipped (or reported as a lone ACK/NAK). */
static void run_damaged_then_intact(lms_direction_t dir, const uint8_t *damaged, size_t dlen,
                                    const lms_vector_t *intact, fh_chunking_t chunking,
                                    const char *msg)
{
    TEST_ASSERT_TRUE(dlen + intact->len <= sizeof g_buf);
    if (dlen > 0u) {
        memmove(g_buf, damaged, dlen);
    }
    memcpy(g_buf + dlen, intact->bytes, intact->len);
    fh_init(&g_h, dir, &g_log, msg, (uint32_t)(dlen * 2654435761u) | 1u);
    fh_run(&g_h, g_buf, dlen + intact->len, chunking);
    const lms_framer_stats_t *s = stats();
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(1u, g_log.count[LMS_FRAMER_TELEGRAM], msg);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(1u, fh_log_find(&g_log, intact->bytes, intact->len), msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(1u, s->telegrams, msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(intact->len, s->telegram_bytes, msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(dlen + intact->len, s->bytes_in, msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(dlen, s->bytes_skipped + s->acks + s->naks, msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(s->bytes_skipped > 0u ? 1u : 0u, s->resyncs, msg);
    /* The intact telegram is the last event. */
    TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_FRAMER_TELEGRAM, g_log.events[g_log.n_events - 1u].event,
                                  msg);
}

static uint32_t errors(void)
{
    return stats()->crc_errors + stats()->length_errors + stats()->truncated;
}

typedef struct {
    const char *damaged;
    const char *intact;
} pair_t;

static const pair_t k_pairs[] = {
    {"V35", "V22"}, {"V35", "V35"}, {"V30", "V22"}, {"V32", "V30"}, {"V28", "V21"},
    {"V21", "V21"}, {"V24", "V35"}, {"V07", "V01"}, {"V34", "V08"}, {"V13", "V13"},
    {"V08", "V34"},
};
#define N_PAIRS (sizeof k_pairs / sizeof k_pairs[0])

/* --- truncation ---------------------------------------------------------- */

static void test_lms_framer_faults_truncation_at_every_offset(void)
{
    for (size_t p = 0u; p < N_PAIRS; p++) {
        const lms_vector_t *d = vec(k_pairs[p].damaged);
        const lms_vector_t *t = vec(k_pairs[p].intact);
        for (size_t cut = 0u; cut < d->len; cut++) {
            char msg[48];
            (void)snprintf(msg, sizeof msg, "%s cut at %u, then %s", d->id, (unsigned)cut, t->id);
            run_damaged_then_intact(d->direction, d->bytes, cut, t, rotate(cut), msg);
            if (cut >= 2u) { /* STX and address arrived: a candidate existed */
                TEST_ASSERT_TRUE_MESSAGE(errors() >= 1u, msg);
            }
        }
    }
}

/* --- single-bit flips ---------------------------------------------------- */

static void test_lms_framer_faults_every_single_bit_flip(void)
{
    static uint8_t damaged[LMS_TELEGRAM_MAX];
    size_t runs = 0u;
    for (size_t p = 0u; p < N_PAIRS; p++) {
        const lms_vector_t *d = vec(k_pairs[p].damaged);
        const lms_vector_t *t = vec(k_pairs[p].intact);
        if (p > 0u && strcmp(k_pairs[p - 1u].damaged, d->id) == 0) {
            continue; /* V35 once is enough */
        }
        for (size_t i = 0u; i < d->len; i++) {
            for (unsigned bit = 0u; bit < 8u; bit++) {
                memcpy(damaged, d->bytes, d->len);
                damaged[i] = (uint8_t)(damaged[i] ^ (1u << bit));
                char msg[48];
                (void)snprintf(msg, sizeof msg, "%s byte %u bit %u, then %s", d->id, (unsigned)i,
                               bit, t->id);
                run_damaged_then_intact(d->direction, damaged, d->len, t, rotate(runs++), msg);
                TEST_ASSERT_TRUE_MESSAGE(stats()->bytes_skipped + errors() > 0u, msg);
                if (i >= 2u || (i == 1u && bit != 7u)) {
                    /* STX and a plausible address: the candidate must fail. */
                    TEST_ASSERT_TRUE_MESSAGE(errors() >= 1u, msg);
                }
            }
        }
    }
    TEST_ASSERT_TRUE(runs > 2976u);
}

/* --- corrupted length field ---------------------------------------------- */

/* True when L is impossible for the telegram t by the header's rules, so
 * the framer must count a length error. */
static bool length_must_fail(const lms_vector_t *t, size_t l)
{
    if (l == 0u || l > LMS_LENGTH_MAX) {
        return true;
    }
    const uint8_t code = t->bytes[4];
    if (t->direction == LMS_FROM_SCANNER) {
        if (l < 2u) {
            return true;
        }
        if (code == LMS_REPLY_VALUES) {
            const size_t n = tu_get_le16(&t->bytes[5]) & 0x3FFu;
            return l != 2u * n + 4u && l != 2u * n + 6u;
        }
        return code == LMS_REPLY_VARIANT || code == LMS_REPLY_TYPE || code == LMS_REPLY_MODE;
    }
    if (code == LMS_CMD_CONFIG_WRITE) {
        return l != 33u && l != 35u;
    }
    if (code == LMS_CMD_STATUS || code == LMS_CMD_VARIANT) {
        return true; /* only their own exact size */
    }
    return false;
}

static void test_lms_framer_faults_corrupted_length_field(void)
{
    static const char *const ids[] = {"V35", "V30", "V32", "V24", "V28", "V21",
                                      "V34", "V08", "V13", "V07"};
    static uint8_t damaged[LMS_TELEGRAM_MAX];
    size_t runs = 0u;
    for (size_t k = 0u; k < sizeof ids / sizeof ids[0]; k++) {
        const lms_vector_t *d = vec(ids[k]);
        const lms_vector_t *t = vec(d->direction == LMS_FROM_SCANNER ? "V22" : "V01");
        const size_t l = d->len - LMS_OVERHEAD;
        const size_t ls[] = {0u, 1u, 2u, l - 1u, l + 1u, l - 2u, l + 2u, 2u * l, l / 2u,
                             l ^ 0x100u, LMS_LENGTH_MAX, LMS_LENGTH_MAX + 1u, 0x7FFFu, 0xFFFFu};
        for (size_t j = 0u; j < sizeof ls / sizeof ls[0]; j++) {
            if (ls[j] == l || ls[j] > 0xFFFFu) {
                continue;
            }
            for (int fix = 0; fix < 2; fix++) {
                memcpy(damaged, d->bytes, d->len);
                tu_put_le16(&damaged[2], (uint16_t)ls[j]);
                if (fix != 0) {
                    tu_fix_crc(damaged, d->len); /* a CRC over the wrong L: still no telegram */
                }
                char msg[48];
                (void)snprintf(msg, sizeof msg, "%s L %u crc %s", d->id, (unsigned)ls[j],
                               fix != 0 ? "fixed" : "old");
                run_damaged_then_intact(d->direction, damaged, d->len, t, rotate(runs++), msg);
                TEST_ASSERT_TRUE_MESSAGE(errors() >= 1u, msg);
                if (length_must_fail(d, ls[j])) {
                    TEST_ASSERT_TRUE_MESSAGE(stats()->length_errors >= 1u, msg);
                }
            }
        }
    }
}

/* --- garbage in front ---------------------------------------------------- */

static void test_lms_framer_faults_garbage_before(void)
{
    static const struct {
        uint8_t bytes[8];
        size_t len;
    } fixed[] = {
        {{0x02}, 1u},
        {{0x02, 0x02}, 2u},
        {{0x02, 0x80}, 2u},
        {{0x02, 0x80, 0x02}, 3u},
        {{0x02, 0x80, 0x02, 0x80}, 4u},
        {{0x02, 0x80, 0x02, 0x80, 0x02}, 5u},
        {{0x02, 0x81, 0x03, 0x00}, 4u},
        {{0x02, 0x80, 0x00}, 3u},
        {{0x02, 0x80, 0xFF}, 3u},
        {{0x02, 0x80, 0x0E, 0x00, 0xB0}, 5u},
        {{0x02, 0x80, 0x03, 0x00, 0xA0, 0x00}, 6u},
        {{0x06, 0x15}, 2u},
        {{0x06, 0x02, 0x15}, 3u},
        {{0x80}, 1u},
        {{0x00, 0x00, 0x00, 0x02, 0x00}, 5u},
        {{0x02, 0x00, 0x01, 0x00}, 4u},
        {{0x02, 0x00, 0x02}, 3u},
    };
    static const char *const intact_ids[] = {"V35", "V21", "V30", "V07", "V08"};
    static uint8_t garbage[300];
    uint32_t rng = 0x6A5Bu;
    size_t runs = 0u;
    for (size_t t = 0u; t < sizeof intact_ids / sizeof intact_ids[0]; t++) {
        const lms_vector_t *v = vec(intact_ids[t]);
        for (size_t g = 0u; g < sizeof fixed / sizeof fixed[0]; g++) {
            char msg[48];
            (void)snprintf(msg, sizeof msg, "garbage %u before %s", (unsigned)g, v->id);
            run_damaged_then_intact(v->direction, fixed[g].bytes, fixed[g].len, v,
                                    rotate(runs++), msg);
        }
        /* Seeded random garbage, rich in 02, 8x, 00, 06 and 15. */
        for (unsigned r = 0u; r < 200u; r++) {
            const size_t len = tu_rand_range(&rng, 1u, (uint32_t)sizeof garbage);
            for (size_t i = 0u; i < len; i++) {
                static const uint8_t favourites[6] = {0x02u, 0x80u, 0x81u, 0x00u, 0x06u, 0x15u};
                const uint32_t c = tu_rand_range(&rng, 0u, 9u);
                garbage[i] = c < 6u ? favourites[c] : tu_rand_byte(&rng);
            }
            char msg[48];
            (void)snprintf(msg, sizeof msg, "random garbage %u before %s", r, v->id);
            run_damaged_then_intact(v->direction, garbage, len, v, rotate(runs++), msg);
        }
    }
}

/* --- a long B0 stream with seeded faults ---------------------------------- */

#define STREAM_TELEGRAMS 2500u
#define STREAM_CAP (STREAM_TELEGRAMS * (LMS_TELEGRAM_MAX + 64u))

typedef struct {
    uint32_t offset; /* in the stream */
    uint16_t len;
} expected_t;

static uint8_t g_stream[STREAM_CAP];
static expected_t g_expected[STREAM_TELEGRAMS];

typedef struct {
    size_t n_expected;
    size_t next;       /* index of the next intact telegram to be reported */
    size_t unexpected; /* CRC-valid telegrams that are not the next intact one */
    size_t first_unexpected_at;
} stream_check_t;

static void stream_sink(void *ctx, lms_framer_event_t ev, const uint8_t *t, size_t len)
{
    stream_check_t *c = (stream_check_t *)ctx;
    if (ev != LMS_FRAMER_TELEGRAM) {
        return;
    }
    if (c->next < c->n_expected) {
        const expected_t *e = &g_expected[c->next];
        if (e->len == len && memcmp(&g_stream[e->offset], t, len) == 0) {
            c->next++;
            return;
        }
    }
    if (c->unexpected++ == 0u) {
        c->first_unexpected_at = c->next;
    }
}

typedef struct {
    size_t n;          /* stream bytes */
    size_t n_faults;   /* faults injected */
    size_t n_expected; /* intact telegrams */
} stream_info_t;

static stream_info_t build_faulty_stream(uint32_t seed)
{
    static lms_scan_t scan;
    static uint8_t t[LMS_TELEGRAM_MAX];
    static const uint16_t counts[3] = {181u, 361u, 401u};
    uint32_t rng = seed;
    stream_info_t info = {0u, 0u, 0u};
    for (size_t k = 0u; k < STREAM_TELEGRAMS; k++) {
        memset(&scan, 0, sizeof scan);
        scan.count = counts[tu_rand_range(&rng, 0u, 2u)];
        scan.unit = (tu_rand(&rng) & 1u) ? LMS_UNIT_MM : LMS_UNIT_CM;
        scan.has_indices = (tu_rand(&rng) & 3u) == 0u;
        scan.scan_index = (uint8_t)k;
        scan.telegram_index = (uint8_t)(k * 7u);
        if (scan.count == 181u && (tu_rand(&rng) & 1u)) {
            scan.is_partial = true;
            scan.partial_index = (uint8_t)(k & 3u);
        }
        scan.status = 0x10u;
        const bool raw_words = (tu_rand(&rng) & 1u) != 0u;
        for (size_t i = 0u; i < scan.count; i++) {
            scan.values[i] = raw_words ? (uint16_t)tu_rand(&rng)
                                       : (uint16_t)tu_rand_range(&rng, 0u, 0x1FFFu);
        }
        size_t tl = 0u;
        TEST_ASSERT_EQUAL_INT(LMS_OK, lms_encode_scan(t, sizeof t, 0x80u, &scan, &tl));

        /* Faults between telegrams leave this one intact. */
        const uint32_t pick = tu_rand_range(&rng, 0u, 99u);
        uint8_t *s = g_stream + info.n;
        size_t pre = 0u;
        if (pick >= 88u && pick < 92u) { /* garbage */
            pre = tu_rand_range(&rng, 1u, 50u);
            for (size_t i = 0u; i < pre; i++) {
                const uint32_t c = tu_rand_range(&rng, 0u, 3u);
                s[i] = c == 0u ? 0x02u : c == 1u ? 0x80u : tu_rand_byte(&rng);
            }
        } else if (pick >= 92u && pick < 95u) { /* a bogus header, any L */
            s[0] = 0x02u;
            s[1] = (uint8_t)(0x80u | tu_rand_byte(&rng));
            tu_put_le16(&s[2], (uint16_t)tu_rand_range(&rng, 0u, 900u));
            pre = 4u;
            if (tu_rand(&rng) & 1u) {
                s[4] = LMS_REPLY_VALUES;
                pre = 5u;
            }
        } else if (pick >= 95u && pick < 97u) { /* a lone ACK or NAK */
            s[0] = (tu_rand(&rng) & 1u) ? LMS_ACK : LMS_NAK;
            pre = 1u;
        }
        if (pre > 0u) {
            info.n_faults++;
        }
        s += pre;

        /* Faults inside the telegram. */
        size_t out_len = tl;
        if (pick < 4u) { /* flip one bit */
            memcpy(s, t, tl);
            const size_t at = tu_rand_range(&rng, 0u, (uint32_t)tl - 1u);
            s[at] = (uint8_t)(s[at] ^ (1u << tu_rand_range(&rng, 0u, 7u)));
        } else if (pick < 7u) { /* cut short */
            out_len = tu_rand_range(&rng, 1u, (uint32_t)tl - 1u);
            memcpy(s, t, out_len);
        } else if (pick < 9u) { /* one byte lost */
            const size_t at = tu_rand_range(&rng, 0u, (uint32_t)tl - 1u);
            memcpy(s, t, at);
            memcpy(s + at, t + at + 1u, tl - at - 1u);
            out_len = tl - 1u;
        } else if (pick < 11u) { /* one byte doubled */
            const size_t at = tu_rand_range(&rng, 0u, (uint32_t)tl - 1u);
            memcpy(s, t, at + 1u);
            memcpy(s + at + 1u, t + at, tl - at);
            out_len = tl + 1u;
        } else if (pick < 13u) { /* a run of bytes overwritten */
            memcpy(s, t, tl);
            const size_t at = tu_rand_range(&rng, 0u, (uint32_t)tl - 1u);
            const size_t run = tu_rand_range(&rng, 1u, 16u);
            for (size_t i = at; i < at + run && i < tl; i++) {
                s[i] = tu_rand_byte(&rng);
            }
        } else {
            memcpy(s, t, tl);
        }
        const bool intact = out_len == tl && memcmp(s, t, tl) == 0;
        if (intact) {
            g_expected[info.n_expected].offset = (uint32_t)(s - g_stream);
            g_expected[info.n_expected].len = (uint16_t)tl;
            info.n_expected++;
        } else {
            info.n_faults++;
        }
        info.n += pre + out_len;
        TEST_ASSERT_TRUE(info.n + LMS_TELEGRAM_MAX + 64u <= STREAM_CAP);
    }
    return info;
}

static void run_faulty_stream(uint32_t seed, fh_chunking_t chunking, const char *name)
{
    const stream_info_t info = build_faulty_stream(seed);
    TEST_ASSERT_TRUE_MESSAGE(info.n_faults > STREAM_TELEGRAMS / 10u, name);
    TEST_ASSERT_TRUE_MESSAGE(info.n_expected > STREAM_TELEGRAMS * 3u / 4u, name);
    stream_check_t check = {info.n_expected, 0u, 0u, 0u};
    fh_init(&g_h, LMS_FROM_SCANNER, NULL, name, seed);
    g_h.sink = stream_sink;
    g_h.sink_ctx = &check;
    fh_run(&g_h, g_stream, info.n, chunking);
    char msg[96];
    (void)snprintf(msg, sizeof msg, "%s: %u of %u intact telegrams, %u unexpected (first at %u)",
                   name, (unsigned)check.next, (unsigned)info.n_expected,
                   (unsigned)check.unexpected, (unsigned)check.first_unexpected_at);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, check.unexpected, msg);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(info.n_expected, check.next, msg);
    const lms_framer_stats_t *s = stats();
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(info.n_expected, s->telegrams, msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(info.n, s->bytes_in, msg);
    TEST_ASSERT_TRUE_MESSAGE(s->crc_errors > 0u, msg);
    TEST_ASSERT_TRUE_MESSAGE(s->length_errors > 0u, msg);
    TEST_ASSERT_TRUE_MESSAGE(s->resyncs > 0u && s->resyncs <= info.n_faults, msg);
    TEST_ASSERT_TRUE_MESSAGE(s->acks + s->naks > 0u, msg);
}

static void test_lms_framer_faults_long_stream_random_chunks(void)
{
    run_faulty_stream(0xFA017001u, FH_CHUNK_RANDOM, "stream seed 1, random chunks");
}

static void test_lms_framer_faults_long_stream_whole(void)
{
    run_faulty_stream(0xFA017002u, FH_CHUNK_WHOLE, "stream seed 2, whole");
}

static void test_lms_framer_faults_long_stream_small_chunks(void)
{
    run_faulty_stream(0xFA017003u, FH_CHUNK_SMALL, "stream seed 3, small chunks");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lms_framer_faults_truncation_at_every_offset);
    RUN_TEST(test_lms_framer_faults_every_single_bit_flip);
    RUN_TEST(test_lms_framer_faults_corrupted_length_field);
    RUN_TEST(test_lms_framer_faults_garbage_before);
    RUN_TEST(test_lms_framer_faults_long_stream_random_chunks);
    RUN_TEST(test_lms_framer_faults_long_stream_whole);
    RUN_TEST(test_lms_framer_faults_long_stream_small_chunks);
    return UNITY_END();
}
