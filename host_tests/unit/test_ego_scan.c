/* test_ego_scan.c - the LMS adapter (firmware/ego_lms.c) and scan
 * preparation (estimator/ego_scan.c) together: polar LMS values to
 * vehicle-frame points, against double-precision geometry, and the segment
 * structure on constructed scans; the objects (EGO_POINT_OBJECT) on
 * constructed scenes and, against the rule computed in doubles, on random
 * ones. The generic range input on its own: test_ego_range.c. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ego_lms.h"
#include "ego_scan.h"
#include "fx_host.h"
#include "test_rng.h"
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
    /* The break also says which side is farther: value 92 (2 deg) lies
     * farther out on the wall than value 89 (-1 deg). */
    const unsigned rises =
        ((g_lms.values[92] & 0x1FFFu) > (g_lms.values[89] & 0x1FFFu)) ? EGO_LINK_RISES : 0u;
    TEST_ASSERT_EQUAL_HEX8(EGO_LINK_BREAK | EGO_LINK_GAP | rises, g_scan.flags[before_gap]);
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
    /* A motion no vehicle makes (faster than EGO_MAX_SPEED over its
     * interval: the fuzzer's prior of metres over a microsecond moved
     * points by kilometres) de-skews nothing: the points as measured. */
    ego_skew_t wild = skew;
    wild.dt_us = 1u;
    TEST_ASSERT_EQUAL_INT(EGO_PREP_OK, ego_scan_prepare_deskewed(&g_range, &p, &wild, &g_scan));
    static ego_scan_t measured;
    TEST_ASSERT_EQUAL_INT(EGO_PREP_OK, ego_scan_prepare(&g_range, &p, &measured));
    TEST_ASSERT_EQUAL_UINT16(measured.count, g_scan.count);
    TEST_ASSERT_EQUAL_INT32_ARRAY(measured.x, g_scan.x, measured.count);
    TEST_ASSERT_EQUAL_INT32_ARRAY(measured.y, g_scan.y, measured.count);
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

/* --- Objects (EGO_POINT_OBJECT) ------------------------------------------ */

/* The LMS value word for "no return" (mode 00: 0x1FF7..0x1FFF special). */
#define NO_RETURN 0x1FFFu

/* An empty scene: count values in centimetres, every one without a
 * return. */
static void make_dark_scan(unsigned count)
{
    memset(&g_lms, 0, sizeof g_lms);
    g_lms.count = (uint16_t)count;
    g_lms.unit = LMS_UNIT_CM;
    for (unsigned k = 0u; k < count; k++) {
        g_lms.values[k] = NO_RETURN;
    }
}

/* The range of value k (m), or INFINITY without one. */
static double value_range(unsigned k)
{
    const unsigned raw = g_lms.values[k] & 0x1FFFu;
    return (raw >= 0x1FF7u) ? INFINITY : raw * 0.01;
}

/* A straight surface from (x0, y0) to (x1, y1) in the scanner's frame (x
 * along its 90-deg beam): every beam that hits it nearer than what it saw
 * so far sees it. */
static void cast_surface(double x0, double y0, double x1, double y1)
{
    const double qx = x1 - x0;
    const double qy = y1 - y0;
    for (unsigned k = 0u; k < g_lms.count; k++) {
        const double a = beam_rad(k, g_lms.count);
        const double dx = cos(a);
        const double dy = sin(a);
        const double den = dx * qy - dy * qx; /* d x q */
        if (fabs(den) < 1e-12) {
            continue; /* along the beam */
        }
        const double t = (x0 * qy - y0 * qx) / den; /* (p x q) / (d x q) */
        const double u = (x0 * dy - y0 * dx) / den; /* (p x d) / (d x q) */
        if (t > 0.0 && u >= 0.0 && u <= 1.0 && t < value_range(k)) {
            g_lms.values[k] = word_of(t, LMS_UNIT_CM);
        }
    }
}

/* Value k seen at r metres (a surface at that range), or, r 0, no return. */
static void set_value(unsigned k, double r)
{
    g_lms.values[k] = (r > 0.0) ? word_of(r, LMS_UNIT_CM) : (uint16_t)NO_RETURN;
}

/* The prepared point of value k (the count of valid values before it), or
 * -1 when value k gave none. */
static int point_of_value(unsigned k)
{
    if (!isfinite(value_range(k))) {
        return -1;
    }
    int i = 0;
    for (unsigned j = 0u; j < k; j++) {
        i += isfinite(value_range(j)) ? 1 : 0;
    }
    return i;
}

static bool is_object(int i)
{
    return (g_scan.flags[i] & EGO_POINT_OBJECT) != 0u;
}

/* Values first..last (all with returns) are exactly the points of one
 * segment, and each of its points is an object or none is; true when it
 * is one. */
static bool segment_is_object(unsigned first, unsigned last, const char *what)
{
    const int a = point_of_value(first);
    const int b = point_of_value(last);
    TEST_ASSERT_TRUE_MESSAGE(a >= 0 && b >= a && b - a == (int)(last - first), what);
    TEST_ASSERT_TRUE_MESSAGE(a == 0 || !ego_scan_linked(&g_scan, (uint16_t)(a - 1)), what);
    TEST_ASSERT_TRUE_MESSAGE(b + 1 == (int)g_scan.count || !ego_scan_linked(&g_scan, (uint16_t)b), what);
    for (int i = a; i < b; i++) {
        TEST_ASSERT_TRUE_MESSAGE(ego_scan_linked(&g_scan, (uint16_t)i), what);
    }
    for (int i = a; i <= b; i++) {
        TEST_ASSERT_EQUAL_MESSAGE(is_object(a), is_object(i), what);
    }
    return is_object(a);
}

/* The points of values first..last that are objects. */
static unsigned objects_among(unsigned first, unsigned last)
{
    unsigned n = 0u;
    for (unsigned k = first; k <= last; k++) {
        const int i = point_of_value(k);
        n += (i >= 0 && is_object(i)) ? 1u : 0u;
    }
    return n;
}

/* The values from first to last whose beams see the surface x = d, |y| <=
 * half (the scanner's frame, 1-deg values), and the ones just beside it. */
static void beams_of(double d, double half, unsigned *first, unsigned *last)
{
    *first = 181u;
    *last = 0u;
    for (unsigned k = 0u; k < 181u; k++) {
        const double a = beam_rad(k, 181u);
        if (cos(a) > 0.0 && fabs(d * tan(a)) <= half) {
            *first = (k < *first) ? k : *first;
            *last = k;
        }
    }
    TEST_ASSERT_TRUE(*first > 0u && *last + 1u < 181u && *first <= *last);
}

/* The back of a truck (2.4 m) 10 m ahead, in front of a wall 30 m away:
 * its points are an object, the wall's are not (a wall the field's edge
 * cuts short, and longer than 3 m). A 5 m block in its place is longer
 * than an object. */
static void test_ego_scan_object_in_front_of_a_far_wall(void)
{
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    for (unsigned wide = 0u; wide < 2u; wide++) {
        const double half = (wide == 0u) ? 1.2 : 2.5;
        make_dark_scan(181u);
        cast_surface(30.0, -100.0, 30.0, 100.0);
        cast_surface(10.0, -half, 10.0, half);
        prepare(&p);
        unsigned first;
        unsigned last;
        beams_of(10.0, half, &first, &last);
        char what[64];
        (void)snprintf(what, sizeof what, "a block %.1f m wide at 10 m", 2.0 * half);
        /* The wall 30 m away either side of it. */
        TEST_ASSERT_TRUE_MESSAGE(value_range(first - 1u) > 29.0 && value_range(last + 1u) > 29.0, what);
        const bool object = segment_is_object(first, last, what);
        TEST_ASSERT_EQUAL_MESSAGE(wide == 0u, object, what);
        TEST_ASSERT_EQUAL_UINT_MESSAGE((wide == 0u) ? last - first + 1u : 0u, objects_among(0u, 180u), what);
    }
}

/* A recess: a wall 10 m ahead with an opening 2 m wide, a back wall 12 m
 * away behind it. The back wall seen through the opening is short and cut
 * off by jumps, but the points beyond both its ends are nearer: it stands
 * behind them, no object. */
static void test_ego_scan_recess_is_no_object(void)
{
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    make_dark_scan(181u);
    cast_surface(10.0, -100.0, 10.0, -1.0);
    cast_surface(10.0, 1.0, 10.0, 100.0);
    cast_surface(12.0, -1.5, 12.0, 1.5);
    prepare(&p);
    unsigned first;
    unsigned last;
    beams_of(10.0, 1.0, &first, &last);
    TEST_ASSERT_TRUE(value_range(first) > 11.9 && value_range(last) > 11.9);
    TEST_ASSERT_TRUE(value_range(first - 1u) < 10.5 && value_range(last + 1u) < 10.5);
    TEST_ASSERT_FALSE(segment_is_object(first, last, "the recess"));
    TEST_ASSERT_EQUAL_UINT(0u, objects_among(0u, 180u));
}

/* A truck back 10 m ahead in an opening of a wall 8 m away; the beams
 * beside it, through the opening, see nothing. The points beyond the dark
 * beams are nearer than the truck's ends, but the beams between saw
 * nothing near: an object. With those beams seeing something 9 m away
 * instead (nearer than the truck), it stands behind: no object. */
static void test_ego_scan_object_between_dark_beams(void)
{
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    for (unsigned dark = 0u; dark < 2u; dark++) {
        make_dark_scan(181u);
        cast_surface(8.0, -100.0, 8.0, -1.8);
        cast_surface(8.0, 1.8, 8.0, 100.0);
        cast_surface(10.0, -1.2, 10.0, 1.2);
        unsigned first;
        unsigned last;
        beams_of(10.0, 1.2, &first, &last);
        /* Dark beams on both sides, then the wall 8 m away. */
        TEST_ASSERT_FALSE(isfinite(value_range(first - 1u)));
        TEST_ASSERT_FALSE(isfinite(value_range(last + 1u)));
        unsigned before = first - 1u;
        while (!isfinite(value_range(before))) {
            before--;
        }
        unsigned after = last + 1u;
        while (!isfinite(value_range(after))) {
            after++;
        }
        TEST_ASSERT_TRUE(value_range(before) < 9.0 && value_range(after) < 9.0);
        if (dark == 1u) {
            for (unsigned k = before + 1u; k < first; k++) {
                set_value(k, 9.0);
            }
            for (unsigned k = last + 1u; k < after; k++) {
                set_value(k, 9.0);
            }
        }
        prepare(&p);
        const char *what = (dark == 0u) ? "dark beams beside it" : "nearer returns beside it";
        if (dark == 0u) {
            const int a = point_of_value(first);
            TEST_ASSERT_TRUE_MESSAGE((g_scan.flags[a - 1] & EGO_LINK_GAP) != 0u, what);
            TEST_ASSERT_TRUE_MESSAGE((g_scan.flags[point_of_value(last)] & EGO_LINK_GAP) != 0u, what);
        }
        TEST_ASSERT_EQUAL_MESSAGE(dark == 0u, segment_is_object(first, last, what), what);
        TEST_ASSERT_EQUAL_UINT_MESSAGE((dark == 0u) ? last - first + 1u : 0u, objects_among(0u, 180u), what);
    }
}

/* A post (an arc of ten 1-deg beams 5 m away, 0.8 m across) at the
 * field's edges and in the middle of it, the wall 30 m away behind it
 * (beyond about 68 deg the wall is out of reach: no returns). In the
 * middle it stands in front of the wall: an object. At the first or the
 * last value, or with the first values dark (its first point is still
 * the scan's first), what lies beyond the edge is not known: no object,
 * though its other end stands in front. */
static void test_ego_scan_object_at_the_field_edge(void)
{
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    static const unsigned starts[4] = {0u, 3u, 171u, 40u};
    for (unsigned c = 0u; c < 4u; c++) {
        make_dark_scan(181u);
        cast_surface(30.0, -100.0, 30.0, 100.0);
        const unsigned first = starts[c];
        const unsigned last = first + 9u;
        for (unsigned k = first; k <= last; k++) {
            set_value(k, 5.0);
        }
        prepare(&p);
        char what[48];
        (void)snprintf(what, sizeof what, "a post at values %u..%u", first, last);
        const bool edge = point_of_value(first) == 0 || point_of_value(last) + 1 == (int)g_scan.count;
        TEST_ASSERT_EQUAL_MESSAGE(c < 3u, edge, what);
        TEST_ASSERT_EQUAL_MESSAGE(c == 3u, segment_is_object(first, last, what), what);
        TEST_ASSERT_EQUAL_UINT_MESSAGE((c == 3u) ? 10u : 0u, objects_among(0u, 180u), what);
    }
}

static double rng_unit(uint64_t *rng)
{
    return (double)(test_rng_next(rng) >> 11) * (1.0 / 9007199254740992.0);
}

/* A random scene in the scanner's frame: a far wall (most scenes), side
 * walls (some), one to eight surfaces 0.2-6 m long 2-30 m away facing the
 * scanner within 60 deg, dark beams and dark runs, 1 cm of range noise. */
static void make_random_scene(uint64_t *rng)
{
    const double pi = FX_HOST_PI;
    make_dark_scan(((test_rng_next(rng) & 1u) != 0u) ? 181u : 361u);
    if (rng_unit(rng) < 0.8) {
        const double d = 15.0 + 25.0 * rng_unit(rng);
        const double phi = (rng_unit(rng) - 0.5) * 1.0;
        const double cx = d * cos(phi);
        const double cy = d * sin(phi);
        cast_surface(cx + 200.0 * sin(phi), cy - 200.0 * cos(phi), cx - 200.0 * sin(phi),
                     cy + 200.0 * cos(phi));
    }
    if (rng_unit(rng) < 0.4) {
        const double w = 3.0 + 7.0 * rng_unit(rng);
        cast_surface(0.5, w, 100.0, w);
        cast_surface(0.5, -w, 100.0, -w);
    }
    const unsigned surfaces = 1u + (unsigned)(test_rng_next(rng) % 8u);
    for (unsigned n = 0u; n < surfaces; n++) {
        const double rho = 2.0 + 28.0 * rng_unit(rng);
        const double beta = (rng_unit(rng) - 0.5) * 170.0 * pi / 180.0;
        const double len = 0.2 + 5.8 * rng_unit(rng);
        const double turn = beta + pi / 2.0 + (rng_unit(rng) - 0.5) * 120.0 * pi / 180.0;
        const double cx = rho * cos(beta);
        const double cy = rho * sin(beta);
        const double hx = 0.5 * len * cos(turn);
        const double hy = 0.5 * len * sin(turn);
        cast_surface(cx - hx, cy - hy, cx + hx, cy + hy);
    }
    for (unsigned k = 0u; k < g_lms.count; k++) {
        const double r = value_range(k);
        if (isfinite(r)) {
            set_value(k, r + 0.01 * (rng_unit(rng) - 0.5) * 2.0);
        }
        if (rng_unit(rng) < 0.02) {
            set_value(k, 0.0);
        }
    }
    const unsigned runs = (unsigned)(test_rng_next(rng) % 3u);
    for (unsigned n = 0u; n < runs; n++) {
        const unsigned at = (unsigned)(test_rng_next(rng) % g_lms.count);
        const unsigned len = 1u + (unsigned)(test_rng_next(rng) % 5u);
        for (unsigned k = at; k < at + len && k < g_lms.count; k++) {
            set_value(k, 0.0);
        }
    }
}

/* A point's range from the scanner, m (its Q16.16 coordinates in
 * doubles: within 2e-5 m of the range it was measured at). */
static double range_of(uint16_t i)
{
    return hypot(fx_q16_16_to_double(g_scan.x[i]) - fx_q16_16_to_double(g_scan.origin_x),
                 fx_q16_16_to_double(g_scan.y[i]) - fx_q16_16_to_double(g_scan.origin_y));
}

/* Ranges closer than this are too close to tell apart (a centimetre scan
 * never has them across a break). */
#define RANGE_MARGIN 1e-3 /* m */

/* Point b against point a: +1 farther, -1 nearer, 0 too close to tell. */
static int farther(uint16_t b, uint16_t a)
{
    const double diff = range_of(b) - range_of(a);
    return (diff > RANGE_MARGIN) ? 1 : (diff < -RANGE_MARGIN) ? -1 : 0;
}

/* The in-front rule at a segment's end `end`, beyond it `beyond` (-1 or
 * count at the field's edge) through `link`: +1 in front, -1 not, 0 too
 * close to tell. */
static int front_rule(uint16_t end, int beyond, uint8_t link)
{
    if (beyond < 0 || beyond >= (int)g_scan.count) {
        return -1;
    }
    if ((link & EGO_LINK_GAP) != 0u) {
        return 1;
    }
    return farther((uint16_t)beyond, end);
}

#define OBJECT_SCENES 300u
#define EXTENT_MARGIN 1e-3 /* m */

/* Random scenes (random mounts, so the scanner is not the vehicle's
 * origin; every second scan de-skewed): a break says whether the point
 * after it lies farther (EGO_LINK_RISES), a link within a segment does
 * not; every segment's points are all objects or none; a segment is
 * one when, computed in doubles from its points, it is at most 3 m from
 * end to end and both its ends stand in front (the point beyond is
 * farther from the scanner, or a gap lies between; never at the field's
 * edge), and only then (away from 3 m and from equal ranges by a
 * margin). */
static void test_ego_scan_objects_follow_the_rule_on_random_scenes(void)
{
    uint64_t rng = 0x5CA7u;
    ego_prep_params_t p;
    ego_prep_defaults(&p);
    unsigned objects = 0u;
    unsigned short_behind = 0u; /* short, but not in front at an end */
    unsigned long_ones = 0u;
    unsigned unclear = 0u;
    for (unsigned scene = 0u; scene < OBJECT_SCENES; scene++) {
        g_lmsp.mount_x = fx_q16_16_from_double(-1.0 + 3.0 * rng_unit(&rng));
        g_lmsp.mount_y = fx_q16_16_from_double(-1.0 + 2.0 * rng_unit(&rng));
        g_lmsp.mount_theta = fx_bam32_from_rad((rng_unit(&rng) - 0.5) * 60.0 * FX_HOST_PI / 180.0);
        make_random_scene(&rng);
        g_work = g_lms;
        TEST_ASSERT_EQUAL_INT(EGO_LMS_OK, ego_lms_to_range(&g_work, &g_lmsp, &g_range));
        if (scene % 2u == 0u) {
            TEST_ASSERT_EQUAL_INT(EGO_PREP_OK, ego_scan_prepare(&g_range, &p, &g_scan));
        } else {
            /* De-skewed with a motion of up to 15 m/s and 0.5 rad/s over
             * 26.7 ms that the static scene did not have: the points move
             * (a 0.5-deg scan's passes apart, its surfaces broken into
             * pieces) and the links and objects come from where they are. */
            ego_skew_t skew;
            skew.dt_us = 26667u;
            skew.motion.x = fx_q16_16_from_double(0.4 * rng_unit(&rng));
            skew.motion.y = fx_q16_16_from_double(0.02 * (rng_unit(&rng) - 0.5));
            skew.motion.theta = fx_bam32_from_rad(0.026 * (rng_unit(&rng) - 0.5));
            TEST_ASSERT_EQUAL_INT(EGO_PREP_OK, ego_scan_prepare_deskewed(&g_range, &p, &skew, &g_scan));
        }
        uint16_t first = 0u;
        for (uint16_t i = 0u; i < g_scan.count; i++) {
            if (i + 1u < g_scan.count && ego_scan_linked(&g_scan, i)) {
                TEST_ASSERT_EQUAL_HEX8(0u, g_scan.flags[i] & EGO_LINK_RISES);
                continue;
            }
            /* A break says whether the next point is farther. */
            if (i + 1u < g_scan.count && farther((uint16_t)(i + 1u), i) != 0) {
                char link[96];
                (void)snprintf(link, sizeof link, "scene %u, link %u: ranges %.4f %.4f m, flags 0x%02x", scene,
                               i, range_of(i), range_of((uint16_t)(i + 1u)), g_scan.flags[i]);
                TEST_ASSERT_EQUAL_MESSAGE(farther((uint16_t)(i + 1u), i) > 0,
                                          (g_scan.flags[i] & EGO_LINK_RISES) != 0u, link);
            }
            const double extent =
                hypot(fx_q16_16_to_double(g_scan.x[i]) - fx_q16_16_to_double(g_scan.x[first]),
                      fx_q16_16_to_double(g_scan.y[i]) - fx_q16_16_to_double(g_scan.y[first]));
            const uint8_t link_before = (first > 0u) ? g_scan.flags[first - 1u] : 0u;
            const int front_first = front_rule(first, (int)first - 1, link_before);
            const int front_last = front_rule(i, (int)i + 1, g_scan.flags[i]);
            const bool marked = is_object(first);
            char msg[200];
            (void)snprintf(msg, sizeof msg,
                           "scene %u, points %u..%u of %u: extent %.4f m, in front %d %d, marked %d", scene,
                           first, i, g_scan.count, extent, front_first, front_last, marked);
            for (uint16_t k = first; k <= i; k++) {
                TEST_ASSERT_EQUAL_MESSAGE(marked, is_object(k), msg);
            }
            if (marked) {
                TEST_ASSERT_TRUE_MESSAGE(extent <= 3.0 + EXTENT_MARGIN, msg);
                TEST_ASSERT_TRUE_MESSAGE(front_first >= 0 && front_last >= 0, msg);
            }
            const bool clear_short = extent <= 3.0 - EXTENT_MARGIN;
            if (clear_short && front_first > 0 && front_last > 0) {
                TEST_ASSERT_TRUE_MESSAGE(marked, msg);
                objects++;
            } else if (extent > 3.0 + EXTENT_MARGIN) {
                TEST_ASSERT_FALSE_MESSAGE(marked, msg);
                long_ones++;
            } else if (clear_short && (front_first < 0 || front_last < 0)) {
                TEST_ASSERT_FALSE_MESSAGE(marked, msg);
                short_behind++;
            } else {
                unclear++;
            }
            first = (uint16_t)(i + 1u);
        }
    }
    char seen[160];
    (void)snprintf(seen, sizeof seen,
                   "segments: %u objects, %u short but not in front, %u longer than 3 m, %u too close to tell",
                   objects, short_behind, long_ones, unclear);
    TEST_MESSAGE(seen);
    TEST_ASSERT_TRUE_MESSAGE(objects >= OBJECT_SCENES / 2u, seen);
    TEST_ASSERT_TRUE_MESSAGE(short_behind >= OBJECT_SCENES / 4u, seen);
    TEST_ASSERT_TRUE_MESSAGE(long_ones >= OBJECT_SCENES / 2u, seen);
    TEST_ASSERT_TRUE_MESSAGE(unclear * 100u <= objects + short_behind + long_ones, seen);
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
    RUN_TEST(test_ego_scan_object_in_front_of_a_far_wall);
    RUN_TEST(test_ego_scan_recess_is_no_object);
    RUN_TEST(test_ego_scan_object_between_dark_beams);
    RUN_TEST(test_ego_scan_object_at_the_field_edge);
    RUN_TEST(test_ego_scan_objects_follow_the_rule_on_random_scenes);
    return UNITY_END();
}
