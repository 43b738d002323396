/* test_ego_scan.c - the LMS adapter (firmware/ego_lms.c) and scan
 * preparation (estimator/ego_scan.c) together: polar LMS values to
 * vehicle-frame points, against double-precision geometry, and the segment
 * structure on constructed scans. The generic range input on its own:
 * test_ego_range.c. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ego_lms.h"
#include "ego_scan.h"
#include "fx_host.h"
#include "unity.h"

static lms_scan_t g_lms;
static ego_lms_params_t g_lmsp; /* mount and measuring mode: defaults before each test */
static lms_scan_t g_work; /* g_lms with its values turned into ranges */
static ego_range_scan_t g_range;
static ego_scan_t g_scan;

void setUp(void)
{
    ego_lms_defaults(&g_lmsp);
}

void tearDown(void)
{
}

/* Raw LMS word of a range in the scan's unit (mode 00, 13 bits). */
static uint16_t word_of(double metres, lms_unit_t unit)
{
    const double units = metres * (unit == LMS_UNIT_MM ? 1000.0 : 100.0);
    const long v = lround(units);
    return (uint16_t)((v > 0x1FF6) ? 0x1FF7 : v);
}

/* Vehicle-frame beam angle (rad) of LMS value k: 180-deg fields start at
 * -90 deg, 100-deg fields at -50 deg. */
static double beam_rad(unsigned k, unsigned count)
{
    double start = -90.0;
    double step = 1.0;
    switch (count) {
    case 361u:
        step = 0.5;
        break;
    case 101u:
        start = -50.0;
        break;
    case 201u:
        start = -50.0;
        step = 0.5;
        break;
    case 401u:
        start = -50.0;
        step = 0.25;
        break;
    default:
        break;
    }
    return (start + step * k) * FX_HOST_PI / 180.0;
}

/* A scanner in front of a wall x = d (vehicle frame, no mount offset). */
static void make_wall_scan(unsigned count, lms_unit_t unit, double d)
{
    memset(&g_lms, 0, sizeof g_lms);
    g_lms.count = (uint16_t)count;
    g_lms.unit = unit;
    for (unsigned k = 0u; k < count; k++) {
        const double c = cos(beam_rad(k, count));
        g_lms.values[k] = (c > 0.05) ? word_of(d / c, unit) : 0x1FF7u;
    }
}

static void prepare(const ego_prep_params_t *p)
{
    g_work = g_lms;
    TEST_ASSERT_EQUAL_INT(EGO_LMS_OK, ego_lms_to_range(&g_work, &g_lmsp, &g_range));
    TEST_ASSERT_EQUAL_INT(EGO_PREP_OK, ego_scan_prepare(&g_range, p, &g_scan));
}

/* Every point against the exact polar -> Cartesian of its integer range. */
static void check_points_against_double(const ego_prep_params_t *p, double mx, double my,
                                        double mtheta)
{
    const double unit_m = (g_lms.unit == LMS_UNIT_MM) ? 0.001 : 0.01;
    uint16_t i = 0u;
    double worst = 0.0;
    for (unsigned k = 0u; k < g_lms.count; k++) {
        const unsigned raw = g_lms.values[k] & 0x1FFFu;
        const double r = raw * unit_m;
        if (raw >= 0x1FF7u || r < fx_q16_16_to_double(p->min_range) ||
            r > fx_q16_16_to_double(p->max_range)) {
            continue;
        }
        const double a = beam_rad(k, g_lms.count) + mtheta;
        const double ex = mx + r * cos(a);
        const double ey = my + r * sin(a);
        TEST_ASSERT_TRUE(i < g_scan.count);
        const double err = fmax(fabs(fx_q16_16_to_double(g_scan.x[i]) - ex),
                                fabs(fx_q16_16_to_double(g_scan.y[i]) - ey));
        worst = (err > worst) ? err : worst;
        i++;
    }
    TEST_ASSERT_EQUAL_UINT16(i, g_scan.count);
    char msg[64];
    (void)snprintf(msg, sizeof msg, "worst %.3g m", worst);
    /* Q16.16 rounding of range and result: a few LSB of 15 um. */
    TEST_ASSERT_TRUE_MESSAGE(worst < 4.0 / 65536.0, msg);
}

static void test_ego_scan_wall_in_every_layout(void)
{
    const unsigned counts[] = {181u, 361u, 101u, 201u, 401u};
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    for (unsigned c = 0u; c < 5u; c++) {
        make_wall_scan(counts[c], LMS_UNIT_MM, 3.0);
        prepare(&p);
        TEST_ASSERT_EQUAL_UINT16(counts[c], g_scan.beams);
        /* The mirror's timing: 1 deg a turn at 75 Hz, finer scans interlace turns. */
        const unsigned turns = (counts[c] == 181u || counts[c] == 101u) ? 1u : (counts[c] == 401u) ? 4u : 2u;
        TEST_ASSERT_EQUAL_UINT32(turns, ego_range_passes(&g_range));
        TEST_ASSERT_EQUAL_UINT32(13333u, g_range.pass_us);
        TEST_ASSERT_EQUAL_UINT32(37037u, g_range.beam_ns);
        TEST_ASSERT_TRUE(g_scan.count > 50u);
        check_points_against_double(&p, 0.0, 0.0, 0.0);
        for (uint16_t i = 0u; i < g_scan.count; i++) {
            TEST_ASSERT_INT32_WITHIN(40, FX_Q16_16_C(3.0), g_scan.x[i]); /* 1 mm quantum */
        }
    }
}

/* The bounded profile's thinning: a beam spacing of 1 deg keeps every
 * second value of a 0.5-deg scan, every fourth of a 0.25-deg one, and
 * every value of a 1-deg scan; the kept points are exactly the full
 * scan's points at those beams, and they stay one segment. */
static void test_ego_scan_beam_spacing_thins_fine_scans(void)
{
    const unsigned counts[] = {181u, 361u, 401u};
    const unsigned steps[] = {1u, 2u, 4u};
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    for (unsigned c = 0u; c < 3u; c++) {
        static ego_scan_t full;
        make_wall_scan(counts[c], LMS_UNIT_MM, 3.0);
        p.beam_spacing = 0u;
        prepare(&p);
        full = g_scan;
        p.beam_spacing = FX_BAM32_DEG_C(1.0);
        prepare(&p);
        /* The wall is seen in a contiguous run of beams: every steps[c]-th
         * of them is kept. */
        TEST_ASSERT_TRUE(g_scan.count + 1u >= full.count / steps[c]);
        TEST_ASSERT_TRUE(g_scan.count <= full.count / steps[c] + 1u);
        uint16_t j = 0u;
        for (uint16_t i = 0u; i < g_scan.count; i++) {
            while (j < full.count && full.bearing[j] != g_scan.bearing[i]) {
                j++;
            }
            TEST_ASSERT_TRUE(j < full.count);
            TEST_ASSERT_EQUAL_INT32(full.x[j], g_scan.x[i]);
            TEST_ASSERT_EQUAL_INT32(full.y[j], g_scan.y[i]);
            if (i + 1u < g_scan.count) {
                TEST_ASSERT_TRUE(j + steps[c] < full.count);
                TEST_ASSERT_EQUAL_UINT32(full.bearing[j + steps[c]], g_scan.bearing[i + 1u]);
                TEST_ASSERT_TRUE(ego_scan_linked(&g_scan, i));
            }
        }
    }
}

/* The spacing's lever arm: the points' RMS range times the kept beams'
 * spacing, against a double oracle on a wall and, thinned to 1 deg, on it
 * again. */
static void test_ego_scan_spacing_arm(void)
{
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    for (unsigned thin = 0u; thin < 2u; thin++) {
        make_wall_scan(361u, LMS_UNIT_CM, 7.5);
        p.beam_spacing = (thin == 1u) ? FX_BAM32_DEG_C(1.0) : 0u;
        prepare(&p);
        double sum = 0.0;
        for (uint16_t i = 0u; i < g_scan.count; i++) {
            const double x = fx_q16_16_to_double(g_scan.x[i]);
            const double y = fx_q16_16_to_double(g_scan.y[i]);
            sum += x * x + y * y;
        }
        const double spacing = ((thin == 1u) ? 1.0 : 0.5) * FX_HOST_PI / 180.0;
        const double oracle = sqrt(sum / g_scan.count) * spacing;
        const double got = fx_q16_16_to_double(g_scan.spacing_arm);
        char msg[80];
        (void)snprintf(msg, sizeof msg, "thin %u: %.5f m, oracle %.5f m", thin, got, oracle);
        TEST_ASSERT_TRUE_MESSAGE(fabs(got - oracle) < 1e-3 * oracle + 1e-4, msg);
    }
}

static void test_ego_scan_centimetres_and_mount(void)
{
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    g_lmsp.mount_x = FX_Q16_16_C(1.5);
    g_lmsp.mount_y = FX_Q16_16_C(-0.25);
    g_lmsp.mount_theta = FX_BAM32_DEG_C(30.0);
    make_wall_scan(361u, LMS_UNIT_CM, 20.0);
    prepare(&p);
    check_points_against_double(&p, 1.5, -0.25, 30.0 * FX_HOST_PI / 180.0);
    /* The beam straight ahead of the scanner (value 180) lands at the
     * mount point plus 20 m along 30 deg. */
    uint16_t ahead = 0u;
    for (unsigned k = 0u; k < 180u; k++) {
        ahead = (uint16_t)(ahead + ((g_lms.values[k] & 0x1FFFu) < 0x1FF7u ? 1u : 0u));
    }
    TEST_ASSERT_INT32_WITHIN(8, FX_Q16_16_C(1.5 + 20.0 * 0.86602540378), g_scan.x[ahead]);
    TEST_ASSERT_INT32_WITHIN(8, FX_Q16_16_C(-0.25 + 20.0 * 0.5), g_scan.y[ahead]);
}

static void test_ego_scan_special_values_leave_gaps(void)
{
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    make_wall_scan(181u, LMS_UNIT_MM, 3.0);
    g_lms.values[90] = 0x1FFFu;                   /* no return */
    g_lms.values[91] = 0x1FFEu;                   /* dazzle */
    g_lms.values[100] = (uint16_t)(0x8000u | 3000u); /* dazzle flag on a range: kept */
    prepare(&p);
    /* Values 31..149 hit the wall within 8.18 m (cos > 0.3667). */
    uint16_t expected = 0u;
    uint16_t before_gap = 0u;
    for (unsigned k = 0u; k < 181u; k++) {
        const unsigned raw = g_lms.values[k] & 0x1FFFu;
        if (raw < 0x1FF7u && raw >= 100u) {
            if (k < 90u) {
                before_gap = expected;
            }
            expected++;
        }
    }
    TEST_ASSERT_EQUAL_UINT16(expected, g_scan.count);
    TEST_ASSERT_EQUAL_HEX8(EGO_LINK_BREAK | EGO_LINK_GAP, g_scan.flags[before_gap]);
    for (uint16_t i = 0u; i + 1u < g_scan.count; i++) {
        if (i != before_gap) {
            TEST_ASSERT_EQUAL_HEX8_MESSAGE(0u, g_scan.flags[i], "a plain wall has no breaks");
        }
    }
    TEST_ASSERT_EQUAL_HEX8(EGO_LINK_BREAK, g_scan.flags[g_scan.count - 1u]);
}

static void test_ego_scan_range_jumps_break(void)
{
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    make_wall_scan(181u, LMS_UNIT_MM, 6.0);
    for (unsigned k = 85u; k <= 95u; k++) { /* a post 2 m ahead */
        g_lms.values[k] = word_of(2.0 / cos(beam_rad(k, 181u)), LMS_UNIT_MM);
    }
    prepare(&p);
    unsigned jumps = 0u;
    for (uint16_t i = 0u; i + 1u < g_scan.count; i++) {
        if (g_scan.flags[i] & EGO_LINK_JUMP) {
            TEST_ASSERT_TRUE(g_scan.flags[i] & EGO_LINK_BREAK);
            jumps++;
        }
    }
    TEST_ASSERT_EQUAL_UINT(2u, jumps);
}

static void test_ego_scan_occlusion_edge(void)
{
    /* A wall along the x axis at y = -0.5 m, seen at grazing angles: at 0.5
     * deg steps near -9.5 deg the range changes too little for a jump, but
     * the wall runs within 10 deg of the beams: occlusion edges. Further
     * out (|angle| > 10.5 deg) the links are ordinary. */
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    memset(&g_lms, 0, sizeof g_lms);
    g_lms.count = 361u;
    g_lms.unit = LMS_UNIT_MM;
    for (unsigned k = 0u; k < 361u; k++) {
        const double a = beam_rad(k, 361u);
        g_lms.values[k] = (a < -0.09) ? word_of(-0.5 / sin(a), LMS_UNIT_MM) : 0x1FF7u;
    }
    prepare(&p);
    TEST_ASSERT_TRUE(g_scan.count > 100u);
    unsigned occlusions = 0u;
    for (uint16_t i = 0u; i + 1u < g_scan.count; i++) {
        const double a = atan2(fx_q16_16_to_double(g_scan.y[i + 1u]),
                               fx_q16_16_to_double(g_scan.x[i + 1u]));
        const bool grazing = fabs(a) < 9.9 * FX_HOST_PI / 180.0;
        const bool clear = fabs(a) > 10.6 * FX_HOST_PI / 180.0;
        if (g_scan.flags[i] & EGO_LINK_OCCLUSION) {
            occlusions++;
            TEST_ASSERT_FALSE_MESSAGE(clear, "an ordinary link marked occlusion");
        } else {
            TEST_ASSERT_FALSE_MESSAGE(grazing && !(g_scan.flags[i] & EGO_LINK_JUMP),
                                      "a grazing link not marked");
        }
    }
    TEST_ASSERT_TRUE(occlusions > 0u);
}

static void test_ego_scan_range_limits_and_errors(void)
{
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    p.max_range = FX_Q16_16_C(4.0);
    make_wall_scan(181u, LMS_UNIT_MM, 3.0);
    prepare(&p);
    check_points_against_double(&p, 0.0, 0.0, 0.0);

    TEST_ASSERT_EQUAL_INT(EGO_PREP_ERR_ARG, ego_scan_prepare(NULL, &p, &g_scan));
    TEST_ASSERT_EQUAL_INT(EGO_PREP_ERR_ARG, ego_scan_prepare(&g_range, NULL, &g_scan));
    TEST_ASSERT_EQUAL_INT(EGO_PREP_ERR_ARG, ego_scan_prepare(&g_range, &p, NULL));
    TEST_ASSERT_EQUAL_INT(EGO_LMS_ERR_ARG, ego_lms_to_range(NULL, &g_lmsp, &g_range));
    TEST_ASSERT_EQUAL_INT(EGO_LMS_ERR_ARG, ego_lms_to_range(&g_work, NULL, &g_range));
    TEST_ASSERT_EQUAL_INT(EGO_LMS_ERR_ARG, ego_lms_to_range(&g_work, &g_lmsp, NULL));
    g_work = g_lms;
    g_lmsp.meas_mode = 0x3Fu; /* reflectivity: not ranges */
    TEST_ASSERT_EQUAL_INT(EGO_LMS_ERR_ARG, ego_lms_to_range(&g_work, &g_lmsp, &g_range));
    TEST_ASSERT_EQUAL_UINT16(0u, g_range.count);
    g_lmsp.meas_mode = 0x07u;
    TEST_ASSERT_EQUAL_INT(EGO_LMS_ERR_ARG, ego_lms_to_range(&g_work, &g_lmsp, &g_range));
    ego_lms_defaults(&g_lmsp);
    g_work = g_lms;
    g_work.count = 180u; /* no LMS variant */
    TEST_ASSERT_EQUAL_INT(EGO_LMS_ERR_LAYOUT, ego_lms_to_range(&g_work, &g_lmsp, &g_range));
    TEST_ASSERT_EQUAL_UINT16(0u, g_range.count);
}

/* De-skewing: the LMS at 0.5 deg (two mirror turns 13.3 ms apart) on a
 * vehicle at 20 m/s turning 0.5 rad/s, 1 m ahead of its origin, facing
 * a wall 6 m ahead of the origin at the scan's time. Each value is
 * ray-cast from where the scanner was at its own time (constant twist);
 * de-skewed with that motion, every point lies on the wall (the scan
 * time's frame) within 3 mm; taken as measured at once, they spread over
 * centimetres, and ego_scan_prepare is that. */
static void test_ego_scan_deskews_an_interlaced_scan_in_motion(void)
{
    const double v = 20.0;
    const double w = 0.5;
    const double mount = 1.0;
    const double wall = 6.0;
    g_lmsp.mount_x = FX_Q16_16_C(1.0);
    memset(&g_lms, 0, sizeof g_lms);
    g_lms.count = 361u;
    g_lms.unit = LMS_UNIT_MM;
    /* Value k: turn k % 2, k / 2 degrees into it (whole degrees). */
    double mean = 0.0;
    for (unsigned k = 0u; k < 361u; k++) {
        const unsigned degrees = k / 2u;
        mean += ((k % 2u) * 13333.0 + (double)degrees * 37.037) * 1e-6 / 361.0;
    }
    for (unsigned k = 0u; k < 361u; k++) {
        const unsigned degrees = k / 2u;
        const double tau = (k % 2u) * 0.013333 + (double)degrees * 37.037e-6 - mean;
        /* The vehicle at tau on its arc, the scanner 1 m ahead on it. */
        const double th = w * tau;
        const double px = v * sin(th) / w + mount * cos(th);
        const double py = v * (1.0 - cos(th)) / w + mount * sin(th);
        const double c = cos(beam_rad(k, 361u) + th);
        g_lms.values[k] = (c > 0.2) ? word_of((wall - px) / c, LMS_UNIT_MM) : 0x1FF7u;
        (void)py;
    }
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    g_work = g_lms;
    TEST_ASSERT_EQUAL_INT(EGO_LMS_OK, ego_lms_to_range(&g_work, &g_lmsp, &g_range));
    const double dt = 2.0 / 75.0;
    ego_skew_t skew;
    skew.dt_us = 26667u;
    skew.motion.x = FX_Q16_16_C(v * sin(w * dt) / w);
    skew.motion.y = FX_Q16_16_C(v * (1.0 - cos(w * dt)) / w);
    skew.motion.theta = (fx_bam32_t)(uint32_t)lround(w * dt / 6.283185307179586 * 4294967296.0);
    TEST_ASSERT_EQUAL_INT(EGO_PREP_OK, ego_scan_prepare_deskewed(&g_range, &p, &skew, &g_scan));
    TEST_ASSERT_TRUE(g_scan.count > 100u);
    double worst = 0.0;
    for (uint16_t i = 0u; i < g_scan.count; i++) {
        worst = fmax(worst, fabs(fx_q16_16_to_double(g_scan.x[i]) - wall));
    }
    char msg[64];
    (void)snprintf(msg, sizeof msg, "de-skewed: %.4f m off the wall", worst);
    TEST_ASSERT_TRUE_MESSAGE(worst < 0.003, msg);
    TEST_MESSAGE(msg);
    /* The two passes, 0.27 m apart along the track, cross over: the
     * points are in the order of their bearings from the scanner at the
     * scan's time, each bearing its point's direction, and the wall is one
     * segment (as measured, each pass's points zig-zag with the other's). */
    unsigned breaks = 0u;
    double off_bearing = 0.0;
    for (uint16_t i = 0u; i < g_scan.count; i++) {
        if (i > 0u) {
            TEST_ASSERT_TRUE(fx_bam32_diff(g_scan.bearing[i], g_scan.bearing[i - 1u]) > 0);
        }
        if (i + 1u < g_scan.count && !ego_scan_linked(&g_scan, i)) {
            breaks++;
        }
        const double dir = atan2(fx_q16_16_to_double(g_scan.y[i]) - fx_q16_16_to_double(g_scan.origin_y),
                                 fx_q16_16_to_double(g_scan.x[i]) - fx_q16_16_to_double(g_scan.origin_x));
        const double b = (double)(int32_t)g_scan.bearing[i] / 4294967296.0 * 6.283185307179586;
        off_bearing = fmax(off_bearing, fabs(remainder(dir - b, 6.283185307179586)));
    }
    TEST_ASSERT_TRUE(off_bearing < 1e-4);
    TEST_ASSERT_EQUAL_UINT(0u, breaks);
    TEST_ASSERT_EQUAL_INT(EGO_PREP_OK, ego_scan_prepare(&g_range, &p, &g_scan));
    worst = 0.0;
    for (uint16_t i = 0u; i < g_scan.count; i++) {
        worst = fmax(worst, fabs(fx_q16_16_to_double(g_scan.x[i]) - wall));
    }
    (void)snprintf(msg, sizeof msg, "as measured: %.4f m off the wall", worst);
    TEST_ASSERT_TRUE_MESSAGE(worst > 0.1, msg);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_ego_scan_wall_in_every_layout);
    RUN_TEST(test_ego_scan_beam_spacing_thins_fine_scans);
    RUN_TEST(test_ego_scan_spacing_arm);
    RUN_TEST(test_ego_scan_centimetres_and_mount);
    RUN_TEST(test_ego_scan_special_values_leave_gaps);
    RUN_TEST(test_ego_scan_range_jumps_break);
    RUN_TEST(test_ego_scan_occlusion_edge);
    RUN_TEST(test_ego_scan_range_limits_and_errors);
    RUN_TEST(test_ego_scan_deskews_an_interlaced_scan_in_motion);
    return UNITY_END();
}
