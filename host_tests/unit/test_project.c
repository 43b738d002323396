/* test_project.c - the projection ranking of the coarse search's windows
 * (estimator/ego_project.c) against its double oracle (ref/project_ref.c)
 * and on ray-cast scans of known motion. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ego.h"
#include "ego_project.h"
#include "ego_tfit.h"
#include "fx_host.h"
#include "project_ref.h"
#include "synth_scan.h"
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
static ego_project_scratch_t g_scratch;
static double g_score[(2 * EGO_PROJECT_MAX_SIDE + 1) * (2 * EGO_PROJECT_MAX_SIDE + 1)];

#define DEG (FX_HOST_PI / 180.0)

/* The walls seen from (x, y, heading), prepared with chord tangents (as
 * the estimator prepares a scan). */
static void prepared_in(const synth_wall_t *walls, unsigned n, double x, double y,
                        double heading_deg, ego_scan_t *scan)
{
    synth_scan(walls, n, x, y, heading_deg * DEG, 361u, LMS_UNIT_CM, &g_lms);
    ego_prep_params_t prep;
    ego_prep_defaults(&prep);
    TEST_ASSERT_EQUAL_INT(EGO_PREP_OK, ego_scan_prepare(synth_range(&g_lms), &prep, scan));
    ego_tfit_chord_scan(scan);
}

static void prepared(double x, double y, double heading_deg, ego_scan_t *scan)
{
    prepared_in(synth_room, synth_room_walls, x, y, heading_deg, scan);
}

static double metres(fx_q16_16_t v)
{
    return fx_q16_16_to_double(v);
}

/* Ranks the window around (cx, cy) for the rotation theta_deg and checks
 * the best cell is within one bin of (tx, ty). */
static void check_finds(double tx, double ty, double theta_deg, double cx, double cy,
                        double window, double bin_m)
{
    prepared(0.0, 0.0, 0.0, &g_last);
    prepared(tx, ty, theta_deg, &g_current);
    const ego_pose_t around = {(fx_bam32_t)(int32_t)llround(theta_deg / 360.0 * 4294967296.0),
                               (fx_q16_16_t)llround(cx * 65536.0), (fx_q16_16_t)llround(cy * 65536.0)};
    ego_project_cells_t cells;
    const fx_q16_16_t bin = (fx_q16_16_t)llround(bin_m * 65536.0);
    const fx_q16_16_t win = (fx_q16_16_t)llround(window * 65536.0);
    const uint32_t units = ego_project_cells(&g_last, &g_current, 0u, &around, win, bin, &g_scratch,
                                             &cells);
    char msg[160];
    (void)snprintf(msg, sizeof msg, "truth (%.2f, %.2f), best (%.3f, %.3f) of %u, units %u of %u",
                   tx, ty, metres(cells.cell[0].x), metres(cells.cell[0].y), (unsigned)cells.count,
                   (unsigned)units,
                   (unsigned)ego_project_cost_max(&g_last, &g_current, win, bin));
    TEST_ASSERT_EQUAL_UINT_MESSAGE(EGO_PROJECT_CELLS, cells.count, msg);
    TEST_ASSERT_TRUE_MESSAGE(fabs(metres(cells.cell[0].x) - tx) <= bin_m + 1e-4, msg);
    TEST_ASSERT_TRUE_MESSAGE(fabs(metres(cells.cell[0].y) - ty) <= bin_m + 1e-4, msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(around.theta, cells.cell[0].theta, msg);
    TEST_ASSERT_TRUE_MESSAGE(units > 0u, msg);
    TEST_ASSERT_TRUE_MESSAGE(units <= ego_project_cost_max(&g_last, &g_current, win, bin), msg);
}

static void test_projection_finds_a_translation_in_the_wide_window(void)
{
    check_finds(1.3, -0.9, 0.0, 0.0, 0.0, 1.6, 0.1);
    check_finds(-0.7, 0.45, 12.0, 0.0, 0.0, 1.6, 0.1);
}

static void test_projection_finds_a_translation_in_the_first_window(void)
{
    /* 4 m at 0.2 m: the window when no motion is known (20 cells each side). */
    check_finds(2.4, 1.1, 25.0, 0.0, 0.0, 4.0, 0.2);
    check_finds(-3.1, -2.2, -8.0, 0.0, 0.0, 4.0, 0.2);
}

static void test_projection_window_off_centre(void)
{
    /* The window centred on a prediction 0.8 m off the truth. */
    check_finds(1.0, 0.2, 5.0, 0.4, -0.4, 1.6, 0.1);
}

/* Every cell's oracle score: the fixed-point best is the oracle's best (or
 * within 2 % of its score: a point on a bin's edge may fall either side),
 * and the cells returned are at least 3 cells apart, best first by the
 * oracle's scores too within the same tolerance. */
static void test_projection_against_the_double_oracle(void)
{
    static const double cases[][6] = {
        /* tx, ty, theta deg, cx, cy, window */
        {1.3, -0.9, 0.0, 0.0, 0.0, 1.6},
        {0.6, 0.3, 20.0, 0.2, 0.1, 1.0},
        {-1.6, 1.2, -15.0, 0.0, 0.0, 2.0},
        {0.05, 0.0, 1.0, 0.0, 0.0, 0.6},
    };
    for (unsigned c = 0u; c < sizeof cases / sizeof cases[0]; c++) {
        const double *q = cases[c];
        prepared(0.0, 0.0, 0.0, &g_last);
        prepared(q[0], q[1], q[2], &g_current);
        const fx_bam32_t theta = (fx_bam32_t)(int32_t)llround(q[2] / 360.0 * 4294967296.0);
        const ego_pose_t around = {theta, (fx_q16_16_t)llround(q[3] * 65536.0),
                                   (fx_q16_16_t)llround(q[4] * 65536.0)};
        const fx_q16_16_t bin = FX_Q16_16_C(0.1);
        const fx_q16_16_t win = (fx_q16_16_t)llround(q[5] * 65536.0);
        const fx_bam32_t main_dir = FX_BAM32_DEG_C(30.0); /* any direction will do */
        ego_project_cells_t cells;
        (void)ego_project_cells(&g_last, &g_current, main_dir, &around, win, bin, &g_scratch, &cells);
        const int n = project_ref_scores(&g_last, &g_current, fx_bam32_to_rad(main_dir),
                                         fx_bam32_to_rad(theta), fx_q16_16_to_double(around.x),
                                         fx_q16_16_to_double(around.y), fx_q16_16_to_double(win),
                                         0.1, g_score);
        TEST_ASSERT_EQUAL_INT(ego_project_side(win, bin), n);
        const unsigned cells_n = (unsigned)((2 * n + 1) * (2 * n + 1));
        double best = 0.0;
        for (unsigned i = 0u; i < cells_n; i++) {
            best = (g_score[i] > best) ? g_score[i] : best;
        }
        TEST_ASSERT_TRUE(best > 0.0);
        for (unsigned k = 0u; k < cells.count; k++) {
            const long ix = lround((fx_q16_16_to_double(cells.cell[k].x) - fx_q16_16_to_double(around.x)) / 0.1);
            const long iy = lround((fx_q16_16_to_double(cells.cell[k].y) - fx_q16_16_to_double(around.y)) / 0.1);
            TEST_ASSERT_TRUE(ix >= -n && ix <= n && iy >= -n && iy <= n);
            const double v = g_score[(unsigned)((ix + n) * (2 * n + 1) + (iy + n))];
            char msg[128];
            (void)snprintf(msg, sizeof msg, "case %u cell %u (%ld, %ld): oracle %.4f, best %.4f", c,
                           k, ix, iy, v, best);
            if (k == 0u) {
                TEST_ASSERT_TRUE_MESSAGE(v >= 0.98 * best, msg);
            }
            for (unsigned j = 0u; j < k; j++) {
                const long jx = lround((fx_q16_16_to_double(cells.cell[j].x) - fx_q16_16_to_double(around.x)) / 0.1);
                const long jy = lround((fx_q16_16_to_double(cells.cell[j].y) - fx_q16_16_to_double(around.y)) / 0.1);
                TEST_ASSERT_TRUE_MESSAGE(labs(jx - ix) > 2 || labs(jy - iy) > 2, msg);
                const double w = g_score[(unsigned)((jx + n) * (2 * n + 1) + (jy + n))];
                TEST_ASSERT_TRUE_MESSAGE(w >= 0.98 * v, msg);
            }
        }
    }
}

/* Nothing to rank: no window, or scans without points. */
static void test_projection_of_nothing(void)
{
    prepared(0.0, 0.0, 0.0, &g_last);
    prepared(0.5, 0.0, 0.0, &g_current);
    const ego_pose_t around = {0u, 0, 0};
    ego_project_cells_t cells;
    TEST_ASSERT_EQUAL_UINT32(0u, ego_project_cells(&g_last, &g_current, 0u, &around, 0,
                                                   FX_Q16_16_C(0.1), &g_scratch, &cells));
    TEST_ASSERT_EQUAL_UINT(0u, cells.count);
    TEST_ASSERT_EQUAL_UINT32(0u, ego_project_cells(&g_last, &g_current, 0u, &around,
                                                   FX_Q16_16_C(1.0), 0, &g_scratch, &cells));
    g_current.count = 0u;
    const uint32_t units = ego_project_cells(&g_last, &g_current, 0u, &around, FX_Q16_16_C(1.0),
                                             FX_Q16_16_C(0.1), &g_scratch, &cells);
    TEST_ASSERT_TRUE(units <= ego_project_cost_max(&g_last, &g_current, FX_Q16_16_C(1.0),
                                                   FX_Q16_16_C(0.1)));
    TEST_ASSERT_EQUAL_UINT(EGO_PROJECT_CELLS, cells.count); /* all tied at 0: row order */
    TEST_ASSERT_EQUAL_INT32(-10 * FX_Q16_16_C(0.1), cells.cell[0].x);
    TEST_ASSERT_EQUAL_INT32(-10 * FX_Q16_16_C(0.1), cells.cell[0].y);
    /* A window wider than the cap is ranked over the cap. */
    TEST_ASSERT_EQUAL_INT32(EGO_PROJECT_MAX_SIDE, ego_project_side(FX_Q16_16_C(9.0), FX_Q16_16_C(0.1)));
    TEST_ASSERT_EQUAL_INT32(EGO_PROJECT_MAX_SIDE, ego_project_side(FX_Q16_16_C(4.0), FX_Q16_16_C(0.2)));
}

/* The ranking in steps (a direction a step, then the cells) gives the
 * cells of the ranking at once, each step within its own bound; and every
 * step of the light search's rankings (ego.c: the wide window, 1.6 m at
 * 0.2 m, or the first, 4 m at 0.4 m: at most 10 cells each side) fits the
 * smallest default budget beside a scan's bookkeeping for scans up to the
 * capacity, so a search that ranks in steps always goes on. */
static void test_projection_in_steps(void)
{
    prepared(0.0, 0.0, 0.0, &g_last);
    prepared(1.1, -0.6, 8.0, &g_current);
    const ego_pose_t around = {(fx_bam32_t)(int32_t)llround(8.0 / 360.0 * 4294967296.0), 0, 0};
    const fx_q16_16_t win = FX_Q16_16_C(1.6);
    const fx_q16_16_t bin = FX_Q16_16_C(0.2);
    ego_project_cells_t whole;
    const uint32_t whole_units =
        ego_project_cells(&g_last, &g_current, 0u, &around, win, bin, &g_scratch, &whole);
    memset(&g_scratch, 0xA5, sizeof g_scratch);
    uint32_t units = 0u;
    for (unsigned k = 0u; k < EGO_PROJECT_DIRS; k++) {
        const uint32_t step = ego_project_direction(&g_last, &g_current, 0u, &around, win, bin, k,
                                                    &g_scratch);
        TEST_ASSERT_TRUE(step > 0u);
        TEST_ASSERT_TRUE(step <= ego_project_direction_cost_max(&g_last, &g_current, win, bin));
        units += step;
    }
    ego_project_cells_t stepped;
    const uint32_t rank = ego_project_rank(0u, &around, win, bin, &g_scratch, &stepped);
    TEST_ASSERT_EQUAL_UINT32(ego_project_rank_cost(win, bin), rank);
    TEST_ASSERT_EQUAL_UINT32(whole_units, units + rank);
    TEST_ASSERT_EQUAL_UINT(whole.count, stepped.count);
    TEST_ASSERT_EQUAL_MEMORY(whole.cell, stepped.cell, sizeof whole.cell[0] * whole.count);
    TEST_ASSERT_TRUE(fabs(metres(stepped.cell[0].x) - 1.1) <= 0.2 + 1e-4);
    TEST_ASSERT_TRUE(fabs(metres(stepped.cell[0].y) + 0.6) <= 0.2 + 1e-4);
    /* The dearest step: full scans, the light search's widest ranking. */
    g_last.count = EGO_MAX_POINTS;
    g_current.count = EGO_MAX_POINTS;
    const fx_q16_16_t widest = 10 * bin;
    const uint32_t room = EGO_DEFAULT_WORK_MIN - EGO_COST_SCAN;
    TEST_ASSERT_TRUE(ego_project_direction_cost_max(&g_last, &g_current, widest, bin) <= room);
    TEST_ASSERT_TRUE(ego_project_rank_cost(widest, bin) <= room);
}

/* A corridor 3 m wide along x with door frames jutting 0.4 m from its
 * walls: along x only the frames tell how far the scanner went. */
static const synth_wall_t g_frames[] = {
    {-100.0, -1.5, 100.0, -1.5}, {-100.0, 1.5, 100.0, 1.5}, {4.0, 1.5, 4.0, 1.1},
    {7.5, -1.5, 7.5, -1.1},      {11.0, 1.5, 11.0, 1.1},    {16.0, -1.5, 16.0, -1.1},
    {23.0, 1.5, 23.0, 1.1},
};

/* The shift along direction dir_deg from around (cx, cy, theta_deg) to the
 * truth (tx, ty): found within a bin of the truth's projection, at a shift
 * whose correlation is the double oracle's maximum (2 %), within the
 * units it may cost. */
static void check_along(const synth_wall_t *walls, unsigned nwalls, double tx, double ty,
                        double theta_deg, double cx, double cy, double dir_deg, double window)
{
    prepared_in(walls, nwalls, 0.0, 0.0, 0.0, &g_last);
    prepared_in(walls, nwalls, tx, ty, theta_deg, &g_current);
    const fx_bam32_t theta = (fx_bam32_t)(int32_t)llround(theta_deg / 360.0 * 4294967296.0);
    const fx_bam32_t dir = (fx_bam32_t)(int32_t)llround(dir_deg / 360.0 * 4294967296.0);
    const ego_pose_t around = {theta, (fx_q16_16_t)llround(cx * 65536.0),
                               (fx_q16_16_t)llround(cy * 65536.0)};
    const fx_q16_16_t bin = FX_Q16_16_C(0.1);
    const fx_q16_16_t win = (fx_q16_16_t)llround(window * 65536.0);
    fx_q16_16_t shift = 0;
    uint32_t units = 0u;
    const bool found =
        ego_project_along(&g_last, &g_current, dir, &around, win, bin, &g_scratch, &shift, &units);
    const double c = cos(dir_deg * DEG);
    const double s = sin(dir_deg * DEG);
    const double want = (tx - cx) * c + (ty - cy) * s;
    char msg[160];
    (void)snprintf(msg, sizeof msg, "shift %.3f m, truth %.3f m, units %u of %u", metres(shift),
                   want, (unsigned)units,
                   (unsigned)ego_project_along_cost_max(&g_last, &g_current, win, bin));
    TEST_ASSERT_TRUE_MESSAGE(found, msg);
    TEST_ASSERT_TRUE_MESSAGE(fabs(metres(shift) - want) <= 0.1 + 1e-4, msg);
    TEST_ASSERT_TRUE_MESSAGE(units > 0u, msg);
    TEST_ASSERT_TRUE_MESSAGE(units <= ego_project_along_cost_max(&g_last, &g_current, win, bin), msg);
    double corr[2 * EGO_PROJECT_MAX_SIDE + 1];
    double centre = 0.0;
    const int n = project_ref_along(&g_last, &g_current, dir_deg * DEG, theta_deg * DEG,
                                    metres(around.x), metres(around.y), window, 0.1, corr, &centre);
    TEST_ASSERT_EQUAL_INT(ego_project_side(win, bin), n);
    double best = 0.0;
    for (int j = 0; j <= 2 * n; j++) {
        best = (corr[j] > best) ? corr[j] : best;
    }
    const double projected = metres(around.x) * c + metres(around.y) * s + metres(shift);
    const long j = lround(projected / 0.1 - centre);
    TEST_ASSERT_TRUE_MESSAGE(j >= -n && j <= n, msg);
    TEST_ASSERT_TRUE_MESSAGE(corr[j + n] >= 0.98 * best, msg);
}

static void test_projection_along_finds_a_missed_speed(void)
{
    /* Predicted 2.0 m along the corridor, driven 2.7 m. */
    check_along(g_frames, sizeof g_frames / sizeof g_frames[0], 2.7, 0.05, 0.5, 2.0, 0.05, 0.0,
                1.0);
    /* Braked: 1.2 m short of 3 m. */
    check_along(g_frames, sizeof g_frames / sizeof g_frames[0], 1.8, -0.1, -1.0, 3.0, -0.1, 0.0,
                1.5);
    /* In the room, along an oblique direction of travel. */
    check_along(synth_room, synth_room_walls, 0.6, 0.35, 3.0, 0.1, 0.05, 30.0, 0.8);
}

/* Walls along the direction only: nothing faces it, no shift. */
static void test_projection_along_a_bare_corridor(void)
{
    prepared_in(synth_corridor, synth_corridor_walls, 0.0, 0.0, 0.0, &g_last);
    prepared_in(synth_corridor, synth_corridor_walls, 1.0, 0.0, 0.0, &g_current);
    const ego_pose_t around = {0u, FX_Q16_16_C(0.5), 0};
    fx_q16_16_t shift = 12345;
    uint32_t units = 0u;
    TEST_ASSERT_FALSE(ego_project_along(&g_last, &g_current, 0u, &around, FX_Q16_16_C(1.0),
                                        FX_Q16_16_C(0.1), &g_scratch, &shift, &units));
    TEST_ASSERT_TRUE(units > 0u);
    TEST_ASSERT_TRUE(units <= ego_project_along_cost_max(&g_last, &g_current, FX_Q16_16_C(1.0),
                                                         FX_Q16_16_C(0.1)));
    /* No window: no work. */
    TEST_ASSERT_FALSE(ego_project_along(&g_last, &g_current, 0u, &around, 0, FX_Q16_16_C(0.1),
                                        &g_scratch, &shift, &units));
    TEST_ASSERT_EQUAL_UINT32(0u, units);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_projection_finds_a_translation_in_the_wide_window);
    RUN_TEST(test_projection_finds_a_translation_in_the_first_window);
    RUN_TEST(test_projection_window_off_centre);
    RUN_TEST(test_projection_against_the_double_oracle);
    RUN_TEST(test_projection_of_nothing);
    RUN_TEST(test_projection_in_steps);
    RUN_TEST(test_projection_along_finds_a_missed_speed);
    RUN_TEST(test_projection_along_a_bare_corridor);
    return UNITY_END();
}
