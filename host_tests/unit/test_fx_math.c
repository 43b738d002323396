/* test_fx_math.c - fx_sincos / fx_sin / fx_cos, fx_atan2 and fx_sqrt_u64
 * (ego_fx_math.h) against references computed on the host.
 *
 * References:
 *  - sin, cos, atan2: long double (x86-64: 64-bit mantissa) sinl, cosl,
 *    atan2l; every int64 converts to long double exactly. The reference's
 *    own error is below 1e-8 LSB of the result formats (the errors are
 *    tracked in 1/1024 LSB, so it cannot show). On a host whose long double
 *    is the 53-bit double, the reference is still good to about 1e-6 LSB.
 *  - square root: integer arithmetic only (q is the rounded root of v iff
 *    q^2 - q < v <= q^2 + q), no floating point.
 *
 * Errors are compared in integers: the error in units of 1/1024 LSB,
 * rounded, against a limit; the message names the worst case. Each test
 * also prints its worst case as an INFO line (docs/fixed-point.md).
 *
 * Default run: dense samples (every 2^12-th angle, all angles near the
 * quarter points, 2^18 atan2 directions at 6 magnitudes plus small, edge
 * and random vectors, every v < 2^24), about 1 s under ASan. Exhaustive
 * mode, FX_MATH_EXHAUSTIVE=1 in the environment or --exhaustive on the
 * command line, adds: all 2^32 angles, 2^20 directions x 63 magnitudes and
 * 2^26 random atan2 pairs, every v < 2^32 and k^2 + {-1, 0, 1, k, k + 1}
 * for every k < 2^32 (minutes in a Release build); otherwise those tests
 * are not run at all (not reported as ignored: the default run is its own
 * complete set).
 */
#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ego_fx_math.h"
#include "test_rng.h"
#include "unity.h"

static bool exhaustive;

/* The emulated target (software floating point under QEMU) checks one in
 * 2^TARGET_THIN of the sampled cases of the largest sweeps: the same code
 * and the same kinds of cases as the host, which checks them all, in a
 * sixteenth of the time (38 s of CI's two cores otherwise). */
#if defined(LMSEGO_UNIT_ON_TARGET)
#define TARGET_THIN 4u
#else
#define TARGET_THIN 0u
#endif

void setUp(void)
{
}

void tearDown(void)
{
}

/* splitmix64 (test_rng.h), fixed seed per test. */
static uint64_t rng_state;

static uint64_t rng_next(void)
{
    return test_rng_next(&rng_state);
}

#define TWO_PI_L 6.283185307179586476925286766559005768L
#define TURN_L 4294967296.0L /* binary-angle units per turn */
#define Q30_L 1073741824.0L  /* Q2.30 units per 1.0 */
#define SUB 1024             /* errors are tracked in 1/SUB LSB */
#define RANGE_M 81.9L        /* LMS maximum range, for the metres figures */

static long double bam_to_rad(long double bam)
{
    return bam * (TWO_PI_L / TURN_L);
}

/* ------------------------------------------------------------------------
 * Worst-error tracking
 * ---------------------------------------------------------------------- */

typedef struct {
    int64_t worst;       /* largest |error| seen, 1/SUB LSB */
    long double worst_abs; /* the same in LSB, unrounded */
    long double err;     /* that error, signed, LSB */
    int64_t arg1;        /* the input(s) where it occurred */
    int64_t arg2;
    int64_t got;         /* result there */
    long double exact;   /* reference there */
    uint64_t count;      /* cases checked */
} worst_t;

static void worst_init(worst_t *w)
{
    memset(w, 0, sizeof *w);
    w->worst = -1;
}

static void worst_note(worst_t *w, long double err, int64_t arg1, int64_t arg2, int64_t got,
                       long double exact)
{
    w->count++;
    if (fabsl(err) > w->worst_abs || w->worst < 0) {
        w->worst_abs = fabsl(err);
        w->worst = (int64_t)llroundl(fabsl(err) * (long double)SUB);
        w->err = err;
        w->arg1 = arg1;
        w->arg2 = arg2;
        w->got = got;
        w->exact = exact;
    }
}

/* Asserts worst <= limit (1/SUB LSB, a tolerance, so unsigned: Unity takes
 * the delta of INT_WITHIN uncast as UNITY_UINT) and prints the worst case
 * (INFO). */
static void worst_check(const worst_t *w, uint32_t limit, const char *what)
{
    char msg[320];
    (void)snprintf(msg, sizeof msg,
                   "%s: worst %+.4Lf LSB (%lld/%d) at (%lld, %lld): got %lld, exact %.4Lf; %llu cases",
                   what, w->err, (long long)w->worst, SUB, (long long)w->arg1,
                   (long long)w->arg2, (long long)w->got, w->exact,
                   (unsigned long long)w->count);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(w->count > 0u, "no cases checked");
    TEST_ASSERT_INT_WITHIN_MESSAGE(limit, 0, w->worst, msg);
}

/* ------------------------------------------------------------------------
 * sin / cos
 * ---------------------------------------------------------------------- */

/* Limit for sin and cos: the error bound of docs/fixed-point.md, 0.76 LSB
 * of Q2.30 (table rounding 0.25 + final rounding 0.5 + < 0.01). The design
 * target was 4 LSB. */
#define SINCOS_LIMIT 779

typedef struct {
    worst_t sin;
    worst_t cos;
} sincos_worst_t;

static void sincos_check_one(sincos_worst_t *w, fx_bam32_t a, long double exact_s,
                             long double exact_c)
{
    fx_q2_30_t s;
    fx_q2_30_t c;
    fx_sincos(a, &s, &c);
    worst_note(&w->sin, (long double)s - exact_s * Q30_L, (int64_t)a, 0, s, exact_s * Q30_L);
    worst_note(&w->cos, (long double)c - exact_c * Q30_L, (int64_t)a, 0, c, exact_c * Q30_L);
}

static void sincos_check_ref(sincos_worst_t *w, fx_bam32_t a)
{
    const long double rad = bam_to_rad((long double)a);
    sincos_check_one(w, a, sinl(rad), cosl(rad));
}

/* Checks the n consecutive angles base + i, i < n <= 2^16, against a
 * reference that calls sinl/cosl once, at base, and adds the offset d by
 * the addition theorem with sin d = d - d^3/6 + d^5/120 and
 * cos d = 1 - d^2/2 + d^4/24 (d < 9.6e-5 rad: omitted terms < 1e-27). */
static void sincos_check_block(sincos_worst_t *w, fx_bam32_t base, uint32_t n, uint32_t stride)
{
    const long double rb = bam_to_rad((long double)base);
    const long double sb = sinl(rb);
    const long double cb = cosl(rb);
    for (uint32_t i = 0u; i < n; i += stride) {
        const long double d = bam_to_rad((long double)i);
        const long double d2 = d * d;
        const long double sd = d * (1.0L - d2 / 6.0L * (1.0L - d2 / 20.0L));
        const long double cd = 1.0L - d2 / 2.0L * (1.0L - d2 / 12.0L);
        sincos_check_one(w, base + i, sb * cd + cb * sd, cb * cd - sb * sd);
    }
}

static void test_fx_sincos_quarter_points_exact(void)
{
    const fx_bam32_t angles[4] = {0u, FX_BAM32_QUARTER, FX_BAM32_HALF, 3u * FX_BAM32_QUARTER};
    const fx_q2_30_t sins[4] = {0, FX_Q2_30_ONE, 0, -FX_Q2_30_ONE};
    const fx_q2_30_t coss[4] = {FX_Q2_30_ONE, 0, -FX_Q2_30_ONE, 0};
    for (unsigned i = 0u; i < 4u; i++) {
        fx_q2_30_t s = 12345;
        fx_q2_30_t c = 12345;
        fx_sincos(angles[i], &s, &c);
        TEST_ASSERT_EQUAL_HEX32((uint32_t)sins[i], (uint32_t)s);
        TEST_ASSERT_EQUAL_HEX32((uint32_t)coss[i], (uint32_t)c);
        TEST_ASSERT_EQUAL_HEX32((uint32_t)sins[i], (uint32_t)fx_sin(angles[i]));
        TEST_ASSERT_EQUAL_HEX32((uint32_t)coss[i], (uint32_t)fx_cos(angles[i]));
    }
    /* 45 deg: sqrt(2)/2 * 2^30 = 759250124.99 -> 759250125. 30 deg: 2^29. */
    TEST_ASSERT_EQUAL_INT32(759250125, fx_sin(FX_BAM32_QUARTER / 2u));
    TEST_ASSERT_EQUAL_INT32(759250125, fx_cos(FX_BAM32_QUARTER / 2u));
    TEST_ASSERT_INT_WITHIN(1, 1 << 29, fx_sin(FX_BAM32_DEG_C(30)));
    TEST_ASSERT_INT_WITHIN(1, 1 << 29, fx_cos(FX_BAM32_DEG_C(60)));
    TEST_ASSERT_INT_WITHIN(1, -(1 << 29), fx_sin(FX_BAM32_DEG_C(-30)));
    /* One LSB off a quarter point: sin(2 pi / 2^32) * 2^30 = 1.57 -> 2. */
    TEST_ASSERT_EQUAL_INT32(2, fx_sin(1u));
    TEST_ASSERT_EQUAL_INT32(-2, fx_sin(0xFFFFFFFFu));
    TEST_ASSERT_EQUAL_INT32(FX_Q2_30_ONE, fx_cos(1u));
    TEST_ASSERT_EQUAL_INT32(FX_Q2_30_ONE, fx_sin(FX_BAM32_QUARTER + 1u));
}

/* fx_sin and fx_cos are exactly the two outputs of fx_sincos. */
static void test_fx_sin_cos_match_sincos(void)
{
    rng_state = 0x51Cu;
    for (unsigned i = 0u; i < 100000u; i++) {
        const fx_bam32_t a = (fx_bam32_t)rng_next();
        fx_q2_30_t s;
        fx_q2_30_t c;
        fx_sincos(a, &s, &c);
        if (s != fx_sin(a) || c != fx_cos(a)) {
            char msg[96];
            (void)snprintf(msg, sizeof msg, "fx_sin/fx_cos differ from fx_sincos at 0x%08X",
                           (unsigned)a);
            TEST_FAIL_MESSAGE(msg);
        }
    }
}

/* Every 2^12-th angle (all 257 nodes of each quadrant and all ties
 * between them; block reference), the same grid shifted by pseudo-random
 * offsets, all angles within 4096 LSB of each quarter point, and every
 * angle within 16 LSB of each node and each tie (direct sinl/cosl, an
 * independent check of the block reference). */
static void test_fx_sincos_dense_sample(void)
{
    sincos_worst_t w;
    worst_init(&w.sin);
    worst_init(&w.cos);
    for (uint32_t blk = 0u; blk < (1u << 16); blk++) {
        sincos_check_block(&w, blk << 16, 1u << 16, 1u << (12u + TARGET_THIN));
    }
    rng_state = 0xD05Eu;
    for (uint32_t i = 0u; i < (1u << 16); i++) {
        sincos_check_ref(&w, (i << 16) + (uint32_t)(rng_next() & 0xFFFFu));
    }
    for (uint32_t q = 0u; q < 4u; q++) {
        sincos_check_block(&w, q * FX_BAM32_QUARTER - 4096u, 8193u, 1u);
    }
    for (uint32_t k = 0u; k < 1024u; k++) {
        for (uint32_t d = 0u; d <= 32u; d++) {
            sincos_check_ref(&w, (k << 22) + d - 16u);
            sincos_check_ref(&w, (k << 22) + (1u << 21) + d - 16u);
        }
    }
    worst_check(&w.sin, SINCOS_LIMIT, "sin Q2.30");
    worst_check(&w.cos, SINCOS_LIMIT, "cos Q2.30");
}

/* The symmetries hold bit for bit: random angles, every angle within
 * 2^15 LSB of each quarter point, and every angle within 32 LSB of each
 * table node and each tie between two nodes, in all four quadrants. */
static void test_fx_sincos_identities(void)
{
    rng_state = 0x1DE7u;
    const uint32_t n_random = 1u << 18;
    const uint32_t n_quarter = 1u << 18;
    const uint32_t n_nodes = 2048u * 64u;
    for (uint32_t i = 0u; i < n_random + n_quarter + n_nodes; i++) {
        fx_bam32_t a;
        if (i < n_random) {
            a = (fx_bam32_t)rng_next();
        } else if (i < n_random + n_quarter) {
            const uint32_t j = i - n_random;
            a = (j & 3u) * FX_BAM32_QUARTER + (j >> 2) - 32768u;
        } else {
            const uint32_t j = i - n_random - n_quarter;
            a = ((j >> 6) << 21) + (j & 63u) - 32u; /* nodes at 2^22, ties between */
        }
        const fx_q2_30_t s = fx_sin(a);
        const fx_q2_30_t c = fx_cos(a);
        bool ok = true;
        const char *which = "";
        if (fx_sin(0u - a) != -s) {
            ok = false;
            which = "sin(-a) == -sin(a)";
        } else if (fx_sin(a + FX_BAM32_HALF) != -s) {
            ok = false;
            which = "sin(a + half) == -sin(a)";
        } else if (fx_sin(a + FX_BAM32_QUARTER) != c) {
            ok = false;
            which = "cos(a) == sin(a + quarter)";
        } else if (fx_cos(0u - a) != c) {
            ok = false;
            which = "cos(-a) == cos(a)";
        } else if (fx_sin(FX_BAM32_HALF - a) != s) {
            ok = false;
            which = "sin(half - a) == sin(a)";
        } else if (fx_cos(FX_BAM32_QUARTER - a) != s) {
            ok = false;
            which = "cos(quarter - a) == sin(a)";
        }
        if (!ok) {
            char msg[128];
            (void)snprintf(msg, sizeof msg, "%s fails at a = 0x%08X", which, (unsigned)a);
            TEST_FAIL_MESSAGE(msg);
        }
    }
}

/* sin^2 + cos^2 stays within 2 LSB of 1 (a consequence of the 1 LSB
 * bound), and sin is non-decreasing on the first quadrant around every
 * node and tie (the exhaustive mode checks every angle). */
static void test_fx_sincos_pythagoras_and_monotonic(void)
{
    rng_state = 0x9E7u;
    for (uint32_t i = 0u; i < (1u << 18); i++) {
        const fx_bam32_t a = (fx_bam32_t)rng_next();
        fx_q2_30_t s;
        fx_q2_30_t c;
        fx_sincos(a, &s, &c);
        const int64_t n = (int64_t)s * s + (int64_t)c * c - ((int64_t)1 << 60);
        /* |n| <= 2 * 2 * 2^30 (two terms, 1 LSB each, times 2 * 1.0). */
        TEST_ASSERT_TRUE_MESSAGE(n <= ((int64_t)4 << 30) && n >= -((int64_t)4 << 30),
                                 "sin^2 + cos^2 off 1 by more than 2 LSB");
    }
    for (uint32_t k = 0u; k < 512u; k++) {
        const uint32_t centre = (k << 21); /* nodes and ties of quadrant 0 */
        for (uint32_t d = 0u; d < 256u; d++) {
            const fx_bam32_t a = centre + d - 128u;
            if (a >= FX_BAM32_QUARTER) {
                continue; /* below 0 (wrapped) */
            }
            if (fx_sin(a + 1u) < fx_sin(a) || fx_cos(a + 1u) > fx_cos(a)) {
                char msg[96];
                (void)snprintf(msg, sizeof msg, "not monotonic at 0x%08X", (unsigned)a);
                TEST_FAIL_MESSAGE(msg);
            }
        }
    }
}

/* All 2^32 angles (exhaustive mode), with the block reference of
 * sincos_check_block over blocks of 2^16 angles. Also checks, at every
 * angle, monotonicity on the first quadrant and the three symmetries. */
static void test_fx_sincos_all_angles(void)
{
    if (!exhaustive) {
        TEST_IGNORE_MESSAGE("exhaustive: set FX_MATH_EXHAUSTIVE=1 or pass --exhaustive");
    }
    sincos_worst_t w;
    worst_init(&w.sin);
    worst_init(&w.cos);
    for (uint32_t blk = 0u; blk < (1u << 16); blk++) {
        sincos_check_block(&w, blk << 16, 1u << 16, 1u);
    }
    uint64_t non_monotonic = 0u;
    uint64_t not_symmetric = 0u;
    fx_q2_30_t prev_s = 0;
    fx_q2_30_t prev_c = FX_Q2_30_ONE;
    fx_bam32_t a = 0u;
    do {
        fx_q2_30_t s;
        fx_q2_30_t c;
        fx_sincos(a, &s, &c);
        if (a < FX_BAM32_QUARTER) {
            if (a > 0u && (s < prev_s || c > prev_c)) {
                non_monotonic++;
            }
            prev_s = s;
            prev_c = c;
        }
        if (fx_sin(a + FX_BAM32_QUARTER) != c || fx_sin(0u - a) != -s ||
            fx_sin(a + FX_BAM32_HALF) != -s) {
            not_symmetric++;
        }
        a++;
    } while (a != 0u);
    worst_check(&w.sin, SINCOS_LIMIT, "sin Q2.30, all 2^32 angles");
    worst_check(&w.cos, SINCOS_LIMIT, "cos Q2.30, all 2^32 angles");
    TEST_ASSERT_TRUE_MESSAGE(non_monotonic == 0u, "sin/cos not monotonic on the first quadrant");
    TEST_ASSERT_TRUE_MESSAGE(not_symmetric == 0u,
                             "cos(a) == sin(a + quarter), sin(-a) == -sin(a) or "
                             "sin(a + half) == -sin(a) fails somewhere");
}

/* ------------------------------------------------------------------------
 * atan2
 * ---------------------------------------------------------------------- */

/* Limit for atan2: the error bound of docs/fixed-point.md, 0.92 LSB of the
 * binary angle (final rounding 0.5 + input rounding 0.26 + quotient 0.08 +
 * cubic and coefficients 0.08). The design target was 64 LSB. */
#define ATAN2_LIMIT 942

/* Exact atan2 in binary-angle units, in [0, 2^32). */
static long double atan2_exact(int64_t y, int64_t x)
{
    long double a = atan2l((long double)y, (long double)x) * (TURN_L / TWO_PI_L);
    if (a < 0.0L) {
        a += TURN_L;
    }
    return a;
}

static void atan2_check(worst_t *w, int64_t y, int64_t x)
{
    const fx_bam32_t got = fx_atan2(y, x);
    const long double exact = atan2_exact(y, x);
    long double err = (long double)got - exact;
    if (err >= TURN_L / 2.0L) {
        err -= TURN_L;
    } else if (err < -TURN_L / 2.0L) {
        err += TURN_L;
    }
    worst_note(w, err, y, x, (int64_t)got, exact);
}

static const int64_t positive_edges[] = {
    1, 2, 3, 7, 255, 65535, 2147483647, 2147483648, 4294967295, 4294967296, 4294967297,
    (int64_t)1 << 52, ((int64_t)1 << 53) + 1, (int64_t)1 << 62, ((int64_t)1 << 62) + 1,
    INT64_MAX - 1, INT64_MAX};

static void test_fx_atan2_axes_and_diagonals_exact(void)
{
    TEST_ASSERT_EQUAL_HEX32(0u, fx_atan2(0, 0));
    TEST_ASSERT_EQUAL_HEX32(FX_BAM32_HALF, fx_atan2(0, INT64_MIN));
    TEST_ASSERT_EQUAL_HEX32(3u * FX_BAM32_QUARTER, fx_atan2(INT64_MIN, 0));
    TEST_ASSERT_EQUAL_HEX32(5u * (FX_BAM32_QUARTER / 2u), fx_atan2(INT64_MIN, INT64_MIN));
    for (size_t i = 0u; i < sizeof positive_edges / sizeof positive_edges[0]; i++) {
        const int64_t p = positive_edges[i];
        TEST_ASSERT_EQUAL_HEX32(0u, fx_atan2(0, p));
        TEST_ASSERT_EQUAL_HEX32(FX_BAM32_QUARTER, fx_atan2(p, 0));
        TEST_ASSERT_EQUAL_HEX32(FX_BAM32_HALF, fx_atan2(0, -p));
        TEST_ASSERT_EQUAL_HEX32(3u * FX_BAM32_QUARTER, fx_atan2(-p, 0));
        TEST_ASSERT_EQUAL_HEX32(1u * (FX_BAM32_QUARTER / 2u), fx_atan2(p, p));
        TEST_ASSERT_EQUAL_HEX32(3u * (FX_BAM32_QUARTER / 2u), fx_atan2(p, -p));
        TEST_ASSERT_EQUAL_HEX32(5u * (FX_BAM32_QUARTER / 2u), fx_atan2(-p, -p));
        TEST_ASSERT_EQUAL_HEX32(7u * (FX_BAM32_QUARTER / 2u), fx_atan2(-p, p));
    }
    /* |INT64_MIN| = 2^63 against INT64_MAX = 2^63 - 1: just off the
     * diagonal, within 1 LSB of it. */
    TEST_ASSERT_UINT_WITHIN(1u, 3u * (FX_BAM32_QUARTER / 2u), fx_atan2(INT64_MAX, INT64_MIN));
    TEST_ASSERT_UINT_WITHIN(1u, 7u * (FX_BAM32_QUARTER / 2u), fx_atan2(INT64_MIN, INT64_MAX));
}

/* Every vector with |x|, |y| <= 24, and the named tiny ones. */
static void test_fx_atan2_small_vectors(void)
{
    TEST_ASSERT_EQUAL_HEX32(FX_BAM32_HALF, fx_atan2(0, -1));
    TEST_ASSERT_EQUAL_HEX32(FX_BAM32_QUARTER / 2u, fx_atan2(1, 1));
    /* atan(1/2) = 0.4636476 rad = 316933406.68 -> 316933407. */
    TEST_ASSERT_UINT_WITHIN(1u, 316933407u, fx_atan2(1, 2));
    TEST_ASSERT_UINT_WITHIN(1u, FX_BAM32_QUARTER - 316933407u, fx_atan2(2, 1));
    worst_t w;
    worst_init(&w);
    for (int64_t y = -24; y <= 24; y++) {
        for (int64_t x = -24; x <= 24; x++) {
            if (x != 0 || y != 0) {
                atan2_check(&w, y, x);
            }
        }
    }
    worst_check(&w, ATAN2_LIMIT, "atan2 |x|,|y| <= 24");
}

/* Every pair of edge values (INT64_MIN, INT64_MAX, 0, +-1, powers of two
 * and their neighbours). */
static void test_fx_atan2_edge_pairs(void)
{
    int64_t edges[2u * sizeof positive_edges / sizeof positive_edges[0] + 2u];
    size_t n = 0u;
    edges[n++] = 0;
    edges[n++] = INT64_MIN;
    for (size_t i = 0u; i < sizeof positive_edges / sizeof positive_edges[0]; i++) {
        edges[n++] = positive_edges[i];
        edges[n++] = -positive_edges[i];
    }
    worst_t w;
    worst_init(&w);
    for (size_t i = 0u; i < n; i++) {
        for (size_t j = 0u; j < n; j++) {
            if (edges[i] != 0 || edges[j] != 0) {
                atan2_check(&w, edges[i], edges[j]);
            }
        }
    }
    worst_check(&w, ATAN2_LIMIT, "atan2 edge pairs");
}

/* Directions i * 2^32 / n_angles (plus a pseudo-random sub-step) at
 * magnitude r: x = round(r cos), y = round(r sin). */
static void atan2_sweep(worst_t *w, uint32_t n_angles_log2, const long double *mags,
                        size_t n_mags)
{
    rng_state = 0x5EE9u;
    for (uint32_t i = 0u; i < (1u << n_angles_log2); i++) {
        const uint32_t step = 32u - n_angles_log2;
        const fx_bam32_t a = (i << step) + (uint32_t)(rng_next() >> (32u + n_angles_log2));
        const long double rad = bam_to_rad((long double)a);
        const long double c = cosl(rad);
        const long double s = sinl(rad);
        for (size_t m = 0u; m < n_mags; m++) {
            const int64_t x = llroundl(mags[m] * c);
            const int64_t y = llroundl(mags[m] * s);
            if (x != 0 || y != 0) {
                atan2_check(w, y, x);
            }
        }
    }
}

static void test_fx_atan2_direction_sweep(void)
{
    /* 1, ~30, 2^20, ~2^31.5, 2^45, 2^62 */
    const long double mags[] = {1.0L, 30.5L, 1048576.0L, 3037000499.0L, 35184372088832.0L,
                                4611686018427387904.0L};
    worst_t w;
    worst_init(&w);
    atan2_sweep(&w, 18u - TARGET_THIN, mags, sizeof mags / sizeof mags[0]);
    worst_check(&w, ATAN2_LIMIT, "atan2 sweep 2^18 directions (host) x 6 magnitudes");
}

/* Random pairs: uniform int64 bits, and both components of random bit
 * lengths (so that very flat and very steep vectors, and tiny ones,
 * occur). */
static int64_t rng_s64_any_length(void)
{
    const uint64_t r = rng_next();
    const unsigned bits = (unsigned)(r % 64u); /* magnitude < 2^bits */
    const uint64_t mag = (bits == 0u) ? 0u : (rng_next() >> (64u - bits));
    return ((r >> 32) & 1u) != 0u ? -(int64_t)mag : (int64_t)mag;
}

static void atan2_random(worst_t *w, uint32_t count)
{
    for (uint32_t i = 0u; i < count; i++) {
        int64_t y;
        int64_t x;
        if ((i & 1u) != 0u) {
            y = (int64_t)rng_next();
            x = (int64_t)rng_next();
        } else {
            y = rng_s64_any_length();
            x = rng_s64_any_length();
        }
        if (x != 0 || y != 0) {
            atan2_check(w, y, x);
        }
    }
}

static void test_fx_atan2_random_pairs(void)
{
    worst_t w;
    worst_init(&w);
    rng_state = 0xA7A2u;
    atan2_random(&w, 1u << (18u - TARGET_THIN));
    worst_check(&w, ATAN2_LIMIT, "atan2 random int64 pairs");
}

/* Vectors whose division needs the second correction of a 16-bit quotient
 * digit estimate (Knuth's algorithm D): a divisor l whose low half is
 * large makes the estimate from its high half too big. With |y| < |x| <
 * 2^32 and x >= 2^31, x is the divisor and y the dividend unchanged. The
 * named ones were found by search: (y, x) = (2205701923, 2816868269),
 * (1394787157, 2198863683) need two on the high digit, (1525418302,
 * 2358902562) and (30745795, 2150629176) on the low one; the loop makes
 * about 3000 more such cases, at four magnitudes. */
static void test_fx_atan2_division_corrections(void)
{
    static const int64_t named[][2] = {{2205701923, 2816868269}, {1394787157, 2198863683},
                                       {2135722528, 2338914212}, {2080571114, 2306735973},
                                       {1525418302, 2358902562}, {3519372840, 3869245330},
                                       {30745795, 2150629176}};
    worst_t w;
    worst_init(&w);
    for (size_t i = 0u; i < sizeof named / sizeof named[0]; i++) {
        atan2_check(&w, named[i][0], named[i][1]);
        atan2_check(&w, named[i][1], named[i][0]);
        atan2_check(&w, -named[i][0] * 1024, named[i][1] * 1024);
    }
    rng_state = 0xD1Du;
    for (uint32_t i = 0u; i < (1u << 16); i++) {
        const uint64_t r = rng_next();
        const uint32_t l = 0x80000000u | ((uint32_t)r & 0x7FFF0000u) | 0xFF00u | ((uint32_t)(r >> 32) & 0xFFu);
        const uint32_t y = (uint32_t)(rng_next() % l);
        const unsigned k = (unsigned)(i & 3u) * 10u; /* 2^0, 2^10, 2^20, 2^30 */
        atan2_check(&w, (int64_t)((uint64_t)y << k), (int64_t)((uint64_t)l << k));
    }
    worst_check(&w, ATAN2_LIMIT, "atan2 two-correction divisions");
}

/* Exact identities: sign flips, mirror, swap, power-of-two scaling. */
static void test_fx_atan2_identities(void)
{
    rng_state = 0x1D2u;
    for (uint32_t i = 0u; i < (1u << 18); i++) {
        int64_t y = rng_s64_any_length();
        int64_t x = rng_s64_any_length();
        if (y == INT64_MIN) {
            y++;
        }
        if (x == INT64_MIN) {
            x++;
        }
        const fx_bam32_t a = fx_atan2(y, x);
        const char *which = NULL;
        if (x == 0 && y == 0) {
            continue;
        }
        if (fx_atan2(-y, x) != 0u - a) {
            which = "atan2(-y, x) == -atan2(y, x)";
        } else if (fx_atan2(y, -x) != FX_BAM32_HALF - a) {
            which = "atan2(y, -x) == half - atan2(y, x)";
        } else if (fx_atan2(x, y) != FX_BAM32_QUARTER - a) {
            which = "atan2(x, y) == quarter - atan2(y, x)";
        }
        /* Power-of-two scaling changes nothing (the normalisation is a
         * shift): scale both while they fit. */
        const uint64_t ax = x < 0 ? (uint64_t)(-x) : (uint64_t)x;
        const uint64_t ay = y < 0 ? (uint64_t)(-y) : (uint64_t)y;
        const uint64_t big = ax > ay ? ax : ay;
        unsigned k = (unsigned)(rng_next() % 8u);
        while (k > 0u && big > ((uint64_t)INT64_MAX >> k)) {
            k--;
        }
        if (which == NULL && k > 0u &&
            fx_atan2((int64_t)((uint64_t)y << k), (int64_t)((uint64_t)x << k)) != a) {
            which = "atan2(y 2^k, x 2^k) == atan2(y, x)";
        }
        if (which != NULL) {
            char msg[160];
            (void)snprintf(msg, sizeof msg, "%s fails at (%lld, %lld)", which, (long long)y,
                           (long long)x);
            TEST_FAIL_MESSAGE(msg);
        }
    }
}

/* Exhaustive mode: 2^20 directions x 63 magnitudes (2^0 .. 2^62 and
 * 1.5 x those), and 2^26 random pairs. */
static void test_fx_atan2_exhaustive_sweep(void)
{
    if (!exhaustive) {
        TEST_IGNORE_MESSAGE("exhaustive: set FX_MATH_EXHAUSTIVE=1 or pass --exhaustive");
    }
    long double mags[63];
    size_t n = 0u;
    for (unsigned e = 0u; e <= 62u; e += 2u) {
        mags[n++] = ldexpl(1.0L, (int)e);
        if (e < 61u) {
            mags[n++] = 1.5L * ldexpl(1.0L, (int)e + 1);
        }
    }
    worst_t w;
    worst_init(&w);
    atan2_sweep(&w, 20u, mags, n);
    worst_check(&w, ATAN2_LIMIT, "atan2 sweep 2^20 directions x 63 magnitudes");
    worst_t r;
    worst_init(&r);
    rng_state = 0xE4A7u;
    atan2_random(&r, 1u << 26);
    worst_check(&r, ATAN2_LIMIT, "atan2 2^26 random int64 pairs");
}

/* ------------------------------------------------------------------------
 * Square root (integer reference only)
 * ---------------------------------------------------------------------- */

/* q is the correctly rounded root of v: q^2 - q < v <= q^2 + q (no tie is
 * possible), or the saturated 2^32 - 1 above (2^32 - 1/2)^2. */
static bool sqrt_ok(uint64_t v, uint32_t q)
{
    const uint64_t q2 = (uint64_t)q * q;
    if (q == 0u) {
        return v == 0u;
    }
    if (v <= q2 - q) {
        return false;
    }
    return q == UINT32_MAX || v <= q2 + q;
}

static void sqrt_fail(uint64_t v, uint32_t got, const char *what)
{
    char msg[160];
    (void)snprintf(msg, sizeof msg, "%s: fx_sqrt_u64(%llu) = %u is not the rounded root", what,
                   (unsigned long long)v, (unsigned)got);
    TEST_FAIL_MESSAGE(msg);
}

static void sqrt_expect(uint64_t v, uint32_t expected, const char *what)
{
    const uint32_t got = fx_sqrt_u64(v);
    if (got != expected || !sqrt_ok(v, got)) {
        sqrt_fail(v, got, what);
    }
}

/* fx_bits_u32 (shared by the quick arctangent and ITCP's cone) against a
 * count by halving, at every power of two, its neighbours and all ones. */
static void test_fx_bits_u32(void)
{
    for (unsigned k = 0u; k < 32u; k++) {
        const uint32_t values[3] = {(uint32_t)1u << k, ((uint32_t)1u << k) + 1u,
                                    (uint32_t)(((uint64_t)1u << (k + 1u)) - 1u)};
        for (unsigned v = 0u; v < 3u; v++) {
            unsigned expected = 0u;
            for (uint32_t d = values[v]; d != 0u; d >>= 1) {
                expected++;
            }
            TEST_ASSERT_EQUAL_UINT32(expected, fx_bits_u32(values[v]));
        }
    }
}

static void test_fx_sqrt_named_values(void)
{
    TEST_ASSERT_EQUAL_UINT32(0u, fx_sqrt_u64(0u));
    TEST_ASSERT_EQUAL_UINT32(1u, fx_sqrt_u64(1u));
    TEST_ASSERT_EQUAL_UINT32(1u, fx_sqrt_u64(2u));  /* 1.414 */
    TEST_ASSERT_EQUAL_UINT32(2u, fx_sqrt_u64(3u));  /* 1.732 */
    TEST_ASSERT_EQUAL_UINT32(2u, fx_sqrt_u64(6u));  /* 2.449 */
    TEST_ASSERT_EQUAL_UINT32(3u, fx_sqrt_u64(7u));  /* 2.646 */
    TEST_ASSERT_EQUAL_UINT32(65536u, fx_sqrt_u64((uint64_t)1 << 32));
    TEST_ASSERT_EQUAL_UINT32(2147483648u, fx_sqrt_u64((uint64_t)1 << 62));
    /* sqrt(2^63) = 3037000499.976 -> 3037000500. */
    TEST_ASSERT_EQUAL_UINT32(3037000500u, fx_sqrt_u64((uint64_t)1 << 63));
    /* Top of the range: (2^32 - 1)^2 + (2^32 - 1) = 2^64 - 2^32 still rounds
     * down; from 2^64 - 2^32 + 1 the rounded root 2^32 saturates. */
    TEST_ASSERT_EQUAL_UINT32(4294967295u, fx_sqrt_u64(0xFFFFFFFE00000001u));
    TEST_ASSERT_EQUAL_UINT32(4294967295u, fx_sqrt_u64(0xFFFFFFFF00000000u));
    TEST_ASSERT_EQUAL_UINT32(4294967295u, fx_sqrt_u64(0xFFFFFFFF00000001u));
    TEST_ASSERT_EQUAL_UINT32(4294967295u, fx_sqrt_u64(UINT64_MAX));
    TEST_ASSERT_EQUAL_UINT32(4294967294u, fx_sqrt_u64(0xFFFFFFFC00000004u)); /* (2^32-2)^2 */
    TEST_ASSERT_EQUAL_UINT32(4294967294u, fx_sqrt_u64(0xFFFFFFFD00000002u)); /* k^2 + k */
    TEST_ASSERT_EQUAL_UINT32(4294967295u, fx_sqrt_u64(0xFFFFFFFD00000003u)); /* k^2 + k + 1 */
    /* Q32.32 in, Q16.16 out: sqrt(2.0) = 1.41421356 -> 92682 (92681.90). */
    TEST_ASSERT_EQUAL_UINT32(92682u, fx_sqrt_u64((uint64_t)2 << 32));
    /* 81.9 m squared in Q32.32 back to Q16.16. */
    TEST_ASSERT_EQUAL_UINT32(5367398u, fx_sqrt_u64((uint64_t)5367398u * 5367398u));
}

/* Every v < 2^24; the expected root steps up right after each k^2 + k. */
static void test_fx_sqrt_all_below_2_24(void)
{
    uint32_t q = 0u;
    uint64_t next_step = 1u; /* q^2 + q + 1: first v whose root is q + 1 */
    uint32_t bad = 0u;
    uint64_t first_bad = 0u;
    for (uint64_t v = 0u; v < ((uint64_t)1 << 24); v++) {
        if (v == next_step) {
            q++;
            next_step = (uint64_t)q * q + q + 1u;
        }
        if (fx_sqrt_u64(v) != q) {
            if (bad == 0u) {
                first_bad = v;
            }
            bad++;
        }
    }
    if (bad != 0u) {
        sqrt_fail(first_bad, fx_sqrt_u64(first_bad), "every v < 2^24");
    }
    TEST_ASSERT_EQUAL_UINT32(4096u, q); /* sqrt(2^24 - 1) = 4095.9999 */
}

/* k^2 - 1, k^2, k^2 + 1, k^2 + k, k^2 + k + 1 for one k. */
static void sqrt_check_square(uint32_t k)
{
    const uint64_t k2 = (uint64_t)k * k;
    const uint32_t up = (k == UINT32_MAX) ? k : k + 1u;
    if (k > 0u) {
        sqrt_expect(k2 - 1u, k == 1u ? 0u : k, "k^2 - 1");
    }
    sqrt_expect(k2, k, "k^2");
    sqrt_expect(k2 + 1u, k == 0u ? 1u : k, "k^2 + 1");
    sqrt_expect(k2 + k, k, "k^2 + k");
    sqrt_expect(k2 + k + 1u, up, "k^2 + k + 1");
}

/* Perfect squares and their neighbours: k on a prime stride over the whole
 * range, every k near the powers of two, the last 2^16 k. */
static void test_fx_sqrt_squares_and_neighbours(void)
{
    for (uint64_t k = 0u; k <= UINT32_MAX; k += 4099u) {
        sqrt_check_square((uint32_t)k);
    }
    for (unsigned e = 1u; e <= 32u; e++) {
        const uint64_t p = (uint64_t)1 << e;
        for (uint64_t k = p - 64u > p ? 0u : p - 64u; k <= p + 64u && k <= UINT32_MAX; k++) {
            sqrt_check_square((uint32_t)k);
        }
    }
    for (uint64_t k = UINT32_MAX - 65535u; k <= UINT32_MAX; k++) {
        sqrt_check_square((uint32_t)k);
    }
}

static void test_fx_sqrt_random(void)
{
    rng_state = 0x5047u;
    for (uint32_t i = 0u; i < (1u << 20); i++) {
        const uint64_t r = rng_next();
        /* Uniform bits, or a random bit length. */
        const uint64_t v = ((i & 1u) != 0u) ? r : (r >> (rng_next() % 64u));
        const uint32_t got = fx_sqrt_u64(v);
        if (!sqrt_ok(v, got)) {
            sqrt_fail(v, got, "random");
        }
    }
}

/* Exhaustive mode: every v < 2^32, every k < 2^32 with its neighbours, and
 * the top 2^24 values. */
static void test_fx_sqrt_exhaustive(void)
{
    if (!exhaustive) {
        TEST_IGNORE_MESSAGE("exhaustive: set FX_MATH_EXHAUSTIVE=1 or pass --exhaustive");
    }
    uint32_t q = 0u;
    uint64_t next_step = 1u;
    for (uint64_t v = 0u; v <= UINT32_MAX; v++) {
        if (v == next_step) {
            q++;
            next_step = (uint64_t)q * q + q + 1u;
        }
        const uint32_t got = fx_sqrt_u64(v);
        if (got != q) {
            sqrt_fail(v, got, "every v < 2^32");
        }
    }
    for (uint64_t k = 0u; k <= UINT32_MAX; k++) {
        sqrt_check_square((uint32_t)k);
    }
    for (uint64_t v = UINT64_MAX - 0xFFFFFFu;; v++) {
        const uint32_t got = fx_sqrt_u64(v);
        if (!sqrt_ok(v, got)) {
            sqrt_fail(v, got, "top 2^24");
        }
        if (v == UINT64_MAX) {
            break;
        }
    }
}

int main(int argc, char **argv)
{
    const char *env = getenv("FX_MATH_EXHAUSTIVE");
    exhaustive = (env != NULL && strcmp(env, "1") == 0) ||
                 (argc > 1 && strcmp(argv[1], "--exhaustive") == 0);

    UNITY_BEGIN();
    RUN_TEST(test_fx_sincos_quarter_points_exact);
    RUN_TEST(test_fx_sin_cos_match_sincos);
    RUN_TEST(test_fx_sincos_dense_sample);
    RUN_TEST(test_fx_sincos_identities);
    RUN_TEST(test_fx_sincos_pythagoras_and_monotonic);
    if (exhaustive) {
        RUN_TEST(test_fx_sincos_all_angles);
    }
    RUN_TEST(test_fx_atan2_axes_and_diagonals_exact);
    RUN_TEST(test_fx_atan2_small_vectors);
    RUN_TEST(test_fx_atan2_edge_pairs);
    RUN_TEST(test_fx_atan2_direction_sweep);
    RUN_TEST(test_fx_atan2_random_pairs);
    RUN_TEST(test_fx_atan2_division_corrections);
    RUN_TEST(test_fx_atan2_identities);
    if (exhaustive) {
        RUN_TEST(test_fx_atan2_exhaustive_sweep);
    }
    RUN_TEST(test_fx_bits_u32);
    RUN_TEST(test_fx_sqrt_named_values);
    RUN_TEST(test_fx_sqrt_all_below_2_24);
    RUN_TEST(test_fx_sqrt_squares_and_neighbours);
    RUN_TEST(test_fx_sqrt_random);
    if (exhaustive) {
        RUN_TEST(test_fx_sqrt_exhaustive);
    }
    return UNITY_END();
}
