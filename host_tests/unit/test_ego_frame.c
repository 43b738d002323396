/* test_ego_frame.c - the binary ego-motion frame (firmware/ego_frame.h):
 * CRC check values, the documented layout byte by byte, round trips of
 * random and extreme outputs, every single-bit flip, truncation, garbage,
 * chunking invariance; the CSV line formatter (ego_format_line) against
 * an independent printf oracle; and ego_loop's frame mode against its CSV
 * mode on ray-cast scans.
 *
 * Expected CRCs come from Python's binascii.crc_hqx(data, 0xFFFF), an
 * independent CRC-16/CCITT-FALSE implementation.
 */
#include <inttypes.h>
#include <stdio.h>
#include <string.h>

#include "ego_frame.h"
#include "ego_loop.h"
#include "fx_host.h"
#include "lms_encode.h"
#include "lms_test_util.h"
#include "synth_scan.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

#define MAX_FRAMES 64u
#define STREAM_MAX 8192u

/* --- helpers ------------------------------------------------------------ */

static ego_frame_t make_frame(uint32_t scan, uint32_t time_us, int32_t x, int32_t y,
                              uint32_t theta, int32_t vx, int32_t vy, int32_t omega,
                              uint16_t flags, uint8_t iterations, uint16_t matches)
{
    ego_frame_t f;
    memset(&f, 0, sizeof f);
    f.scan = scan;
    f.time_us = time_us;
    f.out.pose.x = x;
    f.out.pose.y = y;
    f.out.pose.theta = theta;
    f.out.vx = vx;
    f.out.vy = vy;
    f.out.omega = omega;
    f.out.flags = flags;
    f.out.iterations = iterations;
    f.out.matches = matches;
    ego_cov_unknown(&f.out.cov);
    return f;
}

static void set_cov(ego_frame_t *f, int32_t xx, int32_t xy, int32_t xt, int32_t yy, int32_t yt,
                    int32_t tt)
{
    f->out.cov.xx = xx;
    f->out.cov.xy = xy;
    f->out.cov.xt = xt;
    f->out.cov.yy = yy;
    f->out.cov.yt = yt;
    f->out.cov.tt = tt;
}

static int32_t rand_s32(uint32_t *seed)
{
    /* Bits to int32 without an implementation-defined conversion. */
    const uint32_t u = tu_rand(seed);
    return (u <= (uint32_t)INT32_MAX) ? (int32_t)u : -(int32_t)(~u) - 1;
}

static ego_frame_t random_frame(uint32_t *seed)
{
    ego_frame_t f = make_frame(tu_rand(seed), tu_rand(seed), rand_s32(seed), rand_s32(seed),
                               tu_rand(seed), rand_s32(seed), rand_s32(seed), rand_s32(seed),
                               (uint16_t)tu_rand(seed), tu_rand_byte(seed), (uint16_t)tu_rand(seed));
    /* Covariances of every size: a random value shifted down 0..31 bits. */
    int32_t c[6];
    for (unsigned k = 0u; k < 6u; k++) {
        const int32_t r = rand_s32(seed);
        const uint32_t down = tu_rand(seed) % 32u;
        c[k] = (r < 0) ? -(int32_t)((uint32_t)(-(r + 1)) >> down) - 1 : (int32_t)((uint32_t)r >> down);
    }
    set_cov(&f, c[0], c[1], c[2], c[3], c[4], c[5]);
    return f;
}

static size_t encode(uint8_t *out, const ego_frame_t *f)
{
    return ego_frame_encode(out, EGO_FRAME_SIZE, f->scan, f->time_us, &f->out);
}

/* Every carried field equal, every other field of the output 0. */
static void assert_same_frame(const ego_frame_t *e, const ego_frame_t *a, const char *msg)
{
    TEST_ASSERT_EQUAL_HEX32_MESSAGE(e->scan, a->scan, msg);
    TEST_ASSERT_EQUAL_HEX32_MESSAGE(e->time_us, a->time_us, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(e->out.pose.x, a->out.pose.x, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(e->out.pose.y, a->out.pose.y, msg);
    TEST_ASSERT_EQUAL_HEX32_MESSAGE(e->out.pose.theta, a->out.pose.theta, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(e->out.vx, a->out.vx, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(e->out.vy, a->out.vy, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(e->out.omega, a->out.omega, msg);
    TEST_ASSERT_EQUAL_HEX16_MESSAGE(e->out.flags, a->out.flags, msg);
    TEST_ASSERT_EQUAL_UINT8_MESSAGE(e->out.iterations, a->out.iterations, msg);
    TEST_ASSERT_EQUAL_UINT16_MESSAGE(e->out.matches, a->out.matches, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(e->out.cov.xx, a->out.cov.xx, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(e->out.cov.xy, a->out.cov.xy, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(e->out.cov.xt, a->out.cov.xt, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(e->out.cov.yy, a->out.cov.yy, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(e->out.cov.yt, a->out.cov.yt, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(e->out.cov.tt, a->out.cov.tt, msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(0u, a->out.dt_us, msg);
    TEST_ASSERT_EQUAL_UINT8_MESSAGE(0u, a->out.candidates, msg);
    TEST_ASSERT_EQUAL_UINT16_MESSAGE(0u, a->out.points, msg);
    TEST_ASSERT_EQUAL_UINT16_MESSAGE(0u, a->out.n_main, msg);
    TEST_ASSERT_EQUAL_UINT16_MESSAGE(0u, a->out.n_non_main, msg);
    TEST_ASSERT_EQUAL_UINT16_MESSAGE(0u, a->out.inliers, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(0, a->out.residual, msg);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(0, a->out.correlation, msg);
}

typedef enum { FEED_WHOLE, FEED_BYTES, FEED_RANDOM } feed_mode_t;

typedef struct {
    ego_frame_t frames[MAX_FRAMES];
    size_t count;
    ego_frame_stats_t stats;
} decoded_t;

static void check_invariant(const ego_frame_decoder_t *d)
{
    const ego_frame_stats_t *st = ego_frame_stats(d);
    TEST_ASSERT_EQUAL_UINT32(st->bytes_in, st->bytes_framed + st->bytes_skipped +
                                               (uint32_t)ego_frame_pending(d));
}

/* Decodes a whole stream (then flushes) in the given chunking. */
static void decode_stream(const uint8_t *s, size_t len, feed_mode_t mode, uint32_t seed,
                          decoded_t *out)
{
    static ego_frame_decoder_t d;
    ego_frame_decoder_init(&d);
    memset(out, 0, sizeof *out);
    size_t pos = 0u;
    while (pos < len) {
        size_t chunk = len - pos;
        if (mode == FEED_BYTES) {
            chunk = 1u;
        } else if (mode == FEED_RANDOM) {
            const size_t r = tu_rand_range(&seed, 1u, 100u);
            chunk = (r < chunk) ? r : chunk;
        }
        size_t off = 0u;
        while (off < chunk) {
            size_t used = 0u;
            ego_frame_t f;
            const ego_frame_event_t ev = ego_frame_feed(&d, &s[pos + off], chunk - off, &used, &f);
            check_invariant(&d);
            TEST_ASSERT_TRUE(used <= chunk - off);
            if (ev == EGO_FRAME_READY) {
                TEST_ASSERT_TRUE(used > 0u);
                TEST_ASSERT_TRUE(out->count < MAX_FRAMES);
                out->frames[out->count++] = f;
            } else {
                TEST_ASSERT_EQUAL_UINT(chunk - off, used);
            }
            off += used;
        }
        pos += chunk;
    }
    ego_frame_flush(&d);
    TEST_ASSERT_EQUAL_UINT(0u, ego_frame_pending(&d));
    check_invariant(&d);
    out->stats = *ego_frame_stats(&d);
}

static void assert_same_stats(const ego_frame_stats_t *e, const ego_frame_stats_t *a)
{
    TEST_ASSERT_EQUAL_UINT32(e->bytes_in, a->bytes_in);
    TEST_ASSERT_EQUAL_UINT32(e->frames, a->frames);
    TEST_ASSERT_EQUAL_UINT32(e->crc_errors, a->crc_errors);
    TEST_ASSERT_EQUAL_UINT32(e->length_errors, a->length_errors);
    TEST_ASSERT_EQUAL_UINT32(e->truncated, a->truncated);
    TEST_ASSERT_EQUAL_UINT32(e->bytes_skipped, a->bytes_skipped);
}

/* --- CRC and layout ----------------------------------------------------- */

static void test_ego_frame_crc_check_values(void)
{
    const uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
    TEST_ASSERT_EQUAL_HEX16(0x29B1u, ego_frame_crc16(check, sizeof check));
    TEST_ASSERT_EQUAL_HEX16(0xFFFFu, ego_frame_crc16(NULL, 0u));
    const uint8_t a = 'A';
    TEST_ASSERT_EQUAL_HEX16(0xB915u, ego_frame_crc16(&a, 1u));
    uint8_t all[256];
    for (size_t i = 0u; i < sizeof all; i++) {
        all[i] = (uint8_t)i;
    }
    TEST_ASSERT_EQUAL_HEX16(0x3FBDu, ego_frame_crc16(all, sizeof all));
}

/* The layout table of ego_frame.h, worked out by hand (CRC: see the top;
 * computed apart from the code under test). */
static const uint8_t example_bytes[EGO_FRAME_SIZE] = {
    0xE5, 0x02, 0x3D,             /* start, version 2, length 61 */
    0x04, 0x03, 0x02, 0x01,       /* scan 0x01020304 */
    0x2B, 0x68, 0x00, 0x00,       /* time 26667 us */
    0x00, 0x80, 0xFE, 0xFF,       /* dx -1.5 m = -98304 */
    0x00, 0x40, 0x00, 0x00,       /* dy 0.25 m = 16384 */
    0x00, 0x00, 0x00, 0x40,       /* dtheta a quarter turn */
    0x00, 0x00, 0x00, 0x80,       /* vx INT32_MIN */
    0x01, 0x00, 0x00, 0x00,       /* vy 1 LSB */
    0xFF, 0xFF, 0xFF, 0x7F,       /* omega INT32_MAX */
    0x22, 0x00,                   /* flags predicted | aperture */
    0xC8,                         /* iterations 200 */
    0x34, 0x12,                   /* matches 0x1234 */
    0x00, 0x04, 0x00, 0x00,       /* cov_xx 1024: 9.537e-07 m^2 */
    0x00, 0xFE, 0xFF, 0xFF,       /* cov_xy -512 */
    0xFF, 0xFF, 0xFF, 0x7F,       /* cov_xt saturated */
    0x00, 0x00, 0x00, 0x40,       /* cov_yy 1 m^2 */
    0x00, 0x00, 0x00, 0x80,       /* cov_yt INT32_MIN */
    0x01, 0x00, 0x00, 0x00,       /* cov_tt 1 LSB */
    0xFC, 0xD5                    /* CRC 0xD5FC of bytes 1..63 */
};

/* Version 1, as the frames were before the covariance: still decoded. */
static const uint8_t example_v1_bytes[EGO_FRAME_V1_SIZE] = {
    0xE5, 0x01, 0x25, 0x04, 0x03, 0x02, 0x01, 0x2B, 0x68, 0x00, 0x00, 0x00, 0x80, 0xFE,
    0xFF, 0x00, 0x40, 0x00, 0x00, 0x00, 0x00, 0x00, 0x40, 0x00, 0x00, 0x00, 0x80, 0x01,
    0x00, 0x00, 0x00, 0xFF, 0xFF, 0xFF, 0x7F, 0x22, 0x00, 0xC8, 0x34, 0x12,
    0x43, 0xB7 /* CRC 0xB743 of bytes 1..39 */
};

static ego_frame_t example_frame(void)
{
    ego_frame_t f = make_frame(0x01020304u, 26667u, -98304, 16384, 0x40000000u, INT32_MIN, 1,
                               INT32_MAX, 0x22u, 200u, 0x1234u);
    set_cov(&f, 1024, -512, INT32_MAX, 0x40000000, INT32_MIN, 1);
    return f;
}

static void test_ego_frame_layout_byte_by_byte(void)
{
    const ego_frame_t f = example_frame();
    uint8_t out[EGO_FRAME_SIZE + 4u];
    memset(out, 0xAA, sizeof out);
    TEST_ASSERT_EQUAL_UINT(66u, EGO_FRAME_SIZE);
    TEST_ASSERT_EQUAL_UINT(EGO_FRAME_SIZE,
                           ego_frame_encode(out, sizeof out, f.scan, f.time_us, &f.out));
    TEST_ASSERT_EQUAL_HEX8_ARRAY(example_bytes, out, EGO_FRAME_SIZE);
    for (size_t i = EGO_FRAME_SIZE; i < sizeof out; i++) {
        TEST_ASSERT_EQUAL_HEX8(0xAAu, out[i]); /* nothing past the frame */
    }
    decoded_t d;
    decode_stream(example_bytes, sizeof example_bytes, FEED_WHOLE, 1u, &d);
    TEST_ASSERT_EQUAL_UINT(1u, d.count);
    assert_same_frame(&f, &d.frames[0], "example");
}

/* A version 1 frame decodes to the same fields, its covariance unknown;
 * both versions in one stream, in any chunking. */
static void test_ego_frame_version_1_still_decodes(void)
{
    ego_frame_t f = example_frame();
    ego_cov_unknown(&f.out.cov);
    static uint8_t s[2u * EGO_FRAME_SIZE + 3u * EGO_FRAME_V1_SIZE];
    size_t len = 0u;
    memcpy(&s[len], example_v1_bytes, EGO_FRAME_V1_SIZE);
    len += EGO_FRAME_V1_SIZE;
    memcpy(&s[len], example_bytes, EGO_FRAME_SIZE);
    len += EGO_FRAME_SIZE;
    memcpy(&s[len], example_v1_bytes, EGO_FRAME_V1_SIZE);
    len += EGO_FRAME_V1_SIZE;
    for (int mode = FEED_WHOLE; mode <= FEED_RANDOM; mode++) {
        decoded_t d;
        decode_stream(s, len, (feed_mode_t)mode, 7u, &d);
        TEST_ASSERT_EQUAL_UINT(3u, d.count);
        TEST_ASSERT_EQUAL_UINT32(0u, d.stats.bytes_skipped);
        TEST_ASSERT_EQUAL_UINT32(len, d.stats.bytes_framed);
        assert_same_frame(&f, &d.frames[0], "version 1");
        const ego_frame_t g = example_frame();
        assert_same_frame(&g, &d.frames[1], "version 2");
        assert_same_frame(&f, &d.frames[2], "version 1 again");
    }
    /* A version 1 length byte under version 2 (and the reverse) is wrong. */
    uint8_t bad[EGO_FRAME_SIZE];
    memcpy(bad, example_bytes, sizeof bad);
    bad[2] = EGO_FRAME_V1_PAYLOAD;
    decoded_t d;
    decode_stream(bad, sizeof bad, FEED_WHOLE, 1u, &d);
    TEST_ASSERT_EQUAL_UINT(0u, d.count);
    TEST_ASSERT_TRUE(d.stats.length_errors >= 1u);
}

static void test_ego_frame_encode_refuses_small_buffers(void)
{
    const ego_frame_t f = example_frame();
    uint8_t out[EGO_FRAME_SIZE];
    memset(out, 0x5A, sizeof out);
    TEST_ASSERT_EQUAL_UINT(0u, ego_frame_encode(out, EGO_FRAME_SIZE - 1u, 1u, 2u, &f.out));
    TEST_ASSERT_EQUAL_UINT(0u, ego_frame_encode(NULL, EGO_FRAME_SIZE, 1u, 2u, &f.out));
    TEST_ASSERT_EQUAL_UINT(0u, ego_frame_encode(out, EGO_FRAME_SIZE, 1u, 2u, NULL));
    TEST_ASSERT_EQUAL_HEX8(0x5Au, out[0]);
}

/* --- round trips --------------------------------------------------------- */

static void test_ego_frame_round_trip_extremes_and_random(void)
{
    static const int32_t s_edges[] = {0, 1, -1, INT32_MAX, INT32_MIN, 65536, -65536, 0x7FFF0000};
    static const uint32_t u_edges[] = {0u, 1u, 0x7FFFFFFFu, 0x80000000u, 0xFFFFFFFFu, 0xE5E5E5E5u};
    const size_t ns = sizeof s_edges / sizeof s_edges[0];
    const size_t nu = sizeof u_edges / sizeof u_edges[0];
    uint32_t seed = 0x1234567u;
    for (unsigned i = 0u; i < 2000u; i++) {
        ego_frame_t f;
        if (i < 64u) { /* every edge value in every field at least once */
            const int32_t s = s_edges[i % ns];
            const uint32_t u = u_edges[i % nu];
            f = make_frame(u, u_edges[(i + 1u) % nu], s, s_edges[(i + 3u) % ns], u,
                           s_edges[(i + 5u) % ns], s_edges[(i + 7u) % ns], s,
                           (uint16_t)(u >> (i % 17u)), (uint8_t)(i * 37u), (uint16_t)u);
        } else {
            f = random_frame(&seed);
        }
        uint8_t b[EGO_FRAME_SIZE];
        TEST_ASSERT_EQUAL_UINT(EGO_FRAME_SIZE, encode(b, &f));
        decoded_t d;
        decode_stream(b, sizeof b, FEED_WHOLE, 1u, &d);
        char msg[32];
        (void)snprintf(msg, sizeof msg, "case %u", i);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(1u, d.count, msg);
        assert_same_frame(&f, &d.frames[0], msg);
        TEST_ASSERT_EQUAL_UINT32(0u, d.stats.bytes_skipped);
    }
}

/* --- corruption ---------------------------------------------------------- */

static void test_ego_frame_every_single_bit_flip_is_rejected(void)
{
    uint32_t seed = 0xBADC0DEu;
    const ego_frame_t a = random_frame(&seed);
    const ego_frame_t b = random_frame(&seed);
    uint8_t s[2u * EGO_FRAME_SIZE];
    (void)encode(s, &a);
    (void)encode(&s[EGO_FRAME_SIZE], &b);
    for (unsigned bit = 0u; bit < 8u * EGO_FRAME_SIZE; bit++) {
        uint8_t t[sizeof s];
        memcpy(t, s, sizeof s);
        t[bit / 8u] ^= (uint8_t)(1u << (bit % 8u));
        char msg[32];
        (void)snprintf(msg, sizeof msg, "bit %u", bit);
        for (int mode = FEED_WHOLE; mode <= FEED_RANDOM; mode++) {
            decoded_t d;
            decode_stream(t, sizeof t, (feed_mode_t)mode, bit + 1u, &d);
            TEST_ASSERT_EQUAL_UINT_MESSAGE(1u, d.count, msg);
            assert_same_frame(&b, &d.frames[0], msg);
            TEST_ASSERT_EQUAL_UINT32_MESSAGE(EGO_FRAME_SIZE, d.stats.bytes_skipped, msg);
            if (bit >= 8u) { /* past the start byte: a counted rejection */
                TEST_ASSERT_TRUE_MESSAGE(d.stats.crc_errors + d.stats.length_errors >= 1u, msg);
            }
        }
    }
}

static void test_ego_frame_truncated_frames(void)
{
    uint32_t seed = 77u;
    const ego_frame_t a = random_frame(&seed);
    const ego_frame_t b = random_frame(&seed);
    uint8_t fa[EGO_FRAME_SIZE];
    uint8_t fb[EGO_FRAME_SIZE];
    (void)encode(fa, &a);
    (void)encode(fb, &b);
    for (size_t cut = 1u; cut < EGO_FRAME_SIZE; cut++) {
        char msg[32];
        (void)snprintf(msg, sizeof msg, "cut %u", (unsigned)cut);
        uint8_t s[2u * EGO_FRAME_SIZE];
        memcpy(s, fa, cut);
        /* Alone: pending until the flush, then one truncated candidate. */
        decoded_t d;
        decode_stream(s, cut, FEED_BYTES, 1u, &d);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, d.count, msg);
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(1u, d.stats.truncated, msg);
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(cut, d.stats.bytes_skipped, msg);
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(0u, d.stats.crc_errors + d.stats.length_errors, msg);
        /* Followed by a good frame: that one is found. */
        memcpy(&s[cut], fb, EGO_FRAME_SIZE);
        decode_stream(s, cut + EGO_FRAME_SIZE, FEED_WHOLE, 1u, &d);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(1u, d.count, msg);
        assert_same_frame(&b, &d.frames[0], msg);
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(cut, d.stats.bytes_skipped, msg);
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(0u, d.stats.truncated, msg);
    }
}

/* Garbage biased towards the bytes that start a candidate. */
static size_t put_garbage(uint8_t *out, size_t n, uint32_t *seed)
{
    static const uint8_t tricky[] = {EGO_FRAME_START, EGO_FRAME_VERSION, EGO_FRAME_PAYLOAD};
    for (size_t i = 0u; i < n; i++) {
        const uint32_t r = tu_rand(seed);
        out[i] = (r % 4u == 0u) ? tricky[(r >> 8) % 3u] : (uint8_t)(r >> 16);
    }
    return n;
}

/* A stream: garbage, then frames each followed by garbage, and a few
 * deliberately bad frames (wrong version, wrong length, wrong CRC). */
static size_t build_noisy_stream(uint8_t *s, size_t cap, uint32_t seed, ego_frame_t *good,
                                 size_t *n_good, uint32_t *n_garbage)
{
    size_t len = 0u;
    *n_good = 0u;
    *n_garbage = 0u;
    for (unsigned k = 0u; k < 40u; k++) {
        const size_t g = tu_rand_range(&seed, 0u, 60u);
        TEST_ASSERT_TRUE(len + g + EGO_FRAME_SIZE <= cap);
        len += put_garbage(&s[len], g, &seed);
        *n_garbage += (uint32_t)g;
        const ego_frame_t f = random_frame(&seed);
        (void)encode(&s[len], &f);
        if (k % 7u == 3u) { /* spoilt: counted as garbage */
            s[len + 1u + (k % 3u)] ^= 0x10u;
            *n_garbage += EGO_FRAME_SIZE;
        } else {
            good[(*n_good)++] = f;
        }
        len += EGO_FRAME_SIZE;
    }
    return len;
}

static void test_ego_frame_garbage_before_and_between(void)
{
    static uint8_t s[STREAM_MAX];
    static ego_frame_t good[MAX_FRAMES];
    static decoded_t d;
    for (uint32_t seed = 1u; seed <= 20u; seed++) {
        size_t n_good = 0u;
        uint32_t n_garbage = 0u;
        const size_t len = build_noisy_stream(s, sizeof s, seed * 7919u, good, &n_good, &n_garbage);
        decode_stream(s, len, FEED_RANDOM, seed, &d);
        TEST_ASSERT_EQUAL_UINT(n_good, d.count);
        for (size_t i = 0u; i < n_good; i++) {
            assert_same_frame(&good[i], &d.frames[i], "noisy");
        }
        TEST_ASSERT_EQUAL_UINT32(n_garbage, d.stats.bytes_skipped);
        TEST_ASSERT_TRUE(d.stats.crc_errors + d.stats.length_errors >= 5u);
    }
}

static void test_ego_frame_chunking_gives_identical_results(void)
{
    static uint8_t s[STREAM_MAX];
    static ego_frame_t good[MAX_FRAMES];
    static decoded_t whole;
    static decoded_t other;
    size_t n_good = 0u;
    uint32_t n_garbage = 0u;
    size_t len = build_noisy_stream(s, sizeof s, 4242u, good, &n_good, &n_garbage);
    /* An unfinished candidate at the end, for the flush. */
    s[len++] = EGO_FRAME_START;
    s[len++] = EGO_FRAME_VERSION;
    s[len++] = EGO_FRAME_PAYLOAD;
    decode_stream(s, len, FEED_WHOLE, 1u, &whole);
    TEST_ASSERT_EQUAL_UINT(n_good, whole.count);
    TEST_ASSERT_EQUAL_UINT32(1u, whole.stats.truncated);
    for (int mode = FEED_BYTES; mode <= FEED_RANDOM; mode++) {
        for (uint32_t seed = 1u; seed <= 5u; seed++) {
            decode_stream(s, len, (feed_mode_t)mode, seed, &other);
            TEST_ASSERT_EQUAL_UINT(whole.count, other.count);
            for (size_t i = 0u; i < whole.count; i++) {
                assert_same_frame(&whole.frames[i], &other.frames[i], "chunking");
            }
            assert_same_stats(&whole.stats, &other.stats);
        }
    }
}

static void test_ego_frame_feed_null_and_empty(void)
{
    ego_frame_decoder_t d;
    ego_frame_decoder_init(&d);
    size_t used = 99u;
    ego_frame_t f;
    TEST_ASSERT_EQUAL_INT(EGO_FRAME_NEED_MORE, ego_frame_feed(&d, NULL, 5u, &used, &f));
    TEST_ASSERT_EQUAL_UINT(0u, used);
    TEST_ASSERT_EQUAL_UINT32(0u, ego_frame_stats(&d)->bytes_in);
    ego_frame_flush(&d);
    TEST_ASSERT_EQUAL_UINT32(0u, ego_frame_stats(&d)->truncated);
}

/* A version 2 candidate whose CRC fails can hold a whole version 1 frame
 * and the start of the next frame after it (fuzz_frame found it, issue 18):
 * the version 1 frame is reported with its own 42 bytes, and the bytes
 * after it stay buffered, so the next frame is still found. The decoder
 * used to count the whole buffer as the frame's and drop the rest. */
static void test_ego_frame_short_frame_inside_a_bad_candidate(void)
{
    static uint8_t s[EGO_FRAME_SIZE + EGO_FRAME_SIZE];
    size_t len = 0u;
    const uint8_t head[] = {0xE5, 0x02, 0x3D, 0x11, 0x22, 0x33, 0x44, 0x55};
    memcpy(&s[len], head, sizeof head);
    len += sizeof head;
    memcpy(&s[len], example_v1_bytes, EGO_FRAME_V1_SIZE);
    len += EGO_FRAME_V1_SIZE;
    /* The bogus candidate ends 16 bytes into the next frame. */
    TEST_ASSERT_EQUAL_UINT(EGO_FRAME_SIZE - 16u, len);
    memcpy(&s[len], example_bytes, EGO_FRAME_SIZE);
    len += EGO_FRAME_SIZE;
    for (int mode = FEED_WHOLE; mode <= FEED_RANDOM; mode++) {
        decoded_t d;
        decode_stream(s, len, (feed_mode_t)mode, 3u, &d);
        TEST_ASSERT_EQUAL_UINT(2u, d.count);
        ego_frame_t f = example_frame();
        ego_cov_unknown(&f.out.cov);
        assert_same_frame(&f, &d.frames[0], "version 1 inside");
        const ego_frame_t g = example_frame();
        assert_same_frame(&g, &d.frames[1], "version 2 after it");
        TEST_ASSERT_EQUAL_UINT32(EGO_FRAME_V1_SIZE + EGO_FRAME_SIZE, d.stats.bytes_framed);
        TEST_ASSERT_EQUAL_UINT32(sizeof head, d.stats.bytes_skipped);
        TEST_ASSERT_EQUAL_UINT32(1u, d.stats.crc_errors);
    }
}

/* --- the CSV line ------------------------------------------------------- */

static void test_ego_format_line_example(void)
{
    const ego_frame_t f = example_frame();
    char line[EGO_LOOP_LINE_MAX];
    const char *expect = "16909060,0.026667,-1.500000,0.250000,1.570796,-32768.000000,0.000015,"
                         "32767.999985,34,200,4660,9.537e-07,-4.768e-07,inf,1.000e+00,-inf,"
                         "9.313e-10\n";
    TEST_ASSERT_EQUAL_UINT(strlen(expect),
                           ego_format_line(line, sizeof line, f.scan, f.time_us, &f.out));
    TEST_ASSERT_EQUAL_STRING(expect, line);
    /* A half turn is -pi; tiny negatives keep their sign. */
    const ego_frame_t g = make_frame(1u, 0u, -1, -32, 0x80000000u, 0, 0, -98304, 0u, 0u, 0u);
    (void)ego_format_line(line, sizeof line, g.scan, g.time_us, &g.out);
    TEST_ASSERT_EQUAL_STRING("1,0.000000,-0.000015,-0.000488,-3.141593,0.000000,0.000000,"
                             "-1.500000,0,0,0,inf,0,0,inf,0,inf\n",
                             line);
    /* A small buffer truncates, NUL-terminated; cap 0 writes nothing. */
    TEST_ASSERT_EQUAL_UINT(9u, ego_format_line(line, 10u, f.scan, f.time_us, &f.out));
    TEST_ASSERT_EQUAL_STRING("16909060,", line);
    line[0] = 'x';
    TEST_ASSERT_EQUAL_UINT(0u, ego_format_line(line, 0u, f.scan, f.time_us, &f.out));
    TEST_ASSERT_EQUAL_HEX8('x', line[0]);
}

/* Micro-units of a Q16.16 value, rounded half away from zero (the CSV's
 * rule), by long division instead of a shift. */
static int64_t ref_micro(int64_t num, int64_t den)
{
    const int64_t mag = (num < 0) ? -num : num;
    const int64_t q = (mag + den / 2) / den;
    return (num < 0) ? -q : q;
}

static void ref_number(char *out, size_t cap, int64_t micro)
{
    const int64_t mag = (micro < 0) ? -micro : micro;
    /* long long, not PRId64: arm-none-eabi-gcc's <stdint.h> leaves newlib's
     * <inttypes.h> without the 64-bit PRI macros (the target_unit images). */
    (void)snprintf(out, cap, "%s%lld.%06lld", (micro < 0) ? "-" : "", (long long)(mag / 1000000),
                   (long long)(mag % 1000000));
}

/* The line the CSV has always had (the format of docs, README and the
 * accuracy tests), from snprintf. */
static void ref_line(char *out, size_t cap, const ego_frame_t *f)
{
    char v[6][40];
    const int32_t q16[5] = {f->out.pose.x, f->out.pose.y, f->out.vx, f->out.vy, f->out.omega};
    int64_t theta = fx_bam32_diff(f->out.pose.theta, 0u);
    ref_number(v[0], sizeof v[0], ref_micro((int64_t)q16[0] * 1000000, 65536));
    ref_number(v[1], sizeof v[1], ref_micro((int64_t)q16[1] * 1000000, 65536));
    /* 6283185 microradians per turn, the loop's constant. */
    ref_number(v[2], sizeof v[2], ref_micro(theta * 6283185, (int64_t)1 << 32));
    for (unsigned i = 2u; i < 5u; i++) {
        ref_number(v[i + 1u], sizeof v[i + 1u], ref_micro((int64_t)q16[i] * 1000000, 65536));
    }
    char c[6][24];
    const int32_t cov[6] = {f->out.cov.xx, f->out.cov.xy, f->out.cov.xt,
                            f->out.cov.yy, f->out.cov.yt, f->out.cov.tt};
    for (unsigned k = 0u; k < 6u; k++) {
        if (cov[k] == INT32_MAX || cov[k] == INT32_MIN) {
            (void)snprintf(c[k], sizeof c[k], "%sinf", (cov[k] < 0) ? "-" : "");
        } else if (cov[k] == 0) {
            (void)snprintf(c[k], sizeof c[k], "0");
        } else {
            (void)snprintf(c[k], sizeof c[k], "%.3e", (double)cov[k] / 1073741824.0);
        }
    }
    (void)snprintf(out, cap,
                   "%" PRIu32 ",%" PRIu32 ".%06" PRIu32 ",%s,%s,%s,%s,%s,%s,%u,%u,%u,%s,%s,%s,%s,%s,%s\n",
                   f->scan, f->time_us / 1000000u, f->time_us % 1000000u, v[0], v[1], v[2], v[3],
                   v[4], v[5], (unsigned)f->out.flags, (unsigned)f->out.iterations,
                   (unsigned)f->out.matches, c[0], c[1], c[2], c[3], c[4], c[5]);
}

static void test_ego_format_line_matches_printf_oracle(void)
{
    uint32_t seed = 99u;
    for (unsigned i = 0u; i < 5000u; i++) {
        ego_frame_t f = random_frame(&seed);
        if (i % 3u == 0u) { /* small values: the sign and rounding of fractions */
            f.out.pose.x = rand_s32(&seed) / 65536;
            f.out.vy = rand_s32(&seed) / 4096;
            f.out.pose.theta = tu_rand(&seed) % 64u;
        } else if (i % 3u == 1u) {
            f.out.pose.theta = 0u - (tu_rand(&seed) % 64u);
        }
        char line[EGO_LOOP_LINE_MAX];
        char expect[512]; /* room for the longest fields (-Wformat-truncation at -Os) */
        const size_t n = ego_format_line(line, sizeof line, f.scan, f.time_us, &f.out);
        ref_line(expect, sizeof expect, &f);
        TEST_ASSERT_EQUAL_STRING(expect, line);
        TEST_ASSERT_EQUAL_UINT(strlen(expect), n);
        TEST_ASSERT_TRUE(n + 1u < EGO_LOOP_LINE_MAX);
    }
}

/* --- ego_loop: frames vs CSV --------------------------------------------- */

typedef struct {
    const uint8_t *in;
    size_t in_len;
    size_t in_pos;
    uint8_t out[32768];
    size_t out_len;
} mem_hal_t;

static int32_t mem_read(void *ctx, uint8_t *buf, size_t cap)
{
    mem_hal_t *m = ctx;
    if (m->in_pos >= m->in_len) {
        return -1;
    }
    size_t n = m->in_len - m->in_pos;
    n = (n < cap) ? n : cap;
    n = (n < 97u) ? n : 97u; /* odd chunks: telegrams straddle reads */
    memcpy(buf, &m->in[m->in_pos], n);
    m->in_pos += n;
    return (int32_t)n;
}

static void mem_write(void *ctx, const uint8_t *buf, size_t len)
{
    mem_hal_t *m = ctx;
    TEST_ASSERT_TRUE(m->out_len + len <= sizeof m->out);
    memcpy(&m->out[m->out_len], buf, len);
    m->out_len += len;
}

static uint32_t mem_now(void *ctx)
{
    (void)ctx;
    return 0u;
}

static void run_loop(const uint8_t *stream, size_t len, bool frames, mem_hal_t *m,
                     ego_loop_stats_t *stats)
{
    static ego_loop_t loop;
    ego_loop_config_t config;
    ego_loop_defaults(&config);
    config.frames = frames;
    memset(m, 0, sizeof *m);
    m->in = stream;
    m->in_len = len;
    const ego_hal_t hal = {mem_read, mem_write, mem_now, m};
    ego_loop_init(&loop, &config);
    for (unsigned guard = 0u; guard < 10000u; guard++) {
        if (ego_loop_step(&loop, &hal) == EGO_LOOP_END) {
            break;
        }
    }
    *stats = *ego_loop_stats(&loop);
}

static void test_ego_loop_frames_decode_to_its_csv(void)
{
    enum { SCANS = 8 };
    static uint8_t stream[SCANS * (2u * LMS_SCAN_MAX_VALUES + 16u) + 8u];
    static lms_scan_t scan;
    static mem_hal_t csv;
    static mem_hal_t bin;
    static decoded_t d;
    size_t len = 0u;
    for (unsigned k = 0u; k < SCANS; k++) {
        memset(&scan, 0, sizeof scan);
        /* A drive with a turn, and a scan with a wall lost to make a flag. */
        synth_scan(synth_room, synth_room_walls, 0.08 * k, 0.01 * k * k,
                   (2.0 * k) * FX_HOST_PI / 180.0, 181u, LMS_UNIT_CM, &scan);
        scan.address = 0x80u;
        if (k == 3u) {
            stream[len++] = 0x42u; /* a stray byte between telegrams */
        }
        size_t written = 0u;
        TEST_ASSERT_EQUAL_INT(LMS_OK, lms_encode_scan(&stream[len], sizeof stream - len, 0x80u,
                                                      &scan, &written));
        len += written;
    }
    ego_loop_stats_t st_csv;
    ego_loop_stats_t st_bin;
    run_loop(stream, len, false, &csv, &st_csv);
    run_loop(stream, len, true, &bin, &st_bin);
    TEST_ASSERT_EQUAL_UINT32(SCANS, st_csv.scans);
    TEST_ASSERT_EQUAL_UINT32(SCANS - 1u, st_csv.lines);
    TEST_ASSERT_EQUAL_UINT32(st_csv.lines, st_bin.lines);
    TEST_ASSERT_EQUAL_UINT((SCANS - 1u) * EGO_FRAME_SIZE, bin.out_len);

    decode_stream(bin.out, bin.out_len, FEED_BYTES, 1u, &d);
    TEST_ASSERT_EQUAL_UINT(SCANS - 1u, d.count);
    TEST_ASSERT_EQUAL_UINT32(0u, d.stats.bytes_skipped);
    static char text[sizeof csv.out];
    size_t n = (size_t)snprintf(text, sizeof text, "%s", EGO_LOOP_CSV_HEADER);
    for (size_t i = 0u; i < d.count; i++) {
        TEST_ASSERT_EQUAL_UINT32(i + 1u, d.frames[i].scan);
        n += ego_format_line(&text[n], sizeof text - n, d.frames[i].scan, d.frames[i].time_us,
                             &d.frames[i].out);
    }
    TEST_ASSERT_EQUAL_UINT(csv.out_len, n);
    TEST_ASSERT_EQUAL_MEMORY(csv.out, text, n);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_ego_frame_crc_check_values);
    RUN_TEST(test_ego_frame_layout_byte_by_byte);
    RUN_TEST(test_ego_frame_version_1_still_decodes);
    RUN_TEST(test_ego_frame_encode_refuses_small_buffers);
    RUN_TEST(test_ego_frame_round_trip_extremes_and_random);
    RUN_TEST(test_ego_frame_every_single_bit_flip_is_rejected);
    RUN_TEST(test_ego_frame_truncated_frames);
    RUN_TEST(test_ego_frame_garbage_before_and_between);
    RUN_TEST(test_ego_frame_chunking_gives_identical_results);
    RUN_TEST(test_ego_frame_feed_null_and_empty);
    RUN_TEST(test_ego_frame_short_frame_inside_a_bad_candidate);
    RUN_TEST(test_ego_format_line_example);
    RUN_TEST(test_ego_format_line_matches_printf_oracle);
    RUN_TEST(test_ego_loop_frames_decode_to_its_csv);
    return UNITY_END();
}
