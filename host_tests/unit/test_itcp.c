/* test_itcp.c - ITCP and ICP (estimator/ego_itcp.c): the closed form against
 * its double oracle, and registration of constructed scans with known
 * motion. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fx_host.h"
#include "ego_hist.h"
#include "ego_itcp.h"
#include "itcp_ref.h"
#include "lms_test_util.h"
#include "synth_scan.h"
#include "ego_tfit.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

static lms_scan_t g_lms;
static ego_scan_t g_last;
static ego_scan_t g_current;
static ego_hist_t g_hist;

static double rad_of(fx_bam32_t a)
{
    return (double)fx_bam32_diff(a, 0u) * FX_HOST_PI / 2147483648.0;
}

static void prepared_scan(const synth_wall_t *walls, unsigned nwalls, double x, double y,
                          double heading, ego_scan_t *scan)
{
    synth_scan(walls, nwalls, x, y, heading, 361u, LMS_UNIT_CM, &g_lms);
    ego_prep_params_t prep;
    ego_prep_defaults(&prep);
    TEST_ASSERT_EQUAL_INT(EGO_PREP_OK, ego_scan_prepare(synth_range(&g_lms), &prep, scan));
    ego_tfit_params_t fit;
    ego_tfit_defaults(&fit);
    ego_tfit_fit_scan(scan, &fit);
}

/* g_last at the origin, g_current moved by (dx, dy, th radians), the walls
 * seen from both; the main direction of g_last (its HTAH, in g_hist). */
static fx_bam32_t prepared_pair(const synth_wall_t *walls, unsigned nwalls, double dx, double dy,
                                double th)
{
    prepared_scan(walls, nwalls, 0.0, 0.0, 0.0, &g_last);
    prepared_scan(walls, nwalls, dx, dy, th, &g_current);
    ego_hist_params_t hp;
    ego_hist_defaults(&hp);
    (void)ego_hist_build(&g_last, &hp, &g_hist);
    return ego_hist_main_direction(&g_hist);
}

static void test_itcp_closed_form_matches_double_oracle(void)
{
    enum { N = 300 };
    static double x[N], y[N], u[N], v[N];
    static bool on_main[N];
    uint32_t rng = 99u;
    double worst_theta = 0.0;
    double worst_t = 0.0;
    for (unsigned trial = 0u; trial < 200u; trial++) {
        const unsigned n = 3u + tu_rand_range(&rng, 0u, N - 3u);
        const double theta = ((double)tu_rand(&rng) / 4294967296.0 - 0.5) * 1.5;
        const double tx = ((double)tu_rand(&rng) / 4294967296.0 - 0.5) * 6.0;
        const double ty = ((double)tu_rand(&rng) / 4294967296.0 - 0.5) * 6.0;
        const bool weighted = (trial % 2u) == 0u;
        const bool hold = (trial % 5u) == 0u;
        ego_itcp_sums_t sums;
        ego_itcp_sums_clear(&sums);
        for (unsigned k = 0u; k < n; k++) {
            const double px = ((double)tu_rand(&rng) / 4294967296.0 - 0.5) * 100.0;
            const double py = ((double)tu_rand(&rng) / 4294967296.0) * 60.0;
            const double noise_x = ((double)tu_rand(&rng) / 4294967296.0 - 0.5) * 0.05;
            const double noise_y = ((double)tu_rand(&rng) / 4294967296.0 - 0.5) * 0.05;
            const fx_q16_16_t fx = fx_q16_16_from_double(px);
            const fx_q16_16_t fy = fx_q16_16_from_double(py);
            const fx_q16_16_t fu =
                fx_q16_16_from_double(px * cos(theta) - py * sin(theta) + tx + noise_x);
            const fx_q16_16_t fv =
                fx_q16_16_from_double(px * sin(theta) + py * cos(theta) + ty + noise_y);
            on_main[k] = (tu_rand(&rng) % 3u) == 0u;
            x[k] = fx_q16_16_to_double(fx);
            y[k] = fx_q16_16_to_double(fy);
            u[k] = fx_q16_16_to_double(fu);
            v[k] = fx_q16_16_to_double(fv);
            ego_itcp_sums_add(&sums, on_main[k], fx, fy, fu, fv);
        }
        ego_pose_t pose = {fx_bam32_from_rad(theta + 0.01), 0, 0};
        double ref_theta = rad_of(pose.theta);
        double ref_tx = 0.0;
        double ref_ty = 0.0;
        ego_itcp_solve(&sums, weighted, hold, &pose);
        itcp_ref_solve(x, y, u, v, on_main, n, weighted, hold, &ref_theta, &ref_tx, &ref_ty);
        const double e_theta = fabs(rad_of(pose.theta) - ref_theta);
        const double e_t = fmax(fabs(fx_q16_16_to_double(pose.x) - ref_tx),
                                fabs(fx_q16_16_to_double(pose.y) - ref_ty));
        worst_theta = fmax(worst_theta, e_theta);
        worst_t = fmax(worst_t, e_t);
    }
    char msg[96];
    (void)snprintf(msg, sizeof msg, "worst theta %.3g rad, t %.3g m", worst_theta, worst_t);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(worst_theta < 1e-6, msg);
    TEST_ASSERT_TRUE_MESSAGE(worst_t < 1e-4, msg); /* 0.1 mm over a 100 m field */
}

typedef struct {
    double dx, dy, dtheta_deg;
} motion_t;

static void register_room(const motion_t *mo, bool weighted, double init_err_deg, double tol_m,
                          double tol_deg)
{
    const double th = mo->dtheta_deg * FX_HOST_PI / 180.0;
    const fx_bam32_t main_direction = prepared_pair(synth_room, synth_room_walls, mo->dx, mo->dy, th);
    itcp_params_t p;
    ego_itcp_defaults(&p);
    p.weighted = weighted;
    const ego_pose_t initial = {fx_bam32_from_rad(th + init_err_deg * FX_HOST_PI / 180.0), 0, 0};
    ego_itcp_result_t r;
    TEST_ASSERT_EQUAL_INT(EGO_ITCP_OK, ego_itcp_register(&g_last, &g_current, main_direction,
                                                 &initial, false, &p, &r));
    const double ex = fx_q16_16_to_double(r.pose.x) - mo->dx;
    const double ey = fx_q16_16_to_double(r.pose.y) - mo->dy;
    const double et = (rad_of(r.pose.theta) - th) * 180.0 / FX_HOST_PI;
    char msg[160];
    (void)snprintf(msg, sizeof msg,
                   "%s (%.2f, %.2f, %.2f deg): err %.4f %.4f m %.4f deg, it %u conv %d m %u/%u "
                   "in %u res %.4f",
                   weighted ? "ITCP" : "ICP", mo->dx, mo->dy, mo->dtheta_deg, ex, ey, et,
                   (unsigned)r.iterations, (int)r.converged, (unsigned)r.n_main,
                   (unsigned)r.n_non_main, (unsigned)r.inliers,
                   fx_q16_16_to_double(r.residual));
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(fabs(ex) < tol_m && fabs(ey) < tol_m, msg);
    TEST_ASSERT_TRUE_MESSAGE(fabs(et) < tol_deg, msg);
    TEST_ASSERT_TRUE_MESSAGE(r.converged, msg);
    TEST_ASSERT_FALSE_MESSAGE(r.aperture, msg);
    TEST_ASSERT_TRUE_MESSAGE(r.inliers > 200u, msg);
}

static void test_itcp_registers_known_motions(void)
{
    const motion_t motions[] = {
        {0.0, 0.0, 0.0}, {0.10, 0.02, 1.0}, {0.35, -0.12, -4.0}, {0.25, 0.20, 8.0},
    };
    for (unsigned k = 0u; k < sizeof motions / sizeof motions[0]; k++) {
        /* Started at the true rotation plus 0.3 deg (the histogram's
         * accuracy) and zero translation. With 1 cm range steps the errors
         * seen are below 1 mm and 0.016 deg. */
        register_room(&motions[k], true, 0.3, 0.002, 0.03);
        register_room(&motions[k], false, 0.3, 0.002, 0.03);
    }
}

static void test_itcp_hold_rotation_keeps_theta(void)
{
    prepared_scan(synth_room, synth_room_walls, 0.0, 0.0, 0.0, &g_last);
    prepared_scan(synth_room, synth_room_walls, 0.2, -0.1, 0.05, &g_current);
    itcp_params_t p;
    ego_itcp_defaults(&p);
    const ego_pose_t initial = {fx_bam32_from_rad(0.05), 0, 0};
    ego_itcp_result_t r;
    TEST_ASSERT_EQUAL_INT(EGO_ITCP_OK,
                          ego_itcp_register(&g_last, &g_current, 0u, &initial, true, &p, &r));
    TEST_ASSERT_EQUAL_UINT32(initial.theta, r.pose.theta);
    TEST_ASSERT_TRUE(fabs(fx_q16_16_to_double(r.pose.x) - 0.2) < 0.01);
    TEST_ASSERT_TRUE(fabs(fx_q16_16_to_double(r.pose.y) + 0.1) < 0.01);
}

static void test_itcp_flags_the_corridor_aperture(void)
{
    prepared_scan(synth_corridor, synth_corridor_walls, 0.0, 0.0, 0.0, &g_last);
    prepared_scan(synth_corridor, synth_corridor_walls, 0.3, 0.1, 0.02, &g_current);
    (void)ego_hist_build(&g_last, &(ego_hist_params_t){EGO_HIST_HTAH, 3u, FX_Q16_16_C(0.05), NULL}, &g_hist);
    itcp_params_t p;
    ego_itcp_defaults(&p);
    const ego_pose_t initial = {fx_bam32_from_rad(0.02), 0, 0};
    ego_itcp_result_t r;
    (void)ego_itcp_register(&g_last, &g_current, ego_hist_main_direction(&g_hist), &initial, false, &p,
                        &r);
    char msg[96];
    (void)snprintf(msg, sizeof msg, "n_main %u n_non %u y %.4f theta %.5f", (unsigned)r.n_main,
                   (unsigned)r.n_non_main, fx_q16_16_to_double(r.pose.y), rad_of(r.pose.theta));
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(r.aperture, msg);
    TEST_ASSERT_TRUE_MESSAGE(r.n_non_main * 5u < r.n_main, msg);
    /* Across the corridor the position and the heading are observable
     * (seen: 0.4 mm and 0.002 deg off); along it they are not, and the
     * pipeline (ego.c) keeps the predicted motion there. */
    TEST_ASSERT_TRUE_MESSAGE(fabs(fx_q16_16_to_double(r.pose.y) - 0.1) < 0.005, msg);
    TEST_ASSERT_TRUE_MESSAGE(fabs(rad_of(r.pose.theta) - 0.02) < 0.0005, msg);
}

static void test_itcp_fails_cleanly_without_points(void)
{
    prepared_scan(synth_room, synth_room_walls, 0.0, 0.0, 0.0, &g_last);
    memset(&g_current, 0, sizeof g_current);
    itcp_params_t p;
    ego_itcp_defaults(&p);
    const ego_pose_t initial = {123u, 456, -789};
    ego_itcp_result_t r;
    TEST_ASSERT_EQUAL_INT(EGO_ITCP_ERR_FEW_MATCHES,
                          ego_itcp_register(&g_last, &g_current, 0u, &initial, false, &p, &r));
    TEST_ASSERT_EQUAL_UINT32(123u, r.pose.theta);
    TEST_ASSERT_EQUAL_INT32(456, r.pose.x);
    /* Far from anything: no matches within the radius. */
    prepared_scan(synth_room, synth_room_walls, 0.0, 0.0, 0.0, &g_current);
    const ego_pose_t far = {0u, FX_Q16_16_C(50.0), 0};
    TEST_ASSERT_EQUAL_INT(EGO_ITCP_ERR_FEW_MATCHES,
                          ego_itcp_register(&g_last, &g_current, 0u, &far, false, &p, &r));
    TEST_ASSERT_EQUAL_INT(EGO_ITCP_ERR_ARG, ego_itcp_register(NULL, &g_current, 0u, &far, false, &p, &r));
}

/* Distance in double from (qx, qy) to the nearest segment of two linked
 * points of scan (brute force over the whole scan); *at_end: the nearest
 * point is an end of a surface (where ITCP's rules for artificial ends
 * apply, which this oracle leaves out). */
static double brute_force_nearest(const ego_scan_t *scan, double qx, double qy, bool *at_end)
{
    double best = 1e9;
    *at_end = false;
    for (uint16_t j = 0u; j + 1u < scan->count; j++) {
        if ((scan->flags[j] & (EGO_LINK_BREAK | EGO_LINK_OCCLUSION)) != 0u) {
            continue;
        }
        const double ax = fx_q16_16_to_double(scan->x[j]);
        const double ay = fx_q16_16_to_double(scan->y[j]);
        const double dx = fx_q16_16_to_double(scan->x[j + 1u]) - ax;
        const double dy = fx_q16_16_to_double(scan->y[j + 1u]) - ay;
        const double t = ((qx - ax) * dx + (qy - ay) * dy) / (dx * dx + dy * dy);
        const double tc = (t < 0.0) ? 0.0 : (t > 1.0) ? 1.0 : t;
        const double d = hypot(qx - ax - tc * dx, qy - ay - tc * dy);
        if (d < best) {
            best = d;
            const bool end_before = j == 0u || !ego_scan_linked(scan, (uint16_t)(j - 1u));
            const bool end_after = j + 2u >= scan->count || !ego_scan_linked(scan, (uint16_t)(j + 1u));
            *at_end = (t <= 0.0 && end_before) || (t >= 1.0 && end_after);
        }
    }
    return best;
}

/* The scan-order search finds the nearest surface that a search over every
 * segment finds, for points near the middle of the room's surfaces. */
static void test_itcp_nearest_matches_brute_force(void)
{
    prepared_scan(synth_room, synth_room_walls, 0.0, 0.0, 0.0, &g_last);
    uint32_t rng = 7u;
    double worst = 0.0;
    unsigned checked = 0u;
    for (unsigned trial = 0u; trial < 2000u; trial++) {
        const uint16_t j = (uint16_t)tu_rand_range(&rng, 20u, (uint32_t)g_last.count - 22u);
        if ((g_last.flags[j] & (EGO_LINK_BREAK | EGO_LINK_OCCLUSION)) != 0u) {
            continue;
        }
        /* A point up to 0.15 m off the segment's middle part. */
        const double t = 0.2 + 0.6 * (double)tu_rand(&rng) / 4294967296.0;
        const double off_x = ((double)tu_rand(&rng) / 4294967296.0 - 0.5) * 0.3;
        const double off_y = ((double)tu_rand(&rng) / 4294967296.0 - 0.5) * 0.3;
        const double ax = fx_q16_16_to_double(g_last.x[j]);
        const double ay = fx_q16_16_to_double(g_last.y[j]);
        const double qx = ax + t * (fx_q16_16_to_double(g_last.x[j + 1u]) - ax) + off_x;
        const double qy = ay + t * (fx_q16_16_to_double(g_last.y[j + 1u]) - ay) + off_y;
        bool at_end = false;
        const double truth = brute_force_nearest(&g_last, qx, qy, &at_end);
        if (at_end) {
            continue;
        }
        uint64_t d2 = 0u;
        TEST_ASSERT_TRUE(ego_itcp_nearest(&g_last, fx_q16_16_from_double(qx),
                                      fx_q16_16_from_double(qy), FX_Q16_16_C(0.6), &d2));
        const double d = sqrt((double)d2) / 65536.0;
        const double error = fabs(d - truth);
        worst = (error > worst) ? error : worst;
        checked++;
    }
    char msg[96];
    (void)snprintf(msg, sizeof msg, "%u points, worst distance error %.2e m", checked, worst);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(checked > 1000u, msg);
    TEST_ASSERT_TRUE_MESSAGE(worst < 5e-5, msg);
    /* Nothing within the radius: false. */
    uint64_t d2 = 0u;
    TEST_ASSERT_FALSE(ego_itcp_nearest(&g_last, FX_Q16_16_C(1.0), FX_Q16_16_C(0.5), FX_Q16_16_C(0.3),
                                   &d2));
}

/* Free space: in front of the last scan's walls yes, behind them no. */
static void test_itcp_seen_through_is_free_space(void)
{
    prepared_scan(synth_room, synth_room_walls, 0.0, 0.0, 0.0, &g_last);
    const fx_q16_16_t margin = FX_Q16_16_C(0.2);
    TEST_ASSERT_TRUE(ego_itcp_seen_through(&g_last, FX_Q16_16_C(1.0), FX_Q16_16_C(0.5), margin));
    TEST_ASSERT_TRUE(ego_itcp_seen_through(&g_last, FX_Q16_16_C(5.0), FX_Q16_16_C(0.5), margin));
    /* Within the margin of the far wall (x = 10), and behind it. */
    TEST_ASSERT_FALSE(ego_itcp_seen_through(&g_last, FX_Q16_16_C(9.9), FX_Q16_16_C(0.5), margin));
    TEST_ASSERT_FALSE(ego_itcp_seen_through(&g_last, FX_Q16_16_C(10.5), FX_Q16_16_C(0.5), margin));
    /* Behind the angled wall from (7, 4) to (9, 2.5). */
    TEST_ASSERT_FALSE(ego_itcp_seen_through(&g_last, FX_Q16_16_C(9.5), FX_Q16_16_C(3.0), margin));
    /* Behind the box at x 2.0-2.6, y -1.0..-0.4. */
    TEST_ASSERT_FALSE(ego_itcp_seen_through(&g_last, FX_Q16_16_C(3.5), FX_Q16_16_C(-1.0), margin));
}

/* Probes g_last at trials random points in x0 .. x0 + 12 m, -6 .. 6 m with
 * one prober, each against ego_itcp_nearest and ego_itcp_seen_through
 * asked afresh; counts the outcomes in seen. */
static void probes_agree(fx_q16_16_t radius, fx_q16_16_t margin, int32_t x0, unsigned trials,
                         uint32_t *rng, unsigned seen[3])
{
    ego_itcp_prober_t prober;
    ego_itcp_prober_init(&prober, &g_last, radius, margin);
    for (unsigned trial = 0u; trial < trials; trial++) {
        const fx_q16_16_t qx = (fx_q16_16_t)tu_rand_range(rng, 0u, 12u << 16) + x0 * 65536;
        const fx_q16_16_t qy = (fx_q16_16_t)tu_rand_range(rng, 0u, 12u << 16) - (6 << 16);
        uint64_t d_probe = 0u;
        uint64_t d_nearest = 0u;
        const ego_itcp_probe_t p = ego_itcp_probe(&prober, qx, qy, &d_probe);
        const bool near = ego_itcp_nearest(&g_last, qx, qy, radius, &d_nearest) &&
                          d_nearest < (uint64_t)((int64_t)radius * radius);
        const ego_itcp_probe_t expected =
            near ? EGO_ITCP_PROBE_SURFACE
                 : (ego_itcp_seen_through(&g_last, qx, qy, margin) ? EGO_ITCP_PROBE_SEEN_THROUGH
                                                               : EGO_ITCP_PROBE_NOTHING);
        TEST_ASSERT_EQUAL_INT(expected, p);
        if (near) {
            TEST_ASSERT_TRUE(d_nearest == d_probe);
        }
        seen[p]++;
    }
}

/* The coarse search's combined query gives what the two queries give. */
static void test_itcp_probe_is_nearest_then_free_space(void)
{
    prepared_scan(synth_room, synth_room_walls, 0.0, 0.0, 0.0, &g_last);
    uint32_t rng = 11u;
    unsigned seen[3] = {0u, 0u, 0u};
    probes_agree(FX_Q16_16_C(0.1), FX_Q16_16_C(0.2), -1, 3000u, &rng, seen);
    /* Every outcome occurred. */
    TEST_ASSERT_TRUE(seen[EGO_ITCP_PROBE_NOTHING] > 0u);
    TEST_ASSERT_TRUE(seen[EGO_ITCP_PROBE_SURFACE] > 0u);
    TEST_ASSERT_TRUE(seen[EGO_ITCP_PROBE_SEEN_THROUGH] > 0u);
}

/* The widest scan ego_range_check accepts (EGO_MAX_SWEEP, uniform steps,
 * from several first bearings): the prober, which starts each bearing
 * search where the last ended, still agrees with nearest and seen_through
 * asked afresh. A scan of a whole turn, whose last beam rounded onto the
 * first, broke this (fuzz_itcp, E4): its middle bearing was the first
 * beam's, and the searches placed a point by where they started. */
static void test_itcp_probe_agrees_on_the_widest_scan(void)
{
    enum { BEAMS = 360 }; /* within the Cortex-M builds' capacity (401) too */
    static uint16_t range[BEAMS];
    for (unsigned k = 0u; k < BEAMS; k++) {
        /* A room 3-5 m around, with a gap: mm. */
        range[k] = (k % 97u == 13u) ? 0u : (uint16_t)(4000.0 + 1000.0 * sin(k * 0.05));
    }
    ego_range_scan_t in;
    memset(&in, 0, sizeof in);
    in.count = BEAMS;
    in.range = range;
    in.range_unit_um = 1000u;
    in.bearing_step = ((uint64_t)(EGO_MAX_SWEEP - 1u) << 32) / (BEAMS - 1u);
    ego_prep_params_t prep;
    ego_prep_defaults(&prep);
    ego_tfit_params_t fit;
    ego_tfit_defaults(&fit);
    uint32_t rng = 5u;
    unsigned seen[3] = {0u, 0u, 0u};
    for (uint32_t first = 0u; first < 8u; first++) {
        in.first_bearing = ((uint64_t)first << 61) + 0x40000000u * first;
        TEST_ASSERT_TRUE(ego_range_check(&in));
        TEST_ASSERT_EQUAL_INT(EGO_PREP_OK, ego_scan_prepare(&in, &prep, &g_last));
        ego_tfit_fit_scan(&g_last, &fit);
        probes_agree(FX_Q16_16_C(0.3), FX_Q16_16_C(0.2), -6, 400u, &rng, seen);
    }
    TEST_ASSERT_TRUE(seen[EGO_ITCP_PROBE_NOTHING] > 0u);
    TEST_ASSERT_TRUE(seen[EGO_ITCP_PROBE_SURFACE] > 0u);
    TEST_ASSERT_TRUE(seen[EGO_ITCP_PROBE_SEEN_THROUGH] > 0u);
}

/* The first run's work cap: at most max_points of count, spread over the
 * whole scan. */
static void test_itcp_sample_stride_caps_the_points(void)
{
    TEST_ASSERT_EQUAL_UINT16(1u, ego_itcp_sample_stride(361u, 0u));
    TEST_ASSERT_EQUAL_UINT16(1u, ego_itcp_sample_stride(40u, 40u));
    TEST_ASSERT_EQUAL_UINT16(1u, ego_itcp_sample_stride(0u, 40u));
    for (uint16_t count = 1u; count <= 401u; count++) {
        for (uint16_t cap = 1u; cap <= 64u; cap++) {
            const uint16_t stride = ego_itcp_sample_stride(count, cap);
            const uint16_t taken = (uint16_t)((count - stride / 2u + stride - 1u) / stride);
            TEST_ASSERT_TRUE(taken <= cap);
            /* The smallest such stride: one less would take too many. */
            if (stride > 1u) {
                const uint16_t s1 = (uint16_t)(stride - 1u);
                TEST_ASSERT_TRUE((count - s1 / 2u + s1 - 1u) / s1 > cap ||
                                 (count + s1 - 1u) / s1 > cap);
            }
        }
    }
}

/* A registration of the run tests: scans, start and parameters. */
typedef struct {
    double dx, dy, dtheta_deg; /* the current scan's pose */
    double init_err_deg;       /* the initial rotation's error */
    double init_x;             /* the initial translation */
    uint16_t max_points;
    bool corridor;             /* the corridor, else the room */
    bool weighted;
    bool hold_rotation;
    bool tangent_gate;
} run_case_t;

static const run_case_t g_run_cases[] = {
    {0.25, 0.20, 8.0, 0.3, 0.0, 0u, false, true, false, false},
    {0.10, 0.02, 1.0, 0.3, 0.0, 0u, false, false, false, false},
    {0.35, -0.12, -4.0, 0.3, 0.0, 0u, false, true, false, true},
    {0.20, -0.10, 2.9, 0.0, 0.0, 0u, false, true, true, false},
    {0.35, -0.12, -4.0, 0.3, 0.0, 40u, false, true, false, false},
    {0.30, 0.10, 1.1, 0.0, 0.0, 0u, true, true, false, false}, /* the corridor */
    {0.0, 0.0, 0.0, 0.0, 50.0, 0u, false, true, false, false},  /* too far: few matches */
};

static itcp_params_t g_run_params;

/* Prepares g_last and g_current for case c; *initial and *main_direction
 * to start from. */
static void run_case_setup(const run_case_t *c, ego_pose_t *initial, fx_bam32_t *main_direction)
{
    const bool corridor = c->corridor;
    const synth_wall_t *walls = corridor ? synth_corridor : synth_room;
    const unsigned nwalls = corridor ? synth_corridor_walls : synth_room_walls;
    const double th = c->dtheta_deg * FX_HOST_PI / 180.0;
    *main_direction = prepared_pair(walls, nwalls, c->dx, c->dy, th);
    ego_itcp_defaults(&g_run_params);
    g_run_params.weighted = c->weighted;
    g_run_params.tangent_gate = c->tangent_gate;
    g_run_params.max_points = c->max_points;
    initial->theta = fx_bam32_from_rad(th + c->init_err_deg * FX_HOST_PI / 180.0);
    initial->x = fx_q16_16_from_double(c->init_x);
    initial->y = 0;
}

static void assert_same_result(const ego_itcp_result_t *a, const ego_itcp_result_t *b)
{
    TEST_ASSERT_EQUAL_UINT32(a->pose.theta, b->pose.theta);
    TEST_ASSERT_EQUAL_INT32(a->pose.x, b->pose.x);
    TEST_ASSERT_EQUAL_INT32(a->pose.y, b->pose.y);
    TEST_ASSERT_EQUAL_UINT8(a->iterations, b->iterations);
    TEST_ASSERT_EQUAL(a->converged, b->converged);
    TEST_ASSERT_EQUAL(a->aperture, b->aperture);
    TEST_ASSERT_EQUAL_UINT16(a->matches, b->matches);
    TEST_ASSERT_EQUAL_UINT16(a->n_main, b->n_main);
    TEST_ASSERT_EQUAL_UINT16(a->n_non_main, b->n_non_main);
    TEST_ASSERT_EQUAL_UINT16(a->inliers, b->inliers);
    TEST_ASSERT_EQUAL_UINT16(a->group_points[0], b->group_points[0]);
    TEST_ASSERT_EQUAL_UINT16(a->group_points[1], b->group_points[1]);
    TEST_ASSERT_EQUAL_INT32(a->group_fit[0], b->group_fit[0]);
    TEST_ASSERT_EQUAL_INT32(a->group_fit[1], b->group_fit[1]);
    TEST_ASSERT_EQUAL_INT32(a->residual, b->residual);
}

#define POINT_MAX ((uint64_t)EGO_COST_MATCH_POINT_MAX(EGO_ITCP_MAX_WALK))

static ego_itcp_run_t g_run;

/* A run cut into many small pieces (a meter of just more than one point,
 * started afresh for every call) gives ego_itcp_register's result, the
 * meter is never overdrawn, and the pieces add up to what one unlimited
 * call spends. */
static void test_itcp_run_in_small_pieces_is_register(void)
{
    for (unsigned k = 0u; k < sizeof g_run_cases / sizeof g_run_cases[0]; k++) {
        const run_case_t *c = &g_run_cases[k];
        ego_pose_t initial;
        fx_bam32_t main_direction;
        run_case_setup(c, &initial, &main_direction);
        ego_itcp_result_t expected;
        const ego_itcp_status_t expected_status =
            ego_itcp_register(&g_last, &g_current, main_direction, &initial, c->hold_rotation,
                              &g_run_params, &expected);

        ego_itcp_run_start(&g_run, &g_last, &g_current, main_direction, &initial,
                           c->hold_rotation, &g_run_params);
        ego_work_t work;
        ego_work_start(&work, EGO_WORK_UNLIMITED);
        TEST_ASSERT_TRUE(ego_itcp_run_step(&g_run, &work));
        const uint64_t total = work.used;
        ego_itcp_result_t r;
        TEST_ASSERT_EQUAL_INT(expected_status, ego_itcp_run_result(&g_run, &r));
        assert_same_result(&expected, &r);

        ego_itcp_run_start(&g_run, &g_last, &g_current, main_direction, &initial,
                           c->hold_rotation, &g_run_params);
        TEST_ASSERT_EQUAL_INT(EGO_ITCP_ERR_UNFINISHED, ego_itcp_run_result(&g_run, &r));
        uint64_t spent = 0u;
        uint32_t calls = 0u;
        bool finished = false;
        while (!finished && calls < 1000000u) {
            ego_work_start(&work, POINT_MAX + 1u);
            finished = ego_itcp_run_step(&g_run, &work);
            TEST_ASSERT_TRUE(work.used <= work.limit);
            TEST_ASSERT_TRUE(finished || work.used > 0u); /* progress every call */
            spent += work.used;
            calls++;
        }
        TEST_ASSERT_TRUE(finished);
        TEST_ASSERT_EQUAL_INT(expected_status, ego_itcp_run_result(&g_run, &r));
        assert_same_result(&expected, &r);
        TEST_ASSERT_TRUE(spent == total);
        char msg[128];
        (void)snprintf(msg, sizeof msg, "case %u: status %d, %u iterations, %llu units in %u calls",
                       k, (int)expected_status, (unsigned)r.iterations,
                       (unsigned long long)total, (unsigned)calls);
        TEST_MESSAGE(msg);
        TEST_ASSERT_TRUE(total > 0u);
        /* A finished run spends nothing more. */
        ego_work_start(&work, POINT_MAX);
        TEST_ASSERT_TRUE(ego_itcp_run_step(&g_run, &work));
        TEST_ASSERT_TRUE(work.used == 0u);
    }
}

/* A meter that cannot pay for one point makes no progress: nothing spent
 * beyond its limit, false, and the run goes on unchanged afterwards. */
static void test_itcp_run_too_small_a_meter_makes_no_progress(void)
{
    ego_pose_t initial;
    fx_bam32_t main_direction;
    run_case_setup(&g_run_cases[0], &initial, &main_direction);
    ego_itcp_result_t expected;
    TEST_ASSERT_EQUAL_INT(EGO_ITCP_OK, ego_itcp_register(&g_last, &g_current, main_direction,
                                                         &initial, false, &g_run_params,
                                                         &expected));
    ego_itcp_run_start(&g_run, &g_last, &g_current, main_direction, &initial, false,
                       &g_run_params);
    ego_work_t work;
    for (unsigned k = 0u; k < 3u; k++) {
        ego_work_start(&work, POINT_MAX - 1u);
        TEST_ASSERT_FALSE(ego_itcp_run_step(&g_run, &work));
        TEST_ASSERT_TRUE(work.used == 0u);
    }
    /* A meter already partly used: what is left counts. */
    ego_work_start(&work, POINT_MAX + 5000u);
    work.used = 5001u;
    TEST_ASSERT_FALSE(ego_itcp_run_step(&g_run, &work));
    TEST_ASSERT_TRUE(work.used == 5001u);
    /* Partway through: one point, then a meter too small again. */
    ego_work_start(&work, POINT_MAX);
    TEST_ASSERT_FALSE(ego_itcp_run_step(&g_run, &work));
    TEST_ASSERT_TRUE(work.used > 0u && work.used <= work.limit);
    ego_work_start(&work, POINT_MAX - 1u);
    TEST_ASSERT_FALSE(ego_itcp_run_step(&g_run, &work));
    TEST_ASSERT_TRUE(work.used == 0u);
    ego_work_start(&work, 0u);
    TEST_ASSERT_FALSE(ego_itcp_run_step(&g_run, &work));
    TEST_ASSERT_TRUE(work.used == 0u);
    ego_work_start(&work, EGO_WORK_UNLIMITED);
    TEST_ASSERT_TRUE(ego_itcp_run_step(&g_run, &work));
    ego_itcp_result_t r;
    TEST_ASSERT_EQUAL_INT(EGO_ITCP_OK, ego_itcp_run_result(&g_run, &r));
    assert_same_result(&expected, &r);
    /* Finished at the start: bad arguments, no points. */
    ego_itcp_run_start(&g_run, NULL, &g_current, 0u, &initial, false, &g_run_params);
    ego_work_start(&work, 0u);
    TEST_ASSERT_TRUE(ego_itcp_run_step(&g_run, &work));
    TEST_ASSERT_EQUAL_INT(EGO_ITCP_ERR_ARG, ego_itcp_run_result(&g_run, &r));
    TEST_ASSERT_EQUAL_INT(EGO_ITCP_ERR_ARG, ego_itcp_run_result(NULL, &r));
    TEST_ASSERT_TRUE(ego_itcp_run_step(NULL, &work));
}

/* max_points thins the first run only: the fine run and the statistics
 * pass take every point. The test reads the run's private fields (radius,
 * stride) to see which pass takes which points. */
static void test_itcp_max_points_thins_the_first_run_only(void)
{
    ego_pose_t initial;
    fx_bam32_t main_direction;
    run_case_setup(&g_run_cases[4], &initial, &main_direction);
    const uint16_t thinned = ego_itcp_sample_stride(g_current.count, g_run_params.max_points);
    TEST_ASSERT_TRUE(thinned > 1u);
    ego_itcp_run_start(&g_run, &g_last, &g_current, main_direction, &initial, false,
                       &g_run_params);
    unsigned coarse_passes = 0u;
    unsigned fine_passes = 0u;
    bool finished = false;
    for (uint32_t calls = 0u; !finished && calls < 1000000u; calls++) {
        ego_work_t work;
        ego_work_start(&work, POINT_MAX + 1u);
        if (g_run.radius == g_run_params.radius_fine) {
            TEST_ASSERT_EQUAL_UINT16(1u, g_run.stride);
            fine_passes++;
        } else if (g_run.radius > g_run_params.radius_min) {
            TEST_ASSERT_EQUAL_UINT16(thinned, g_run.stride);
            coarse_passes++;
        }
        finished = ego_itcp_run_step(&g_run, &work);
    }
    TEST_ASSERT_TRUE(finished);
    TEST_ASSERT_TRUE(coarse_passes > 0u);
    TEST_ASSERT_TRUE(fine_passes > 0u);
    ego_itcp_result_t r;
    TEST_ASSERT_EQUAL_INT(EGO_ITCP_OK, ego_itcp_run_result(&g_run, &r));
    TEST_ASSERT_TRUE(r.converged);
    /* The statistics pass counted every current point. */
    TEST_ASSERT_EQUAL_UINT16(g_current.count, r.group_points[0] + r.group_points[1]);
    TEST_ASSERT_TRUE(r.matches > g_run_params.max_points);
    /* And the pose is as good as with every point throughout. */
    const double ex = fx_q16_16_to_double(r.pose.x) - g_run_cases[4].dx;
    const double ey = fx_q16_16_to_double(r.pose.y) - g_run_cases[4].dy;
    const double et = rad_of(r.pose.theta) * 180.0 / FX_HOST_PI - g_run_cases[4].dtheta_deg;
    char msg[96];
    (void)snprintf(msg, sizeof msg, "err %.4f %.4f m %.4f deg, %u matches", ex, ey, et,
                   (unsigned)r.matches);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(fabs(ex) < 0.002 && fabs(ey) < 0.002 && fabs(et) < 0.03, msg);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_itcp_closed_form_matches_double_oracle);
    RUN_TEST(test_itcp_registers_known_motions);
    RUN_TEST(test_itcp_hold_rotation_keeps_theta);
    RUN_TEST(test_itcp_flags_the_corridor_aperture);
    RUN_TEST(test_itcp_fails_cleanly_without_points);
    RUN_TEST(test_itcp_sample_stride_caps_the_points);
    RUN_TEST(test_itcp_nearest_matches_brute_force);
    RUN_TEST(test_itcp_seen_through_is_free_space);
    RUN_TEST(test_itcp_probe_is_nearest_then_free_space);
    RUN_TEST(test_itcp_probe_agrees_on_the_widest_scan);
    RUN_TEST(test_itcp_run_in_small_pieces_is_register);
    RUN_TEST(test_itcp_run_too_small_a_meter_makes_no_progress);
    RUN_TEST(test_itcp_max_points_thins_the_first_run_only);
    return UNITY_END();
}
