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
#include "lms_test_util.h"
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
/* 0.5 deg as a Q32.32 binary angle: 2^64 / 720, rounded. */
#define STEP_Q32 25620477880152158ull
/* Ranges in cm as a sensor with 1 cm resolution and 60 m reach reports
 * them. */
#define UNIT_UM 10000u
#define MAX_RANGE_M 60.0
/* Scans apart: 26.7 ms (the campus drive at its own speed). */
#define PERIOD_S (2.0 / 75.0)

static uint16_t g_range[BEAMS];
static fx_bam32_t g_bearing[BEAMS];
static ego_range_scan_t g_scan;
static ego_state_t g_state;
static ego_params_t g_params;
static wmap_t g_map;

static double rad_of_bam(uint32_t a)
{
    return (double)(int32_t)a * FX_HOST_PI / 2147483648.0;
}

/* The 360-degree scan from pose: beam k at bearing -180 deg + k * 0.5 deg
 * in the vehicle frame (uniform, or the same bearings from a table), the
 * sensor 0.3 m ahead of the vehicle's origin. */
static void cast_scan(wpose_t pose, bool per_beam)
{
    memset(&g_scan, 0, sizeof g_scan);
    g_scan.count = BEAMS;
    g_scan.range = g_range;
    g_scan.range_unit_um = UNIT_UM;
    g_scan.origin_x = FX_Q16_16_C(0.3);
    g_scan.origin_y = 0;
    g_scan.first_bearing = EGO_BEARING_Q32(0x80000000u);
    g_scan.bearing_step = STEP_Q32;
    const double ox = pose.x + 0.3 * cos(pose.theta);
    const double oy = pose.y + 0.3 * sin(pose.theta);
    for (uint16_t k = 0u; k < BEAMS; k++) {
        g_bearing[k] = ego_range_bearing(&g_scan, k);
        const double a = pose.theta + rad_of_bam(g_bearing[k]);
        const double r = wmap_cast(&g_map, ox, oy, cos(a), sin(a));
        g_range[k] = (isfinite(r) && r <= MAX_RANGE_M) ? (uint16_t)lround(r * 100.0) : 0u;
    }
    g_scan.bearing = per_beam ? g_bearing : NULL;
}

typedef struct {
    unsigned pairs;
    unsigned failed;     /* error above 0.10 m or 1 deg */
    unsigned flagged;
    unsigned flags; /* every flag seen */    /* any flag but FIRST */
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
    g_params.work_per_s = 0u; /* the algorithm on a generic sensor, unbounded */
    ego_reset(&g_state);
    errors_t e;
    memset(&e, 0, sizeof e);
    wpose_t last = campus->pose(first, PERIOD_S, 0.0);
    for (unsigned i = 0u; i < n; i++) {
        const wpose_t pose = campus->pose(first + i, PERIOD_S, 0.0);
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
        e.flags |= out.flags;
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
    (void)snprintf(msg, sizeof msg, "pairs %u failed %u flagged %u (flags 0x%x) mean %.2f mm %.4f deg worst %.2f mm %.4f deg",
                   e.pairs, e.failed, e.flagged, e.flags, 1000.0 * e.sum_trans / e.pairs, e.sum_rot / e.pairs,
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
    g_params.work_per_s = 0u; /* the algorithm on a generic sensor, unbounded */
    ego_reset(&g_state);
    ego_output_t out;
    cast_scan(campus->pose(400u, PERIOD_S, 0.0), false);
    TEST_ASSERT_TRUE(ego_range_check(&g_scan));
    TEST_ASSERT_EQUAL_INT(EGO_OK, ego_process(&g_state, &g_params, &g_scan, 0u, &out));

    ego_range_scan_t bad = g_scan;
    bad.count = (uint16_t)(EGO_MAX_BEAMS + 1u); /* beyond the capacity */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad = g_scan;
    bad.range = NULL; /* no ranges */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad = g_scan;
    bad.range_unit_um = 0u; /* no unit */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad.range_unit_um = 500001u; /* 65535 units would not fit Q16.16 metres */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad = g_scan;
    bad.bearing_step = 0u; /* no step */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad.bearing_step = (uint64_t)1 << 63; /* half a turn: direction unknown */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad.bearing_step = UINT64_MAX / 719u + 1u; /* 719 steps: more than one turn */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad.bearing_step = UINT64_MAX / 719u; /* one turn: the last beam rounds onto the first */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    const uint64_t widest = ((uint64_t)(EGO_MAX_SWEEP - 1u) << 32) / 719u;
    bad.bearing_step = widest + 1u; /* a unit of the last place past EGO_MAX_SWEEP */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad.bearing_step = widest; /* the widest: its last beam within EGO_MAX_SWEEP, wherever it starts */
    for (uint32_t first = 0u; first < 4u; first++) {
        bad.first_bearing = ((uint64_t)first << 62) + 0x80000000u * first; /* fractions too */
        TEST_ASSERT_TRUE(ego_range_check(&bad));
        const uint32_t sweep = ego_range_bearing(&bad, 719u) - ego_range_bearing(&bad, 0u);
        TEST_ASSERT_TRUE(sweep >= EGO_MAX_SWEEP - 2u && sweep <= EGO_MAX_SWEEP);
    }
    /* Uniform steps near the widest, against the division that states the
     * rule (ego_scan.c checks it without one). */
    uint32_t rng = 7u;
    for (unsigned trial = 0u; trial < 20000u; trial++) {
        bad = g_scan;
        bad.count = (uint16_t)(2u + tu_rand_range(&rng, 0u, 398u));
        const uint64_t limit = ((uint64_t)(EGO_MAX_SWEEP - 1u) << 32) / (bad.count - 1u);
        const uint64_t off = tu_rand_range(&rng, 0u, 64u);
        bad.bearing_step = (trial % 2u == 0u) ? limit + 32u - off
                                              : ((uint64_t)tu_rand(&rng) << 32 | tu_rand(&rng));
        const bool expected = bad.bearing_step != 0u && bad.bearing_step < ((uint64_t)1 << 63) &&
                              bad.bearing_step <= limit;
        TEST_ASSERT_EQUAL_INT(expected, ego_range_check(&bad));
    }
    static fx_bam32_t table[BEAMS];
    for (uint16_t k = 0u; k < BEAMS; k++) { /* a table of the widest sweep: fine */
        table[k] = 0x10000000u + (fx_bam32_t)((uint64_t)EGO_MAX_SWEEP * k / 719u);
    }
    bad = g_scan;
    bad.bearing = table;
    TEST_ASSERT_TRUE(ego_range_check(&bad));
    table[719]++; /* a unit wider: its last beam within two units of its first */
    TEST_ASSERT_FALSE(ego_range_check(&bad));
    memcpy(table, g_bearing, sizeof table);
    table[300] = table[299] - 1u; /* goes back */
    bad = g_scan;
    bad.bearing = table;
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    table[300] = table[299] + 0x80000000u; /* half a turn at once */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad = g_scan;
    bad.passes = (uint8_t)(EGO_MAX_PASSES + 1u); /* more passes than any sensor interlaces */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad.passes = 2u;
    bad.pass_us = 500000u;
    bad.beam_ns = 1400000u; /* 0.5 s + 359 * 1.4 ms: longer than a second */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad.beam_ns = 1390000u; /* 0.5 s + 359 * 1.39 ms: within a second */
    TEST_ASSERT_TRUE(ego_range_check(&bad));
    bad = g_scan;
    bad.origin_x = EGO_MAX_ORIGIN; /* a sensor 100 m off the vehicle's origin: fine */
    bad.origin_y = -EGO_MAX_ORIGIN;
    TEST_ASSERT_TRUE(ego_range_check(&bad));
    bad.origin_x = EGO_MAX_ORIGIN + 1; /* beyond: refused on either axis */
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    bad.origin_x = 0;
    bad.origin_y = -EGO_MAX_ORIGIN - 1;
    TEST_ASSERT_EQUAL_INT(EGO_ERR_SCAN, ego_process(&g_state, &g_params, &bad, 26667u, &out));
    TEST_ASSERT_FALSE(ego_range_check(NULL));

    /* The state kept the good scan: the next one matches it. */
    cast_scan(campus->pose(401u, PERIOD_S, 0.0), false);
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
    g_params.work_per_s = 0u; /* the algorithm on a generic sensor, unbounded */
    ego_reset(&g_state);
    memset(&g_scan, 0, sizeof g_scan);
    g_scan.bearing_step = STEP_Q32;
    g_scan.range_unit_um = UNIT_UM;
    ego_output_t out;
    TEST_ASSERT_EQUAL_INT(EGO_OK, ego_process(&g_state, &g_params, &g_scan, 0u, &out));
    g_scan.count = 1u;
    g_scan.range = g_range;
    g_range[0] = 500u; /* 5 m */
    TEST_ASSERT_EQUAL_INT(EGO_OK, ego_process(&g_state, &g_params, &g_scan, 26667u, &out));
    TEST_ASSERT_TRUE((out.flags & EGO_FLAG_TOO_FEW_POINTS) != 0u);
    /* One beam from a table of one bearing, in two interlaced passes: the
     * preparation thins to whole passes and read the spacing of beams 0
     * and 1 past the table's end (finding E3; ASan in the asan build). */
    static const fx_bam32_t one_bearing[1] = {0x40000000u};
    g_scan.bearing = one_bearing;
    g_scan.passes = 2u;
    g_scan.pass_us = 13333u;
    TEST_ASSERT_EQUAL_INT(EGO_OK, ego_process(&g_state, &g_params, &g_scan, 53334u, &out));
    TEST_ASSERT_TRUE((out.flags & EGO_FLAG_TOO_FEW_POINTS) != 0u);
}

/* Beam times: two passes interlaced (the LMS 2xx at 0.5 deg), the scan's
 * time their mean, the lag to the last beam; and none at all. */
static void test_ego_range_beam_times_of_interlaced_passes(void)
{
    memset(&g_scan, 0, sizeof g_scan);
    g_scan.count = 361u;
    g_scan.range = g_range;
    g_scan.range_unit_um = UNIT_UM;
    g_scan.bearing_step = STEP_Q32;
    TEST_ASSERT_EQUAL_UINT32(0u, ego_range_beam_ns(&g_scan, 360u)); /* at once */
    TEST_ASSERT_EQUAL_UINT32(0u, ego_range_mean_ns(&g_scan));
    TEST_ASSERT_EQUAL_UINT32(0u, ego_range_lag_ns(&g_scan));
    g_scan.passes = 2u;
    g_scan.pass_us = 13333u;
    g_scan.beam_ns = 37037u;
    TEST_ASSERT_TRUE(ego_range_check(&g_scan));
    TEST_ASSERT_EQUAL_UINT32(0u, ego_range_beam_ns(&g_scan, 0u));
    TEST_ASSERT_EQUAL_UINT32(13333000u, ego_range_beam_ns(&g_scan, 1u));
    TEST_ASSERT_EQUAL_UINT32(37037u, ego_range_beam_ns(&g_scan, 2u));
    TEST_ASSERT_EQUAL_UINT32(180u * 37037u, ego_range_beam_ns(&g_scan, 360u));
    TEST_ASSERT_EQUAL_UINT32(13333000u + 179u * 37037u, ego_range_beam_ns(&g_scan, 359u));
    /* Mean: pass 0 has 181 beams at 0..180, pass 1 has 180 at 13.333 ms + 0..179. */
    const double mean = (181.0 * 90.0 * 37037.0 + 180.0 * (13333000.0 + 89.5 * 37037.0)) / 361.0;
    TEST_ASSERT_INT32_WITHIN(1, (int32_t)mean, (int32_t)ego_range_mean_ns(&g_scan));
    TEST_ASSERT_INT32_WITHIN(1, (int32_t)(13333000.0 + 179.0 * 37037.0 - mean),
                             (int32_t)ego_range_lag_ns(&g_scan));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_ego_range_360_deg_720_beams_tracks_the_campus_drive);
    RUN_TEST(test_ego_range_per_beam_bearings_equal_uniform_ones);
    RUN_TEST(test_ego_range_malformed_scans_are_refused);
    RUN_TEST(test_ego_range_tiny_scans_are_flagged);
    RUN_TEST(test_ego_range_beam_times_of_interlaced_passes);
    return UNITY_END();
}
