/* test_tfit.c - robust tangents (estimator/ego_tfit.c) against the double
 * oracle (host_tests/ref/tfit_ref.c) and on constructed scans. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fx_host.h"
#include "lms_test_util.h"
#include "ego_tfit.h"
#include "tfit_ref.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

#define SIGMA_MIN FX_Q16_16_C(0.005)

static double deg(double rad)
{
    return rad * 180.0 / FX_HOST_PI;
}

/* Gaussian noise from the tests' xorshift generator (Box-Muller). */
static double gauss(uint32_t *rng)
{
    const double u1 = ((double)tu_rand(rng) + 1.0) / 4294967297.0;
    const double u2 = (double)tu_rand(rng) / 4294967296.0;
    return sqrt(-2.0 * log(u1)) * cos(2.0 * FX_HOST_PI * u2);
}

/* count points along direction dir (rad) through (0, 0), spacing step (m),
 * noise sigma (m) across the line, quantised to Q16.16. */
static void make_line(double dir, double step, double sigma, uint32_t *rng, unsigned count,
                      fx_q16_16_t *x, fx_q16_16_t *y, double *dx, double *dy)
{
    for (unsigned k = 0u; k < count; k++) {
        const double along = ((double)k - (double)(count - 1u) / 2.0) * step;
        const double across = (sigma > 0.0) ? sigma * gauss(rng) : 0.0;
        x[k] = fx_q16_16_from_double(along * cos(dir) - across * sin(dir));
        y[k] = fx_q16_16_from_double(along * sin(dir) + across * cos(dir));
        dx[k] = fx_q16_16_to_double(x[k]);
        dy[k] = fx_q16_16_to_double(y[k]);
    }
}

static void test_tfit_exact_lines_every_direction(void)
{
    fx_q16_16_t x[7];
    fx_q16_16_t y[7];
    double dx[7];
    double dy[7];
    uint32_t rng = 1u;
    double worst = 0.0;
    for (unsigned a = 0u; a < 3600u; a += 7u) {
        const double dir = (double)a * FX_HOST_PI / 3600.0; /* 0 .. 180 deg */
        make_line(dir, 0.05, 0.0, &rng, 7u, x, y, dx, dy);
        fx_bam32_t tangent = 0u;
        fx_q16_16_t rms = -1;
        TEST_ASSERT_TRUE(ego_tfit_fit(x, y, 7u, 2u, SIGMA_MIN, &tangent, &rms));
        TEST_ASSERT_EQUAL_UINT32(0u, tangent >> 31); /* modulo 180 deg */
        const double err = fx_host_line_angle_diff(fx_bam32_to_rad(tangent), dir);
        worst = (err > worst) ? err : worst;
        TEST_ASSERT_TRUE(rms >= 0 && rms <= 2);
    }
    /* Points 5 cm apart quantised to 15 um: the line itself is only known
     * to about 2e-4 rad; the fit must not add to that. */
    char msg[80];
    (void)snprintf(msg, sizeof msg, "worst %.6f deg", deg(worst));
    TEST_ASSERT_TRUE_MESSAGE(deg(worst) < 0.02, msg);
}

static void test_tfit_matches_double_oracle(void)
{
    fx_q16_16_t x[11];
    fx_q16_16_t y[11];
    double dx[11];
    double dy[11];
    uint32_t rng = 12345u;
    double worst_plain = 0.0;
    double worst_robust = 0.0;
    double worst_rms = 0.0;
    double worst_blob = 0.0; /* noise as large as the spacing: a blob */
    unsigned ill_conditioned = 0u;
    for (unsigned trial = 0u; trial < 2000u; trial++) {
        const unsigned count = 3u + (unsigned)tu_rand_range(&rng, 0u, 8u);
        const double dir = (double)tu_rand(&rng) / 4294967296.0 * FX_HOST_PI;
        const double step = 0.02 + (double)tu_rand_range(&rng, 0u, 500u) / 1000.0;
        const double sigma = (double)tu_rand_range(&rng, 0u, 30u) / 1000.0;
        make_line(dir, step, sigma, &rng, count, x, y, dx, dy);
        for (unsigned passes = 0u; passes <= 2u; passes += 2u) {
            fx_bam32_t tangent = 0u;
            fx_q16_16_t rms = 0;
            double ref_tangent = 0.0;
            double ref_rms = 0.0;
            double margin = 0.0;
            const bool ok =
                ego_tfit_fit(x, y, (uint16_t)count, (uint8_t)passes, SIGMA_MIN, &tangent, &rms);
            const bool ref_ok = tfit_ref_fit(dx, dy, count, passes, fx_q16_16_to_double(SIGMA_MIN),
                                             &ref_tangent, &ref_rms, &margin);
            TEST_ASSERT_EQUAL_INT(ref_ok, ok);
            if (!ok) {
                continue;
            }
            if (margin < 1e-2) {
                ill_conditioned++; /* a weight at eq. 2's jump: either side is right */
                continue;
            }
            const double err = fx_host_line_angle_diff(fx_bam32_to_rad(tangent), ref_tangent);
            const double rms_err = fabs(fx_q16_16_to_double(rms) - ref_rms);
            if (passes == 0u) {
                worst_plain = (err > worst_plain) ? err : worst_plain;
            } else if (sigma <= step / 2.0) {
                worst_robust = (err > worst_robust) ? err : worst_robust;
            } else {
                worst_blob = (err > worst_blob) ? err : worst_blob;
            }
            worst_rms = (rms_err > worst_rms) ? rms_err : worst_rms;
        }
    }
    char msg[160];
    (void)snprintf(msg, sizeof msg,
                   "plain %.7f deg robust %.7f deg (blobs %.7f deg) rms %.7f m, %u at the jump",
                   deg(worst_plain), deg(worst_robust), deg(worst_blob), worst_rms, ill_conditioned);
    TEST_MESSAGE(msg);
    /* The same inputs (exactly representable) through the same equations:
     * only rounding separates the two. Robust fits feed the rounded
     * residuals back into the weights, so where the noise is as large as
     * the point spacing (a blob, whose direction is barely defined) the
     * answers drift further apart; fits with a residual at eq. 2's jump are
     * counted, not compared. */
    TEST_ASSERT_TRUE_MESSAGE(deg(worst_plain) < 0.001, msg);
    TEST_ASSERT_TRUE_MESSAGE(deg(worst_robust) < 0.02, msg);
    TEST_ASSERT_TRUE_MESSAGE(deg(worst_blob) < 0.1, msg);
    TEST_ASSERT_TRUE_MESSAGE(worst_rms < 0.0002, msg);
    TEST_ASSERT_TRUE_MESSAGE(ill_conditioned < 40u, msg); /* of 4000 fits */
}

static void test_tfit_m_estimator_rejects_an_outlier(void)
{
    fx_q16_16_t x[7];
    fx_q16_16_t y[7];
    double dx[7];
    double dy[7];
    uint32_t rng = 7u;
    const double dir = 0.3;
    make_line(dir, 0.10, 0.002, &rng, 7u, x, y, dx, dy);
    /* The sixth point sits 0.25 m off the line (another surface). */
    x[5] = fx_add_q16(x[5], fx_q16_16_from_double(-0.25 * sin(dir)));
    y[5] = fx_add_q16(y[5], fx_q16_16_from_double(0.25 * cos(dir)));
    fx_bam32_t plain = 0u;
    fx_bam32_t robust = 0u;
    fx_q16_16_t rms = 0;
    TEST_ASSERT_TRUE(ego_tfit_fit(x, y, 7u, 0u, SIGMA_MIN, &plain, &rms));
    TEST_ASSERT_TRUE(ego_tfit_fit(x, y, 7u, 2u, SIGMA_MIN, &robust, &rms));
    const double plain_err = deg(fx_host_line_angle_diff(fx_bam32_to_rad(plain), dir));
    const double robust_err = deg(fx_host_line_angle_diff(fx_bam32_to_rad(robust), dir));
    char msg[80];
    (void)snprintf(msg, sizeof msg, "plain %.3f deg, robust %.3f deg", plain_err, robust_err);
    TEST_ASSERT_TRUE_MESSAGE(plain_err > 5.0, msg);
    TEST_ASSERT_TRUE_MESSAGE(robust_err < 1.0, msg);
}

static void test_tfit_rejects_degenerate_input(void)
{
    const fx_q16_16_t x[3] = {0, 0, 0};
    const fx_q16_16_t y[3] = {0, 1, 2};
    fx_bam32_t tangent = 123u;
    fx_q16_16_t rms = 456;
    TEST_ASSERT_FALSE(ego_tfit_fit(x, y, 1u, 2u, SIGMA_MIN, &tangent, &rms));
    TEST_ASSERT_FALSE(ego_tfit_fit(x, y, 0u, 2u, SIGMA_MIN, &tangent, &rms));
    TEST_ASSERT_FALSE(ego_tfit_fit(NULL, y, 3u, 2u, SIGMA_MIN, &tangent, &rms));
    TEST_ASSERT_FALSE(ego_tfit_fit(x, y, 2u * EGO_TFIT_MAX_HALF_WINDOW + 2u, 2u, SIGMA_MIN, &tangent, &rms));
    TEST_ASSERT_EQUAL_UINT32(123u, tangent);
    TEST_ASSERT_EQUAL_INT32(456, rms);
    /* Two points: a line, along y. */
    TEST_ASSERT_TRUE(ego_tfit_fit(x, y, 2u, 2u, SIGMA_MIN, &tangent, &rms));
    TEST_ASSERT_TRUE(fx_host_line_angle_diff(fx_bam32_to_rad(tangent), FX_HOST_PI / 2.0) < 1e-6);
}

/* A scan of two walls meeting in a corner, with a break in one of them. */
static void make_corner_scan(ego_scan_t *scan)
{
    memset(scan, 0, sizeof *scan);
    uint16_t n = 0u;
    /* Wall 1 along x at y = 2 (points 0..19), wall 2 along y at x = 4
     * (points 20..39); a break between 29 and 30. */
    for (int k = 0; k < 20; k++) {
        scan->x[n] = fx_q16_16_from_double(2.0 + 0.1 * k);
        scan->y[n] = fx_q16_16_from_double(2.0);
        n++;
    }
    for (int k = 0; k < 20; k++) {
        scan->x[n] = fx_q16_16_from_double(4.0);
        scan->y[n] = fx_q16_16_from_double(1.9 - 0.1 * k);
        n++;
    }
    scan->count = n;
    for (uint16_t i = 0u; i < n; i++) {
        scan->flags[i] = 0u;
    }
    scan->flags[29] = EGO_LINK_BREAK | EGO_LINK_JUMP;
    scan->flags[n - 1u] = EGO_LINK_BREAK;
    /* An isolated pair at the end of wall 2 cannot be fitted with 3. */
    scan->flags[37] = EGO_LINK_BREAK | EGO_LINK_GAP;
}

static void test_tfit_scan_follows_segments(void)
{
    static ego_scan_t scan;
    make_corner_scan(&scan);
    ego_tfit_params_t params;
    ego_tfit_defaults(&params);
    ego_tfit_fit_scan(&scan, &params);

    for (uint16_t i = 0u; i < 16u; i++) { /* wall 1, away from the corner */
        TEST_ASSERT_TRUE(scan.flags[i] & EGO_POINT_HAS_TANGENT);
        TEST_ASSERT_TRUE(fx_host_line_angle_diff(fx_bam32_to_rad(scan.tangent[i]), 0.0) < 1e-4);
    }
    for (uint16_t i = 24u; i < 30u; i++) { /* wall 2 up to the break */
        TEST_ASSERT_TRUE(scan.flags[i] & EGO_POINT_HAS_TANGENT);
        TEST_ASSERT_TRUE(
            fx_host_line_angle_diff(fx_bam32_to_rad(scan.tangent[i]), FX_HOST_PI / 2.0) < 1e-4);
    }
    /* Points 30..37 form their own segment; 38..39 are too few. */
    TEST_ASSERT_TRUE(scan.flags[30] & EGO_POINT_HAS_TANGENT);
    TEST_ASSERT_TRUE(scan.flags[37] & EGO_POINT_HAS_TANGENT);
    TEST_ASSERT_FALSE(scan.flags[38] & EGO_POINT_HAS_TANGENT);
    TEST_ASSERT_FALSE(scan.flags[39] & EGO_POINT_HAS_TANGENT);
    /* The link flags are kept. */
    TEST_ASSERT_TRUE(scan.flags[29] & EGO_LINK_BREAK);
    TEST_ASSERT_TRUE(scan.flags[37] & EGO_LINK_GAP);
}

/* The search refines tangents point by point within its budget: a point
 * fitted alone gets the tangent a fit of every point gives it, and its
 * neighbours are left alone. */
static void test_tfit_point_fits_like_the_scan(void)
{
    static ego_scan_t all;
    static ego_scan_t some;
    make_corner_scan(&all);
    make_corner_scan(&some);
    ego_tfit_params_t params;
    ego_tfit_defaults(&params);
    ego_tfit_fit_scan(&all, &params);
    unsigned fitted = 0u;
    for (uint16_t i = 1u; i < all.count; i = (uint16_t)(i + 3u)) {
        ego_tfit_fit_point(&some, &params, i);
    }
    for (uint16_t i = 0u; i < all.count; i++) {
        if (i % 3u == 1u) {
            TEST_ASSERT_EQUAL_UINT8(all.flags[i], some.flags[i]);
            TEST_ASSERT_EQUAL_UINT32(all.tangent[i], some.tangent[i]);
            fitted += (some.flags[i] & EGO_POINT_HAS_TANGENT) != 0u ? 1u : 0u;
        } else {
            TEST_ASSERT_FALSE(some.flags[i] & EGO_POINT_HAS_TANGENT);
            /* The link flags are kept. */
            TEST_ASSERT_EQUAL_UINT8(all.flags[i] & (uint8_t)~EGO_POINT_HAS_TANGENT,
                                    some.flags[i]);
        }
    }
    TEST_ASSERT_TRUE(fitted >= 10u);
}

/* Chord tangents (tracking's): a chord spans 0.2 m at least, widened over
 * up to 4 linked neighbours on each side, so 1 cm of range noise on a
 * near wall (0.5 deg apart at 3.75 m: 3.3 cm) leaves nearly every point
 * within the main direction's 10 deg; each tangent is the direction of the
 * chord the double oracle picks the same way; a segment's end uses one
 * side, a lone point gets none. */
static void test_tfit_chord_spans_its_minimum(void)
{
    static ego_scan_t scan;
    double dx[48];
    double dy[48];
    uint32_t rng = 12345u;
    const double wall = 0.3; /* rad */
    memset(&scan, 0, sizeof scan);
    scan.count = 48u;
    make_line(wall, 0.033, 0.01, &rng, 40u, scan.x, scan.y, dx, dy);
    scan.flags[39] = EGO_LINK_BREAK;                 /* the wall ends at 39 */
    scan.x[40] = FX_Q16_16_C(5.0);                   /* 40: a lone point */
    scan.flags[40] = EGO_LINK_BREAK;
    for (uint16_t i = 41u; i < 48u; i++) {           /* 41..47: a short run */
        scan.x[i] = FX_Q16_16_C(9.0);
        scan.y[i] = (fx_q16_16_t)(i * FX_Q16_16_C(0.05));
    }
    scan.flags[47] = EGO_LINK_BREAK;
    ego_tfit_chord_scan(&scan);
    unsigned along = 0u;
    for (uint16_t i = 0u; i < 40u; i++) {
        TEST_ASSERT_TRUE(scan.flags[i] & EGO_POINT_HAS_TANGENT);
        /* The oracle: widen on both sides until the chord spans 0.2 m. */
        int a = i;
        int b = i;
        for (int k = 0; k < 4; k++) {
            a = (a > 0) ? a - 1 : a;
            b = (b < 39) ? b + 1 : b;
            if (hypot(dx[b] - dx[a], dy[b] - dy[a]) >= 0.2) {
                break;
            }
        }
        const double chord = atan2(dy[b] - dy[a], dx[b] - dx[a]);
        char msg[96];
        (void)snprintf(msg, sizeof msg, "point %u: chord %d..%d", (unsigned)i, a, b);
        TEST_ASSERT_TRUE_MESSAGE(
            fx_host_line_angle_diff(fx_bam32_to_rad(scan.tangent[i]), chord) < 0.01, msg);
        along += fx_host_line_angle_diff(fx_bam32_to_rad(scan.tangent[i]), wall) < 10.0 * FX_HOST_PI / 180.0
                     ? 1u
                     : 0u;
    }
    TEST_ASSERT_TRUE(along >= 38u);
    TEST_ASSERT_FALSE(scan.flags[40] & EGO_POINT_HAS_TANGENT);
    /* The run at x = 9 m: vertical wherever the chord lies in it. */
    for (uint16_t i = 41u; i < 48u; i++) {
        TEST_ASSERT_TRUE(scan.flags[i] & EGO_POINT_HAS_TANGENT);
        TEST_ASSERT_TRUE(fx_host_line_angle_diff(fx_bam32_to_rad(scan.tangent[i]), FX_HOST_PI / 2.0) < 0.01);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_tfit_exact_lines_every_direction);
    RUN_TEST(test_tfit_matches_double_oracle);
    RUN_TEST(test_tfit_m_estimator_rejects_an_outlier);
    RUN_TEST(test_tfit_rejects_degenerate_input);
    RUN_TEST(test_tfit_scan_follows_segments);
    RUN_TEST(test_tfit_point_fits_like_the_scan);
    RUN_TEST(test_tfit_chord_spans_its_minimum);
    return UNITY_END();
}
