/* test_ego_range.c - the estimator's generic range input (estimator/
 * ego_range.h) without any LMS code: a 360-degree sensor with 720 beams
 * (0.5 deg), a geometry no LMS 2xx has, ray-cast in the synthetic world's
 * campus (host_tests/world), through ego_process; uniform and per-beam
 * bearings; and the checks that refuse a malformed scan. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ego.h"
#include "ego_range.h"
#include "fx_host.h"
#include "unity.h"
#include "world_map.h"
#include "world_scenario.h"

void setUp(void)
{
}

void tearDown(void)
{
}

#define BEAMS 720u
/* 0.5 deg as a binary angle, rounded: 720 of them stay within one turn. */
#define STEP_BAM 5965232u
/* Ranges as a sensor with 1 cm resolution and 60 m reach reports them. */
#define MAX_RANGE_M 60.0
/* Scans apart: 26.7 ms (the campus drive at its own speed). */
#define PERIOD_S (2.0 / 75.0)

static ego_range_scan_t g_scan;
static ego_state_t g_state;
static ego_params_t g_params;
static wmap_t g_map;

static double rad_of_bam(uint32_t a)
{
    return (double)(int32_t)a * FX_HOST_PI / 2147483648.0;
}

/* The 360-degree scan from pose: beam k at bearing -180 deg + k * STEP_BAM
 * in the vehicle frame, the sensor 0.3 m ahead of the vehicle's origin. */
static void cast_scan(wpose_t pose, bool per_beam)
{
    memset(&g_scan, 0, sizeof g_scan);
    g_scan.count = BEAMS;
    g_scan.origin_x = FX_Q16_16_C(0.3);
    g_scan.origin_y = 0;
    g_scan.per_beam_bearing = per_beam;
    g_scan.first_bearing = 0x80000000u;
    g_scan.bearing_step = STEP_BAM;
    const double ox = pose.x + 0.3 * cos(pose.theta);
    const double oy = pose.y + 0.3 * sin(pose.theta);
    for (uint16_t k = 0u; k < BEAMS; k++) {
        const uint32_t bam = 0x80000000u + (uint32_t)k * STEP_BAM;
        g_scan.bearing[k] = bam;
        const double a = pose.theta + rad_of_bam(bam);
        const double r = wmap_cast(&g_map, ox, oy, cos(a), sin(a));
        g_scan.valid[k] = isfinite(r) && r <= MAX_RANGE_M;
        const double cm = g_scan.valid[k] ? round(r * 100.0) : 0.0;
        g_scan.range[k] = (fx_q16_16_t)lround(cm / 100.0 * 65536.0);
    }
}

typedef struct {
    unsigned pairs;
    unsigned failed;     /* error above 0.10 m or 1 deg */
    unsigned flagged;    /* any flag but FIRST */
    double sum_trans;    /* m */
    double sum_rot;      /* deg */
    double worst_trans;
    double worst_rot;
} errors_t;

/* Scans first .. first + n - 1 of the campus drive through the estimator,
 * each pair's pose against the truth. */
static errors_t run_campus(unsigned first, unsigned n, bool per_beam)
{
    const wscenario_t *campus = wscenario_find("campus");
    TEST_ASSERT_NOT_NULL(campus);
    wmap_init(&g_map);
    campus->build_map(&g_map);
    ego_defaults(&g_params);
    ego_reset(&g_state);
    errors_t e;
    memset(&e, 0, sizeof e);
    wpose_t last = campus->pose(first, PERIOD_S);
    for (unsigned i = 0u; i < n; i++) {
        const wpose_t pose = campus->pose(first + i, PERIOD_S);
        cast_scan(pose, per_beam);
        ego_output_t out;
        const uint32_t t_us = (uint32_t)lround(i * PERIOD_S * 1e6);
        TEST_ASSERT_EQUAL_INT(EGO_OK, ego_process(&g_state, &g_params, &g_scan, t_us, &out));
        if (i == 0u) {
            TEST_ASSERT_EQUAL_HEX16(EGO_FLAG_FIRST, out.flags);
            last = pose;
            continue;
        }
        /* The truth: this pose in the frame of the last. */
        const double c = cos(last.theta);
        const double s = sin(last.theta);
        const double tx = c * (pose.x - last.x) + s * (pose.y - last.y);
        const double ty = -s * (pose.x - last.x) + c * (pose.y - last.y);
        const double tt = atan2(sin(pose.theta - last.theta), cos(pose.theta - last.theta));
        const double dx = fx_q16_16_to_double(out.pose.x) - tx;
        const double dy = fx_q16_16_to_double(out.pose.y) - ty;
        const double trans = hypot(dx, dy);
        const double d = rad_of_bam(out.pose.theta) - tt;
        const double rot = fabs(atan2(sin(d), cos(d))) * 180.0 / FX_HOST_PI;
        e.pairs++;
        e.failed += (trans > 0.10 || rot > 1.0) ? 1u : 0u;
        e.flagged += (out.flags != 0u) ? 1u : 0u;
        e.sum_trans += trans;
        e.sum_rot += rot;
        e.worst_trans = fmax(e.worst_trans, trans);
        e.worst_rot = fmax(e.worst_rot, rot);
        last = pose;
    }
    wmap_free(&g_map);
    return e;
}

/* 150 scans of the campus drive (its first corner included) seen by a
 * 360-degree, 720-beam sensor: every pair within the failure bounds, mean
 * errors of the order of the LMS sequences' (docs/estimator.md), no flag. */
static void test_ego_range_360_deg_720_beams_tracks_the_campus_drive(void)
{
    const errors_t e = run_campus(150u, 150u, false);
    char msg[160];
    (void)snprintf(msg, sizeof msg, "pairs %u failed %u flagged %u mean %.2f mm %.4f deg worst %.2f mm %.4f deg",
                   e.pairs, e.failed, e.flagged, 1000.0 * e.sum_trans / e.pairs, e.sum_rot / e.pairs,
                   1000.0 * e.worst_trans, e.worst_rot);
    TEST_MESSAGE(msg);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(149u, e.pairs, msg);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, e.failed, msg);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, e.flagged, msg);
    TEST_ASSERT_TRUE_MESSAGE(e.sum_trans / e.pairs < 0.005, msg);
    TEST_ASSERT_TRUE_MESSAGE(e.sum_rot / e.pairs < 0.02, msg);
}

/* The same bearings given per beam give the same answers, bit for bit,
 * and a second run after ego_reset gives the first run's: nothing is left
 * over in the state (ITCP once read the bearing one past the last point). */
static void test_ego_range_per_beam_bearings_equal_uniform_ones(void)
{
    const errors_t uniform = run_campus(300u, 20u, false);
    const errors_t table = run_campus(300u, 20u, true);
    TEST_ASSERT_EQUAL_UINT(uniform.pairs, table.pairs);
    TEST_ASSERT_EQUAL_MEMORY(&uniform.sum_trans, &table.sum_trans, sizeof(double));
    TEST_ASSERT_EQUAL_MEMORY(&uniform.sum_rot, &table.sum_rot, sizeof(double));
    TEST_ASSERT_EQUAL_MEMORY(&uniform.worst_trans, &table.worst_trans, sizeof(double));
}

/* Malformed scans are refused (EGO_ERR_SCAN) and leave the state alone. */
static void test_ego_range_malformed_scans_are_refused(void)
{
    const wscenario_t *campus = wscenario_find("campus");
    wmap_init(&g_map);
    campus->build_map(&g_map);
    ego_defaults(&g_params);
    ego_reset(&g_state);
    ego_output_t out;
    cast_scan(campus->pose(400u, PERIOD_S), false);
    TEST_ASSERT_TRUE(ego_range_check(&g_scan));
    TEST_ASSERT_EQUAL_INT(EGO_OK, ego_process(&g_state, &g_params, &g_scan, 0u, &out));

    static ego_range_scan_t bad;
    bad = g_scan;
    bad.count = (uint16_t)(EGO_MAX_BEAMS + 1u); /* beyond the capacity */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad = g_scan;
    bad.bearing_step = 0u; /* no step */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad.bearing_step = 0x80000000u; /* half a turn: direction unknown */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad.bearing_step = STEP_BAM + 10000u; /* 719 steps: more than one turn */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad = g_scan;
    bad.per_beam_bearing = true;
    bad.bearing[300] = bad.bearing[299] - 1u; /* goes back */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    TEST_ASSERT_FALSE(ego_range_check(NULL));

    /* The state kept the good scan: the next one matches it. */
    cast_scan(campus->pose(401u, PERIOD_S), false);
    TEST_ASSERT_EQUAL_INT(EGO_OK, ego_process(&g_state, &g_params, &g_scan, 26667u, &out));
    TEST_ASSERT_EQUAL_HEX16(0u, out.flags);
    TEST_ASSERT_TRUE(out.matches > 300u);
    wmap_free(&g_map);
}

/* An empty or one-beam scan is legal and gives a flagged answer, not a
 * crash: too few points. */
static void test_ego_range_tiny_scans_are_flagged(void)
{
    ego_defaults(&g_params);
    ego_reset(&g_state);
    memset(&g_scan, 0, sizeof g_scan);
    g_scan.bearing_step = STEP_BAM;
    ego_output_t out;
    TEST_ASSERT_EQUAL_INT(EGO_OK, ego_process(&g_state, &g_params, &g_scan, 0u, &out));
    g_scan.count = 1u;
    g_scan.valid[0] = true;
    g_scan.range[0] = FX_Q16_16_C(5.0);
    TEST_ASSERT_EQUAL_INT(EGO_OK, ego_process(&g_state, &g_params, &g_scan, 26667u, &out));
    TEST_ASSERT_TRUE((out.flags & EGO_FLAG_TOO_FEW_POINTS) != 0u);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_ego_range_360_deg_720_beams_tracks_the_campus_drive);
    RUN_TEST(test_ego_range_per_beam_bearings_equal_uniform_ones);
    RUN_TEST(test_ego_range_malformed_scans_are_refused);
    RUN_TEST(test_ego_range_tiny_scans_are_flagged);
    return UNITY_END();
}
