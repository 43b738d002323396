/* test_pose.c - composing poses (estimator/ego_pose.c) against a double
 * oracle: ego_pose_then and ego_pose_from on random poses over the whole
 * turn and up to 1 km, exact with no turn, inverse of each other, and
 * saturating (not wrapping) at the edge of Q16.16. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "ego_pose.h"
#include "fx_host.h"
#include "test_rng.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

/* splitmix64 (test_rng.h), fixed seed: the same poses on every run and every host. */
static uint64_t rng_state = 12345u;

static uint64_t rng_next(void)
{
    return test_rng_next(&rng_state);
}

/* A random translation component within +-limit m (Q16.16). */
static fx_q16_16_t rng_m(double limit)
{
    const double u = (double)(rng_next() >> 11) / 9007199254740992.0; /* [0, 1) */
    return fx_q16_16_from_double((2.0 * u - 1.0) * limit);
}

static ego_pose_t rng_pose(double limit)
{
    const ego_pose_t p = {(fx_bam32_t)rng_next(), rng_m(limit), rng_m(limit)};
    return p;
}

/* The oracle: a then b, or b from a, in double. */
static void oracle_then(const ego_pose_t *a, const ego_pose_t *b, double *x, double *y)
{
    const double t = fx_bam32_to_rad(a->theta);
    const double bx = fx_q16_16_to_double(b->x);
    const double by = fx_q16_16_to_double(b->y);
    *x = fx_q16_16_to_double(a->x) + cos(t) * bx - sin(t) * by;
    *y = fx_q16_16_to_double(a->y) + sin(t) * bx + cos(t) * by;
}

static void oracle_from(const ego_pose_t *a, const ego_pose_t *b, double *x, double *y)
{
    const double t = fx_bam32_to_rad(a->theta);
    const double dx = fx_q16_16_to_double(b->x) - fx_q16_16_to_double(a->x);
    const double dy = fx_q16_16_to_double(b->y) - fx_q16_16_to_double(a->y);
    *x = cos(t) * dx + sin(t) * dy;
    *y = -sin(t) * dx + cos(t) * dy;
}

/* The error in Q16.16 LSB. */
static double lsb_off(fx_q16_16_t v, double want)
{
    return fabs(fx_q16_16_to_double(v) - want) * 65536.0;
}

/* Random cases; on the Cortex-M test images (soft doubles under QEMU) a
 * fiftieth of them. */
#if defined(LMSEGO_UNIT_ON_TARGET)
#define CASES 4000u
#else
#define CASES 200000u
#endif

/* Within 0.5 LSB of rounding plus the sine table's 2^-30 times the length
 * (1 km: 0.06 LSB) and the one rounding of the sum: under 0.75 LSB. */
#define MAX_LSB 0.75

static void test_then_and_from_match_the_oracle(void)
{
    double worst = 0.0;
    for (unsigned k = 0u; k < CASES; k++) {
        const double limit = (k % 2u == 0u) ? 1.0 : 1000.0;
        const ego_pose_t a = rng_pose(limit);
        const ego_pose_t b = rng_pose(limit);
        double x;
        double y;
        oracle_then(&a, &b, &x, &y);
        const ego_pose_t t = ego_pose_then(&a, &b);
        TEST_ASSERT_EQUAL_UINT32((uint32_t)(a.theta + b.theta), t.theta);
        const double e1 = fmax(lsb_off(t.x, x), lsb_off(t.y, y));
        oracle_from(&a, &b, &x, &y);
        const ego_pose_t f = ego_pose_from(&a, &b);
        TEST_ASSERT_EQUAL_UINT32((uint32_t)(b.theta - a.theta), f.theta);
        const double e2 = fmax(lsb_off(f.x, x), lsb_off(f.y, y));
        worst = fmax(worst, fmax(e1, e2));
    }
    char msg[48];
    (void)snprintf(msg, sizeof msg, "worst %.3f LSB", worst);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(worst < MAX_LSB, msg);
}

/* No turn: the translations add and subtract exactly. */
static void test_no_turn_is_exact(void)
{
    for (unsigned k = 0u; k < CASES / 20u; k++) {
        ego_pose_t a = rng_pose(1000.0);
        a.theta = 0u;
        const ego_pose_t b = rng_pose(1000.0);
        const ego_pose_t t = ego_pose_then(&a, &b);
        TEST_ASSERT_EQUAL_INT32(a.x + b.x, t.x);
        TEST_ASSERT_EQUAL_INT32(a.y + b.y, t.y);
        const ego_pose_t f = ego_pose_from(&a, &b);
        TEST_ASSERT_EQUAL_INT32(b.x - a.x, f.x);
        TEST_ASSERT_EQUAL_INT32(b.y - a.y, f.y);
        TEST_ASSERT_EQUAL_UINT32(b.theta, f.theta);
    }
}

/* from(a, then(a, b)) gives b back within two roundings. */
static void test_from_undoes_then(void)
{
    for (unsigned k = 0u; k < CASES / 2u; k++) {
        const ego_pose_t a = rng_pose(100.0);
        const ego_pose_t b = rng_pose(100.0);
        const ego_pose_t t = ego_pose_then(&a, &b);
        const ego_pose_t back = ego_pose_from(&a, &t);
        TEST_ASSERT_EQUAL_UINT32(b.theta, back.theta);
        TEST_ASSERT_INT32_WITHIN(2, b.x, back.x);
        TEST_ASSERT_INT32_WITHIN(2, b.y, back.y);
    }
}

/* At the edge of Q16.16 the sums saturate; they never wrap. */
static void test_saturates_at_the_edge(void)
{
    const ego_pose_t a = {0u, INT32_MAX, INT32_MIN};
    const ego_pose_t b = {0u, INT32_MAX, INT32_MIN};
    const ego_pose_t t = ego_pose_then(&a, &b);
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, t.x);
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, t.y);
    const ego_pose_t f = ego_pose_from(&b, &(ego_pose_t){0u, INT32_MIN, INT32_MAX});
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, f.x);
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, f.y);
    /* Half a turn of the largest vector: -32768 m turned is +32768 m, one LSB beyond. */
    const ego_pose_t half = {0x80000000u, 0, 0};
    const ego_pose_t edge = {0u, INT32_MIN, 0};
    const ego_pose_t h = ego_pose_then(&half, &edge);
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, h.x);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_then_and_from_match_the_oracle);
    RUN_TEST(test_no_turn_is_exact);
    RUN_TEST(test_from_undoes_then);
    RUN_TEST(test_saturates_at_the_edge);
    return UNITY_END();
}
