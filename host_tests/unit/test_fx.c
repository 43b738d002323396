/* test_fx.c - the inline helpers and constant macros of ego_fx.h: rounding
 * shift over its whole shift range and the int64 edges (INT64_MIN and
 * INT64_MAX included), ties, saturation, the Q16.16 and Q16.16 x Q2.30
 * products, saturating add/sub, the binary-angle difference over the wrap,
 * and the compile-time constant macros. Each helper is also compared with
 * an independent reference (integer division and remainder instead of
 * shifts) on seeded random inputs.
 */
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "ego_fx.h"
#include "test_rng.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

/* splitmix64 (test_rng.h), fixed seed: the same inputs on every run and every host. */
static uint64_t rng_state;

static uint64_t rng_next(void)
{
    return test_rng_next(&rng_state);
}

/* A random int64: uniform bits, or a random bit length, either sign. */
static int64_t rng_s64(void)
{
    const uint64_t r = rng_next();
    if ((r & 1u) != 0u) {
        return (int64_t)rng_next();
    }
    const unsigned bits = (unsigned)((r >> 1) % 64u);
    const uint64_t mag = rng_next() >> (63u - bits); /* < 2^(bits + 1) */
    return ((r >> 8) & 1u) != 0u ? -(int64_t)(mag >> 1) : (int64_t)(mag >> 1);
}

/* 64-bit comparison with both values in the failure text (the subset has
 * no _INT64 assertions). */
static void expect_s64(int64_t expected, int64_t actual, const char *what)
{
    if (expected != actual) {
        char msg[160];
        (void)snprintf(msg, sizeof msg, "%s: expected %lld, was %lld", what,
                       (long long)expected, (long long)actual);
        TEST_FAIL_MESSAGE(msg);
    }
}

/* Reference for fx_shr_round_s64: v / 2^s by C division (truncates toward
 * zero), then away from zero when the dropped part is at least half. */
static int64_t ref_shr_round(int64_t v, unsigned s)
{
    const int64_t p = (int64_t)((uint64_t)1 << s); /* s <= 62 */
    int64_t q = v / p;
    const int64_t rem = v % p;
    const int64_t arem = rem < 0 ? -rem : rem;
    if (arem >= p - arem) {
        q += (v < 0) ? -1 : 1;
    }
    return q;
}

static int64_t ref_sat_s32(int64_t v)
{
    return v > INT32_MAX ? INT32_MAX : (v < INT32_MIN ? INT32_MIN : v);
}

/* ---- fx_shr_round_s64 ---- */

static void test_fx_shr_round_small_values_and_ties(void)
{
    /* x.5 rounds away from zero, on both sides. */
    expect_s64(1, fx_shr_round_s64(1, 1u), "0.5");
    expect_s64(-1, fx_shr_round_s64(-1, 1u), "-0.5");
    expect_s64(2, fx_shr_round_s64(3, 1u), "1.5");
    expect_s64(-2, fx_shr_round_s64(-3, 1u), "-1.5");
    expect_s64(3, fx_shr_round_s64(5, 1u), "2.5 (not to even)");
    expect_s64(-3, fx_shr_round_s64(-5, 1u), "-2.5 (not to even)");
    expect_s64(1, fx_shr_round_s64(2, 2u), "0.5 at s = 2");
    expect_s64(0, fx_shr_round_s64(1, 2u), "0.25");
    expect_s64(0, fx_shr_round_s64(-1, 2u), "-0.25");
    expect_s64(1, fx_shr_round_s64(3, 2u), "0.75");
    expect_s64(-1, fx_shr_round_s64(-3, 2u), "-0.75");
    expect_s64(0, fx_shr_round_s64(0, 1u), "0, s = 1");
    expect_s64(0, fx_shr_round_s64(0, 62u), "0, s = 62");
    /* Just below and at a tie, large shift. */
    const int64_t half62 = (int64_t)1 << 61;
    expect_s64(0, fx_shr_round_s64(half62 - 1, 62u), "2^61 - 1 >> 62");
    expect_s64(1, fx_shr_round_s64(half62, 62u), "2^61 >> 62");
    expect_s64(0, fx_shr_round_s64(-(half62 - 1), 62u), "-(2^61 - 1) >> 62");
    expect_s64(-1, fx_shr_round_s64(-half62, 62u), "-2^61 >> 62");
    /* Exact multiples are exact. */
    for (unsigned s = 1u; s <= 62u; s++) {
        expect_s64(-1, fx_shr_round_s64(-((int64_t)1 << s), s), "-2^s >> s");
        expect_s64(1, fx_shr_round_s64((int64_t)1 << s, s), "2^s >> s");
    }
}

static void test_fx_shr_round_int64_edges(void)
{
    /* INT64_MAX / 2 = 2^62 - 0.5 -> 2^62; INT64_MIN / 2 = -2^62 exactly. */
    expect_s64((int64_t)1 << 62, fx_shr_round_s64(INT64_MAX, 1u), "INT64_MAX >> 1");
    expect_s64(-((int64_t)1 << 62), fx_shr_round_s64(INT64_MIN, 1u), "INT64_MIN >> 1");
    expect_s64(-((int64_t)1 << 62), fx_shr_round_s64(INT64_MIN + 1, 1u), "(INT64_MIN + 1) >> 1");
    expect_s64(2, fx_shr_round_s64(INT64_MAX, 62u), "INT64_MAX >> 62");
    expect_s64(-2, fx_shr_round_s64(INT64_MIN, 62u), "INT64_MIN >> 62");
    expect_s64(-2, fx_shr_round_s64(INT64_MIN + 1, 62u), "(INT64_MIN + 1) >> 62");
    expect_s64(4294967296, fx_shr_round_s64(INT64_MAX, 31u), "INT64_MAX >> 31");
    expect_s64(-4294967296, fx_shr_round_s64(INT64_MIN, 31u), "INT64_MIN >> 31");
    /* Every shift amount at the edges and around zero, against the
     * reference. */
    const int64_t edges[] = {INT64_MIN, INT64_MIN + 1, INT64_MIN + 2, -4294967297, -4294967296,
                             -65537, -65536, -3, -2, -1, 0, 1, 2, 3, 65536, 65537,
                             4294967296, 4294967297, INT64_MAX - 2, INT64_MAX - 1, INT64_MAX};
    for (unsigned s = 1u; s <= 62u; s++) {
        for (size_t i = 0u; i < sizeof edges / sizeof edges[0]; i++) {
            char what[64];
            (void)snprintf(what, sizeof what, "%lld >> %u", (long long)edges[i], s);
            expect_s64(ref_shr_round(edges[i], s), fx_shr_round_s64(edges[i], s), what);
        }
    }
}

/* Ties at every shift: k * 2^s + 2^(s-1) and its negation, for several k. */
static void test_fx_shr_round_ties_every_shift(void)
{
    for (unsigned s = 1u; s <= 62u; s++) {
        const int64_t half = (int64_t)1 << (s - 1u);
        const int64_t ks[] = {0, 1, 2, 7};
        for (size_t i = 0u; i < sizeof ks / sizeof ks[0]; i++) {
            if (ks[i] > (INT64_MAX - half) >> s) {
                continue;
            }
            const int64_t v = ks[i] * ((int64_t)1 << s) + half;
            char what[64];
            (void)snprintf(what, sizeof what, "tie %lld >> %u", (long long)v, s);
            expect_s64(ks[i] + 1, fx_shr_round_s64(v, s), what);
            expect_s64(-(ks[i] + 1), fx_shr_round_s64(-v, s), what);
            expect_s64(ks[i], fx_shr_round_s64(v - 1, s), what);
            expect_s64(-ks[i], fx_shr_round_s64(-(v - 1), s), what);
        }
    }
}

static void test_fx_shr_round_random_against_reference(void)
{
    rng_state = 0x5EEDu;
    for (unsigned i = 0u; i < 200000u; i++) {
        const int64_t v = rng_s64();
        const unsigned s = 1u + (unsigned)(rng_next() % 62u);
        const int64_t got = fx_shr_round_s64(v, s);
        const int64_t want = ref_shr_round(v, s);
        if (got != want) {
            char what[64];
            (void)snprintf(what, sizeof what, "%lld >> %u", (long long)v, s);
            expect_s64(want, got, what);
        }
    }
}

/* ---- fx_sat_s32 ---- */

static void test_fx_sat_s32_edges(void)
{
    TEST_ASSERT_EQUAL_INT32(0, fx_sat_s32(0));
    TEST_ASSERT_EQUAL_INT32(-1, fx_sat_s32(-1));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_sat_s32(INT32_MAX));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_sat_s32((int64_t)INT32_MAX + 1));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_sat_s32(INT32_MIN));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_sat_s32((int64_t)INT32_MIN - 1));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_sat_s32(INT64_MAX));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_sat_s32(INT64_MIN));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_sat_s32(4294967296));  /* no wrap to 0 */
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_sat_s32(-4294967296));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_sat_s32(4294967295));  /* no wrap to -1 */
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_sat_s32(-4294967295)); /* no wrap to 1 */
    rng_state = 0x5A7u;
    for (unsigned i = 0u; i < 100000u; i++) {
        const int64_t v = rng_s64();
        expect_s64(ref_sat_s32(v), fx_sat_s32(v), "fx_sat_s32 random");
    }
}

/* ---- products ---- */

static void test_fx_mul_q16_q30_values(void)
{
    const fx_q2_30_t one = FX_Q2_30_ONE;
    TEST_ASSERT_EQUAL_INT32(FX_Q16_16_ONE, fx_mul_q16_q30(FX_Q16_16_ONE, one));
    TEST_ASSERT_EQUAL_INT32(-FX_Q16_16_ONE, fx_mul_q16_q30(FX_Q16_16_ONE, -one));
    TEST_ASSERT_EQUAL_INT32(12345678, fx_mul_q16_q30(12345678, one));
    TEST_ASSERT_EQUAL_INT32(-12345678, fx_mul_q16_q30(-12345678, one));
    TEST_ASSERT_EQUAL_INT32(6172839, fx_mul_q16_q30(12345678, one / 2)); /* exact half */
    /* 1 LSB x 0.5 = 0.5 LSB -> 1 (away from zero); x -0.5 -> -1. */
    TEST_ASSERT_EQUAL_INT32(1, fx_mul_q16_q30(1, one / 2));
    TEST_ASSERT_EQUAL_INT32(-1, fx_mul_q16_q30(1, -one / 2));
    TEST_ASSERT_EQUAL_INT32(-1, fx_mul_q16_q30(-1, one / 2));
    TEST_ASSERT_EQUAL_INT32(0, fx_mul_q16_q30(1, one / 2 - 1));
    TEST_ASSERT_EQUAL_INT32(0, fx_mul_q16_q30(-1, one / 2 - 1));
    /* 3 x 0.5 = 1.5 -> 2. */
    TEST_ASSERT_EQUAL_INT32(2, fx_mul_q16_q30(3, one / 2));
    TEST_ASSERT_EQUAL_INT32(-2, fx_mul_q16_q30(-3, one / 2));
    /* Q2.30 reaches -2.0: only the full-scale products saturate. */
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_mul_q16_q30(INT32_MIN, INT32_MIN)); /* +2^32 */
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_mul_q16_q30(INT32_MAX, INT32_MIN));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_mul_q16_q30(INT32_MIN, one));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_mul_q16_q30(INT32_MAX, one));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_mul_q16_q30(INT32_MIN, -one)); /* 2^31 does not fit */
    /* 16384 m x (2 - 1 LSB) is exactly INT32_MAX; 1 LSB more saturates. */
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_mul_q16_q30(0x40000000, INT32_MAX));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_mul_q16_q30(0x40000001, INT32_MAX));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN + 1, fx_mul_q16_q30(-0x40000000, INT32_MAX));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_mul_q16_q30(-0x40000001, INT32_MAX));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN + 1, fx_mul_q16_q30(INT32_MAX, -one));
    TEST_ASSERT_EQUAL_INT32(0, fx_mul_q16_q30(INT32_MAX, 0));
    TEST_ASSERT_EQUAL_INT32(0, fx_mul_q16_q30(0, INT32_MIN));
    /* 81.9 m x cos(60 deg) = 40.95 m. */
    TEST_ASSERT_EQUAL_INT32(FX_Q16_16_C(40.95), fx_mul_q16_q30(FX_Q16_16_C(81.9), one / 2));
}

static void test_fx_mul_q16_values(void)
{
    TEST_ASSERT_EQUAL_INT32(FX_Q16_16_C(3.0), fx_mul_q16(FX_Q16_16_C(1.5), FX_Q16_16_C(2.0)));
    TEST_ASSERT_EQUAL_INT32(FX_Q16_16_C(-3.0), fx_mul_q16(FX_Q16_16_C(-1.5), FX_Q16_16_C(2.0)));
    TEST_ASSERT_EQUAL_INT32(FX_Q16_16_C(0.25), fx_mul_q16(FX_Q16_16_C(-0.5), FX_Q16_16_C(-0.5)));
    /* 1 LSB x 0.5 -> 1; 1 LSB x (0.5 - 1 LSB) -> 0; negative side mirrors. */
    TEST_ASSERT_EQUAL_INT32(1, fx_mul_q16(1, 0x8000));
    TEST_ASSERT_EQUAL_INT32(-1, fx_mul_q16(-1, 0x8000));
    TEST_ASSERT_EQUAL_INT32(0, fx_mul_q16(1, 0x7FFF));
    TEST_ASSERT_EQUAL_INT32(0, fx_mul_q16(-1, 0x7FFF));
    TEST_ASSERT_EQUAL_INT32(1, fx_mul_q16(1, 0x8001));
    /* Saturation: 256 x 128 = 32768 does not fit, (256 - 1/128) x 128 does. */
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_mul_q16(FX_Q16_16_C(256.0), FX_Q16_16_C(128.0)));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_mul_q16(FX_Q16_16_C(-256.0), FX_Q16_16_C(128.0)));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_mul_q16(INT32_MIN, INT32_MIN));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_mul_q16(INT32_MIN, INT32_MAX));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX - 127, fx_mul_q16(INT32_MAX - 127, FX_Q16_16_ONE));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_mul_q16(INT32_MIN, FX_Q16_16_ONE));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_mul_q16(INT32_MIN, -FX_Q16_16_ONE));
    TEST_ASSERT_EQUAL_INT32(0x7FFF0000, fx_mul_q16(FX_Q16_16_C(255.9921875), FX_Q16_16_C(128.0)));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_mul_q16(0x7FFFFF00, 0x00010080));
}

static void test_fx_products_random_against_reference(void)
{
    rng_state = 0x9D0Du;
    for (unsigned i = 0u; i < 200000u; i++) {
        const int32_t a = (int32_t)(uint32_t)rng_next();
        int32_t b = (int32_t)(uint32_t)rng_next();
        if ((i & 1u) != 0u) {
            const int shift = (int)(rng_next() % 31u);
            b = b / (int32_t)(1 << shift); /* smaller magnitudes too */
        }
        const int64_t p = (int64_t)a * b;
        expect_s64(ref_sat_s32(ref_shr_round(p, 30u)), fx_mul_q16_q30(a, b), "fx_mul_q16_q30");
        expect_s64(ref_sat_s32(ref_shr_round(p, 16u)), fx_mul_q16(a, b), "fx_mul_q16");
    }
}

/* ---- add / sub ---- */

static void test_fx_add_sub_saturate(void)
{
    TEST_ASSERT_EQUAL_INT32(FX_Q16_16_C(3.5), fx_add_q16(FX_Q16_16_C(1.25), FX_Q16_16_C(2.25)));
    TEST_ASSERT_EQUAL_INT32(FX_Q16_16_C(-1.0), fx_sub_q16(FX_Q16_16_C(1.25), FX_Q16_16_C(2.25)));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_add_q16(INT32_MAX, 1));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_add_q16(INT32_MAX, INT32_MAX));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_add_q16(INT32_MIN, -1));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_add_q16(INT32_MIN, INT32_MIN));
    TEST_ASSERT_EQUAL_INT32(-1, fx_add_q16(INT32_MIN, INT32_MAX));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_add_q16(INT32_MAX - 1, 1));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_sub_q16(INT32_MAX, -1));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_sub_q16(0, INT32_MIN));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_sub_q16(-1, INT32_MIN)); /* exact, no clamp */
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_sub_q16(INT32_MIN, 1));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_sub_q16(INT32_MIN, INT32_MAX));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN + 1, fx_sub_q16(0, INT32_MAX));
    TEST_ASSERT_EQUAL_INT32(0, fx_sub_q16(INT32_MIN, INT32_MIN));
    rng_state = 0xADDu;
    for (unsigned i = 0u; i < 200000u; i++) {
        const int32_t a = (int32_t)(uint32_t)rng_next();
        const int32_t b = (int32_t)(uint32_t)rng_next();
        expect_s64(ref_sat_s32((int64_t)a + b), fx_add_q16(a, b), "fx_add_q16");
        expect_s64(ref_sat_s32((int64_t)a - b), fx_sub_q16(a, b), "fx_sub_q16");
    }
}

/* ---- fx_bam32_diff ---- */

/* Reference: (a - b) mod 2^32 brought into [-2^31, 2^31) in int64. */
static int64_t ref_bam_diff(uint32_t a, uint32_t b)
{
    int64_t d = ((int64_t)a - (int64_t)b) % 4294967296;
    if (d >= 2147483648) {
        d -= 4294967296;
    }
    if (d < -2147483648) {
        d += 4294967296;
    }
    return d;
}

static void test_fx_bam32_diff_edges(void)
{
    TEST_ASSERT_EQUAL_INT32(0, fx_bam32_diff(0u, 0u));
    TEST_ASSERT_EQUAL_INT32(1, fx_bam32_diff(1u, 0u));
    TEST_ASSERT_EQUAL_INT32(-1, fx_bam32_diff(0u, 1u));
    TEST_ASSERT_EQUAL_INT32(1, fx_bam32_diff(0u, 0xFFFFFFFFu));  /* across the wrap */
    TEST_ASSERT_EQUAL_INT32(-1, fx_bam32_diff(0xFFFFFFFFu, 0u));
    TEST_ASSERT_EQUAL_INT32(7, fx_bam32_diff(5u, 0xFFFFFFFEu));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_bam32_diff(0x7FFFFFFFu, 0u));
    /* Exactly half a turn is -half (the range is [-half, half)). */
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_bam32_diff(FX_BAM32_HALF, 0u));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_bam32_diff(0u, FX_BAM32_HALF));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, fx_bam32_diff(0xC0000000u, FX_BAM32_QUARTER));
    TEST_ASSERT_EQUAL_INT32(-INT32_MAX, fx_bam32_diff(0x80000001u, 0u));
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, fx_bam32_diff(0u, 0x80000001u));
    TEST_ASSERT_EQUAL_INT32((int32_t)FX_BAM32_QUARTER, fx_bam32_diff(FX_BAM32_QUARTER, 0u));
    TEST_ASSERT_EQUAL_INT32(-(int32_t)FX_BAM32_QUARTER, fx_bam32_diff(0u, FX_BAM32_QUARTER));
    TEST_ASSERT_EQUAL_INT32(-(int32_t)FX_BAM32_QUARTER, fx_bam32_diff(0xC0000000u, 0u));
    TEST_ASSERT_EQUAL_INT32(2, fx_bam32_diff(1u, 0xFFFFFFFFu));
    const uint32_t edges[] = {0u, 1u, 2u, 0x3FFFFFFFu, 0x40000000u, 0x7FFFFFFEu, 0x7FFFFFFFu,
                              0x80000000u, 0x80000001u, 0xBFFFFFFFu, 0xC0000000u, 0xFFFFFFFEu,
                              0xFFFFFFFFu};
    for (size_t i = 0u; i < sizeof edges / sizeof edges[0]; i++) {
        for (size_t j = 0u; j < sizeof edges / sizeof edges[0]; j++) {
            expect_s64(ref_bam_diff(edges[i], edges[j]), fx_bam32_diff(edges[i], edges[j]),
                       "fx_bam32_diff edges");
        }
    }
    rng_state = 0xB4A3u;
    for (unsigned i = 0u; i < 200000u; i++) {
        const uint32_t a = (uint32_t)rng_next();
        const uint32_t b = (uint32_t)rng_next();
        expect_s64(ref_bam_diff(a, b), fx_bam32_diff(a, b), "fx_bam32_diff random");
    }
}

/* ---- constants ---- */

/* In a static initializer (a constant expression, folded at compile time). */
static const fx_q16_16_t k_range_max = FX_Q16_16_C(81.9);
static const fx_bam32_t k_beam_step = FX_BAM32_DEG_C(0.25);

static void test_fx_q16_16_constants(void)
{
    TEST_ASSERT_EQUAL_INT32(0x00010000, FX_Q16_16_ONE);
    TEST_ASSERT_EQUAL_INT32(0x40000000, FX_Q2_30_ONE);
    TEST_ASSERT_EQUAL_INT32(0, FX_Q16_16_C(0.0));
    TEST_ASSERT_EQUAL_INT32(0x00010000, FX_Q16_16_C(1.0));
    TEST_ASSERT_EQUAL_INT32(0x00010000, FX_Q16_16_C(1));
    TEST_ASSERT_EQUAL_INT32(-0x00010000, FX_Q16_16_C(-1.0));
    TEST_ASSERT_EQUAL_INT32(0x00008000, FX_Q16_16_C(0.5));
    TEST_ASSERT_EQUAL_INT32(-0x00008000, FX_Q16_16_C(-0.5));
    TEST_ASSERT_EQUAL_INT32(1, FX_Q16_16_C(1.0 / 65536.0));
    TEST_ASSERT_EQUAL_INT32(-1, FX_Q16_16_C(-1.0 / 65536.0));
    /* Ties away from zero (1.5 and 2.5 LSB), not to even. */
    TEST_ASSERT_EQUAL_INT32(2, FX_Q16_16_C(1.5 / 65536.0));
    TEST_ASSERT_EQUAL_INT32(3, FX_Q16_16_C(2.5 / 65536.0));
    TEST_ASSERT_EQUAL_INT32(-2, FX_Q16_16_C(-1.5 / 65536.0));
    TEST_ASSERT_EQUAL_INT32(-3, FX_Q16_16_C(-2.5 / 65536.0));
    TEST_ASSERT_EQUAL_INT32(0, FX_Q16_16_C(0.49 / 65536.0));
    /* 81.9 m = 5367398.4 LSB -> 5367398. */
    TEST_ASSERT_EQUAL_INT32(5367398, FX_Q16_16_C(81.9));
    TEST_ASSERT_EQUAL_INT32(-5367398, FX_Q16_16_C(-81.9));
    TEST_ASSERT_EQUAL_INT32(5367398, k_range_max);
    TEST_ASSERT_EQUAL_INT32(0x7FFF0000, FX_Q16_16_C(32767.0));
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, FX_Q16_16_C(-32768.0));
    TEST_ASSERT_EQUAL_INT32(0x7FFFFFFF, FX_Q16_16_C(32767.99998));
    TEST_ASSERT_EQUAL_INT32(1000, FX_Q16_16_C(0.0152587890625)); /* 1000 / 65536 */
}

static void test_fx_bam32_constants(void)
{
    TEST_ASSERT_EQUAL_HEX32(0x40000000u, FX_BAM32_QUARTER);
    TEST_ASSERT_EQUAL_HEX32(0x80000000u, FX_BAM32_HALF);
    TEST_ASSERT_EQUAL_HEX32(0x00000000u, FX_BAM32_DEG_C(0));
    TEST_ASSERT_EQUAL_HEX32(0x20000000u, FX_BAM32_DEG_C(45));
    TEST_ASSERT_EQUAL_HEX32(0x40000000u, FX_BAM32_DEG_C(90));
    TEST_ASSERT_EQUAL_HEX32(0x80000000u, FX_BAM32_DEG_C(180));
    TEST_ASSERT_EQUAL_HEX32(0xC0000000u, FX_BAM32_DEG_C(270));
    TEST_ASSERT_EQUAL_HEX32(0x00000000u, FX_BAM32_DEG_C(360)); /* one turn wraps */
    TEST_ASSERT_EQUAL_HEX32(0x40000000u, FX_BAM32_DEG_C(450));
    TEST_ASSERT_EQUAL_HEX32(0xC0000000u, FX_BAM32_DEG_C(-90));
    TEST_ASSERT_EQUAL_HEX32(0x80000000u, FX_BAM32_DEG_C(-180));
    TEST_ASSERT_EQUAL_HEX32(0x80000000u, FX_BAM32_DEG_C(180.0));
    /* 1 deg = 11930464.71 -> 11930465; -1 deg is its two's complement. */
    TEST_ASSERT_EQUAL_UINT32(11930465u, FX_BAM32_DEG_C(1));
    TEST_ASSERT_EQUAL_UINT32(0u - 11930465u, FX_BAM32_DEG_C(-1));
    /* 0.25 deg (the LMS's finest step) = 2982616.18 -> 2982616. */
    TEST_ASSERT_EQUAL_UINT32(2982616u, FX_BAM32_DEG_C(0.25));
    TEST_ASSERT_EQUAL_UINT32(2982616u, k_beam_step);
    /* 0.5 deg = 5965232.36 -> 5965232; 1/3 deg = 3976821.57 -> 3976822. */
    TEST_ASSERT_EQUAL_UINT32(5965232u, FX_BAM32_DEG_C(0.5));
    TEST_ASSERT_EQUAL_UINT32(3976822u, FX_BAM32_DEG_C(1.0 / 3.0));
    TEST_ASSERT_EQUAL_UINT32(0u - 3976822u, FX_BAM32_DEG_C(-1.0 / 3.0));
    /* 1 LSB is 360 / 2^32 deg; half of it rounds away from zero. */
    TEST_ASSERT_EQUAL_UINT32(1u, FX_BAM32_DEG_C(360.0 / 4294967296.0));
    TEST_ASSERT_EQUAL_UINT32(2u, FX_BAM32_DEG_C(1.5 * 360.0 / 4294967296.0));
    TEST_ASSERT_EQUAL_UINT32(0xFFFFFFFEu, FX_BAM32_DEG_C(-1.5 * 360.0 / 4294967296.0));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_fx_shr_round_small_values_and_ties);
    RUN_TEST(test_fx_shr_round_int64_edges);
    RUN_TEST(test_fx_shr_round_ties_every_shift);
    RUN_TEST(test_fx_shr_round_random_against_reference);
    RUN_TEST(test_fx_sat_s32_edges);
    RUN_TEST(test_fx_mul_q16_q30_values);
    RUN_TEST(test_fx_mul_q16_values);
    RUN_TEST(test_fx_products_random_against_reference);
    RUN_TEST(test_fx_add_sub_saturate);
    RUN_TEST(test_fx_bam32_diff_edges);
    RUN_TEST(test_fx_q16_16_constants);
    RUN_TEST(test_fx_bam32_constants);
    return UNITY_END();
}
